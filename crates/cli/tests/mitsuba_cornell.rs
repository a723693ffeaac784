//! Bitterli's Cornell box in its two descriptions, `cornell-box/mitsuba/scene_v3.xml`
//! (Mitsuba 3) and `cornell-box/scene-v4.pbrt` (pbrt-v4), render to the same image within
//! noise: every pixel's difference is measured in units of its standard error (from both
//! renders' own per-pixel sample variances, independent sampler), and so is the difference
//! of the image means. A 5% brightness error fails the test (checked in the test itself).
//! It fails when the shared scenes cannot be found, unless `MCRENDER_SKIP_SHARED_SCENES`
//! is set (then a visible `SKIPPED` line).

mod common;

use mcrender_core::color::Rgb;
use mcrender_core::render::{render, RenderOptions};
use mcrender_core::scene::{SamplerKind, Scene};
use mcrender_formats::load;

use common::agreement::agreement;
use common::shared_scenes::shared_scenes_dir;

const SIZE: u32 = 64;
const SPP: u32 = 128;

/// Mean image and per-pixel variance of the mean.
fn render_file(path: &std::path::Path, seed: u64) -> (Vec<Rgb>, Vec<Rgb>) {
    let mut desc = load(path).expect("scene loads").description;
    desc.film.width = SIZE;
    desc.film.height = SIZE;
    desc.sampler.kind = SamplerKind::Independent;
    desc.sampler.samples_per_pixel = SPP;
    desc.sampler.seed = seed;
    let scene = Scene::build(&desc).expect("builds");
    let out = render(&scene, &RenderOptions::default(), &|_, _| {}).expect("renders");
    (out.film.mean_image(), out.film.variance_image())
}

#[test]
fn mitsuba_and_pbrt_cornell_boxes_agree_within_noise() {
    let Some(dir) = shared_scenes_dir("mitsuba_and_pbrt_cornell_boxes_agree_within_noise") else {
        return;
    };
    let m = render_file(&dir.join("cornell-box/mitsuba/scene_v3.xml"), 1);
    let p = render_file(&dir.join("cornell-box/scene-v4.pbrt"), 2);
    let a = agreement(&m, &p, 1.0);
    let (fraction, mean_z) = (a.within, a.max_mean_z);
    eprintln!(
        "Cornell box, Mitsuba vs pbrt description: {:.3}% of channels within 3.29 sigma, image-mean z {mean_z:.2}",
        fraction * 100.0
    );
    // Expected 99.9% for identical images; sample variances at 128 spp are themselves noisy.
    assert!(fraction > 0.99, "only {:.3}% of pixel channels agree", fraction * 100.0);
    assert!(mean_z < 4.0, "image means differ by {mean_z:.2} standard errors");
    // The test can fail: 5% brighter is far outside the noise.
    let scaled_z = agreement(&m, &p, 1.05).max_mean_z;
    eprintln!("the same with the Mitsuba render 5% brighter: image-mean z {scaled_z:.2}");
    assert!(scaled_z > 4.0, "a 5% brightness error went unnoticed (z {scaled_z:.2})");
}
