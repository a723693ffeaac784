//! Tests of emission sampling: directions against `pdf_le` (chi-square), positions on the
//! scene disk, the densities `pdf_le` reports for every sample, and the power estimated by
//! `Le |cos| / (pdf_pos pdf_dir)` against each light's analytic power.

use std::sync::Arc;

use super::*;
use crate::light::{scene_center, scene_radius, SpotFalloff};
use crate::math::{Bounds3, Mat4, Transform, UVec2};
use crate::sampling::chi2::{suite_seed, Chi2Test, RectGrid, SphereGrid, SIGNIFICANCE};
use crate::sampling::Pcg32;
use crate::shape::{BilinearMesh, BilinearPatch, Cylinder, Disk, Shape, Sphere, SphereClip, Triangle, TriangleMesh};
use crate::texture::FloatTexture;

fn bounds() -> Bounds3 {
    Bounds3 {
        min: Vec3::new(-1.0, -2.0, 0.0),
        max: Vec3::new(3.0, 1.0, 2.0),
    }
}

fn area(shape: Shape, two_sided: bool, alpha: Option<f32>) -> Light {
    Light::DiffuseArea(DiffuseAreaLight {
        shape,
        radiance: Rgb::new(1.0, 2.0, 0.5),
        two_sided,
        alpha: alpha.map(FloatTexture::Constant),
    })
}

fn triangle() -> Shape {
    let mesh = Arc::new(TriangleMesh {
        positions: vec![
            Vec3::new(-1.0, 1.0, -0.5),
            Vec3::new(1.5, 1.2, -0.5),
            Vec3::new(0.0, 0.8, 1.0),
        ],
        indices: vec![0, 1, 2],
        ..Default::default()
    });
    Shape::Triangle(Triangle::new(mesh, 0))
}

fn saddle() -> Shape {
    let mesh = BilinearMesh {
        positions: vec![
            Vec3::new(-1.0, -0.8, 1.0),
            Vec3::new(1.2, -1.0, 1.8),
            Vec3::new(-0.9, 1.1, 1.6),
            Vec3::new(1.0, 0.9, 0.7),
        ],
        indices: vec![0, 1, 2, 3],
        ..Default::default()
    };
    Shape::Bilinear(BilinearPatch::new(Arc::new(mesh), 0))
}

fn transform(m: Mat4) -> Transform {
    Transform::new(m).unwrap()
}

