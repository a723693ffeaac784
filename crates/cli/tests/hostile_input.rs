//! Regression tests for the hostile inputs of issue 10, each named after its bug: every one
//! is refused *before* rendering (so quickly), with one line naming what is wrong, exit code
//! 2, and no output file.

mod common;

use std::path::Path;
use std::time::{Duration, Instant};

use common::{mcrender, scene, stderr};

fn cornell() -> String {
    scene("cornell-box/scene-v4.pbrt")
}

/// Run `mcrender args` in `dir`; expect exit code 2 within `limit`, one line on stderr, no
/// control characters in it; return it.
fn refused(args: &[&str], dir: &Path, limit: Duration) -> String {
    let start = Instant::now();
    let o = mcrender(args, dir);
    let took = start.elapsed();
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
    assert!(took < limit, "{args:?} took {took:?} to fail: {err}");
    assert_eq!(err.lines().count(), 1, "{args:?}: not one line: {err}");
    assert!(!err.trim_end().chars().any(char::is_control), "{args:?}: {err:?}");
    err
}

/// No image files in `dir`.
fn no_images(dir: &Path) {
    let left: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(Result::ok)
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".png") || n.ends_with(".exr") || n.contains(".tmp-"))
        .collect();
    assert!(left.is_empty(), "files left behind: {left:?}");
}

const FAST: Duration = Duration::from_secs(10);

#[test]
fn resolution_16384x16384_is_refused_before_allocating() {
    let dir = tempfile::tempdir().unwrap();
    let err = refused(
        &[
            "render",
            &cornell(),
            "--resolution",
            "16384x16384",
            "--max-memory",
            "8G",
            "-o",
            "a.png",
            "-q",
        ],
        dir.path(),
        FAST,
    );
    assert!(
        err.contains("memory limit of 8.0 GiB") && err.contains("46.0 GiB"),
        "{err}"
    );
    no_images(dir.path());
    // Beyond the renderer's own bounds it is a flag error (clap's, with a usage hint).
    let o = mcrender(&["render", &cornell(), "--resolution", "100000x2", "-q"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).lines().next().unwrap().contains("32768"), "{}", stderr(&o));
}

#[test]
fn output_in_missing_directory_is_reported_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    // 100,000 samples per pixel would take minutes: the error must come first.
    let err = refused(
        &["render", &cornell(), "--spp", "100000", "-o", "missing/a.png", "-q"],
        dir.path(),
        FAST,
    );
    assert!(err.contains("\"missing\" does not exist"), "{err}");
}

#[test]
fn output_in_read_only_directory_is_reported_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    // /sys takes no new files, even from root.
    let err = refused(
        &["render", &cornell(), "--spp", "100000", "-o", "/sys/a.png", "-q"],
        dir.path(),
        FAST,
    );
    assert!(err.contains("cannot write in \"/sys\""), "{err}");
}

#[test]
fn failing_variance_output_leaves_no_main_image() {
    let dir = tempfile::tempdir().unwrap();
    let err = refused(
        &[
            "render",
            &cornell(),
            "--resolution",
            "8x8",
            "--spp",
            "1",
            "-o",
            "a.exr",
            "--variance-output",
            "/sys/v.exr",
            "-q",
        ],
        dir.path(),
        FAST,
    );
    assert!(err.contains("--variance-output"), "{err}");
    no_images(dir.path());
    // The same file twice would lose the image.
    let err = refused(
        &["render", &cornell(), "-o", "a.exr", "--variance-output", "a.exr", "-q"],
        dir.path(),
        FAST,
    );
    assert!(err.contains("same file"), "{err}");
}

#[test]
fn threads_100000_is_refused_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let err = refused(&["render", &cornell(), "--threads", "100000", "-q"], dir.path(), FAST);
    assert!(err.contains("--threads 100000") && err.contains("1024"), "{err}");
    no_images(dir.path());
}

#[test]
fn spp_4294967295_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let err = refused(&["render", &cornell(), "--spp", "4294967295", "-q"], dir.path(), FAST);
    assert!(
        err.contains("4294967295 samples per pixel") && err.contains("16777216"),
        "{err}"
    );
    no_images(dir.path());
}

#[test]
fn ten_megabyte_token_is_not_echoed_in_error() {
    let dir = tempfile::tempdir().unwrap();
    let text = format!("WorldBegin\n{}\n", "x".repeat(10 << 20));
    std::fs::write(dir.path().join("big.pbrt"), text).unwrap();
    let err = refused(&["render", "big.pbrt", "-q"], dir.path(), FAST);
    assert!(err.len() < 300, "{} bytes of error", err.len());
    assert!(
        err.contains("big.pbrt:2:1") && err.contains("(10485760 characters)"),
        "{err}"
    );
    // A quoted string too.
    let text = format!("WorldBegin\nShape \"{}\"\n", "y".repeat(10 << 20));
    std::fs::write(dir.path().join("big.pbrt"), text).unwrap();
    let err = refused(&["render", "big.pbrt", "-q"], dir.path(), FAST);
    assert!(err.len() < 300, "{} bytes of error", err.len());
}

