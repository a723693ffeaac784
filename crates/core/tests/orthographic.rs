//! The orthographic camera under path tracing, light tracing and BDPT against closed
//! forms: the camera inside a closed diffuse sphere whose radiance is the same at every
//! point and in every direction (a point light at the centre, or the sphere itself
//! emitting), seen through a window 1 wide. Each integrator's image mean must match within
//! 4 standard errors, pinhole and thin lens; the light tracer and BDPT's `t = 1` strategy
//! exercise the camera's importance (`sample_wi`), BDPT's MIS its densities.

mod common;

use common::direct_loops::{bdpt_mean, light_trace};
use common::*;
use mcrender_core::color::Rgb;
use mcrender_core::math::{Mat4, Transform, Vec3, PI};
use mcrender_core::scene::{BdptDesc, Projection, SceneDescription};

/// Light tracing's image mean and its standard error.
fn light_traced(d: &SceneDescription) -> ([f64; 3], [f64; 3]) {
    let (_, mean, se) = light_trace(d);
    (mean, se)
}

/// Make the camera (at the centre of the scenes' sphere) orthographic, looking down a
/// turned axis through a window 1 wide, optionally through a lens of `lens_radius`
/// focused at distance 0.8.
fn orthographic_view(d: &mut SceneDescription, lens_radius: f32) {
    let camera_from_world = Mat4::look_at_lh(Vec3::ZERO, Vec3::new(0.3, -0.2, 1.0), Vec3::Y);
    d.camera.world_from_camera = Transform::new(camera_from_world).unwrap().inverse();
    d.camera.projection = Projection::Orthographic;
    d.camera.screen_window = Some([-0.5, 0.5, -0.5, 0.5]);
    d.camera.lens_radius = lens_radius;
    d.camera.focal_distance = 0.8;
}

fn check_all(label: &str, mut d: SceneDescription, expected: Rgb, spp: [u32; 3]) {
    for lens in [0.0, 0.1] {
        orthographic_view(&mut d, lens);
        d.sampler.samples_per_pixel = spp[0];
        let out = render_desc(&d);
        assert_eq!(out.stats.nonfinite_samples, 0);
        assert_close(
            &format!("{label}, lens {lens}, path"),
            mean_and_standard_error(&out),
            expected,
        );
        d.sampler.samples_per_pixel = spp[1];
        assert_close(
            &format!("{label}, lens {lens}, light tracing"),
            light_traced(&d),
            expected,
        );
        d.sampler.samples_per_pixel = spp[2];
        assert_close(
            &format!("{label}, lens {lens}, BDPT"),
            bdpt_mean(&d, BdptDesc::default()),
            expected,
        );
    }
}

/// A diffuse sphere of albedo 1/2 and radius 1 lit by a point light of intensity pi at
/// its centre, on the window plane (see `point_lit_sphere`): up to depth 3, L = 7/8
/// wherever the camera looks; the light is a delta and the camera (pinhole) a delta in
/// direction, so light tracing connects every vertex along the axis.
#[test]
fn point_lit_sphere_seen_orthographically() {
    let mut d = point_lit_sphere(PI);
    d.integrator.max_depth = 3;
    check_all("point-lit sphere", d, Rgb::splat(0.875), [64, 16384, 64]);
}

/// A closed sphere of radius 2 emitting Le inwards with albedo a: up to depth 2,
/// L = Le (1 + a + a^2); the emission reaches the camera through the light tracer's
/// connection of the light's own points.
#[test]
fn emissive_sphere_seen_orthographically() {
    let le = Rgb::new(1.0, 2.0, 0.5);
    let a = Rgb::new(0.5, 0.25, 0.75);
    let mut d = emissive_sphere(2.0, a, le);
    d.integrator.max_depth = 2;
    let expected = Rgb::new(
        le.r * (1.0 + a.r + a.r * a.r),
        le.g * (1.0 + a.g + a.g * a.g),
        le.b * (1.0 + a.b + a.b * a.b),
    );
    check_all("emissive sphere", d, expected, [64, 16384, 64]);
}

/// The tests can fail: light tracing against a value 3% off is rejected.
#[test]
#[should_panic(expected = "closed form")]
fn a_wrong_expectation_is_rejected() {
    let mut d = point_lit_sphere(PI);
    d.integrator.max_depth = 3;
    orthographic_view(&mut d, 0.0);
    d.sampler.samples_per_pixel = 16384;
    assert_close("light tracing, 3% off", light_traced(&d), Rgb::splat(0.875 * 1.03));
}