/// Every kind of light, prepared for the scene `bounds()`, with a label and the fraction of
/// its nominal power it emits (the alpha of a cut-out).
fn all_lights() -> Vec<(Light, &'static str, f32)> {
    let sphere_m = Mat4::from_translation(Vec3::new(0.0, 0.0, 2.0)) * Mat4::from_scale(Vec3::splat(0.7));
    let clip = SphereClip {
        z_min: -0.3,
        z_max: 0.8,
        phi_max: 250f32.to_radians(),
    };
    let disk_m = Mat4::from_translation(Vec3::new(0.2, 0.1, 1.0)) * Mat4::from_rotation_y(0.4);
    let spot_m = Mat4::from_translation(Vec3::new(0.5, 0.5, 1.0)) * Mat4::from_rotation_x(0.7);
    let cylinder_m = Mat4::from_translation(Vec3::new(1.0, -0.5, 1.0))
        * Mat4::from_rotation_y(0.5)
        * Mat4::from_scale(Vec3::new(1.2, 0.7, 1.0));
    let mut lights = vec![
        (area(triangle(), false, None), "triangle", 1.0),
        (area(triangle(), true, None), "two-sided triangle", 1.0),
        (area(triangle(), false, Some(0.5)), "alpha 0.5 triangle", 0.5),
        (
            area(Shape::Sphere(Sphere::new(1.0, transform(sphere_m), false)), false, None),
            "sphere",
            1.0,
        ),
        (
            area(
                Shape::Sphere(Sphere::partial(1.0, clip, transform(sphere_m), false)),
                true,
                None,
            ),
            "two-sided partial sphere",
            1.0,
        ),
        (
            area(
                Shape::Disk(Disk::new(0.1, 1.2, 0.4, 1.25 * PI, transform(disk_m), false)),
                false,
                None,
            ),
            "annulus sector",
            1.0,
        ),
        (
            area(
                Shape::Cylinder(Cylinder::new(0.6, -0.4, 0.7, 1.5 * PI, transform(cylinder_m), false)),
                false,
                None,
            ),
            "elliptic cut cylinder",
            1.0,
        ),
        (area(saddle(), false, None), "bilinear patch", 1.0),
        (area(saddle(), true, None), "two-sided bilinear patch", 1.0),
        (
            Light::Point(PointLight {
                position: Vec3::new(0.3, 0.2, 0.1),
                intensity: Rgb::new(3.0, 2.0, 1.0),
            }),
            "point",
            1.0,
        ),
        (
            Light::Spot(SpotLight {
                world_from_light: transform(spot_m),
                intensity: Rgb::splat(4.0),
                cos_falloff_start: 30f32.to_radians().cos(),
                cos_falloff_end: 45f32.to_radians().cos(),
                falloff: SpotFalloff::SmoothCosine,
                projection: None,
            }),
            "spot",
            1.0,
        ),
        (
            Light::Spot(SpotLight {
                world_from_light: transform(spot_m),
                intensity: Rgb::splat(4.0),
                cos_falloff_start: 30f32.to_radians().cos(),
                cos_falloff_end: 45f32.to_radians().cos(),
                falloff: SpotFalloff::LinearAngle,
                projection: None,
            }),
            "spot, linear in angle",
            1.0,
        ),
        (
            Light::Distant(DistantLight {
                direction: Vec3::new(0.3, -0.4, 1.0).normalize(),
                radiance: Rgb::splat(2.0),
                scene_radius: 0.0,
                scene_center: Vec3::ZERO,
            }),
            "distant",
            1.0,
        ),
        (
            Light::UniformInfinite(UniformInfiniteLight {
                radiance: Rgb::splat(0.5),
                scene_radius: 0.0,
                scene_center: Vec3::ZERO,
            }),
            "uniform infinite",
            1.0,
        ),
        (env_light(), "image infinite", 1.0),
    ];
    for (l, _, _) in &mut lights {
        l.preprocess(&bounds());
    }
    lights
}

/// An 8 x 8 equal-area environment with a bright spot and a dark pixel, rotated.
fn env_light() -> Light {
    let (w, h) = (8, 8);
    let mut px = vec![Rgb::new(0.5, 0.4, 0.3); (w * h) as usize];
    px[(2 * w + 5) as usize] = Rgb::new(40.0, 30.0, 20.0);
    px[(6 * w + 1) as usize] = Rgb::BLACK;
    Light::ImageInfinite(ImageInfiniteLight::new(
        w,
        h,
        &px,
        1.5,
        crate::light::EnvMapping::EqualArea,
        &transform(Mat4::from_rotation_x(0.6)),
    ))
}

/// Relative disagreement between a sample's pdfs and `pdf_le` above which the sample counts
/// as disagreeing.
const PDF_DISAGREEMENT: f32 = 2e-3;

