//! Checks every lobe must pass: chi-square of `sample_f` against `pdf`, sampled values
//! consistent with `f` and `pdf`, energy conservation (white furnace), reciprocity.

use super::*;
use crate::math::Vec3;
use crate::sampling::chi2::{suite_seed, Chi2Test, SphereGrid, SIGNIFICANCE};
use crate::sampling::{sample_uniform_sphere, uniform_sphere_pdf, Pcg32};

/// Outgoing directions to test, on both sides and at grazing angles.
pub(crate) fn test_directions() -> Vec<Vec3> {
    vec![
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::new(0.3, -0.4, 0.8).normalize(),
        Vec3::new(0.9, 0.1, 0.2).normalize(),
        Vec3::new(-0.7, 0.5, -0.3).normalize(),
        Vec3::new(0.999, 0.0, 0.04).normalize(),
    ]
}

/// Chi-square test of the lobe's sampling against its pdf, for each test direction.
pub(crate) fn check_sampling_matches_pdf(bxdf: &Bxdf, label: &str) {
    let dirs = test_directions();
    for (i, &wo) in dirs.iter().enumerate() {
        let test = Chi2Test::new(200_000, suite_seed() + i as u64).with_test_count(dirs.len() as u32);
        let report = test.sphere(
            SphereGrid::default(),
            |u, rng: &mut Pcg32| {
                bxdf.sample_f(wo, rng.next_f32(), u)
                    .filter(|s| s.pdf > 0.0)
                    .map(|s| s.wi)
            },
            |wi| bxdf.pdf(wo, wi),
        );
        assert!(report.passes(SIGNIFICANCE), "{label}, wo = {wo}: {report}");
    }
}

/// Sampled `f` and `pdf` equal the evaluated ones; reciprocity; the directional albedo
/// estimated by importance sampling equals the one estimated by uniform sphere sampling
/// (so `f` and `pdf` agree) and does not exceed one.
pub(crate) fn check_consistency_and_energy(bxdf: &Bxdf, label: &str) -> Vec<f32> {
    let mut rng = Pcg32::new(7, suite_seed());
    let mut albedos = Vec::new();
    for wo in test_directions() {
        let n = 200_000;
        let (mut by_sampling, mut by_uniform) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let u = Vec2::new(rng.next_f32(), rng.next_f32());
            if let Some(s) = bxdf.sample_f(wo, rng.next_f32(), u) {
                let f = bxdf.f(wo, s.wi);
                let pdf = bxdf.pdf(wo, s.wi);
                assert!(
                    (f - s.f).max_component().abs() <= 1e-4 * (1.0 + f.max_component()),
                    "{label}: sampled f {:?} != f {f:?}",
                    s.f
                );
                assert!(
                    (pdf - s.pdf).abs() <= 1e-3 * (1.0 + pdf),
                    "{label}: sampled pdf {} != pdf {pdf}",
                    s.pdf
                );
                let r = bxdf.f(s.wi, wo);
                assert!(
                    (r - f).max_component().abs() <= 1e-4 * (1.0 + f.max_component()),
                    "{label}: f not reciprocal"
                );
                by_sampling += f64::from((s.f * (s.wi.z.abs() / s.pdf)).average());
            }
            let wi = sample_uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()));
            by_uniform += f64::from((bxdf.f(wo, wi) * (wi.z.abs() / uniform_sphere_pdf())).average());
        }
        let (a, b) = (by_sampling / f64::from(n), by_uniform / f64::from(n));
        assert!(a <= 1.0 + 1e-3, "{label}, wo = {wo}: albedo {a} > 1");
        assert!(
            (a - b).abs() < 0.01,
            "{label}, wo = {wo}: albedo by sampling {a} vs by uniform directions {b}"
        );
        albedos.push(a as f32);
    }
    albedos
}

#[test]
fn diffuse_sampling_matches_its_pdf() {
    check_sampling_matches_pdf(
        &Bxdf::Diffuse(DiffuseBxdf {
            r: Rgb::new(0.5, 0.8, 0.2),
        }),
        "diffuse",
    );
}

#[test]
fn diffuse_white_furnace_reflects_everything() {
    let albedos = check_consistency_and_energy(&Bxdf::Diffuse(DiffuseBxdf { r: Rgb::WHITE }), "diffuse");
    for a in albedos {
        assert!((a - 1.0).abs() < 1e-4, "white diffuse albedo {a}");
    }
}

#[test]
fn black_diffuse_has_no_lobe() {
    let b = Bsdf::new(Vec3::Z, Vec3::X, Bxdf::Diffuse(DiffuseBxdf { r: Rgb::BLACK }));
    assert!(b.flags().is_empty());
    assert!(b.sample_f(Vec3::Z, 0.5, Vec2::splat(0.5)).is_none());
}

#[test]
fn bsdf_frame_round_trips_world_directions() {
    let ns = Vec3::new(0.2, 0.9, -0.1).normalize();
    let b = Bsdf::new(ns, Vec3::X, Bxdf::Diffuse(DiffuseBxdf { r: Rgb::WHITE }));
    let wo = Vec3::new(0.1, 0.5, 0.3).normalize();
    let s = b.sample_f(wo, 0.3, Vec2::new(0.2, 0.7)).unwrap();
    assert!(s.wi.dot(ns) > 0.0, "reflection stays on the side of wo");
    assert!((b.pdf(wo, s.wi) - s.pdf).abs() < 1e-4);
}
