//! Analytic scenes whose radiance is known in closed form. Each render's mean must agree
//! with the closed form within 4 standard errors estimated from the render's own samples.

mod common;

use common::*;
use mcrender_core::color::Rgb;
use mcrender_core::math::PI;

/// A diffuse sphere of albedo 0.5 and radius 1 seen from inside, lit by a point light of
/// intensity pi at its centre: direct radiance is (a/pi)(I/r^2) = 0.5, and the
/// interreflections inside a sphere add a geometric series, L = 0.5 / (1 - 0.5) = 1.
#[test]
fn sphere_lit_from_its_centre_has_radiance_one() {
    let mut d = point_lit_sphere(PI);
    d.integrator.max_depth = u32::MAX;
    d.sampler.samples_per_pixel = 2048;
    assert_mean_radiance(&d, Rgb::splat(1.0));
}

/// A closed sphere emitting Le inwards with albedo a: every point sees radiance L from
/// everywhere, so L = Le + a L, L = Le / (1 - a). Unbounded depth: only Russian roulette
/// ends paths, and the result stays unbiased.
#[test]
fn closed_emissive_sphere_has_radiance_le_over_one_minus_albedo() {
    let le = Rgb::new(1.0, 2.0, 0.5);
    let a = Rgb::new(0.5, 0.25, 0.75);
    let d0 = emissive_sphere(2.0, a, le);
    let mut d = d0.clone();
    d.integrator.max_depth = u32::MAX;
    d.sampler.samples_per_pixel = 2048;
    let expected = Rgb::new(le.r / (1.0 - a.r), le.g / (1.0 - a.g), le.b / (1.0 - a.b));
    assert_mean_radiance(&d, expected);
    // Depth 0 sees the emission only; the outward-facing normal would see nothing.
    let mut d = d0.clone();
    d.integrator.max_depth = 0;
    d.sampler.samples_per_pixel = 4;
    assert_mean_radiance(&d, le);
    let mut d = d0;
    d.shapes[0].flip_normals = false;
    d.integrator.max_depth = 0;
    d.sampler.samples_per_pixel = 4;
    assert_mean_radiance(&d, Rgb::BLACK);
}

/// A receiver inside a closed sphere emitting L (a uniform sky, black otherwise): the
/// irradiance is pi L, so a diffuse receiver of albedo rho has radiance rho L.
#[test]
fn irradiance_under_uniform_sky_is_pi_l() {
    let l = 1.5;
    let rho = 0.8;
    let (mut d, expected) = receiver_under_sky(l, rho);
    d.sampler.samples_per_pixel = 4096;
    assert_mean_radiance(&d, expected);
}

/// A square emitter of side 2s at height h, centred above the receiver and facing it.
/// The view factor from a point below the corner of an a x b rectangle at distance c is
/// F = 1/(2 pi) [X/sqrt(1+X^2) atan(Y/sqrt(1+X^2)) + Y/sqrt(1+Y^2) atan(X/sqrt(1+Y^2))],
/// X = a/c, Y = b/c; the centred square is four such corners, and E = pi L F.
#[test]
fn irradiance_under_a_square_light_matches_the_view_factor() {
    let (mut d, expected) = receiver_under_square_light(0.5, 1.0, 3.0, 0.7);
    d.sampler.samples_per_pixel = 4096;
    assert_mean_radiance(&d, expected);
}

/// A sphere light of radius R at distance d above the receiver: E = pi L (R/d)^2.
#[test]
fn irradiance_under_a_sphere_light_matches_the_closed_form() {
    let (mut d, expected) = receiver_under_sphere_light(0.3, 1.2, 2.0, 0.9);
    d.sampler.samples_per_pixel = 4096;
    assert_mean_radiance(&d, expected);
}

/// An open cylinder light of radius R around the receiver's axis, from height a to b,
/// emitting inwards: E = pi L (R^2 / (R^2 + a^2) - R^2 / (R^2 + b^2)).
#[test]
fn irradiance_inside_a_cylinder_light_matches_the_closed_form() {
    let (mut d, expected) = receiver_inside_cylinder_light(0.5, 0.3, 1.4, 2.0, 0.8);
    d.sampler.samples_per_pixel = 4096;
    assert_mean_radiance(&d, expected);
}

/// A closed can (cylinder wall and two disk lids) emitting Le inwards with albedo a, seen
/// from its centre: L = Le / (1 - a) at unbounded depth, by paths that bounce between the
/// curved wall and the lids with light sampling on both.
#[test]
fn closed_emissive_can_has_radiance_le_over_one_minus_albedo() {
    let le = Rgb::new(1.0, 2.0, 0.5);
    let a = Rgb::new(0.5, 0.25, 0.75);
    let mut d = emissive_can(1.0, 1.5, a, le);
    d.integrator.max_depth = u32::MAX;
    d.sampler.samples_per_pixel = 1024;
    let expected = Rgb::new(le.r / (1.0 - a.r), le.g / (1.0 - a.g), le.b / (1.0 - a.b));
    assert_mean_radiance(&d, expected);
}

/// A disk light of radius R at height h on the receiver's axis, facing down:
/// E = pi L R^2 / (R^2 + h^2).
#[test]
fn irradiance_under_a_disk_light_matches_the_closed_form() {
    let (mut d, expected) = receiver_under_disk_light(0.6, 0.9, 2.5, 0.8);
    d.sampler.samples_per_pixel = 4096;
    assert_mean_radiance(&d, expected);
}
