//! Light tracing and SPPM on Bitterli's Cornell box: light tracing within noise of the path
//! tracer at small size, SPPM converging to the Mitsuba 3 reference, both identical with
//! 1 and 2 threads.

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

use mcrender_core::color::Rgb;
use mcrender_core::film::{block_means_of, downsample_box};
use mcrender_core::integrator::sppm::{render_with_threads, SppmSettings};
use mcrender_core::math::Vec2;
use mcrender_core::render::{render, RenderOptions};
use mcrender_core::scene::{FilterDesc, IntegratorKind, SamplerKind, Scene, SceneDescription};
use mcrender_formats::image_io::read_exr;
use mcrender_formats::pbrt::load_file;

fn repo_file(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..").join(rel)
}

/// The Cornell box at `res` x `res`, box filter one pixel wide (splats land in one pixel),
/// independent sampler, depth 16.
fn cornell(res: u32, spp: u32, kind: IntegratorKind) -> SceneDescription {
    let mut d = load_file(&repo_file("scenes/cornell-box/scene-v4.pbrt"))
        .expect("scene loads")
        .description;
    d.film.width = res;
    d.film.height = res;
    d.filter = FilterDesc::Box {
        radius: Vec2::splat(0.5),
    };
    d.sampler.kind = SamplerKind::Independent;
    d.sampler.samples_per_pixel = spp;
    d.sampler.seed = 3;
    d.integrator.max_depth = 16;
    d.integrator.kind = kind;
    d
}

fn render_image(d: &SceneDescription, threads: usize) -> Vec<Rgb> {
    let scene = Scene::build(d).expect("scene builds");
    let opts = RenderOptions {
        threads: Some(threads),
        ..Default::default()
    };
    render(&scene, &opts, &|_, _| {}).expect("render").film.mean_image()
}

/// Image means per channel and the relative RMS difference of 8x8-pixel block means
/// (luminance) between two images of size `res`.
fn compare(a: &[Rgb], b: &[Rgb], res: u32, block: u32) -> ([f64; 3], f64) {
    let mean = |img: &[Rgb], c: usize| img.iter().map(|p| f64::from(p[c])).sum::<f64>() / img.len() as f64;
    let rel = [0, 1, 2].map(|c| (mean(a, c) - mean(b, c)) / mean(b, c));
    let (_, _, ba) = block_means_of(a, res, res, block).unwrap();
    let (_, _, bb) = block_means_of(b, res, res, block).unwrap();
    let lum = |m: &[f64; 3]| 0.2126 * m[0] + 0.7152 * m[1] + 0.0722 * m[2];
    let rms = (ba
        .iter()
        .zip(&bb)
        .map(|(x, y)| ((lum(x) - lum(y)) / lum(y).max(1e-3)).powi(2))
        .sum::<f64>()
        / ba.len() as f64)
        .sqrt();
    (rel, rms)
}

/// Light tracing against the path tracer on the same 32x32 Cornell box: image means
/// within 0.75% per channel and 8x8-pixel block means within 2.5% RMS (measured at 1024
/// spp each: means within 0.12%, block RMS 0.64%).
#[test]
fn light_tracing_matches_the_path_tracer_on_the_cornell_box() {
    let path = render_image(&cornell(32, 1024, IntegratorKind::Path), 2);
    let light = render_image(&cornell(32, 1024, IntegratorKind::LightPath), 2);
    let (rel, rms) = compare(&light, &path, 32, 8);
    eprintln!("light tracing vs path tracing: mean differences {rel:?}, block RMS {rms:.4}");
    assert!(rel.iter().all(|r| r.abs() < 0.0075), "means differ: {rel:?}");
    assert!(rms < 0.025, "block means differ by {rms}");
}

#[test]
fn light_tracing_is_identical_with_one_and_two_threads() {
    let d = cornell(16, 8, IntegratorKind::LightPath);
    assert_eq!(render_image(&d, 1), render_image(&d, 2));
}

fn sppm(d: &SceneDescription, iterations: u32, threads: usize) -> Vec<Rgb> {
    let scene = Scene::build(d).expect("scene builds");
    let settings = SppmSettings {
        iterations,
        photons_per_iteration: 100_000,
        initial_radius: 0.05,
        seed: 5,
        max_depth: d.integrator.max_depth,
    };
    let (out, _) = render_with_threads(&scene, &settings, Some(threads), &|_, _| {}, &AtomicBool::new(false)).unwrap();
    out.film.mean_image()
}

/// SPPM against the Mitsuba reference (box-downsampled 256 -> 64): the error of the
/// block means falls as iterations grow and ends within 4% RMS, means within 2%
/// (measured: 3.7% RMS after 2 iterations, 2.25% after 24, means within 0.4%; the
/// reference's tent filter at 256x256 accounts for part of the rest).
#[test]
fn sppm_converges_to_the_cornell_box_reference() {
    let reference = read_exr(&repo_file("scenes/cornell-box/reference-mitsuba-256.exr")).expect("reference loads");
    let (_, _, reference) = downsample_box(&reference.pixels, 256, 256, 4).unwrap();
    let d = cornell(64, 1, IntegratorKind::Sppm);
    let few = sppm(&d, 2, 2);
    let many = sppm(&d, 24, 2);
    let (rel_few, rms_few) = compare(&few, &reference, 64, 8);
    let (rel, rms) = compare(&many, &reference, 64, 8);
    eprintln!("SPPM vs reference: 2 iterations {rel_few:?} rms {rms_few:.4}; 24 iterations {rel:?} rms {rms:.4}");
    assert!(rms < rms_few, "the error did not fall: {rms_few} -> {rms}");
    assert!(rel.iter().all(|r| r.abs() < 0.02), "means differ: {rel:?}");
    assert!(rms < 0.04, "block means differ by {rms}");
}

#[test]
fn sppm_is_identical_with_one_and_two_threads() {
    let d = cornell(16, 1, IntegratorKind::Sppm);
    assert_eq!(sppm(&d, 3, 1), sppm(&d, 3, 2));
}
