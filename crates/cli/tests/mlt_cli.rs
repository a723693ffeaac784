//! `mcrender render` of a scene file that says `Integrator "mlt"`: rendered by MLT without
//! the fallback warning, the closed form of the scene is met, and the bytes do not depend
//! on the thread count.

mod common;

use std::path::Path;

use common::{mcrender, stderr};
use mcrender_formats::image_io::read_exr;

/// The camera inside a closed sphere emitting 1 with albedo 1/2: up to depth 3 the
/// radiance is (1 - 2^-4) / (1 - 1/2) = 1.875 everywhere. A box filter one pixel wide, so
/// that every splat falls wholly inside the image and the image mean is exactly the
/// bootstrap's normalisation `b`. (With the default Gaussian, splats near the border spill
/// past it and the mean also carries the chains' noise: measured over 80 seeds, 1.880 with
/// a standard deviation of 0.06 per render; `crates/core/tests/mlt.rs` checks that case.)
const SCENE: &str = r#"LookAt 0 0 0  0 0 1  0 1 0
Camera "perspective" "float fov" 60
PixelFilter "box"
Film "rgb" "integer xresolution" 16 "integer yresolution" 12
Integrator "mlt" "integer maxdepth" 3 "integer bootstrapsamples" 20000 "integer chains" 8
    "integer mutationsperpixel" 8
WorldBegin
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [1 1 1]
  ReverseOrientation
  Material "diffuse" "rgb reflectance" [0.5 0.5 0.5]
  Shape "sphere" "float radius" 2
AttributeEnd
"#;

fn render(dir: &Path, threads: &str, out: &str) -> Vec<u8> {
    let o = mcrender(&["render", "scene.pbrt", "--threads", threads, "-o", out, "-q"], dir);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(!err.contains("not implemented"), "fallback warning: {err}");
    assert!(err.contains("MLT"), "not rendered by MLT: {err}");
    std::fs::read(dir.join(out)).unwrap()
}

#[test]
fn renders_a_scene_file_asking_for_mlt() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("scene.pbrt"), SCENE).unwrap();
    let one = render(dir.path(), "1", "one.exr");
    let two = render(dir.path(), "2", "two.exr");
    assert_eq!(one, two, "1 and 2 threads differ");
    let img = read_exr(&dir.path().join("one.exr")).unwrap();
    assert_eq!((img.width, img.height), (16, 12));
    let mean = img.pixels.iter().map(|p| f64::from(p.luminance())).sum::<f64>() / img.pixels.len() as f64;
    // The image mean is the bootstrap's normalisation: 20000 samples per depth put its
    // relative standard error near 0.3% here.
    assert!((mean - 1.875).abs() < 0.02 * 1.875, "image mean {mean} vs 1.875");
}

/// A render with --checkpoint that runs to the end writes the bytes of one without, and
/// removes its checkpoint (interrupted and resumed MLT renders: `tests/checkpoint.rs`).
#[test]
fn a_checkpointed_render_that_finishes_writes_the_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("scene.pbrt"), SCENE).unwrap();
    let plain = render(dir.path(), "2", "plain.exr");
    let o = mcrender(
        &[
            "render",
            "scene.pbrt",
            "-o",
            "x.exr",
            "-q",
            "--checkpoint",
            "c.ckpt",
            "--checkpoint-every",
            "1ms",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read(dir.path().join("x.exr")).unwrap(), plain);
    assert!(!dir.path().join("c.ckpt").exists());
}
