//! Tests of the harness itself: it accepts correct pdfs and rejects wrong ones.

use super::*;
use crate::math::INV_PI;
use crate::sampling::{
    cosine_hemisphere_pdf, sample_cosine_hemisphere, sample_uniform_hemisphere, sample_uniform_sphere,
    uniform_hemisphere_pdf, uniform_sphere_pdf,
};

const N: u32 = 1_000_000;

fn cosine_pdf(w: Vec3) -> f32 {
    cosine_hemisphere_pdf(w.z)
}

#[test]
fn accepts_cosine_samples_against_the_cosine_pdf() {
    let report = Chi2Test::new(N, 3).sphere(
        SphereGrid::default(),
        |u, _| Some(sample_cosine_hemisphere(u)),
        cosine_pdf,
    );
    report.assert_passes(SIGNIFICANCE);
    assert_eq!(report.dof, 100 - 1, "100 cells on the upper hemisphere");
    assert!((report.pdf_integral - 1.0).abs() < 1e-6, "{}", report.pdf_integral);
}

#[test]
fn rejects_uniform_samples_against_the_cosine_pdf() {
    let report = Chi2Test::new(N, 3).sphere(
        SphereGrid::default(),
        |u, _| Some(sample_uniform_hemisphere(u)),
        cosine_pdf,
    );
    report.assert_rejects(SIGNIFICANCE);
    assert!(report.error.is_none());
    // The failure message shows where the samples went.
    let text = report.to_string();
    assert!(
        text.contains("observed") && text.contains("expected") && text.contains("residual"),
        "{text}"
    );
}

#[test]
fn rejects_a_slightly_biased_warp() {
    // z = 1 - 2 u^1.05 instead of 1 - 2 u: a 5 % distortion of the sphere's latitudes.
    let biased = |u: Vec2, _: &mut Pcg32| {
        let w = sample_uniform_sphere(Vec2::new(u.x.powf(1.05), u.y));
        Some(w)
    };
    let report = Chi2Test::new(N, 3).sphere(SphereGrid::default(), biased, |_| uniform_sphere_pdf());
    report.assert_rejects(SIGNIFICANCE);
}

#[test]
fn rejects_samples_where_the_pdf_is_zero() {
    let hemisphere = |w: Vec3| {
        if w.z >= 0.0 {
            uniform_hemisphere_pdf()
        } else {
            0.0
        }
    };
    let report =
        Chi2Test::new(10_000, 3).sphere(SphereGrid::default(), |u, _| Some(sample_uniform_sphere(u)), hemisphere);
    report.assert_rejects(SIGNIFICANCE);
    assert!(
        report.error.as_deref().unwrap_or("").contains("pdf is zero"),
        "{report}"
    );
}

#[test]
fn rejects_invalid_samples() {
    let report = Chi2Test::new(1000, 3).sphere(SphereGrid::default(), |_, _| Some(Vec3::new(0.0, 0.0, 2.0)), |_| 1.0);
    assert!(
        report.error.as_deref().unwrap_or("").contains("not a unit vector"),
        "{report}"
    );
    let grid = RectGrid {
        min: Vec2::ZERO,
        max: Vec2::ONE,
        bins: UVec2::splat(4),
    };
    let report = Chi2Test::new(1000, 3).rect(grid, |u, _| Some(u * 1.5), |_| 1.0);
    assert!(report.error.as_deref().unwrap_or("").contains("outside"), "{report}");
    let grid = IntervalGrid {
        min: 0.0,
        max: 1.0,
        bins: 4,
    };
    let report = Chi2Test::new(1000, 3).interval(grid, |_, _| Some(f32::NAN), |_| 1.0);
    assert!(!report.passes(SIGNIFICANCE));
}

