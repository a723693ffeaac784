//! Bidirectional path tracing against closed forms, strategy by strategy.
//!
//! These tests drive [`BdptIntegrator::li`] directly: every camera sample's value is its
//! own radiance plus everything it splatted (the light-tracing strategies), whose average
//! over all samples is the image mean. The samples are independent, so their spread gives
//! the standard error of the mean without depending on how the film shows splats.

#![allow(clippy::needless_range_loop)]

mod common;

use common::direct_loops::bdpt_mean;
use common::*;
use mcrender_core::color::Rgb;
use mcrender_core::math::{Vec3, PI};
use mcrender_core::scene::{BdptDesc, Scene, SceneDescription};

fn power_mis() -> BdptDesc {
    BdptDesc::default()
}

fn closed_sphere(albedo: f32, le: f32) -> SceneDescription {
    emissive_sphere(2.0, Rgb::splat(albedo), Rgb::splat(le))
}

/// A sphere of albedo 1/2 lit by a point light of intensity pi at its centre: depth k
/// carries 2^-k, so up to depth D the radiance is 1 - 2^-D.
#[test]
fn sphere_lit_from_its_centre() {
    let mut d = point_lit_sphere(PI);
    let depth = 8;
    d.integrator.max_depth = depth;
    d.sampler.samples_per_pixel = 64;
    let expected = 1.0 - 0.5f32.powi(depth as i32);
    assert_close(
        "sphere lit from its centre",
        bdpt_mean(&d, power_mis()),
        Rgb::splat(expected),
    );
}

/// A closed sphere emitting Le with albedo a: depth k carries a^k Le, so up to depth D the
/// radiance is Le (1 - a^(D+1)) / (1 - a), Le / (1 - a) in the limit.
#[test]
fn closed_emissive_sphere() {
    let mut d = closed_sphere(0.5, 1.0);
    let depth = 10;
    d.integrator.max_depth = depth;
    d.sampler.samples_per_pixel = 32;
    let expected = (1.0 - 0.5f32.powi(depth as i32 + 1)) / (1.0 - 0.5);
    assert_close(
        "closed emissive sphere",
        bdpt_mean(&d, power_mis()),
        Rgb::splat(expected),
    );
}

#[test]
fn uniform_sky() {
    let (mut d, expected) = receiver_under_sky(1.5, 0.8);
    d.sampler.samples_per_pixel = 256;
    assert_close("uniform sky", bdpt_mean(&d, power_mis()), expected);
}

#[test]
fn sphere_and_square_lights() {
    let (mut d, expected) = receiver_under_sphere_light(0.5, 1.2, 2.0, 0.9);
    d.sampler.samples_per_pixel = 256;
    assert_close("sphere light", bdpt_mean(&d, power_mis()), expected);

    let (mut d, expected) = receiver_under_square_light(0.8, 1.0, 3.0, 0.7);
    d.sampler.samples_per_pixel = 256;
    assert_close("square light", bdpt_mean(&d, power_mis()), expected);
}

/// Each strategy alone, unweighted, estimates the light of its own path length: in the
/// closed emissive sphere, a^k Le for the paths with k = s + t - 2 bounces.
#[test]
fn each_strategy_alone_estimates_its_path_length() {
    let (a, le) = (0.5f32, 1.0f32);
    let mut d = closed_sphere(a, le);
    let depth = 3;
    d.integrator.max_depth = depth;
    d.sampler.samples_per_pixel = 16;
    for t in 1..=depth + 2 {
        for s in 0..=depth + 2 - t {
            if (s == 1 && t == 1) || s + t < 2 {
                continue;
            }
            let k = s + t - 2;
            let desc = BdptDesc {
                mis: false,
                strategy: Some((s, t)),
                ..BdptDesc::default()
            };
            assert_close(
                &format!("strategy s={s} t={t}"),
                bdpt_mean(&d, desc),
                Rgb::splat(le * a.powi(k as i32)),
            );
        }
    }
}

