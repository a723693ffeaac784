//! Chi-square tests of light sampling: the directions `sample_li` produces at a receiver,
//! against `pdf_li` of the point each direction reaches.

use std::sync::Arc;

use super::*;
use crate::math::{Mat4, Ray, Transform, PI};
use crate::sampling::chi2::{suite_seed, Chi2Test, SphereGrid, SIGNIFICANCE};
use crate::shape::{BilinearMesh, BilinearPatch, Cylinder, Disk, Shape, Sphere, SphereClip, Triangle, TriangleMesh};

fn check_light(light: &DiffuseAreaLight, receiver: Vec3, label: &str) {
    check_light_with(light, receiver, label, 300_000);
}

/// [`check_light`] with `samples` samples.
fn check_light_with(light: &DiffuseAreaLight, receiver: Vec3, label: &str, samples: u32) {
    let recv = Interaction::point(receiver);
    let report = Chi2Test::new(samples, suite_seed()).with_test_count(3).sphere(
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
        alpha: None,
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
        alpha: None,
    };
    check_light(&light, Vec3::new(0.2, -0.1, 2.3), "sphere");
}

/// A cut sphere (zmin, zmax, phimax): sampled over its own part only, and its pdf reached
/// through its own (cut) intersection; with a non-uniform scale too.
#[test]
fn partial_sphere_light_sampling_matches_its_solid_angle_pdf() {
    let clip = SphereClip {
        z_min: -0.3,
        z_max: 0.8,
        phi_max: 250f32.to_radians(),
    };
    for (m, label) in [
        (Mat4::from_translation(Vec3::new(0.0, 0.0, 2.0)), "partial sphere"),
        (
            Mat4::from_translation(Vec3::new(0.5, 0.0, 2.0)) * Mat4::from_scale(Vec3::new(1.2, 0.5, 0.8)),
            "scaled partial sphere",
        ),
    ] {
        let light = DiffuseAreaLight {
            shape: Shape::Sphere(Sphere::partial(1.0, clip, Transform::new(m).unwrap(), true)),
            radiance: Rgb::WHITE,
            two_sided: false,
            alpha: None,
        };
        check_light(&light, m.transform_point3(Vec3::new(0.1, -0.1, 0.2)), label);
    }
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
        alpha: None,
    };
    check_light(&light, Vec3::new(0.6, 0.1, 2.2), "scaled sphere");
}

/// A tilted, non-uniformly scaled disk seen from its emitting side.
#[test]
fn disk_light_sampling_matches_its_solid_angle_pdf() {
    let m = Mat4::from_translation(Vec3::new(0.2, 0.1, 1.0))
        * Mat4::from_rotation_y(0.4)
        * Mat4::from_scale(Vec3::new(1.3, 0.7, 1.0));
    // Flipped: the normal points to world -z-ish, towards the receiver below.
    let light = DiffuseAreaLight {
        shape: Shape::Disk(Disk::new(0.0, 1.0, 0.0, 2.0 * PI, Transform::new(m).unwrap(), true)),
        radiance: Rgb::WHITE,
        two_sided: false,
        alpha: None,
    };
    check_light(&light, Vec3::new(0.3, -0.2, 0.2), "disk");
}

/// An annulus sector: the sampler must stay on the surface that is intersected.
#[test]
fn annulus_sector_light_sampling_matches_its_solid_angle_pdf() {
    let m = Mat4::from_translation(Vec3::new(0.0, 0.0, 0.8));
    let light = DiffuseAreaLight {
        shape: Shape::Disk(Disk::new(0.1, 1.2, 0.4, 1.25 * PI, Transform::new(m).unwrap(), false)),
        radiance: Rgb::WHITE,
        two_sided: true,
        alpha: None,
    };
    check_light(&light, Vec3::new(0.1, 0.2, 0.0), "annulus sector");
}

/// An open cylinder emitting inwards, seen from inside: every direction meets the wall at
/// most once (the rest leave through the open ends, where the pdf is zero), so the pdf is
/// bounded; cut in azimuth, and elliptic under a non-uniform scale (the Jacobian pdf).
#[test]
fn cylinder_light_sampling_matches_its_solid_angle_pdf() {
    for (m, phi_max, label) in [
        (Mat4::from_translation(Vec3::new(0.0, 0.0, 1.0)), 2.0 * PI, "cylinder"),
        (
            Mat4::from_translation(Vec3::new(0.2, 0.0, 1.0))
                * Mat4::from_rotation_x(0.4)
                * Mat4::from_scale(Vec3::new(1.3, 0.6, 0.9)),
            1.4 * PI,
            "scaled cut cylinder",
        ),
    ] {
        let light = DiffuseAreaLight {
            shape: Shape::Cylinder(Cylinder::new(1.0, -0.8, 1.1, phi_max, Transform::new(m).unwrap(), true)),
            radiance: Rgb::WHITE,
            two_sided: false,
            alpha: None,
        };
        // A million samples: the wall's curvature spreads the density over many cells.
        check_light_with(&light, m.transform_point3(Vec3::new(0.2, -0.3, 0.1)), label, 1_000_000);
    }
}

