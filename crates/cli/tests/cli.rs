//! The `mcrender` binary as a user meets it: determinism across thread counts, clear
//! errors with exit code 2 and no partial output for bad input, and the no-argument render.

mod common;

use common::{mcrender, scene, stderr};

fn cornell() -> String {
    scene("cornell-box/scene-v4.pbrt")
}

#[test]
fn same_seed_gives_identical_bytes_with_one_and_two_threads() {
    let dir = tempfile::tempdir().unwrap();
    let scene = cornell();
    let run = |threads: &str, seed: &str, out: &str| {
        let o = mcrender(
            &[
                "render",
                &scene,
                "-o",
                out,
                "--resolution",
                "48x40",
                "--spp",
                "8",
                "--threads",
                threads,
                "--seed",
                seed,
                "-q",
            ],
            dir.path(),
        );
        assert!(o.status.success(), "{}", stderr(&o));
        std::fs::read(dir.path().join(out)).unwrap()
    };
    let one = run("1", "3", "one.exr");
    let two = run("2", "3", "two.exr");
    assert!(one == two, "1-thread and 2-thread renders differ");
    let other_seed = run("2", "4", "other.exr");
    assert!(one != other_seed, "a different seed gave the same image");
}

#[test]
fn malformed_scene_is_rejected_with_location_and_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.pbrt");
    std::fs::write(
        &bad,
        "Film \"rgb\" \"integer xresolution\" [ 64 ]\nWorldBegin\nShape \"sphere\" \"float radius\" [ oops ]\n",
    )
    .unwrap();
    let o = mcrender(&["render", bad.to_str().unwrap(), "-o", "out.png", "-q"], dir.path());
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let msg = stderr(&o);
    assert!(msg.contains("bad.pbrt:3:"), "message lacks file:line: {msg}");
    assert!(!msg.contains("panicked"), "{msg}");
    assert!(!dir.path().join("out.png").exists());
}

#[test]
fn missing_scene_file_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let o = mcrender(&["render", "no-such-scene.pbrt", "-q"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("no-such-scene.pbrt"), "{}", stderr(&o));
}

#[test]
fn absurd_resolution_is_refused_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    let o = mcrender(
        &[
            "render",
            &cornell(),
            "-o",
            "huge.png",
            "--resolution",
            "100000x100000",
            "-q",
        ],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("resolution"), "{}", stderr(&o));
    assert!(!dir.path().join("huge.png").exists());
}

#[test]
fn unknown_output_format_is_refused_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    let o = mcrender(&["render", &cornell(), "-o", "out.jpg", "--spp", "1", "-q"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("out.jpg"), "{}", stderr(&o));
    assert!(!dir.path().join("out.jpg").exists());
}

