//! Checks every lobe must pass: chi-square of `sample_f` against `pdf`, sampled values
//! consistent with `f` and `pdf`, energy conservation (white furnace), reciprocity.

use super::*;
use crate::math::{sqr, Vec3};
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
    check_sampling_matches_pdf_for(bxdf, label, &test_directions());
}

/// [`check_sampling_matches_pdf`] for the outgoing directions `dirs`. (Very sharp lobes
/// make integrating the pdf over the cells slow; test those at fewer directions.)
pub(crate) fn check_sampling_matches_pdf_for(bxdf: &Bxdf, label: &str, dirs: &[Vec3]) {
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
    check_consistency_and_energy_with(bxdf, label, 200_000, |_, _| 1.0)
}

/// [`check_consistency_and_energy`] with `samples` per direction, for lobes that transmit with the radiance scaling
/// `1 / eta'^2`: `eta_of(wo, wi)` is the relative index `eta'` the pair crosses (1 for
/// reflection). The albedo is measured with the scaling undone (times `eta'^2`), which
/// conserves energy; reciprocity is checked in its generalised form
/// `f(wi, wo) = f(wo, wi) eta'^2`.
pub(crate) fn check_consistency_and_energy_with(
    bxdf: &Bxdf,
    label: &str,
    samples: u32,
    eta_of: impl Fn(Vec3, Vec3) -> f32,
) -> Vec<f32> {
    let mut rng = Pcg32::new(7, suite_seed());
    let mut albedos = Vec::new();
    for wo in test_directions() {
        let n = samples;
        let (mut by_sampling, mut by_uniform) = (0.0f64, 0.0f64);
        let (mut sq_sampling, mut sq_uniform) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let u = Vec2::new(rng.next_f32(), rng.next_f32());
            if let Some(s) = bxdf.sample_f(wo, rng.next_f32(), u) {
                let f = bxdf.f(wo, s.wi);
                let pdf = bxdf.pdf(wo, s.wi);
                let eta2 = sqr(eta_of(wo, s.wi));
                assert!(
                    (sqr(s.eta) - eta2).abs() <= 1e-4 * eta2,
                    "{label}: sampled eta {} != {}",
                    s.eta,
                    eta2.sqrt()
                );
                // Relative 1e-3: evaluating recomputes the half vector from wo and wi.
                assert!(
                    (f - s.f).max_component().abs() <= 1e-3 * (1.0 + f.max_component()),
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
                    (r - f * eta2).max_component().abs() <= 3e-3 * (1.0 + r.max_component()),
                    "{label}: f not reciprocal: f(wo, wi) = {f:?}, f(wi, wo) = {r:?}, eta'^2 = {eta2}"
                );
                let v = f64::from((s.f * (s.wi.z.abs() * eta2 / s.pdf)).average());
                assert!(v.is_finite(), "{label}, wo = {wo}: sample {s:?} has weight {v}");
                by_sampling += v;
                sq_sampling += v * v;
            }
            let wi = sample_uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()));
            let eta2 = sqr(eta_of(wo, wi));
            let v = f64::from((bxdf.f(wo, wi) * (wi.z.abs() * eta2 / uniform_sphere_pdf())).average());
            assert!(v.is_finite(), "{label}, wo = {wo}: f({wi}) = {v}");
            by_uniform += v;
            sq_uniform += v * v;
        }
        let n = f64::from(n);
        let (a, b) = (by_sampling / n, by_uniform / n);
        // Standard error of the difference: uniform sampling of a sharp lobe is noisy.
        let var = (sq_sampling / n - a * a + sq_uniform / n - b * b) / n;
        assert!(a <= 1.0 + 1e-3, "{label}, wo = {wo}: albedo {a} > 1");
        assert!(
            (a - b).abs() < 5.0 * var.sqrt() + 2e-3,
            "{label}, wo = {wo}: albedo by sampling {a} vs by uniform directions {b} (standard error {})",
            var.sqrt()
        );
        albedos.push(a as f32);
    }
    albedos
}

/// What a specular lobe must do for one outgoing direction: the mirror direction carries
/// `reflect` of the albedo (`f cos / pdf` times the probability of choosing it), the
/// transmitted direction `transmit_dir` carries `transmit`.
pub(crate) struct SpecularExpectation {
    pub reflect: Rgb,
    pub transmit: Rgb,
    pub transmit_dir: Option<Vec3>,
}