/// Power estimated from `n` emission samples, with its standard error, and how many samples'
/// pdfs disagree with `pdf_le` at the sample by more than [`PDF_DISAGREEMENT`]. A few may,
/// through rounding on a texel's edge (a sample at the border of two pixels of an
/// environment map); a wrong `pdf_le` disagrees on a large share.
fn estimate_power(light: &Light, n: u32, seed: u64) -> (f64, f64, u32) {
    let mut rng = Pcg32::new(seed, 7);
    let (mut sum, mut sum2) = (0.0f64, 0.0f64);
    let mut disagreeing = 0u32;
    for _ in 0..n {
        let u_pos = Vec2::new(rng.next_f32(), rng.next_f32());
        let u_dir = Vec2::new(rng.next_f32(), rng.next_f32());
        let Some(s) = light.sample_le(u_pos, u_dir) else {
            continue;
        };
        let cos = if s.intr.n == Vec3::ZERO {
            1.0
        } else {
            s.intr.n.dot(s.ray.d).abs()
        };
        let x = f64::from(s.le.average() * cos / (s.pdf_pos * s.pdf_dir));
        sum += x;
        sum2 += x * x;
        // The densities `pdf_le` reports where the sample starts (0 for delta parts).
        let (pp, pd) = light.pdf_le(&Ray::new(s.intr.p, s.ray.d), s.intr.n);
        let rel = |a: f32, b: f32| if b == 0.0 { 0.0 } else { (a - b).abs() / b };
        let delta_pos = matches!(light, Light::Point(_) | Light::Spot(_));
        let delta_dir = matches!(light, Light::Distant(_));
        let worst = f32::max(
            if delta_pos { 0.0 } else { rel(pp, s.pdf_pos) },
            if delta_dir { 0.0 } else { rel(pd, s.pdf_dir) },
        );
        disagreeing += u32::from(worst.is_nan() || worst > PDF_DISAGREEMENT);
    }
    let mean = sum / f64::from(n);
    let var = (sum2 / f64::from(n) - mean * mean).max(0.0);
    (mean, (var / f64::from(n)).sqrt(), disagreeing)
}

/// `E[Le |cos| / (pdf_pos pdf_dir)]` is the light's power (pi A L for an area light, twice
/// that two-sided, times alpha for a cut-out; 4 pi I for a point light; pbrt-v4's
/// scene-sized powers for distant and infinite lights), within 4 standard errors.
#[test]
fn emitted_power_estimated_by_sampling_is_the_analytic_power() {
    for (i, (light, label, fraction)) in all_lights().iter().enumerate() {
        let n = 200_000;
        let (mean, se, disagreeing) = estimate_power(light, n, suite_seed() + i as u64);
        let expected = f64::from(light.power().average() * fraction);
        let tol = 4.0 * se + 1e-4 * expected;
        assert!(
            (mean - expected).abs() <= tol,
            "{label}: estimated power {mean} +- {se}, analytic {expected}"
        );
        assert!(
            disagreeing <= n / 10_000,
            "{label}: {disagreeing} of {n} samples' pdfs disagree with pdf_le by more than {PDF_DISAGREEMENT}"
        );
    }
}

/// The estimate can fail: a light that emitted half its power would be caught.
#[test]
fn power_check_can_fail() {
    let light = area(triangle(), false, Some(0.5));
    let (mean, se, _) = estimate_power(&light, 200_000, suite_seed());
    let full = f64::from(light.power().average());
    assert!((mean - full).abs() > 10.0 * se);
}

/// Emitted directions against `pdf_le`'s direction density: for flat emitters (one normal)
/// and for the point, spot and infinite lights, whose directions do not depend on the
/// origin.
#[test]
fn emitted_directions_match_pdf_dir() {
    let lights: Vec<_> = all_lights()
        .into_iter()
        .filter(|(l, label, _)| {
            !label.contains("alpha")
                && !matches!(l, Light::Distant(_))
                && !matches!(l, Light::DiffuseArea(a) if !matches!(a.shape, Shape::Triangle(_) | Shape::Disk(_)))
        })
        .collect();
    let count = lights.len() as u32;
    for (light, label, _) in &lights {
        // Any point of a flat emitter has the same normal.
        let probe = light.sample_le(Vec2::splat(0.3), Vec2::splat(0.4)).unwrap().intr;
        let report = Chi2Test::new(300_000, suite_seed()).with_test_count(count).sphere(
            SphereGrid {
                cos_theta_bins: 20,
                phi_bins: 40,
            },
            |u, rng| {
                let u_pos = Vec2::new(rng.next_f32(), rng.next_f32());
                light.sample_le(u_pos, u).map(|s| s.ray.d)
            },
            |w| light.pdf_le(&Ray::new(probe.p, w), probe.n).1,
        );
        assert!(report.passes(SIGNIFICANCE), "{label}: {report}");
    }
}

