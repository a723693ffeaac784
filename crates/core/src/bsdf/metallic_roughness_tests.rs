//! The metallic-roughness BRDF through the suite's checks (chi-square of sampling against
//! the pdf, sampled values against `f` and `pdf`, reciprocity, albedo by two estimators),
//! plus white furnaces.

use super::*;
use crate::bsdf::tests::{
    check_consistency_and_energy_with, check_sampling_matches_pdf, check_sampling_matches_pdf_for, check_specular,
    test_directions, SpecularExpectation,
};
use crate::bsdf::Bxdf;
use crate::sampling::chi2::suite_seed;
use crate::sampling::{sample_uniform_sphere, uniform_sphere_pdf, Pcg32};

fn lobe(c: Rgb, metallic: f32, roughness: f32) -> Bxdf {
    Bxdf::MetallicRoughness(MetallicRoughnessBxdf::new(c, metallic, roughness))
}

const ORANGE: Rgb = Rgb::new(0.9, 0.5, 0.1);

#[test]
fn sampling_matches_the_mixture_pdf() {
    for (metallic, roughness) in [(0.0, 0.5), (0.5, 0.8), (1.0, 0.4)] {
        let b = lobe(ORANGE, metallic, roughness);
        check_sampling_matches_pdf(&b, &format!("metallic {metallic}, roughness {roughness}"));
    }
    // A sharp lobe (alpha 0.04), at oblique directions only (the cells are slow to integrate).
    let b = lobe(ORANGE, 0.3, 0.2);
    check_sampling_matches_pdf_for(&b, "metallic 0.3, roughness 0.2", &test_directions()[1..=3]);
}

#[test]
fn coloured_lobes_are_consistent_reciprocal_and_below_one() {
    for (metallic, roughness) in [(0.0, 0.3), (0.0, 1.0), (0.5, 0.6), (1.0, 0.2), (1.0, 1.0)] {
        let b = lobe(ORANGE, metallic, roughness);
        check_consistency_and_energy_with(&b, &format!("orange m {metallic} r {roughness}"), 50_000, |_, _| 1.0);
    }
}

/// Directional albedo of `b` for `wo` by sampling, with its standard error.
fn albedo(b: &Bxdf, wo: Vec3, n: u32, rng: &mut Pcg32) -> (f64, f64) {
    let (mut sum, mut sq) = (0.0f64, 0.0f64);
    for _ in 0..n {
        let u = Vec2::new(rng.next_f32(), rng.next_f32());
        if let Some(s) = b.sample_f(wo, rng.next_f32(), u) {
            let v = f64::from((s.f * (s.wi.z.abs() / s.pdf)).average());
            sum += v;
            sq += v * v;
        }
    }
    let mean = sum / f64::from(n);
    (mean, ((sq / f64::from(n) - mean * mean).max(0.0) / f64::from(n)).sqrt())
}

#[test]
fn white_metal_furnace_is_below_one_and_one_when_smooth() {
    let mut rng = Pcg32::new(3, suite_seed());
    // A smooth white metal: F_m = 1 at every angle, a perfect mirror.
    let b = lobe(Rgb::WHITE, 1.0, 0.0);
    let albedos = check_specular(&b, "smooth white metal", |_| SpecularExpectation {
        reflect: Rgb::WHITE,
        transmit: Rgb::BLACK,
        transmit_dir: None,
    });
    assert!(albedos.iter().all(|a| (a - 1.0).abs() < 2e-3), "{albedos:?}");
    // Rough white metals lose only what single-scattering GGX loses: near 1 when
    // nearly smooth, falling with roughness, never above 1.
    let mut last = 1.0 + 1e-9;
    for roughness in [0.1f32, 0.4, 0.7, 1.0] {
        let b = lobe(Rgb::WHITE, 1.0, roughness);
        let (a, se) = albedo(&b, Vec3::Z, 100_000, &mut rng);
        assert!(a <= 1.0 + 4.0 * se, "roughness {roughness}: albedo {a} +- {se}");
        assert!(a < last + 4.0 * se, "roughness {roughness}: albedo {a} after {last}");
        if roughness <= 0.1 {
            assert!(a > 0.99, "roughness {roughness}: albedo {a}");
        }
        last = a;
    }
}