#[test]
fn raw_nul_bytes_are_not_printed() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("nul.pbrt"), b"WorldBegin\nFoo\0\x1b[31m \"a\0b\"\n").unwrap();
    let err = refused(&["render", "nul.pbrt", "-q"], dir.path(), FAST);
    // The word ends at the bracket.
    assert!(err.contains(r#""Foo\0\u{1b}""#), "{err}");
}

#[test]
fn ply_rs_debug_dumps_are_not_shown() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("s.pbrt"),
        "WorldBegin\nShape \"plymesh\" \"string filename\" \"bad.ply\"\n",
    )
    .unwrap();
    for ply in [
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty foo y\nend_header\n",
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nelement face 0\nproperty list uchar int vertex_indices\nend_header\nzz\n",
    ] {
        std::fs::write(dir.path().join("bad.ply"), ply).unwrap();
        let err = refused(&["render", "s.pbrt", "-q"], dir.path(), FAST);
        assert!(err.contains("s.pbrt:2:1") && err.contains("bad.ply"), "{err}");
        for dump in ["ParseError", "Custom", "kind:", "{", "expected: "] {
            assert!(!err.contains(dump), "{dump} in {err}");
        }
    }
}

#[test]
fn os_errors_are_not_doubled() {
    let dir = tempfile::tempdir().unwrap();
    let err = refused(&["convert", "none.png", "out.png"], dir.path(), FAST);
    assert_eq!(err.matches("No such file or directory").count(), 1, "{err}");
    assert!(!err.contains("os error"), "{err}");
    let err = refused(&["render", "none.pbrt", "-q"], dir.path(), FAST);
    assert_eq!(err.matches("No such file or directory").count(), 1, "{err}");
}

#[test]
fn sphere_of_radius_1e38_is_an_error_naming_the_limit() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("s.pbrt"),
        "LookAt 0 0 5 0 0 0 0 1 0\nCamera \"perspective\"\nFilm \"rgb\" \"integer xresolution\" [ 8 ] \"integer yresolution\" [ 8 ]\nWorldBegin\nAttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ]\nShape \"sphere\" \"float radius\" [ 1e38 ]\nAttributeEnd\nShape \"sphere\"\n",
    )
    .unwrap();
    let err = refused(&["render", "s.pbrt", "-o", "a.png", "-q"], dir.path(), FAST);
    assert!(err.contains("1e18") && err.contains("shape 0"), "{err}");
    no_images(dir.path());
}

#[test]
fn max_memory_flag_is_parsed_with_units() {
    let dir = tempfile::tempdir().unwrap();
    let o = mcrender(&["render", &cornell(), "--max-memory", "lots", "-q"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("expected a size such as 4G"), "{}", stderr(&o));
    // A small scene fits a small limit.
    let o = mcrender(
        &[
            "render",
            &cornell(),
            "--max-memory",
            "64M",
            "--resolution",
            "8x8",
            "--spp",
            "1",
            "-o",
            "a.png",
            "-q",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
}

/// `dir/big.tga`: only the header of a 16384x16384 24-bit TGA, so decoding would fail and a
/// refusal must come from the header.
fn write_big_tga_header(dir: &Path) {
    let mut tga = vec![0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0];
    tga.extend(16384u16.to_le_bytes());
    tga.extend(16384u16.to_le_bytes());
    tga.extend([24, 0]);
    std::fs::write(dir.join("big.tga"), tga).unwrap();
}

/// `--max-memory` covers a Mitsuba XML scene's bitmap textures too (its loader reported
/// them as 0 bytes): a 16384x16384 texture is refused from its header, before it is
/// decoded or anything rendered.
#[test]
fn max_memory_refuses_a_mitsuba_scene_with_a_big_texture_before_loading_it() {
    let dir = tempfile::tempdir().unwrap();
    write_big_tga_header(dir.path());
    let xml = r#"<scene version="3.0.0">
<sensor type="perspective"><film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/></film></sensor>
<shape type="sphere">
  <bsdf type="diffuse"><texture type="bitmap" name="reflectance"><string name="filename" value="big.tga"/></texture></bsdf>
</shape>
<emitter type="constant"/>
</scene>
"#;
    std::fs::write(dir.path().join("scene.xml"), xml).unwrap();
    let err = refused(
        &["render", "scene.xml", "--max-memory", "1G", "-o", "a.png", "-q"],
        dir.path(),
        FAST,
    );
    assert!(
        err.contains("scene.xml:4:") && err.contains("16384x16384") && err.contains("memory limit of 1.0 GiB"),
        "{err}"
    );
    no_images(dir.path());
}

/// `--max-memory` covers an OBJ scene's textures too (its loader reported them as 0
/// bytes): a 16384x16384 `map_Kd` is refused from its header, before it is decoded or
/// anything rendered (glTF images: `crates/formats/tests/gltf_loader.rs`).
#[test]
fn max_memory_refuses_an_obj_scene_with_a_big_texture_before_loading_it() {
    let dir = tempfile::tempdir().unwrap();
    write_big_tga_header(dir.path());
    std::fs::write(dir.path().join("m.mtl"), "newmtl m\nKd 1 1 1\nmap_Kd big.tga\n").unwrap();
    std::fs::write(
        dir.path().join("scene.obj"),
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl m\nf 1/1 2/2 3/3\n",
    )
    .unwrap();
    let err = refused(
        &["render", "scene.obj", "--max-memory", "1G", "-o", "a.png", "-q"],
        dir.path(),
        FAST,
    );
    assert!(
        err.contains("scene.obj") && err.contains("16384x16384") && err.contains("memory limit of 1.0 GiB"),
        "{err}"
    );
    no_images(dir.path());
}