/// A wrong direction density is rejected: cosine-weighted sampling is not uniform.
#[test]
fn direction_check_can_fail() {
    let light = area(triangle(), false, None);
    let probe = light.sample_le(Vec2::splat(0.3), Vec2::splat(0.4)).unwrap().intr;
    let report = Chi2Test::new(300_000, suite_seed()).sphere(
        SphereGrid::default(),
        |u, _| light.sample_le(Vec2::splat(0.5), u).map(|s| s.ray.d),
        |w| {
            if w.dot(probe.n) > 0.0 {
                0.5 / PI
            } else {
                0.0
            }
        },
    );
    report.assert_rejects(SIGNIFICANCE);
}

/// Distant and infinite lights start their rays on the disk that covers the scene,
/// perpendicular to the ray, uniformly (`pdf_pos = 1 / pi r^2`), outside the scene's
/// bounding sphere.
#[test]
fn scene_disk_positions_are_uniform() {
    let lights: Vec<_> = all_lights()
        .into_iter()
        .filter(|(l, _, _)| matches!(l, Light::Distant(_) | Light::UniformInfinite(_)))
        .collect();
    let r = scene_radius(&bounds());
    let c = scene_center(&bounds());
    for (light, label, _) in &lights {
        let d = light.sample_le(Vec2::splat(0.5), Vec2::splat(0.25)).unwrap().ray.d;
        let frame = Frame::from_z(d);
        let report = Chi2Test::new(200_000, suite_seed()).with_test_count(2).rect(
            RectGrid {
                min: Vec2::splat(-r),
                max: Vec2::splat(r),
                bins: UVec2::splat(16),
            },
            |u, _| {
                let s = light.sample_le(u, Vec2::splat(0.25))?;
                assert!(
                    (s.ray.o - c).length() >= r * 0.999,
                    "{label}: ray starts inside the scene"
                );
                assert!(((s.ray.o + s.ray.d * r) - s.intr.p).length() < 1e-3 * r);
                let local = frame.to_local(s.intr.p - c);
                assert!(local.z.abs() < 1e-4 * r);
                Some(Vec2::new(local.x, local.y))
            },
            |p| {
                if p.length() <= r {
                    light.pdf_le(&Ray::new(c, d), Vec3::ZERO).0
                } else {
                    0.0
                }
            },
        );
        assert!(report.passes(SIGNIFICANCE), "{label}: {report}");
    }
}

/// Area lights choose points uniformly by area: `pdf_pos` is `1 / A` (for shapes sampled
/// exactly uniformly).
#[test]
fn area_light_positions_have_density_one_over_area() {
    for (light, label, _) in all_lights() {
        let Light::DiffuseArea(a) = &light else { continue };
        if matches!(a.shape, Shape::Bilinear(_) | Shape::Cylinder(_)) {
            // A curved patch and an elliptic cylinder are not sampled uniformly; their pdfs
            // are checked above (and the cylinder's in shape/cylinder_tests.rs).
            continue;
        }
        let s = light.sample_le(Vec2::new(0.2, 0.7), Vec2::new(0.6, 0.1)).unwrap();
        let expected = 1.0 / a.shape.area();
        assert!(
            (s.pdf_pos - expected).abs() < 1e-4 * expected,
            "{label}: {} vs {expected}",
            s.pdf_pos
        );
    }
}

/// One-sided area lights emit only along their normal; two-sided ones on both sides,
/// half of the samples each.
#[test]
fn area_light_sides() {
    let one = area(triangle(), false, None);
    let two = area(triangle(), true, None);
    let mut rng = Pcg32::new(suite_seed(), 3);
    let mut back = 0;
    for _ in 0..10_000 {
        let u = [rng.next_f32(), rng.next_f32(), rng.next_f32(), rng.next_f32()];
        let s = one.sample_le(Vec2::new(u[0], u[1]), Vec2::new(u[2], u[3])).unwrap();
        assert!(s.ray.d.dot(s.intr.n) > 0.0);
        let s = two.sample_le(Vec2::new(u[0], u[1]), Vec2::new(u[2], u[3])).unwrap();
        back += usize::from(s.ray.d.dot(s.intr.n) < 0.0);
    }
    assert!((4700..5300).contains(&back), "{back} of 10000 on the back");
}
