//! Chi-square tests of light sampling: the directions `sample_li` produces at a receiver,
//! against `pdf_li` of the point each direction reaches.

use std::sync::Arc;

use super::*;
use crate::math::{Mat4, Ray, Transform};
use crate::sampling::chi2::{suite_seed, Chi2Test, SphereGrid, SIGNIFICANCE};
use crate::shape::{Shape, Sphere, Triangle, TriangleMesh};

fn check_light(light: &DiffuseAreaLight, receiver: Vec3, label: &str) {
    let recv = Interaction::point(receiver);
    let report = Chi2Test::new(300_000, suite_seed()).with_test_count(3).sphere(
        SphereGrid {
            cos_theta_bins: 20,
            phi_bins: 40,
        },
        |u, _| light.sample_li(&recv, u).map(|s| s.wi),
        |w| {
            let ray = Ray::new(receiver, w);
            let Some(hit) = light.shape.intersect(&ray, f32::INFINITY) else {
                return 0.0;
            };
            let si = light.shape.interaction(&ray, &hit);
            if light.l(si.n(), -w).is_black() {
                return 0.0;
            }
            light.pdf_li(&recv, &si.intr)
        },
    );
    assert!(report.passes(SIGNIFICANCE), "{label}: {report}");
}

#[test]
fn triangle_light_sampling_matches_its_solid_angle_pdf() {
    let mesh = Arc::new(TriangleMesh {
        positions: vec![
            Vec3::new(-1.0, 1.0, -0.5),
            Vec3::new(1.5, 1.2, -0.5),
            Vec3::new(0.0, 0.8, 1.0),
        ],
        indices: vec![0, 1, 2],
        ..Default::default()
    });
    let light = DiffuseAreaLight {
        shape: Shape::Triangle(Triangle::new(mesh, 0)),
        radiance: Rgb::WHITE,
        two_sided: true,
    };
    check_light(&light, Vec3::new(0.1, -0.3, 0.2), "triangle");
}

/// Seen from inside (normals flipped inwards), every direction meets the sphere once and the
/// solid-angle pdf stays bounded; from outside it would diverge at the silhouette (the
/// 1 / cos factor), which no quadrature integrates well. The solid-angle conversion itself
/// is shared with the triangle test above.
#[test]
fn sphere_light_sampling_matches_its_solid_angle_pdf() {
    let t =
        Transform::new(Mat4::from_translation(Vec3::new(0.0, 0.0, 2.0)) * Mat4::from_scale(Vec3::splat(0.7))).unwrap();
    let light = DiffuseAreaLight {
        shape: Shape::Sphere(Sphere::new(1.0, t, true)),
        radiance: Rgb::WHITE,
        two_sided: false,
    };
    check_light(&light, Vec3::new(0.2, -0.1, 2.3), "sphere");
}

#[test]
fn scaled_sphere_light_sampling_matches_its_solid_angle_pdf() {
    // Non-uniform scale: uniform in object space is not uniform in world space; the pdf
    // carries the area Jacobian.
    let m = Mat4::from_translation(Vec3::new(0.5, 0.0, 2.0)) * Mat4::from_scale(Vec3::new(1.2, 0.5, 0.8));
    let light = DiffuseAreaLight {
        shape: Shape::Sphere(Sphere::new(1.0, Transform::new(m).unwrap(), true)),
        radiance: Rgb::WHITE,
        two_sided: false,
    };
    check_light(&light, Vec3::new(0.6, 0.1, 2.2), "scaled sphere");
}

/// `E[1 / pdf_area]` over area samples is the surface area. For an ellipsoid the area has
/// no elementary closed form, so compare with a fine midpoint quadrature of
/// `|dp/dtheta x dp/dphi|` over the parameter rectangle.
#[test]
fn scaled_sphere_area_pdf_integrates_to_one() {
    let s = Vec3::new(1.2, 0.5, 0.8);
    let sphere = Sphere::new(1.0, Transform::new(Mat4::from_scale(s)).unwrap(), false);
    let n = 1000;
    let mut area = 0.0f64;
    let (dt, dp) = (std::f64::consts::PI / n as f64, std::f64::consts::TAU / n as f64);
    for i in 0..n {
        let th = (i as f64 + 0.5) * dt;
        for j in 0..n {
            let ph = (j as f64 + 0.5) * dp;
            let (st, ct, sp, cp) = (th.sin(), th.cos(), ph.sin(), ph.cos());
            let (sx, sy, sz) = (f64::from(s.x), f64::from(s.y), f64::from(s.z));
            let d_th = [sx * ct * cp, sy * ct * sp, -sz * st];
            let d_ph = [-sx * st * sp, sy * st * cp, 0.0];
            let c = [
                d_th[1] * d_ph[2] - d_th[2] * d_ph[1],
                d_th[2] * d_ph[0] - d_th[0] * d_ph[2],
                d_th[0] * d_ph[1] - d_th[1] * d_ph[0],
            ];
            area += (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt() * dt * dp;
        }
    }
    let mut rng = crate::sampling::Pcg32::new(3, suite_seed());
    let m = 400_000;
    let (mut sum, mut sum2) = (0.0f64, 0.0f64);
    for _ in 0..m {
        let ss = sphere.sample_area(crate::math::Vec2::new(rng.next_f32(), rng.next_f32()));
        let v = 1.0 / f64::from(ss.pdf_area);
        assert!(
            (f64::from(sphere.pdf_area(&ss.intr)) * v - 1.0).abs() < 1e-3,
            "pdf_area disagrees with the sample"
        );
        sum += v;
        sum2 += v * v;
    }
    let mean = sum / f64::from(m);
    let se = ((sum2 / f64::from(m) - mean * mean) / f64::from(m)).sqrt();
    assert!(
        (mean - area).abs() < 4.0 * se + 1e-4 * area,
        "E[1/pdf] = {mean} +- {se}, area {area}"
    );
}

#[test]
fn power_sampler_picks_lights_in_proportion_to_power() {
    let lights = vec![
        Light::Point(PointLight {
            position: Vec3::ZERO,
            intensity: Rgb::splat(1.0),
        }),
        Light::Point(PointLight {
            position: Vec3::ZERO,
            intensity: Rgb::splat(3.0),
        }),
        Light::Point(PointLight {
            position: Vec3::ZERO,
            intensity: Rgb::BLACK,
        }),
    ];
    let s = PowerLightSampler::new(&lights);
    assert!((s.pmf(0) - 0.25).abs() < 1e-6 && (s.pmf(1) - 0.75).abs() < 1e-6 && s.pmf(2) == 0.0);
    assert_eq!(s.sample(0.1).unwrap().0, 0);
    assert_eq!(s.sample(0.3).unwrap().0, 1);
    assert_eq!(s.sample(0.999_999).unwrap().0, 1);
}