#[test]
fn unwritable_output_leaves_nothing_behind() {
    let dir = tempfile::tempdir().unwrap();
    let o = mcrender(
        &[
            "render",
            &cornell(),
            "-o",
            "missing-dir/out.png",
            "--resolution",
            "8x8",
            "--spp",
            "1",
            "-q",
        ],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(!dir.path().join("missing-dir").exists());
    let leftovers: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
}

#[test]
fn no_arguments_renders_the_builtin_cornell_box() {
    let dir = tempfile::tempdir().unwrap();
    let o = mcrender(&[], dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let png = dir.path().join("cornell-box.png");
    let img = image::open(&png).expect("a PNG").to_rgb8();
    assert_eq!(img.dimensions(), (256, 256));
    // The red wall is on the left, the green wall on the right (compared in linear light:
    // the walls' albedos are (0.63, 0.065, 0.05) and (0.14, 0.45, 0.091)).
    let linear = |x: u32, y: u32| {
        img.get_pixel(x, y)
            .0
            .map(|v| mcrender_core::color::srgb_to_linear(f32::from(v) / 255.0))
    };
    let (left, right) = (linear(20, 128), linear(235, 128));
    assert!(
        left[0] > 4.0 * left[1] && right[1] > 2.0 * right[0],
        "left {left:?} right {right:?}"
    );
    assert!(stderr(&o).contains("paths/s"), "{}", stderr(&o));
}

#[test]
fn sampler_override_changes_the_samples_but_not_the_picture() {
    let dir = tempfile::tempdir().unwrap();
    let mut means = Vec::new();
    for sampler in ["independent", "stratified", "sobol"] {
        let out = format!("{sampler}.exr");
        let o = mcrender(
            &[
                "render",
                &cornell(),
                "--sampler",
                sampler,
                "--resolution",
                "32x32",
                "--spp",
                "64",
                "-o",
                &out,
                "-q",
            ],
            dir.path(),
        );
        assert!(o.status.success(), "{}", stderr(&o));
        let img = mcrender_formats::image_io::read_exr(&dir.path().join(&out)).unwrap();
        means.push(img.pixels.iter().map(|p| f64::from(p.luminance())).sum::<f64>() / img.pixels.len() as f64);
    }
    // Three unbiased estimates of one image: their means agree to within the noise (a few %).
    for m in &means[1..] {
        assert!((m - means[0]).abs() < 0.05 * means[0], "{means:?}");
    }
    assert!(
        means[0] != means[1] && means[1] != means[2],
        "the override did nothing: {means:?}"
    );
    let o = mcrender(&["render", &cornell(), "--sampler", "halton", "-q"], dir.path());
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn malformed_mitsuba_scene_is_rejected_with_location_and_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    for (name, text, at) in [
        (
            "bad.xml",
            "<scene version=\"3.0.0\">\n  <shape type=\"sphere\">\n</scene>\n",
            "bad.xml:3:",
        ),
        (
            "plugin.xml",
            "<scene version=\"3.0.0\">\n  <bsdf type=\"glitter\"/>\n</scene>\n",
            "plugin.xml:2:3",
        ),
        (
            "ref.xml",
            "<scene version=\"3.0.0\">\n  <shape type=\"sphere\"><ref id=\"gone\"/></shape>\n</scene>\n",
            "ref.xml:2:",
        ),
    ] {
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        let o = mcrender(&["render", path.to_str().unwrap(), "-o", "out.png", "-q"], dir.path());
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        let msg = stderr(&o);
        assert!(msg.contains(at), "{name}: message lacks {at}: {msg}");
        assert!(!msg.contains("panicked"), "{msg}");
        assert!(!dir.path().join("out.png").exists());
    }
}

#[test]
fn mitsuba_scene_renders_with_a_define() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.xml");
    std::fs::write(
        &path,
        r#"<scene version="3.0.0">
  <default name="spp" value="1"/>
  <sensor type="perspective"><float name="fov" value="45"/>
    <transform name="to_world"><lookat origin="0,0,-4" target="0,0,0" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
    <sampler type="independent"><integer name="sample_count" value="$spp"/></sampler>
  </sensor>
  <emitter type="constant"/>
  <shape type="sphere"/>
</scene>"#,
    )
    .unwrap();
    let o = mcrender(
        &["render", path.to_str().unwrap(), "-D", "spp=3", "-o", "out.exr"],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("3 spp"), "{}", stderr(&o));
    assert!(dir.path().join("out.exr").exists());
}

/// A reader that closes the pipe (`mcrender pi | head -1` once `head` has its line) stops the
/// command quietly with status 141 (128 + SIGPIPE, what a shell reports for such a process),
/// never a panic. The pipe's read end is closed before the command starts, so every write
/// meets the closed pipe, whatever the timing.
#[test]
fn closed_stdout_ends_quietly_with_status_141() {
    for args in [&["pi", "--samples", "10,100"][..], &["pi", "--samples", "10", "--json"]] {
        let (reader, writer) = std::io::pipe().unwrap();
        drop(reader);
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_mcrender"))
            .args(args)
            .stdout(writer)
            .output()
            .expect("mcrender runs");
        assert_eq!(o.status.code(), Some(141), "{args:?}: {}", stderr(&o));
        assert_eq!(stderr(&o), "", "{args:?}");
    }
}
