//! Tests of the camera's importance: raster positions invert `generate_ray`, `We` is
//! normalised over the film (and the lens), `pdf_we` is the density of uniformly generated
//! camera rays, and `sample_wi` finds the ray `generate_ray` would trace.

use super::*;
use crate::camera::CameraDesc;
use crate::film::FilmDesc;
use crate::math::{Mat4, Transform};
use crate::sampling::chi2::{suite_seed, Chi2Test, SphereGrid, SIGNIFICANCE};
use crate::sampling::{sample_uniform_sphere, uniform_sphere_pdf, Pcg32};

/// A wide, turned and moved camera (`lens_radius` 0 for a pinhole) whose film's sample
/// bounds are its pixel bounds (a filter of radius 1/2).
fn camera(lens_radius: f32) -> PerspectiveCamera {
    camera_with_filter(lens_radius, 0.5)
}

/// The same camera with a pixel filter of radius `filter_radius`.
fn camera_with_filter(lens_radius: f32, filter_radius: f32) -> PerspectiveCamera {
    let m =
        Mat4::from_translation(Vec3::new(1.0, -2.0, 0.5)) * Mat4::from_rotation_y(0.7) * Mat4::from_rotation_x(-0.3);
    PerspectiveCamera::new(
        &CameraDesc {
            world_from_camera: Transform::new(m).unwrap(),
            fov_degrees: 50.0,
            lens_radius,
            focal_distance: 4.0,
            screen_window: None,
            ..CameraDesc::default()
        },
        &FilmDesc { width: 48, height: 32 },
        Vec2::splat(filter_radius),
    )
}

fn rng_2d(rng: &mut Pcg32) -> Vec2 {
    Vec2::new(rng.next_f32(), rng.next_f32())
}

#[test]
fn raster_position_inverts_generate_ray() {
    let mut rng = Pcg32::new(suite_seed(), 1);
    for lens in [0.0, 0.3] {
        let cam = camera(lens);
        for _ in 0..2000 {
            let p = rng_2d(&mut rng) * Vec2::new(48.0, 32.0);
            let ray = cam.generate_ray(p, rng_2d(&mut rng));
            let (q, cos) = cam.raster_position(&ray).expect("a generated ray lands on the film");
            assert!((q - p).length() < 2e-3, "lens {lens}: {p} came back as {q}");
            assert!((cos - ray.d.dot(cam.forward())).abs() < 1e-5);
        }
        // Backwards and far off-axis rays miss the film.
        let o = cam.generate_ray(Vec2::new(24.0, 16.0), Vec2::splat(0.5)).o;
        assert!(cam.we(&Ray::new(o, -cam.forward())).is_none());
        let side = cam.world_from_camera.vector(Vec3::new(1.0, 0.0, 0.1)).normalize();
        assert!(cam.we(&Ray::new(o, side)).is_none());
    }
}

/// The importance reaches the film's sample bounds: with a filter of radius 1.5, a ray
/// through raster x = -0.9 (within a radius of pixel 0's centre) sees the camera, one
/// through x = -1.1 does not; with radius 1/2 the pixel bounds are the limit.
#[test]
fn importance_covers_the_sample_bounds() {
    let wide = camera_with_filter(0.0, 1.5);
    let narrow = camera(0.0);
    assert_eq!(wide.sample_bounds(), [Vec2::splat(-1.0), Vec2::new(49.0, 33.0)]);
    let ray = |p: Vec2| wide.generate_ray(p, Vec2::splat(0.5));
    for (p, inside_wide, inside_narrow) in [
        (Vec2::new(-0.9, 5.0), true, false),
        (Vec2::new(-1.1, 5.0), false, false),
        (Vec2::new(20.0, 32.9), true, false),
        (Vec2::new(48.5, 33.1), false, false),
        (Vec2::new(0.1, 0.1), true, true),
    ] {
        assert_eq!(wide.we(&ray(p)).is_some(), inside_wide, "{p}");
        assert_eq!(narrow.we(&ray(p)).is_some(), inside_narrow, "{p}");
        assert_eq!(wide.pdf_we(&ray(p)).1 > 0.0, inside_wide, "{p}");
        if let Some((_, q)) = wide.we(&ray(p)) {
            assert!((q - p).length() < 1e-3, "{p} came back as {q}");
        }
    }
}

