//! The estimator lab's guarantees: every direct-lighting technique, with any number of
//! light samples and any Russian roulette setting, is unbiased (agrees with closed forms
//! within 4 standard errors of its own samples), and their variances are ordered where
//! theory fixes the order.

mod common;

use common::*;
use mcrender_core::color::Rgb;
use mcrender_core::math::PI;
use mcrender_core::render::{render, RenderError, RenderOptions};
use mcrender_core::scene::{DirectStrategy, RussianRoulette, Scene, SceneDescription};

fn with(d: &SceneDescription, strategy: DirectStrategy, light_samples: u32) -> SceneDescription {
    let mut d = d.clone();
    d.integrator.direct = strategy;
    d.integrator.light_samples = light_samples;
    d
}

fn check_all_strategies(d: &SceneDescription, expected: Rgb, label: &str) {
    for strategy in DirectStrategy::ALL {
        for n in [1, 3] {
            let out = render_desc(&with(d, strategy, n));
            let (mean, se) = mean_and_standard_error(&out);
            for c in 0..3 {
                let e = f64::from(expected[c]);
                assert!(
                    (mean[c] - e).abs() <= 4.0 * se[c] + 1e-6 * e,
                    "{label}, {} x{n}, channel {c}: {:.5} vs closed form {e:.5} (standard error {:.2e})",
                    strategy.name(),
                    mean[c],
                    se[c]
                );
            }
        }
    }
}

/// The receiver under a uniform sky at 1024 samples per pixel, and its radiance.
fn uniform_sky() -> (SceneDescription, Rgb) {
    let (mut d, expected) = receiver_under_sky(1.5, 0.8);
    d.sampler.samples_per_pixel = 1024;
    (d, expected)
}

#[test]
fn every_technique_is_unbiased_under_a_uniform_sky() {
    let (d, expected) = uniform_sky();
    check_all_strategies(&d, expected, "uniform sky");
}

#[test]
fn every_technique_is_unbiased_under_a_sphere_light() {
    let (mut d, expected) = receiver_under_sphere_light(0.5, 1.2, 2.0, 0.9);
    d.sampler.samples_per_pixel = 2048;
    check_all_strategies(&d, expected, "sphere light");
}

#[test]
fn every_technique_is_unbiased_under_a_square_light() {
    let (mut d, expected) = receiver_under_square_light(0.8, 1.0, 3.0, 0.7);
    d.sampler.samples_per_pixel = 2048;
    check_all_strategies(&d, expected, "square light");
}

/// With interreflection (all bounces) every technique still converges to L_e / (1 - a).
#[test]
fn every_technique_is_unbiased_with_all_bounces() {
    let mut d = emissive_sphere(2.0, Rgb::splat(0.5), Rgb::splat(1.0));
    d.integrator.max_depth = u32::MAX;
    d.sampler.samples_per_pixel = 512;
    check_all_strategies(&d, Rgb::splat(2.0), "closed emissive sphere");
}

#[test]
fn cosine_sampling_beats_uniform_under_a_uniform_sky() {
    let (d, _) = uniform_sky();
    let uniform = mean_pixel_variance(&render_desc(&with(&d, DirectStrategy::UniformHemisphere, 1)));
    let cosine = mean_pixel_variance(&render_desc(&with(&d, DirectStrategy::CosineHemisphere, 1)));
    eprintln!("variance: uniform {uniform:.3e}, cosine {cosine:.3e}");
    assert!(cosine < 0.5 * uniform, "cosine {cosine:.3e} vs uniform {uniform:.3e}");
}

#[test]
fn more_light_samples_lower_the_variance() {
    let (d, _) = uniform_sky();
    let one = mean_pixel_variance(&render_desc(&with(&d, DirectStrategy::LightArea, 1)));
    let four = mean_pixel_variance(&render_desc(&with(&d, DirectStrategy::LightArea, 4)));
    eprintln!("variance: 1 light sample {one:.3e}, 4 light samples {four:.3e}");
    // Direct lighting only: four samples per pixel sample quarter the variance.
    assert!(
        four < 0.3 * one && four > 0.2 * one,
        "1 sample {one:.3e}, 4 samples {four:.3e}"
    );
}

