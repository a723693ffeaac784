//! Tests of the orthographic camera: rays leave the window along the axis, thin-lens rays
//! meet on the plane of focus, differentials are the window's pixel step, the importance
//! inverts `generate_ray`, and `We` is normalised.

use super::*;
use crate::camera::CameraDesc;
use crate::camera::Projection;
use crate::sampling::chi2::suite_seed;
use crate::sampling::{sample_uniform_sphere, uniform_sphere_pdf, Pcg32};

const W: u32 = 40;
const H: u32 = 20;

/// A turned and moved camera with window `[-2, 2] x [-1, 1]` scaled by `scale` (as
/// Mitsuba's `to_world` does).
fn camera(lens_radius: f32, scale: f32) -> OrthographicCamera {
    let m = Mat4::from_translation(Vec3::new(1.0, -2.0, 0.5))
        * Mat4::from_rotation_y(0.7)
        * Mat4::from_rotation_x(-0.3)
        * Mat4::from_scale(Vec3::new(scale, scale, 1.0));
    OrthographicCamera::new(
        &CameraDesc {
            projection: Projection::Orthographic,
            world_from_camera: Transform::new(m).unwrap(),
            lens_radius,
            focal_distance: 3.0,
            ..CameraDesc::default()
        },
        &FilmDesc { width: W, height: H },
        Vec2::splat(0.5),
    )
}

fn rng_2d(rng: &mut Pcg32) -> Vec2 {
    Vec2::new(rng.next_f32(), rng.next_f32())
}

#[test]
fn rays_leave_the_window_along_the_axis() {
    let cam = camera(0.0, 0.5);
    let r = cam.world_from_camera;
    let axis = r.vector(Vec3::Z);
    // The window is [-2, 2] x [-1, 1] at scale 1/2: [-1, 1] x [-0.5, 0.5] in world units.
    assert!((cam.film_area() - 2.0).abs() < 1e-5, "{}", cam.film_area());
    for (p, expected) in [
        (Vec2::ZERO, Vec3::new(-1.0, 0.5, 0.0)),
        (Vec2::new(W as f32, H as f32), Vec3::new(1.0, -0.5, 0.0)),
        (Vec2::new(W as f32 / 2.0, H as f32 / 2.0), Vec3::ZERO),
        (Vec2::new(W as f32 / 4.0, 0.0), Vec3::new(-0.5, 0.5, 0.0)),
    ] {
        let ray = cam.generate_ray(p, Vec2::splat(0.3));
        assert!((ray.d - axis).length() < 1e-5, "{p}: direction {}", ray.d);
        assert!((ray.o - r.point(expected)).length() < 1e-5, "{p}: origin {}", ray.o);
    }
}

#[test]
fn thin_lens_rays_meet_on_the_focal_plane_above_their_window_point() {
    let cam = camera(0.2, 1.0);
    let mut rng = Pcg32::new(suite_seed(), 11);
    for _ in 0..100 {
        let p = rng_2d(&mut rng) * Vec2::new(W as f32, H as f32);
        let pinhole = camera(0.0, 1.0).generate_ray(p, Vec2::ZERO);
        let a = cam.generate_ray(p, rng_2d(&mut rng));
        // The origin is within the lens radius of the window point, on the window plane.
        assert!((a.o - pinhole.o).length() <= 0.2 + 1e-5);
        assert!((a.o - pinhole.o).dot(pinhole.d).abs() < 1e-5);
        let focus = pinhole.at(3.0);
        let t = (focus - a.o).dot(pinhole.d) / a.d.dot(pinhole.d);
        assert!((a.at(t) - focus).length() < 1e-4, "{p}");
    }
}

/// The footprint of a pixel step on a surface facing the camera is the window's pixel
/// step (times pbrt's spp scale), and on a tilted plane it is that step carried along the
/// axis onto the plane.
#[test]
fn differentials_are_the_window_pixel_step_on_the_surface() {
    let cam = camera(0.0, 0.5);
    let r = cam.world_from_camera;
    // Pixel step: 2 / 40 = 0.05 in x and 1 / 20 = 0.05 in y (downwards).
    let (dx, dy) = cam.approximate_dp_dxy(r.point(Vec3::new(0.1, 0.1, 2.0)), -r.vector(Vec3::Z), 1);
    assert!((dx - r.vector(Vec3::new(0.05, 0.0, 0.0))).length() < 1e-5, "{dx}");
    assert!((dy - r.vector(Vec3::new(0.0, -0.05, 0.0))).length() < 1e-5, "{dy}");
    // A plane tilted by 45 degrees about camera y: x steps grow by sqrt 2 along the plane.
    let n = r.normal(Vec3::new(1.0, 0.0, -1.0).normalize());
    let (dx, dy) = cam.approximate_dp_dxy(r.point(Vec3::new(0.0, 0.0, 2.0)), n, 64);
    let expected = r.vector(Vec3::new(0.05, 0.0, 0.05)) * 0.125;
    assert!((dx - expected).length() < 1e-5, "{dx} vs {expected}");
    assert!(
        (dy - r.vector(Vec3::new(0.0, -0.05, 0.0)) * 0.125).length() < 1e-5,
        "{dy}"
    );
    // Rays from two neighbouring pixels hit the tilted plane one footprint apart.
    let plane_hit = |ray: Ray| {
        let p0 = r.point(Vec3::new(0.0, 0.0, 2.0));
        ray.at((p0 - ray.o).dot(n) / ray.d.dot(n))
    };
    let a = plane_hit(cam.generate_ray(Vec2::new(20.0, 10.0), Vec2::ZERO));
    let b = plane_hit(cam.generate_ray(Vec2::new(21.0, 10.0), Vec2::ZERO));
    assert!(((b - a) * 0.125 - dx).length() < 1e-5);
}