/// `integral We cos dw = 1` over the directions from the lens centre (pinhole), and
/// `integral integral We cos dw dA_lens = 1` with a lens: uniform directions on the sphere
/// (and uniform lens points), within 4 standard errors. Over the sample bounds of a wider
/// filter the integrals are the ratio of the sample bounds' area to the pixel bounds'.
#[test]
fn importance_is_normalised() {
    for (lens, radius) in [(0.0, 0.5), (0.3, 0.5), (0.0, 1.5), (0.3, 2.0)] {
        let cam = camera_with_filter(lens, radius);
        let grow = 2.0 * (radius - 0.5);
        let area_ratio = f64::from((48.0 + grow) * (32.0 + grow) / (48.0 * 32.0));
        let mut rng = Pcg32::new(suite_seed(), 2);
        let n = 400_000;
        let (mut sum, mut sum2, mut pdf_sum) = (0.0f64, 0.0f64, 0.0f64);
        for _ in 0..n {
            let pl = cam.lens_radius * sample_uniform_disk_concentric(rng_2d(&mut rng));
            let o = cam.world_from_camera.point(Vec3::new(pl.x, pl.y, 0.0));
            let w = sample_uniform_sphere(rng_2d(&mut rng));
            let ray = Ray::new(o, w);
            let Some((we, _)) = cam.we(&ray) else { continue };
            // Uniform lens point (density 1 / A_lens; 1 for the pinhole's convention).
            let x = f64::from(we * w.dot(cam.forward()) * cam.lens_area() / uniform_sphere_pdf());
            sum += x;
            sum2 += x * x;
            pdf_sum += f64::from(cam.pdf_we(&ray).1 / uniform_sphere_pdf());
        }
        let mean = sum / f64::from(n);
        let se = ((sum2 / f64::from(n) - mean * mean) / f64::from(n)).sqrt();
        assert!(
            (mean - area_ratio).abs() < 4.0 * se,
            "lens {lens}, radius {radius}: integral of We cos = {mean} +- {se}, expected {area_ratio}"
        );
        // pdf_dir is a density over the pixel bounds' directions.
        let pdf_integral = pdf_sum / f64::from(n);
        assert!(
            (pdf_integral - area_ratio).abs() < 0.02,
            "lens {lens}, radius {radius}: pdf_dir integrates to {pdf_integral}, expected {area_ratio}"
        );
    }
}

/// Camera rays through uniformly chosen film points have the direction density `pdf_we`.
#[test]
fn pdf_we_is_the_density_of_generated_rays() {
    let cam = camera(0.0);
    let report = Chi2Test::new(300_000, suite_seed()).sphere(
        SphereGrid {
            cos_theta_bins: 40,
            phi_bins: 80,
        },
        |u, _| Some(cam.generate_ray(u * Vec2::new(48.0, 32.0), Vec2::ZERO).d),
        |w| cam.pdf_we(&Ray::new(cam.world_from_camera.point(Vec3::ZERO), w)).1,
    );
    assert!(report.passes(SIGNIFICANCE), "{report}");
}

/// `sample_wi` picks a lens point and returns the raster position from which
/// `generate_ray` (with the same lens sample) traces the ray from that lens point through
/// the reference point; its density is the lens's area density turned into solid angle.
#[test]
fn sample_wi_finds_the_camera_ray_through_the_point() {
    let mut rng = Pcg32::new(suite_seed(), 3);
    for lens in [0.0, 0.3] {
        let cam = camera(lens);
        let mut found = 0;
        for _ in 0..2000 {
            // A point in front of the camera, possibly off the film.
            let p = cam.generate_ray(
                rng_2d(&mut rng) * Vec2::new(60.0, 40.0) - Vec2::new(6.0, 4.0),
                Vec2::splat(0.5),
            );
            let p_ref = p.at(0.5 + 6.0 * rng.next_f32());
            let u = rng_2d(&mut rng);
            let Some(s) = cam.sample_wi(p_ref, u) else { continue };
            found += 1;
            let ray = cam.generate_ray(s.p_raster, u);
            assert!((ray.o - s.p_lens).length() < 1e-4, "lens {lens}: origin");
            assert!(
                (ray.d + s.wi).length() < 2e-3,
                "lens {lens}: direction {} vs {}",
                ray.d,
                -s.wi
            );
            let d2 = (s.p_lens - p_ref).length_squared();
            let expected = d2 / (s.wi.dot(s.n_lens).abs() * cam.lens_area());
            assert!((s.pdf - expected).abs() < 1e-4 * expected);
            let (we, _) = cam.we(&ray).unwrap();
            assert!((s.we - we).abs() < 1e-3 * we);
        }
        assert!(found > 1000, "lens {lens}: only {found} points seen");
    }
}
