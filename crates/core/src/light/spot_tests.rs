//! Tests of the spot light's Mitsuba falloff and projected image: the falloff's values, its
//! power against a Monte Carlo estimate of the flux through a plane (the irradiance
//! `I(w) cos / r^2` from `sample_li`, integrated over the plane), and which texel a
//! direction reads.

use std::sync::Arc;

use super::*;
use crate::math::Mat4;
use crate::sampling::Pcg32;
use crate::texture::{BitmapFilter, BitmapTexture, BitmapWrap, Texture, TextureMapping};

/// A spot at the origin pointing along +z, beam 15 degrees, cutoff 25 degrees.
fn mitsuba_spot(projection: Option<RgbTexture>) -> SpotLight {
    SpotLight {
        world_from_light: Transform::new(Mat4::IDENTITY).unwrap(),
        intensity: Rgb::new(3.0, 2.0, 1.0),
        cos_falloff_start: 15f32.to_radians().cos(),
        cos_falloff_end: 25f32.to_radians().cos(),
        falloff: SpotFalloff::LinearAngle,
        projection,
    }
}

/// A `w x h` nearest-neighbour bitmap.
fn bitmap(w: u32, h: u32, texels: Vec<Rgb>) -> RgbTexture {
    Texture::Bitmap(Arc::new(BitmapTexture {
        mapping: TextureMapping::default(),
        width: w,
        height: h,
        texels: Arc::new(texels),
        filter: BitmapFilter::Nearest,
        wrap: BitmapWrap::Clamp,
    }))
}

/// The direction at `deg` degrees from +z towards +x.
fn at_angle(deg: f32) -> Vec3 {
    let a = deg.to_radians();
    Vec3::new(a.sin(), 0.0, a.cos())
}

#[test]
fn linear_falloff_values() {
    let s = mitsuba_spot(None);
    assert_eq!(s.falloff(at_angle(0.0)), 1.0);
    assert_eq!(s.falloff(at_angle(14.9)), 1.0);
    assert!((s.falloff(at_angle(20.0)) - 0.5).abs() < 1e-4);
    assert!((s.falloff(at_angle(17.5)) - 0.75).abs() < 1e-4);
    assert_eq!(s.falloff(at_angle(25.1)), 0.0);
    assert_eq!(s.falloff(-Vec3::Z), 0.0);
    // Equal angles: a hard edge.
    assert_eq!(linear_angle_falloff(0.95, 0.9, 0.9), 1.0);
    assert_eq!(linear_angle_falloff(0.85, 0.9, 0.9), 0.0);
}

/// The flux through the plane z = 1, `int E dA` with `E = I(w) cos theta / r^2` from
/// `sample_li`, estimated from uniform points on the square that holds the cone's
/// footprint: `(mean, standard error)` per channel.
fn flux_through_plane(s: &SpotLight, n: u32, seed: u64) -> ([f64; 3], [f64; 3]) {
    let half = 0.5f32; // tan 25 degrees = 0.466 < 0.5
    let area = f64::from(4.0 * half * half);
    let mut rng = Pcg32::new(seed, 11);
    let (mut sum, mut sum2) = ([0.0f64; 3], [0.0f64; 3]);
    for _ in 0..n {
        let p = Vec3::new(
            half * (2.0 * rng.next_f32() - 1.0),
            half * (2.0 * rng.next_f32() - 1.0),
            1.0,
        );
        let e = match s.sample_li(&Interaction::point(p), Vec2::ZERO) {
            Some(li) => li.l * li.wi.z.abs() * (area as f32),
            None => Rgb::BLACK,
        };
        for c in 0..3 {
            let x = f64::from(e[c]);
            sum[c] += x;
            sum2[c] += x * x;
        }
    }
    let n = f64::from(n);
    let mean = sum.map(|x| x / n);
    let se = [0, 1, 2].map(|c| ((sum2[c] / n - mean[c] * mean[c]).max(0.0) / n).sqrt());
    (mean, se)
}