/// A curved (saddle-shaped) emitting patch above the receiver.
fn saddle_light(two_sided: bool) -> DiffuseAreaLight {
    let mesh = BilinearMesh {
        positions: vec![
            Vec3::new(-1.0, -0.8, 1.0),
            Vec3::new(1.2, -1.0, 1.8),
            Vec3::new(-0.9, 1.1, 1.6),
            Vec3::new(1.0, 0.9, 0.7),
        ],
        indices: vec![0, 1, 2, 3],
        // dp/du x dp/dv points up; flipped, it emits downwards.
        flip_normals: true,
        ..Default::default()
    };
    DiffuseAreaLight {
        shape: Shape::Bilinear(BilinearPatch::new(Arc::new(mesh), 0)),
        radiance: Rgb::new(1.0, 2.0, 0.5),
        two_sided,
        alpha: None,
    }
}

/// Light sampling on a curved patch, seen from below and above: directions against the
/// solid-angle pdf, summed over every point of the patch along the direction (light
/// sampling ignores occlusion by the light itself, which shadow rays handle). The receivers
/// see no silhouette (|cos| > 0.27 over the patch), where the 1 / cos of the solid-angle
/// pdf would defeat the quadrature.
#[test]
fn bilinear_patch_light_sampling_matches_its_solid_angle_pdf() {
    let light = saddle_light(true);
    for (k, receiver) in [Vec3::new(0.1, -0.2, 0.0), Vec3::new(0.3, -0.2, 3.0)]
        .into_iter()
        .enumerate()
    {
        let recv = Interaction::point(receiver);
        let report = Chi2Test::new(300_000, suite_seed()).with_test_count(2).sphere(
            SphereGrid {
                cos_theta_bins: 20,
                phi_bins: 40,
            },
            |u, _| light.sample_li(&recv, u).map(|s| s.wi),
            |w| {
                let mut ray = Ray::new(receiver, w);
                let mut pdf = 0.0;
                let mut count = 0;
                while let Some(hit) = light.shape.intersect(&ray, f32::INFINITY) {
                    let si = light.shape.interaction(&ray, &hit);
                    pdf += light.pdf_li(&recv, &si.intr);
                    ray = si.spawn_ray(w);
                    count += 1;
                    assert!(count <= 2, "ray {ray:?} hit {count} times, last {hit:?} {si:?}");
                }
                pdf
            },
        );
        assert!(report.passes(SIGNIFICANCE), "receiver {k}: {report}");
    }
}

