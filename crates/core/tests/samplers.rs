//! Render-level checks of the stratified and Owen-scrambled Sobol' samplers: images made
//! with them converge to the same closed forms as with the independent sampler (no bias
//! from correlated dimensions, also past the Sobol' table on long paths), and on a smooth
//! direct-lighting integral their pixel estimates scatter less.

mod common;

use common::*;
use mcrender_core::color::Rgb;
use mcrender_core::scene::{SamplerKind, SceneDescription};

const KINDS: [SamplerKind; 3] = [
    SamplerKind::Independent,
    SamplerKind::Stratified {
        x_samples: 32,
        y_samples: 32,
        jitter: true,
    },
    SamplerKind::OwenSobol,
];

fn with_sampler(d: &SceneDescription, kind: SamplerKind) -> SceneDescription {
    let mut d = d.clone();
    d.sampler.kind = kind;
    d.sampler.samples_per_pixel = 1024;
    d
}

/// A diffuse receiver under a square light; the radiance at its centre in closed form.
fn square_light() -> (SceneDescription, f64) {
    let (d, expected) = receiver_under_square_light(0.8, 1.0, 3.0, 0.7);
    (d, f64::from(expected.g))
}

#[test]
fn every_sampler_is_unbiased_under_a_square_light() {
    let (d, expected) = square_light();
    for kind in KINDS {
        eprintln!("{kind:?}");
        assert_mean_radiance(&with_sampler(&d, kind), Rgb::splat(expected as f32));
    }
}

#[test]
fn every_sampler_is_unbiased_with_all_bounces() {
    // A closed emissive sphere of albedo 1/2: L = L_e / (1 - a) = 2. Paths run far past the
    // 64 Sobol' dimensions into the padded ones.
    let mut d = emissive_sphere(2.0, Rgb::splat(0.5), Rgb::splat(1.0));
    d.integrator.max_depth = u32::MAX;
    for kind in KINDS {
        eprintln!("{kind:?}");
        let mut d = with_sampler(&d, kind);
        d.sampler.samples_per_pixel = 256;
        if let SamplerKind::Stratified { .. } = kind {
            d.sampler.kind = SamplerKind::Stratified {
                x_samples: 16,
                y_samples: 16,
                jitter: true,
            };
        }
        assert_mean_radiance(&d, Rgb::splat(2.0));
    }
}

#[test]
fn sobol_and_stratified_pixels_scatter_less_under_a_square_light() {
    // Every pixel sees the receiver's centre, so the spread of the pixel values about the
    // closed form is the error of one pixel estimate.
    let (d, expected) = square_light();
    let rms = KINDS.map(|kind| {
        let out = render_desc(&with_sampler(&d, kind));
        let pixels = out.film.pixels();
        let sum_sq: f64 = pixels.iter().map(|p| (f64::from(p.mean()[1]) - expected).powi(2)).sum();
        (sum_sq / pixels.len() as f64).sqrt()
    });
    eprintln!(
        "pixel RMS error: independent {:.2e}, stratified {:.2e}, sobol {:.2e}",
        rms[0], rms[1], rms[2]
    );
    assert!(rms[1] < 0.7 * rms[0] && rms[2] < 0.7 * rms[0], "{rms:?}");
}