/// The same, off the symmetric sphere: a receiver under a square light, where each
/// strategy of one bounce (camera hits the light, light sample, light tracing) has its own
/// noise, and all three must find the closed-form direct light.
#[test]
fn each_direct_strategy_alone_finds_the_direct_light() {
    let (mut d, _) = receiver_under_square_light(0.8, 1.0, 3.0, 0.7);
    d.camera.fov_degrees = 20.0;
    d.film = mcrender_core::scene::FilmDesc { width: 8, height: 8 };
    d.sampler.samples_per_pixel = 512;
    // With a 20 degree view the receiver does not fill the image: compare the strategies
    // with each other and with the full estimate instead of with the closed form.
    let full = bdpt_mean(&d, power_mis());
    for (s, t) in [(0, 3), (1, 2), (2, 1)] {
        let alone = bdpt_mean(
            &d,
            BdptDesc {
                mis: false,
                strategy: Some((s, t)),
                ..BdptDesc::default()
            },
        );
        for c in 0..3 {
            let se = (alone.1[c].powi(2) + full.1[c].powi(2)).sqrt();
            eprintln!("s={s} t={t}: {:.5} vs full {:.5} (se {se:.2e})", alone.0[c], full.0[c]);
            assert!(
                (alone.0[c] - full.0[c]).abs() <= 4.0 * se,
                "strategy s={s} t={t}, channel {c}: {:.5} vs the full estimate {:.5}",
                alone.0[c],
                full.0[c]
            );
        }
    }
}

/// The MIS-weighted strategies add up to the full estimate, sample by sample (each
/// strategy's image uses the same random numbers as the full render).
#[test]
fn weighted_strategies_sum_to_the_full_image() {
    let (s, h, l, rho) = (0.8f32, 1.0f32, 3.0f32, 0.7f32);
    let mut d = empty_scene();
    add_receiver(&mut d, rho);
    add_square_light(&mut d, s, h, Rgb::splat(l));
    add_sphere_light(&mut d, 0.1, Vec3::new(0.3, 0.4, 0.2), Rgb::splat(2.0));
    aim_at_receiver(&mut d);
    d.camera.fov_degrees = 30.0;
    let depth = 3;
    d.integrator.max_depth = depth;
    d.sampler.samples_per_pixel = 64;
    let full = bdpt_mean(&d, power_mis());
    let mut sum = [0.0f64; 3];
    for t in 1..=depth + 2 {
        for s in 0..=depth + 2 - t {
            let desc = BdptDesc {
                strategy: Some((s, t)),
                ..BdptDesc::default()
            };
            let (m, _) = bdpt_mean(&d, desc);
            for c in 0..3 {
                sum[c] += m[c];
            }
        }
    }
    for c in 0..3 {
        eprintln!("channel {c}: sum of strategies {:.6}, full {:.6}", sum[c], full.0[c]);
        assert!(full.0[c] > 0.0);
        assert!(
            (sum[c] - full.0[c]).abs() <= 1e-4 * full.0[c],
            "channel {c}: strategies sum to {:.6}, the full image is {:.6}",
            sum[c],
            full.0[c]
        );
    }
}

/// The image, splats included, is the same bytes with 1 and 2 threads (splats are added in
/// a fixed order, not as threads finish).
#[test]
fn one_and_two_threads_give_identical_bytes() {
    use mcrender_core::render::{render, RenderOptions};
    use mcrender_core::scene::IntegratorKind;
    let (mut d, _) = receiver_under_square_light(0.8, 1.0, 3.0, 0.7);
    d.camera.fov_degrees = 30.0;
    d.film = mcrender_core::scene::FilmDesc { width: 24, height: 20 };
    d.integrator.kind = IntegratorKind::Bdpt;
    d.integrator.max_depth = 3;
    d.sampler.samples_per_pixel = 8;
    let scene = Scene::build(&d).unwrap();
    let image = |threads| {
        let opts = RenderOptions {
            threads: Some(threads),
            tile_size: 8,
        };
        render(&scene, &opts, &|_, _| {}).unwrap().film.mean_image()
    };
    let (a, b) = (image(1), image(2));
    assert!(a.iter().any(|p| !p.is_black()));
    let bits = |v: &[Rgb]| {
        v.iter()
            .flat_map(|p| p.to_array().map(f32::to_bits))
            .collect::<Vec<_>>()
    };
    assert_eq!(bits(&a), bits(&b));
}