#[test]
fn failed_samples_must_match_the_missing_pdf_mass() {
    // A sampler that fails 10 % of the time, drawing the decision from the harness's rng.
    let sometimes = |u: Vec2, rng: &mut Pcg32| (rng.next_f32() >= 0.1).then(|| sample_cosine_hemisphere(u));
    let report = Chi2Test::new(N, 3).sphere(SphereGrid::default(), sometimes, |w| 0.9 * cosine_pdf(w));
    report.assert_passes(SIGNIFICANCE);
    assert!((f64::from(report.failed_samples) / f64::from(N) - 0.1).abs() < 0.002);
    // The same samples against a pdf integrating to 0.95: rejected.
    let report = Chi2Test::new(N, 3).sphere(SphereGrid::default(), sometimes, |w| 0.95 * cosine_pdf(w));
    report.assert_rejects(SIGNIFICANCE);
    // Against a pdf integrating to 1: failures are impossible.
    let report = Chi2Test::new(N, 3).sphere(SphereGrid::default(), sometimes, cosine_pdf);
    assert!(
        report.error.as_deref().unwrap_or("").contains("failed samples"),
        "{report}"
    );
    // One failure in N, as rounding on the domain's edge gives: accepted.
    let mut draws = 0;
    let once = |u: Vec2, _: &mut Pcg32| {
        draws += 1;
        (draws != N / 2).then(|| sample_cosine_hemisphere(u))
    };
    let report = Chi2Test::new(N, 3).sphere(SphereGrid::default(), once, cosine_pdf);
    assert_eq!(report.failed_samples, 1);
    report.assert_passes(SIGNIFICANCE);
}

#[test]
fn rect_and_interval_domains_accept_and_reject() {
    let grid = RectGrid {
        min: Vec2::new(-1.0, 2.0),
        max: Vec2::new(3.0, 4.0),
        bins: UVec2::new(8, 5),
    };
    let uniform = |u: Vec2, _: &mut Pcg32| Some(Vec2::new(-1.0 + 4.0 * u.x, 2.0 + 2.0 * u.y));
    Chi2Test::new(N, 3)
        .rect(grid, uniform, |_| 0.125)
        .assert_passes(SIGNIFICANCE);
    // Density 2 (y - 2) / 4 along y, sampled as if uniform.
    Chi2Test::new(N, 3)
        .rect(grid, uniform, |p| (p.y - 2.0) / 8.0)
        .assert_rejects(SIGNIFICANCE);

    let grid = IntervalGrid {
        min: 0.0,
        max: 1.0,
        bins: 32,
    };
    let linear = |u: f32, _: &mut Pcg32| Some(u.sqrt());
    Chi2Test::new(N, 3)
        .interval(grid, linear, |x| 2.0 * x)
        .assert_passes(SIGNIFICANCE);
    Chi2Test::new(N, 3)
        .interval(grid, linear, |x| 3.0 * x * x)
        .assert_rejects(SIGNIFICANCE);
}

#[test]
fn pcg32_floats_are_uniform() {
    let grid = IntervalGrid {
        min: 0.0,
        max: 1.0,
        bins: 100,
    };
    let report = Chi2Test::new(N, 3).interval(grid, |u, _| Some(u), |_| 1.0);
    report.assert_passes(SIGNIFICANCE);
}

#[test]
fn the_statistic_follows_the_chi_square_distribution() {
    // Under the null hypothesis p-values are uniform: over 40 seeds of a small correct test,
    // few are below 0.05 and their mean is near 1/2 (sd of the mean 0.046).
    let p: Vec<f64> = (0..40)
        .map(|seed| {
            let grid = IntervalGrid {
                min: 0.0,
                max: 1.0,
                bins: 20,
            };
            Chi2Test::new(20_000, seed)
                .interval(grid, |u, _| Some(u.sqrt()), |x| 2.0 * x)
                .p_value
        })
        .collect();
    let mean = p.iter().sum::<f64>() / p.len() as f64;
    assert!((mean - 0.5).abs() < 0.2, "{p:?}");
    assert!(p.iter().filter(|&&v| v < 0.05).count() <= 6, "{p:?}");
}

#[test]
fn pdf_integrals_are_accurate_across_discontinuities() {
    // The uniform disk inside a grid whose cells the rim cuts: the integrals must sum to 1.
    let grid = RectGrid {
        min: Vec2::splat(-1.0),
        max: Vec2::splat(1.0),
        bins: UVec2::splat(7),
    };
    let disk = |p: Vec2| {
        if p.length_squared() <= 1.0 {
            INV_PI
        } else {
            0.0
        }
    };
    let report = Chi2Test::new(1000, 0).rect(grid, |_, _| Some(Vec2::ZERO), disk);
    assert!((report.pdf_integral - 1.0).abs() < 1e-5, "{}", report.pdf_integral);
}