#[test]
fn hemisphere_and_bsdf_sampling_refuse_point_lights() {
    let d = point_lit_sphere(PI);
    for strategy in [
        DirectStrategy::UniformHemisphere,
        DirectStrategy::CosineHemisphere,
        DirectStrategy::Bsdf,
    ] {
        let scene = Scene::build(&with(&d, strategy, 1)).unwrap();
        match render(&scene, &RenderOptions::default(), &|_, _| {}) {
            Err(RenderError::Integrator(e)) => assert!(e.to_string().contains("point"), "{e}"),
            other => panic!(
                "{}: expected a refusal, got {:?}",
                strategy.name(),
                other.map(|o| o.stats)
            ),
        }
    }
    for strategy in [DirectStrategy::LightArea, DirectStrategy::Mis] {
        let mut d = with(&d, strategy, 2);
        d.integrator.max_depth = u32::MAX;
        d.sampler.samples_per_pixel = 1024;
        let (mean, se) = mean_and_standard_error(&render_desc(&d));
        assert!(
            (mean[0] - 1.0).abs() < 4.0 * se[0],
            "{}: {} +- {}",
            strategy.name(),
            mean[0],
            se[0]
        );
    }
}

/// The lecture's Russian roulette settings leave the mean where it was (within noise) and
/// cost fewer rays the more they terminate. Cost is counted in rays, not seconds, so the test
/// does not depend on the machine.
#[test]
fn russian_roulette_is_unbiased_and_saves_work() {
    let mut d = emissive_sphere(2.0, Rgb::splat(0.7), Rgb::splat(1.0));
    d.integrator.max_depth = 64;
    d.sampler.samples_per_pixel = 1024;
    // Without roulette the truncated geometric series: sum_{k=0}^{64} 0.7^k.
    let expected = (1.0 - 0.7f64.powi(65)) / (1.0 - 0.7);
    let settings = [
        RussianRoulette::Off,
        RussianRoulette::Threshold {
            threshold: 0.25,
            probability: 0.5,
        },
        RussianRoulette::Threshold {
            threshold: 0.5,
            probability: 0.5,
        },
        RussianRoulette::Threshold {
            threshold: 0.125,
            probability: 0.9,
        },
        RussianRoulette::Threshold {
            threshold: 1.0,
            probability: 0.9,
        },
        RussianRoulette::Throughput,
        RussianRoulette::Delayed { start_depth: 5 },
        RussianRoulette::Delayed { start_depth: 0 },
    ];
    let mut rays = Vec::new();
    for rr in settings {
        let mut d = d.clone();
        d.integrator.russian_roulette = rr;
        let out = render_desc(&d);
        let (mean, se) = mean_and_standard_error(&out);
        eprintln!(
            "{rr:?}: mean {:.5} +- {:.5}, rays {}",
            mean[0], se[0], out.stats.trace.rays
        );
        assert!(
            (mean[0] - expected).abs() <= 4.0 * se[0] + 1e-5 * expected,
            "{rr:?}: mean {} vs {expected}",
            mean[0]
        );
        rays.push(out.stats.trace.rays);
    }
    // Off traces every path to the limit; more termination, fewer rays.
    assert!(
        rays[1] < rays[0] && rays[2] < rays[1] && rays[4] < rays[3] && rays[3] < rays[0],
        "{rays:?}"
    );
    // Mitsuba's rule cuts later than pbrt's, and earlier when started earlier.
    assert!(rays[5] < rays[6] && rays[6] < rays[0] && rays[7] < rays[6], "{rays:?}");
}

/// Rendering samples [0, 3) and [3, 8) and merging gives the same estimate as rendering
/// [0, 8) at once (up to the order of floating-point additions).
#[test]
fn sample_waves_merge_into_the_whole_render() {
    use mcrender_core::render::render_samples;
    let (mut d, _) = uniform_sky();
    d.sampler.samples_per_pixel = 8;
    let scene = Scene::build(&d).unwrap();
    let opts = RenderOptions::default();
    let whole = render_samples(&scene, &opts, 0..8, &|_, _| {}).unwrap();
    let mut parts = render_samples(&scene, &opts, 0..3, &|_, _| {}).unwrap();
    parts
        .film
        .merge(&render_samples(&scene, &opts, 3..8, &|_, _| {}).unwrap().film);
    for (a, b) in whole.film.pixels().iter().zip(parts.film.pixels()) {
        assert_eq!(a.count, b.count);
        assert!((a.mean() - b.mean()).max_component().abs() < 1e-5);
    }
}