fn assert_within_4_se(mean: [f64; 3], se: [f64; 3], expected: Rgb, label: &str) {
    for c in 0..3 {
        let e = f64::from(expected[c]);
        assert!(
            (mean[c] - e).abs() <= 4.0 * se[c],
            "{label}, channel {c}: flux {:.6} vs {e:.6}, {:.1} standard errors ({:.2e})",
            mean[c],
            (mean[c] - e).abs() / se[c],
            se[c]
        );
        eprintln!(
            "{label}, channel {c}: flux {:.6}, expected {e:.6}, standard error {:.2e}",
            mean[c], se[c]
        );
    }
}

/// The whole cone crosses the plane, so the flux is the power, `2 pi I (1 - (sin e - sin
/// s) / (e - s))`; a falloff that was smooth in cosine instead would give 3.9% more
/// (about 25 standard errors here).
#[test]
fn flux_through_a_plane_is_the_linear_falloff_power() {
    let s = mitsuba_spot(None);
    let (e, b) = (25f32.to_radians(), 15f32.to_radians());
    let expected = s.intensity * (2.0 * PI * (1.0 - (e.sin() - b.sin()) / (e - b)));
    assert!(
        (s.power().r - expected.r).abs() < 1e-5 * expected.r,
        "{:?} vs {expected:?}",
        s.power()
    );
    let (mean, se) = flux_through_plane(&s, 400_000, 1);
    assert_within_4_se(mean, se, expected, "untextured");
    let smooth = SpotLight {
        falloff: SpotFalloff::SmoothCosine,
        ..s.clone()
    };
    assert!((smooth.power().r / s.power().r - 1.039).abs() < 1e-3);
}

/// An image black on its left half and white on its right lights the half-plane x > 0
/// only: half the power, by symmetry.
#[test]
fn projected_half_image_halves_the_flux() {
    let s = mitsuba_spot(Some(bitmap(2, 1, vec![Rgb::BLACK, Rgb::splat(1.0)])));
    let (mean, se) = flux_through_plane(&s, 400_000, 2);
    assert_within_4_se(mean, se, s.power() * 0.5, "right half lit");
    // Light-space +x reads the right column.
    let right = s.intensity_towards(at_angle(10.0));
    assert_eq!(right, s.intensity);
    assert_eq!(s.intensity_towards(at_angle(-10.0)), Rgb::BLACK);
}

/// Light-space +y reads the image's bottom row (Mitsuba's `v = 1/2 + y / (2 z tan)` runs
/// down the image), and the image's edge lies at the cutoff angle along the axes.
#[test]
fn projection_orientation_and_extent() {
    let top = Rgb::new(1.0, 0.0, 0.0);
    let bottom = Rgb::new(0.0, 1.0, 0.0);
    let s = mitsuba_spot(Some(bitmap(1, 2, vec![top, bottom])));
    let a = 10f32.to_radians();
    let down = Vec3::new(0.0, a.sin(), a.cos());
    let up = Vec3::new(0.0, -a.sin(), a.cos());
    assert_eq!(s.intensity_towards(down), s.intensity * bottom);
    assert_eq!(s.intensity_towards(up), s.intensity * top);
    // A 4 x 1 image: the outer columns start at u = 1/4 and 3/4, i.e. at x / z = -+tan(c) / 2.
    let cols = vec![Rgb::splat(1.0), Rgb::splat(2.0), Rgb::splat(3.0), Rgb::splat(4.0)];
    let s = mitsuba_spot(Some(bitmap(4, 1, cols)));
    let t = 25f32.to_radians().tan();
    let dir = |x_over_z: f32| Vec3::new(x_over_z, 0.0, 1.0).normalize();
    let unit = |w: Vec3| s.intensity_towards(w).r / (s.intensity.r * s.falloff(w));
    assert_eq!(unit(dir(0.49 * t)), 3.0);
    assert_eq!(unit(dir(0.51 * t)), 4.0);
    assert_eq!(unit(dir(-0.49 * t)), 2.0);
    assert_eq!(unit(dir(-0.51 * t)), 1.0);
}