/// Irradiance at a point under a one-sided curved emitter, by two independent estimators:
/// sampling the light (with the visibility of the sampled point, since the patch can hide
/// parts of itself) and sampling the hemisphere uniformly (closest hit, emitting side only).
/// They must agree; and the emitted power is `pi A L` with `A` from a fine tessellation.
#[test]
fn bilinear_patch_irradiance_by_two_estimators() {
    let light = saddle_light(false);
    let (x, n) = (Vec3::new(0.2, 0.1, 0.0), Vec3::new(0.3, -0.2, 1.0).normalize());
    let recv = Interaction::point(x);
    let frame = crate::math::Frame::from_z(n);
    let mut rng = crate::sampling::Pcg32::new(17, suite_seed());
    let m = 400_000;
    let mut stats = [(0.0f64, 0.0f64); 2];
    for _ in 0..m {
        let u = crate::math::Vec2::new(rng.next_f32(), rng.next_f32());
        // Light sampling: L cos / p_omega for visible samples.
        let mut est = 0.0;
        if let Some(s) = light.sample_li(&recv, u) {
            let visible = light
                .shape
                .intersect(&Ray::new(x, s.wi), f32::INFINITY)
                .map(|h| light.shape.interaction(&Ray::new(x, s.wi), &h).p())
                .is_some_and(|p| (p - s.p_light.p).length() < 1e-3);
            if visible {
                est = f64::from(s.l.g * s.wi.dot(n).max(0.0) / s.pdf);
            }
        }
        // Uniform hemisphere: L cos / (1 / 2 pi) where the closest hit emits towards x.
        let w = frame.from_local(crate::sampling::sample_uniform_hemisphere(u));
        let ray = Ray::new(x, w);
        let mut est2 = 0.0;
        if let Some(h) = light.shape.intersect(&ray, f32::INFINITY) {
            let si = light.shape.interaction(&ray, &h);
            est2 = f64::from(light.l(si.n(), -w).g * w.dot(n) * 2.0 * PI);
        }
        for (s, e) in stats.iter_mut().zip([est, est2]) {
            s.0 += e;
            s.1 += e * e;
        }
    }
    let [(m1, se1), (m2, se2)] = stats.map(|(s, s2)| {
        let mean = s / f64::from(m);
        (mean, ((s2 / f64::from(m) - mean * mean) / f64::from(m)).sqrt())
    });
    assert!(m1 > 0.3, "irradiance {m1}");
    assert!(
        (m1 - m2).abs() < 4.0 * (se1 * se1 + se2 * se2).sqrt(),
        "light sampling {m1} +- {se1}, hemisphere {m2} +- {se2}"
    );
    // Power: pi A L, A summed over a 200 x 200 triangulation of the patch.
    let Shape::Bilinear(patch) = &light.shape else {
        unreachable!()
    };
    let [p00, p10, p01, p11] = patch.corners();
    let at = |u: f32, v: f32| p00.lerp(p01, v).lerp(p10.lerp(p11, v), u);
    let k = 200;
    let mut area = 0.0f64;
    for i in 0..k {
        for j in 0..k {
            let (u0, v0, u1, v1) = (
                i as f32 / k as f32,
                j as f32 / k as f32,
                (i + 1) as f32 / k as f32,
                (j + 1) as f32 / k as f32,
            );
            let (a, b, c, d) = (at(u0, v0), at(u1, v0), at(u0, v1), at(u1, v1));
            area += 0.5 * f64::from((b - a).cross(d - a).length() + (d - a).cross(c - a).length());
        }
    }
    let power = f64::from(light.power().g);
    let expected = std::f64::consts::PI * area * 2.0;
    assert!(
        (power - expected).abs() < 1e-3 * expected,
        "power {power}, pi A L {expected}"
    );
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

// --- Infinite, distant and spot lights ------------------------------------------------

use crate::math::{Bounds3, Vec2};
use crate::sampling::chi2::RectGrid;

/// An 8 x 8 environment image: dim everywhere, a bright pixel, a black pixel, a coloured
/// row.
fn spot_image(w: u32, h: u32) -> Vec<Rgb> {
    let mut px = vec![Rgb::splat(0.2); (w * h) as usize];
    px[(2 * w + 5) as usize] = Rgb::new(40.0, 30.0, 20.0);
    px[(6 * w + 1) as usize] = Rgb::BLACK;
    for x in 0..w {
        px[(4 * w + x) as usize] = Rgb::new(0.0, 1.0, 3.0);
    }
    px
}

fn unit_bounds() -> Bounds3 {
    Bounds3 {
        min: Vec3::splat(-1.0),
        max: Vec3::splat(1.0),
    }
}

fn check_infinite_light(light: &Light, label: &str) {
    let recv = Interaction::point(Vec3::new(0.1, 0.2, -0.3));
    // Samples whose pdf_li disagrees with the sample's pdf: only rounding at pixel borders
    // may do that, so they must be rare.
    let mut mismatches = 0u32;
    // The image's pixels are much larger than the grid's cells, so the default quadrature
    // panels resolve the pdf's steps.
    let report = Chi2Test::new(500_000, suite_seed()).with_test_count(5).sphere(
        SphereGrid {
            cos_theta_bins: 20,
            phi_bins: 40,
        },
        |u, _| {
            let s = light.sample_li(&recv, u)?;
            // Sample and density agree, and the shadow ray ends outside the scene.
            let pdf = light.pdf_li_direction(s.wi);
            // (Interpolated radiance agrees up to the rounding of the direction round trip.)
            let le = light.le(s.wi);
            let l_differs = (s.l - le).max_component().abs().max((le - s.l).max_component().abs())
                > 1e-3 * (1.0 + le.max_component());
            if (s.pdf - pdf).abs() > 1e-3 * pdf || l_differs {
                mismatches += 1;
            }
            assert!((s.p_light.p - recv.p).length() > 3.4, "{label}: shadow ray too short");
            Some(s.wi)
        },
        |w| light.pdf_li_direction(w),
    );
    assert!(report.passes(SIGNIFICANCE), "{label}: {report}");
    assert!(
        (report.pdf_integral - 1.0).abs() < 2e-3,
        "{label}: pdf integral {}",
        report.pdf_integral
    );
    assert!(
        mismatches < 20,
        "{label}: {mismatches} samples whose pdf or radiance disagree with pdf_li or le"
    );
}

fn env_light(mapping: EnvMapping, w: u32, h: u32, m: Mat4) -> Light {
    let mut l = Light::ImageInfinite(ImageInfiniteLight::new(
        w,
        h,
        &spot_image(w, h),
        1.5,
        mapping,
        &Transform::new(m).unwrap(),
    ));
    l.preprocess(&unit_bounds());
    l
}

#[test]
fn equal_area_env_map_sampling_matches_its_pdf() {
    check_infinite_light(&env_light(EnvMapping::EqualArea, 8, 8, Mat4::IDENTITY), "equal-area");
}

#[test]
fn rotated_env_map_sampling_matches_its_pdf() {
    let m = Mat4::from_rotation_x(-std::f32::consts::FRAC_PI_2) * Mat4::from_rotation_z(0.3);
    check_infinite_light(&env_light(EnvMapping::EqualArea, 8, 8, m), "rotated equal-area");
}

/// A linear map that is not a rotation: the directions are renormalised and the pdf has to
/// carry the Jacobian.
#[test]
fn sheared_env_map_sampling_matches_its_pdf() {
    let m = Mat4::from_cols_array(&[
        1.0, 0.4, 0.0, 0.0, 0.0, 0.8, 0.0, 0.0, 0.3, 0.0, 1.5, 0.0, 0.0, 0.0, 0.0, 1.0,
    ]);
    check_infinite_light(&env_light(EnvMapping::EqualArea, 8, 8, m), "sheared equal-area");
}

#[test]
fn equirect_env_map_sampling_matches_its_pdf() {
    check_infinite_light(&env_light(EnvMapping::Equirect, 16, 8, Mat4::IDENTITY), "equirect");
}

#[test]
fn bilinear_equirect_env_map_sampling_matches_its_pdf() {
    check_infinite_light(
        &env_light(EnvMapping::EquirectBilinear, 16, 8, Mat4::IDENTITY),
        "bilinear equirect",
    );
}

/// Mitsuba's interpolation: exact pixel values on the grid (columns at `(x + 0.5) / w`,
/// rows at `y / (h - 1)`), linear between, wrapping in `u`; positive density wherever the
/// radiance is.
#[test]
fn bilinear_env_map_interpolates_as_mitsuba() {
    let (w, h) = (16u32, 8u32);
    let Light::ImageInfinite(e) = env_light(EnvMapping::EquirectBilinear, w, h, Mat4::IDENTITY) else {
        unreachable!()
    };
    let px = spot_image(w, h);
    let at = |x: u32, y: u32| px[(y * w + x) as usize] * 1.5;
    let node = |x: f32, y: f32| Vec2::new((x + 0.5) / w as f32, y / (h - 1) as f32);
    let close = |a: Rgb, b: Rgb| (a - b).max_component().abs().max((b - a).max_component().abs()) < 1e-4;
    assert!(close(e.lookup(node(5.0, 2.0)), at(5, 2)));
    assert!(close(e.lookup(node(3.0, 4.0)), at(3, 4)));
    // Half-way between two columns and two rows.
    let mid = (at(5, 2) + at(6, 2) + at(5, 3) + at(6, 3)) * 0.25;
    assert!(
        close(e.lookup(node(5.5, 2.5)), mid),
        "{:?} vs {mid:?}",
        e.lookup(node(5.5, 2.5))
    );
    // Wrapping: half-way between the last column and the first.
    let wrap = (at(w - 1, 1) + at(0, 1)) * 0.5;
    assert!(close(e.lookup(Vec2::new(0.0, 1.0 / (h - 1) as f32)), wrap));
    // The poles are the first and last rows.
    assert!(close(e.lookup(Vec2::new(0.5 / w as f32, 0.0)), at(0, 0)));
    assert!(close(e.lookup(Vec2::new(0.5 / w as f32, 1.0)), at(0, h - 1)));
    // The black pixel (1, 6) is surrounded by lit ones: its neighbourhood has radiance and
    // density.
    let d = e.direction(node(1.0, 6.0) + Vec2::new(0.2 / w as f32, 0.0));
    assert!(!e.le(d).is_black());
    assert!(e.pdf_li(d) > 0.0);
}

#[test]
fn uniform_infinite_light_sampling_matches_its_pdf() {
    let mut l = Light::UniformInfinite(UniformInfiniteLight {
        radiance: Rgb::splat(2.0),
        scene_radius: 0.0,
        scene_center: Vec3::ZERO,
    });
    l.preprocess(&unit_bounds());
    check_infinite_light(&l, "uniform");
}

/// The image's pixels are where the mapping says: the centre of the equal-area square is +z,
/// pixel (5, 2) of the bright spot is where the bright samples go, and an equirect image's
/// top row is +z.
#[test]
fn env_map_lookup_follows_the_mapping() {
    let Light::ImageInfinite(l) = env_light(EnvMapping::EqualArea, 8, 8, Mat4::IDENTITY) else {
        unreachable!()
    };
    let bright = l.direction(Vec2::new(5.5 / 8.0, 2.5 / 8.0));
    assert_eq!(l.le(bright), Rgb::new(60.0, 45.0, 30.0));
    assert_eq!(l.le(Vec3::Z), l.lookup(Vec2::splat(0.5)));
    let Light::ImageInfinite(e) = env_light(EnvMapping::Equirect, 16, 8, Mat4::IDENTITY) else {
        unreachable!()
    };
    assert!((e.direction(Vec2::new(0.3, 0.0)) - Vec3::Z).length() < 1e-6);
    assert!((e.direction(Vec2::new(0.25, 0.5)) - Vec3::Y).length() < 1e-6);
    let uv = e.uv(Vec3::new(-0.3, -0.5, 0.2).normalize());
    assert!((e.direction(uv) - Vec3::new(-0.3, -0.5, 0.2).normalize()).length() < 1e-5);
}

/// pbrt-v4's powers: `4 pi^2 r^2 L` for a uniform sky, `pi r^2 L` for a distant light, the
/// same as a uniform sky for a constant environment map in either layout.
#[test]
fn infinite_and_distant_light_powers() {
    let r2 = 3.0f32; // (half the diagonal of [-1, 1]^3)^2
    let mut lights = [
        Light::UniformInfinite(UniformInfiniteLight {
            radiance: Rgb::splat(2.0),
            scene_radius: 0.0,
            scene_center: Vec3::ZERO,
        }),
        Light::Distant(DistantLight {
            direction: Vec3::Z,
            radiance: Rgb::splat(2.0),
            scene_radius: 0.0,
            scene_center: Vec3::ZERO,
        }),
        Light::ImageInfinite(ImageInfiniteLight::new(
            4,
            4,
            &[Rgb::splat(1.0); 16],
            2.0,
            EnvMapping::EqualArea,
            &Transform::IDENTITY,
        )),
        Light::ImageInfinite(ImageInfiniteLight::new(
            6,
            3,
            &[Rgb::splat(1.0); 18],
            2.0,
            EnvMapping::Equirect,
            &Transform::IDENTITY,
        )),
    ];
    lights.iter_mut().for_each(|l| l.preprocess(&unit_bounds()));
    let sky = 4.0 * PI * PI * r2 * 2.0;
    let expected = [sky, PI * r2 * 2.0, sky, sky];
    for (l, e) in lights.iter().zip(expected) {
        assert!((l.power().g - e).abs() < 1e-4 * e, "{l:?}: {} vs {e}", l.power().g);
    }
}

/// pbrt-v4's spot falloff: full intensity inside the falloff start, zero outside the cone,
/// smoothstep in between; Li = I falloff / r^2; the power integrates the falloff.
#[test]
fn spot_light_falloff_and_power() {
    let (start, end) = (20.0f32.to_radians(), 30.0f32.to_radians());
    let pos = Vec3::new(0.0, 2.0, 0.0);
    // Pointing down -y: light-space +z to world -y.
    let m = Mat4::from_translation(pos) * Mat4::from_rotation_x(PI / 2.0);
    let spot = SpotLight {
        world_from_light: Transform::new(m).unwrap(),
        intensity: Rgb::new(3.0, 2.0, 1.0),
        cos_falloff_start: start.cos(),
        cos_falloff_end: end.cos(),
        falloff: SpotFalloff::SmoothCosine,
        projection: None,
    };
    let li_at = |angle: f32| {
        let recv = pos + 2.0 * Vec3::new(angle.sin(), -angle.cos(), 0.0);
        spot.sample_li(&Interaction::point(recv), Vec2::ZERO).map(|s| s.l)
    };
    let on_axis = li_at(0.0).unwrap();
    assert!((on_axis.r - 0.75).abs() < 1e-5, "{on_axis:?}");
    assert!((li_at(19.0f32.to_radians()).unwrap().r - 0.75).abs() < 1e-5);
    assert!(li_at(31.0f32.to_radians()).is_none());
    let a = 25.0f32.to_radians();
    let t = (a.cos() - end.cos()) / (start.cos() - end.cos());
    let expected = 0.75 * t * t * (3.0 - 2.0 * t);
    assert!(
        (li_at(a).unwrap().r - expected).abs() < 1e-4,
        "{:?} vs {expected}",
        li_at(a)
    );
    // Power: integrate the falloff over the sphere numerically.
    let n = 200_000;
    let mut sum = 0.0f64;
    for i in 0..n {
        let cos_t = -1.0 + 2.0 * (i as f64 + 0.5) / n as f64;
        sum += f64::from(smooth_step(cos_t as f32, spot.cos_falloff_end, spot.cos_falloff_start));
    }
    let integral = (sum * 2.0 / n as f64 * 2.0 * std::f64::consts::PI) as f32;
    assert!(
        (spot.power().r - 3.0 * integral).abs() < 1e-3 * spot.power().r,
        "{:?} vs {integral}",
        spot.power()
    );
    assert_eq!(smooth_step(0.5, 0.5, 0.5), 1.0);
    assert_eq!(smooth_step(0.4, 0.5, 0.5), 0.0);
}

/// The distant light arrives from its direction everywhere and its shadow ray leaves the
/// scene.
#[test]
fn distant_light_sample() {
    let mut l = Light::Distant(DistantLight {
        direction: Vec3::new(0.0, 0.6, 0.8),
        radiance: Rgb::splat(5.0),
        scene_radius: 0.0,
        scene_center: Vec3::ZERO,
    });
    l.preprocess(&unit_bounds());
    let recv = Interaction::point(Vec3::new(0.5, -0.5, 0.5));
    let s = l.sample_li(&recv, Vec2::new(0.3, 0.9)).unwrap();
    assert_eq!((s.wi, s.l, s.pdf), (Vec3::new(0.0, 0.6, 0.8), Rgb::splat(5.0), 1.0));
    assert!(((s.p_light.p - recv.p).length() - 2.0 * 3.0f32.sqrt()).abs() < 1e-4);
    assert!(l.is_delta() && !l.is_infinite());
    assert_eq!(l.pdf_li_direction(s.wi), 0.0);
    assert_eq!(l.le(s.wi), Rgb::BLACK);
}

/// The power-based sampler picks an environment map against a point light by pbrt's powers.
#[test]
fn power_sampler_weighs_infinite_lights_by_scene_size() {
    let mut lights = vec![
        Light::UniformInfinite(UniformInfiniteLight {
            radiance: Rgb::splat(1.0),
            scene_radius: 0.0,
            scene_center: Vec3::ZERO,
        }),
        Light::Point(PointLight {
            position: Vec3::ZERO,
            intensity: Rgb::splat(3.0 * PI),
        }),
    ];
    lights.iter_mut().for_each(|l| l.preprocess(&unit_bounds()));
    let s = PowerLightSampler::new(&lights);
    // 4 pi^2 * 3 against 4 pi * 3 pi: equal.
    assert!((s.pmf(0) - 0.5).abs() < 1e-5, "{}", s.pmf(0));
}

#[test]
fn equal_area_grid_sanity() {
    // The chi-square harness's rect grid over the unit square, for the distribution itself.
    let Light::ImageInfinite(l) = env_light(EnvMapping::EqualArea, 8, 8, Mat4::IDENTITY) else {
        unreachable!()
    };
    let grid = RectGrid {
        min: Vec2::ZERO,
        max: Vec2::ONE,
        bins: crate::math::UVec2::new(16, 16),
    };
    let report = Chi2Test::new(200_000, suite_seed()).rect(
        grid,
        |u, _| {
            let s = l.sample_li(&Interaction::point(Vec3::ZERO), u)?;
            Some(l.uv(s.wi))
        },
        |p| l.pdf_li(l.direction(p)) * 4.0 * PI,
    );
    assert!(report.passes(SIGNIFICANCE), "{report}");
}