#[test]
fn raster_position_inverts_generate_ray() {
    let mut rng = Pcg32::new(suite_seed(), 12);
    for (lens, scale) in [(0.0, 1.0), (0.0, 0.5), (0.25, 1.0), (0.25, 2.0)] {
        let cam = camera(lens, scale);
        for _ in 0..1000 {
            let p = rng_2d(&mut rng) * Vec2::new(W as f32, H as f32);
            let ray = cam.generate_ray(p, rng_2d(&mut rng));
            let (q, cos) = cam.raster_position(&ray).expect("a generated ray lands on the film");
            assert!((q - p).length() < 2e-3, "lens {lens}: {p} came back as {q}");
            if lens > 0.0 {
                assert!((cos - ray.d.dot(cam.forward())).abs() < 1e-5);
            }
        }
    }
}

/// `sample_wi` returns the window point and lens sample from which `generate_ray` traces
/// the ray through the reference point, with `We / pdf = 1 / (A cos theta)`.
#[test]
fn sample_wi_finds_the_camera_ray_through_the_point() {
    let mut rng = Pcg32::new(suite_seed(), 13);
    for lens in [0.0, 0.25] {
        let cam = camera(lens, 1.0);
        let mut found = 0;
        for _ in 0..2000 {
            let seed_ray = cam.generate_ray(
                rng_2d(&mut rng) * Vec2::new(48.0, 24.0) - Vec2::new(4.0, 2.0),
                Vec2::splat(0.5),
            );
            let p_ref = seed_ray.at(0.5 + 6.0 * rng.next_f32());
            let u = rng_2d(&mut rng);
            let Some(s) = cam.sample_wi(p_ref, u) else { continue };
            found += 1;
            let ray = cam.generate_ray(s.p_raster, u);
            assert!((ray.o - s.p_lens).length() < 1e-4, "lens {lens}: origin");
            assert!((ray.d + s.wi).length() < 1e-3, "lens {lens}: direction");
            let cos = ray.d.dot(cam.forward());
            let expected = 1.0 / (cam.film_area() * cos);
            assert!(((s.we / s.pdf) / expected - 1.0).abs() < 1e-3, "lens {lens}");
            // BDPT's density of the reference point from the lens point, per unit cosine.
            let pdf = cam.pdf_area_per_cos(s.p_lens, p_ref);
            assert!((pdf / expected - 1.0).abs() < 1e-3, "lens {lens}: {pdf} vs {expected}");
        }
        assert!(found > 1000, "lens {lens}: only {found} points seen");
    }
    // Behind the camera nothing is seen.
    let cam = camera(0.0, 1.0);
    let behind = cam.generate_ray(Vec2::new(20.0, 10.0), Vec2::ZERO).at(-1.0);
    assert!(cam.sample_wi(behind, Vec2::splat(0.5)).is_none());
}

/// With a lens, `integral integral We cos dw dA = 1` over the window plane and the
/// directions (uniform points on a square around the window and uniform directions),
/// within 4 standard errors; `pdf_pos pdf_dir` integrates to 1 too.
#[test]
fn thin_lens_importance_is_normalised() {
    let cam = camera(0.25, 1.0);
    let r = cam.world_from_camera;
    let mut rng = Pcg32::new(suite_seed(), 14);
    let n = 400_000;
    // The origins lie within [-2.25, 2.25] x [-1.25, 1.25].
    let area = 4.5 * 2.5;
    let (mut sum, mut sum2, mut pdf_sum) = (0.0f64, 0.0f64, 0.0f64);
    for _ in 0..n {
        let u = rng_2d(&mut rng);
        let o = r.point(Vec3::new(-2.25 + 4.5 * u.x, -1.25 + 2.5 * u.y, 0.0));
        let w = sample_uniform_sphere(rng_2d(&mut rng));
        let ray = Ray::new(o, w);
        let Some((we, _)) = cam.we(&ray) else { continue };
        let x = f64::from(we * w.dot(cam.forward()) * area / uniform_sphere_pdf());
        sum += x;
        sum2 += x * x;
        let (pos, dir) = cam.pdf_we(&ray);
        pdf_sum += f64::from(pos * dir * area / uniform_sphere_pdf());
    }
    let mean = sum / f64::from(n);
    let se = ((sum2 / f64::from(n) - mean * mean) / f64::from(n)).sqrt();
    assert!((mean - 1.0).abs() < 4.0 * se, "integral of We cos = {mean} +- {se}");
    let pdf_integral = pdf_sum / f64::from(n);
    assert!(
        (pdf_integral - 1.0).abs() < 6.0 * se,
        "pdf integrates to {pdf_integral}"
    );
}