/// Specular lobes cannot be chi-square tested against a pdf (their pdf is a Dirac delta):
/// check that `f` and `pdf` are zero for every pair of directions, that every sample goes
/// exactly to the mirror or the expected transmitted direction, and that the weights,
/// averaged over stratified lobe choices `uc`, equal the expected ones. Returns the albedos
/// (`reflect + transmit`) measured.
pub(crate) fn check_specular(bxdf: &Bxdf, label: &str, expect: impl Fn(Vec3) -> SpecularExpectation) -> Vec<f32> {
    assert!(bxdf.flags().is_specular() && !bxdf.flags().is_non_specular(), "{label}");
    let mut rng = Pcg32::new(11, suite_seed());
    let mut albedos = Vec::new();
    for wo in test_directions() {
        let e = expect(wo);
        let n = 10_000;
        let (mut refl, mut trans) = (Rgb::BLACK, Rgb::BLACK);
        for i in 0..n {
            let uc = (i as f32 + rng.next_f32()) / n as f32;
            let u = Vec2::new(rng.next_f32(), rng.next_f32());
            let Some(s) = bxdf.sample_f(wo, uc, u) else {
                continue;
            };
            assert!(s.flags.is_specular(), "{label}: {:?}", s.flags);
            assert!(s.pdf > 0.0 && s.pdf <= 1.0, "{label}: pdf {}", s.pdf);
            let weight = s.f * (s.wi.z.abs() / s.pdf) / n as f32;
            if s.flags.contains(BxdfFlags::REFLECTION) {
                let mirror = Vec3::new(-wo.x, -wo.y, wo.z);
                assert!(
                    (s.wi - mirror).length() < 1e-5,
                    "{label}: {} is not the mirror of {wo}",
                    s.wi
                );
                assert_eq!(s.eta, 1.0);
                refl += weight;
            } else {
                assert!(s.flags.contains(BxdfFlags::TRANSMISSION), "{label}");
                let t = e.transmit_dir.expect("no transmission expected");
                assert!((s.wi - t).length() < 1e-5, "{label}: transmitted {} != {t}", s.wi);
                trans += weight;
            }
            let w = sample_uniform_sphere(u);
            assert!(bxdf.f(wo, w).is_black() && bxdf.pdf(wo, w) == 0.0, "{label}");
            assert!(bxdf.f(wo, s.wi).is_black() && bxdf.pdf(wo, s.wi) == 0.0, "{label}");
        }
        let close = |a: Rgb, b: Rgb| (a - b).max_component().abs().max((b - a).max_component().abs()) < 2e-3;
        assert!(
            close(refl, e.reflect),
            "{label}, wo = {wo}: reflected {refl:?}, expected {:?}",
            e.reflect
        );
        assert!(
            close(trans, e.transmit),
            "{label}, wo = {wo}: transmitted {trans:?}, expected {:?}",
            e.transmit
        );
        albedos.push((refl + trans).average());
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
    let b = Bsdf::new(Vec3::Z, Vec3::X, Vec3::Z, Bxdf::Diffuse(DiffuseBxdf { r: Rgb::BLACK }));
    assert!(b.flags().is_empty());
    assert!(b.sample_f(Vec3::Z, 0.5, Vec2::splat(0.5)).is_none());
}

#[test]
fn bsdf_frame_round_trips_world_directions() {
    let ns = Vec3::new(0.2, 0.9, -0.1).normalize();
    let b = Bsdf::new(ns, Vec3::X, ns, Bxdf::Diffuse(DiffuseBxdf { r: Rgb::WHITE }));
    let wo = Vec3::new(0.1, 0.5, 0.3).normalize();
    let s = b.sample_f(wo, 0.3, Vec2::new(0.2, 0.7)).unwrap();
    assert!(s.wi.dot(ns) > 0.0, "reflection stays on the side of wo");
    assert!((b.pdf(wo, s.wi) - s.pdf).abs() < 1e-4);
}

#[test]
fn light_leak_guard_follows_the_geometric_normal() {
    // Shading normal tilted 72 degrees from the geometric one (z).
    let ns = Vec3::new(0.95, 0.0, 0.31).normalize();
    let b = Bsdf::new(ns, Vec3::Y, Vec3::Z, Bxdf::Diffuse(DiffuseBxdf { r: Rgb::WHITE }));
    let wo = Vec3::Z;
    // Below the geometric surface, above the shading one: a reflection for the lobe only.
    let leak = Vec3::new(1.0, 0.0, -0.2).normalize();
    assert!(leak.dot(ns) > 0.0);
    assert!(b.f(wo, leak).is_black());
    assert_eq!(b.pdf(wo, leak), 0.0);
    // Above both: unchanged.
    let ok = Vec3::new(0.5, 0.0, 0.5).normalize();
    assert!(!b.f(wo, ok).is_black() && b.pdf(wo, ok) > 0.0);
    // Samples below the geometric surface are dropped; the others keep the lobe's density.
    let mut rng = Pcg32::new(3, 5);
    let (mut kept, mut dropped) = (0, 0);
    for _ in 0..4096 {
        let u = Vec2::new(rng.next_f32(), rng.next_f32());
        match b.sample_f(wo, 0.5, u) {
            Some(s) => {
                kept += 1;
                assert!(s.wi.z > 0.0, "{s:?}");
                assert!((b.pdf(wo, s.wi) - s.pdf).abs() <= 1e-4 * s.pdf, "{s:?}");
            }
            None => dropped += 1,
        }
    }
    assert!(kept > 0 && dropped > 0, "{kept} {dropped}");
}

// ---- conductors -------------------------------------------------------------------------

/// Copper-like RGB index (the veach-mis plates).
const CU_ETA: Rgb = Rgb::new(0.200_438, 0.924_033, 1.102_212);
const CU_K: Rgb = Rgb::new(3.912_949, 2.452_848, 2.142_188);

/// Roughness values the rough lobes are tested at, including an anisotropic one.
const ALPHAS: [(f32, f32); 4] = [(0.05, 0.05), (0.2, 0.2), (0.6, 0.6), (0.1, 0.5)];

fn conductor(ax: f32, ay: f32, eta: Rgb, k: Rgb) -> Bxdf {
    Bxdf::Conductor(ConductorBxdf {
        distrib: Microfacet::trowbridge_reitz(ax, ay),
        eta,
        k,
    })
}

#[test]
fn rough_conductor_sampling_matches_its_pdf() {
    for (ax, ay) in ALPHAS {
        let b = conductor(ax, ay, CU_ETA, CU_K);
        let label = format!("conductor ({ax}, {ay})");
        if ax < 0.1 {
            // An oblique direction from each side.
            check_sampling_matches_pdf_for(&b, &label, &test_directions()[1..=3]);
        } else {
            check_sampling_matches_pdf(&b, &label);
        }
    }
}

#[test]
fn rough_conductor_is_consistent_reciprocal_and_below_one() {
    for (ax, ay) in ALPHAS {
        let b = conductor(ax, ay, CU_ETA, CU_K);
        let albedos = check_consistency_and_energy_with(&b, &format!("Cu ({ax}, {ay})"), 50_000, |_, _| 1.0);
        assert!(albedos.iter().all(|a| *a < 0.9), "copper absorbs: {albedos:?}");
    }
}

#[test]
fn rough_conductor_white_furnace_loses_only_multiple_scattering() {
    // eta = 0 (a purely imaginary index) reflects everything at every angle: F = 1.
    let (eta, k) = (Rgb::BLACK, Rgb::WHITE);
    for cos in [0.01f32, 0.3, 1.0] {
        assert!((fresnel::fr_complex(cos, eta, k) - Rgb::WHITE).max_component().abs() < 1e-5);
    }
    // Single-scattering albedo at normal incidence, against a 1-D quadrature of
    // E = integral D(wm) G(z, wi) cos(theta_m) dwm over the normals that reflect z above
    // the horizon (theta_m < 45 degrees): the energy lost is what would scatter more than
    // once between microfacets, or leave below the horizon, and grows with roughness.
    let expected = |a: f64| {
        let n = 20_000;
        let h = std::f64::consts::FRAC_PI_4 / f64::from(n);
        (0..n)
            .map(|j| {
                let th = (f64::from(j) + 0.5) * h;
                let (t2, c) = (th.tan().powi(2), th.cos());
                let d = 1.0 / (std::f64::consts::PI * a * a * c.powi(4) * (1.0 + t2 / (a * a)).powi(2));
                let lambda_i = 0.5 * ((1.0 + a * a * (2.0 * th).tan().powi(2)).sqrt() - 1.0);
                d / (1.0 + lambda_i) * c * th.sin() * std::f64::consts::TAU * h
            })
            .sum::<f64>()
    };
    let mut last = 1.0f32;
    for alpha in [0.05f32, 0.2, 0.6, 1.0] {
        let b = conductor(alpha, alpha, eta, k);
        let albedos = check_consistency_and_energy_with(&b, &format!("white conductor {alpha}"), 100_000, |_, _| 1.0);
        let (normal, e) = (albedos[0], expected(f64::from(alpha)) as f32);
        assert!(
            (normal - e).abs() < 3e-3,
            "alpha {alpha}: albedo {normal}, quadrature {e}"
        );
        assert!(normal < last, "alpha {alpha}: albedo {normal} (previous {last})");
        last = normal;
    }
    assert!(expected(0.05) > 0.99 && expected(0.6) < 0.6);
}

#[test]
fn smooth_conductor_is_a_fresnel_weighted_mirror() {
    let b = conductor(0.0, 0.0, CU_ETA, CU_K);
    assert_eq!(b.flags(), BxdfFlags::SPECULAR | BxdfFlags::REFLECTION);
    check_specular(&b, "smooth conductor", |wo| SpecularExpectation {
        reflect: fresnel::fr_complex(wo.z.abs(), CU_ETA, CU_K),
        transmit: Rgb::BLACK,
        transmit_dir: None,
    });
}

// ---- dielectrics ------------------------------------------------------------------------

fn dielectric(ax: f32, ay: f32, eta: f32) -> Bxdf {
    Bxdf::Dielectric(DielectricBxdf {
        eta,
        distrib: Microfacet::trowbridge_reitz(ax, ay),
    })
}

/// The relative index a pair crosses for a dielectric of index `eta`.
fn crossing_eta(eta: f32) -> impl Fn(Vec3, Vec3) -> f32 {
    move |wo, wi| {
        if wo.z * wi.z >= 0.0 {
            1.0
        } else if wo.z > 0.0 {
            eta
        } else {
            1.0 / eta
        }
    }
}

#[test]
fn rough_dielectric_sampling_matches_its_pdf() {
    // The sharpest lobe from the inside only (total internal reflection near the critical
    // angle), the others from every test direction (both sides).
    let inside = test_directions()[3];
    check_sampling_matches_pdf_for(&dielectric(0.05, 0.05, 1.5), "dielectric 0.05, eta 1.5", &[inside]);
    for (ax, ay, eta) in [
        (0.2, 0.2, 1.5),
        (0.6, 0.6, 1.5),
        (0.1, 0.5, 1.5),
        (0.3, 0.3, 1.33),
        (0.2, 0.2, 1.0 / 1.5),
    ] {
        check_sampling_matches_pdf(&dielectric(ax, ay, eta), &format!("dielectric ({ax}, {ay}), eta {eta}"));
    }
}

#[test]
fn rough_dielectric_conserves_energy_and_is_reciprocal() {
    for (alpha, eta) in [(0.05, 1.5), (0.2, 1.5), (0.6, 1.5), (0.3, 1.33), (0.2, 1.0 / 1.5)] {
        let label = format!("dielectric {alpha}, eta {eta}");
        let b = dielectric(alpha, alpha, eta);
        let albedos = check_consistency_and_energy_with(&b, &label, 100_000, crossing_eta(eta));
        // Entering a denser medium near normal incidence, little is lost to masking (with
        // eta < 1, microfacets tilted past the critical angle reflect totally, and more is).
        if alpha <= 0.2 && eta > 1.0 {
            assert!(albedos[0] > 0.97, "{label}: {albedos:?}");
        }
    }
    // Anisotropic.
    check_consistency_and_energy_with(
        &dielectric(0.1, 0.5, 1.5),
        "dielectric (0.1, 0.5)",
        100_000,
        crossing_eta(1.5),
    );
}

#[test]
fn rough_dielectric_scales_transmitted_radiance_by_one_over_eta_squared() {
    let b = dielectric(0.3, 0.3, 1.5);
    let wo = Vec3::new(0.3, 0.1, 0.9).normalize();
    let s = (0..64)
        .filter_map(|i| b.sample_f(wo, 0.999, Vec2::new(i as f32 / 64.0, 0.37)))
        .find(|s| s.flags.contains(BxdfFlags::TRANSMISSION))
        .unwrap();
    assert_eq!(s.eta, 1.5);
    let back = b.f(s.wi, wo);
    assert!((back.r / s.f.r - 2.25).abs() < 1e-3, "{back:?} vs {:?}", s.f);
}

/// The smooth dielectric's expectation: `R` to the mirror, `T / eta'^2` to the refracted
/// direction (total internal reflection: everything to the mirror).
fn smooth_dielectric_expectation(eta: f32) -> impl Fn(Vec3) -> SpecularExpectation {
    move |wo| {
        let r = fresnel::fr_dielectric(wo.z, eta);
        match fresnel::refract(wo, Vec3::Z, eta) {
            Some((wt, etap)) => SpecularExpectation {
                reflect: Rgb::splat(r),
                transmit: Rgb::splat((1.0 - r) / sqr(etap)),
                transmit_dir: Some(wt),
            },
            None => SpecularExpectation {
                reflect: Rgb::WHITE,
                transmit: Rgb::BLACK,
                transmit_dir: None,
            },
        }
    }
}

#[test]
fn smooth_dielectric_reflects_and_refracts_by_fresnel() {
    for eta in [1.5, 1.33, 1.0 / 1.5] {
        let b = dielectric(0.0, 0.0, eta);
        let albedos = check_specular(
            &b,
            &format!("smooth dielectric {eta}"),
            smooth_dielectric_expectation(eta),
        );
        // With the radiance scaling undone, R + T = 1 exactly.
        for (wo, a) in test_directions().into_iter().zip(albedos) {
            let e = smooth_dielectric_expectation(eta)(wo);
            let etap = fresnel::refract(wo, Vec3::Z, eta).map_or(1.0, |(_, e)| e);
            let unscaled = e.reflect.r + e.transmit.r * sqr(etap);
            assert!(
                (unscaled - 1.0).abs() < 1e-5,
                "eta {eta}, wo = {wo}: R + T = {unscaled}"
            );
            assert!(a <= 1.0 + 1e-3 || etap < 1.0, "eta {eta}: albedo {a}");
        }
    }
    // Refraction obeys Snell's law, and the sampled eta is the one crossed.
    let b = dielectric(0.0, 0.0, 1.5);
    let wo = Vec3::new(0.5, 0.0, 0.75f32.sqrt());
    let s = b.sample_f(wo, 0.9999, Vec2::ZERO).unwrap();
    assert!((0.5 - 1.5 * (-s.wi.x)).abs() < 1e-5 && s.wi.z < 0.0 && s.eta == 1.5);
}

#[test]
fn index_one_passes_straight_through() {
    for alpha in [0.0, 0.3] {
        let b = dielectric(alpha, alpha, 1.0);
        assert_eq!(b.flags(), BxdfFlags::SPECULAR | BxdfFlags::TRANSMISSION);
        check_specular(&b, "eta 1", |wo| SpecularExpectation {
            reflect: Rgb::BLACK,
            transmit: Rgb::WHITE,
            transmit_dir: Some(-wo),
        });
    }
}

#[test]
fn thin_dielectric_sums_interreflections() {
    let eta = 1.5;
    let b = Bxdf::ThinDielectric(ThinDielectricBxdf { eta });
    let albedos = check_specular(&b, "thin dielectric", |wo| {
        let r = fresnel::fr_dielectric(wo.z.abs(), eta);
        let t = 1.0 - r;
        let r2 = r + t * t * r / (1.0 - r * r);
        SpecularExpectation {
            reflect: Rgb::splat(r2),
            transmit: Rgb::splat(1.0 - r2),
            transmit_dir: Some(-wo),
        }
    });
    assert!(albedos.iter().all(|a| (a - 1.0).abs() < 2e-3), "{albedos:?}");
    // At normal incidence: R' = 2R / (1 + R) = 0.0769 for R = 0.04.
    let (r, _) = ThinDielectricBxdf { eta }.reflectance_transmittance(1.0);
    assert!((r - 0.08 / 1.04).abs() < 1e-5, "{r}");
}

// ---- diffuse transmission ---------------------------------------------------------------

#[test]
fn diffuse_transmission_sampling_matches_its_pdf() {
    let b = Bxdf::DiffuseTransmission(DiffuseTransmissionBxdf {
        r: Rgb::new(0.2, 0.5, 0.1),
        t: Rgb::new(0.7, 0.1, 0.3),
    });
    check_sampling_matches_pdf(&b, "diffuse transmission");
}

#[test]
fn diffuse_transmission_white_furnace() {
    for (r, t, total) in [(0.25, 0.25, 0.5), (0.4, 0.6, 1.0), (0.0, 1.0, 1.0)] {
        let b = Bxdf::DiffuseTransmission(DiffuseTransmissionBxdf {
            r: Rgb::splat(r),
            t: Rgb::splat(t),
        });
        let albedos = check_consistency_and_energy(&b, &format!("diffuse transmission {r} {t}"));
        assert!(albedos.iter().all(|a| (a - total).abs() < 1e-4), "{albedos:?}");
    }
    let black = Bxdf::DiffuseTransmission(DiffuseTransmissionBxdf {
        r: Rgb::BLACK,
        t: Rgb::BLACK,
    });
    assert!(black.flags().is_empty());
    assert!(black.sample_f(Vec3::Z, 0.5, Vec2::splat(0.5)).is_none());
}