#[test]
fn white_furnace_at_normal_incidence_for_all_metallic_and_roughness() {
    // The spec's model exceeds 1 for a white dielectric at oblique incidence (see the
    // module docs and the next test); at normal incidence every mix reflects at most what
    // it receives, and a white metal nowhere more.
    let mut rng = Pcg32::new(5, suite_seed());
    for metallic in [0.0f32, 0.25, 0.5, 0.75, 1.0] {
        for roughness in [0.05f32, 0.3, 0.6, 1.0] {
            let b = lobe(Rgb::WHITE, metallic, roughness);
            let dirs = if metallic == 1.0 {
                test_directions()
            } else {
                vec![Vec3::Z]
            };
            for wo in dirs {
                let (a, se) = albedo(&b, wo, 40_000, &mut rng);
                assert!(
                    a <= 1.0 + 4.0 * se + 1e-3,
                    "metallic {metallic}, roughness {roughness}, wo {wo}: albedo {a} +- {se}"
                );
            }
        }
    }
}

#[test]
fn white_dielectric_exceeds_one_at_oblique_incidence() {
    // Documents the spec model's known excess (measured, so that a change shows): the
    // diffuse weight 1 - F(wo.h) ignores what the specular lobe took.
    let mut rng = Pcg32::new(9, suite_seed());
    let b = lobe(Rgb::WHITE, 0.0, 0.3);
    let grazing = Vec3::new(0.999, 0.0, 0.04).normalize();
    let (a, se) = albedo(&b, grazing, 100_000, &mut rng);
    assert!(a > 1.0 + 4.0 * se, "albedo {a} +- {se}");
    // At normal incidence the albedo is just below 1 (about 0.9996, within the noise of
    // 100,000 samples): the excess is an oblique-incidence effect.
    let (a, se) = albedo(&b, Vec3::Z, 100_000, &mut rng);
    assert!(a <= 1.0 + 4.0 * se, "albedo {a} +- {se}");
    // The albedo by uniform directions agrees (f and pdf consistent) at grazing too.
    let (mut sum, n) = (0.0f64, 400_000);
    for _ in 0..n {
        let wi = sample_uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()));
        sum += f64::from((b.f(grazing, wi) * (wi.z.abs() / uniform_sphere_pdf())).average());
    }
    let (by_sampling, _) = albedo(&b, grazing, 100_000, &mut rng);
    assert!(
        (sum / f64::from(n) - by_sampling).abs() < 0.02,
        "{} vs {by_sampling}",
        sum / f64::from(n)
    );
}

#[test]
fn smooth_dielectric_mirror_carries_the_schlick_fresnel() {
    // Smooth, metallic 0: the mirror direction carries F_d(cos theta_o) and the diffuse
    // part is a separate, non-delta lobe (so the flags are mixed).
    let b = lobe(Rgb::splat(0.5), 0.0, 0.0);
    assert!(b.flags().is_specular() && b.flags().is_non_specular());
    let mut rng = Pcg32::new(13, suite_seed());
    for wo in test_directions() {
        let (mut mirror, n) = (0.0f64, 20_000);
        for i in 0..n {
            let uc = (i as f32 + 0.5) / n as f32;
            let u = Vec2::new(rng.next_f32(), rng.next_f32());
            if let Some(s) = b.sample_f(wo, uc, u) {
                if s.flags.is_specular() {
                    mirror += f64::from((s.f * (s.wi.z.abs() / s.pdf)).average()) / f64::from(n);
                }
            }
        }
        let expected = 0.04 + 0.96 * (1.0 - wo.z.abs()).powi(5);
        assert!(
            (mirror as f32 - expected).abs() < 2e-3,
            "wo {wo}: {mirror} vs {expected}"
        );
    }
}
