//! The unit disk, uniformly: Shirley and Chiu's concentric map (low distortion, keeps
//! strata compact) and the simpler polar map.

use super::azimuth_fraction;
use crate::math::{Vec2, INV_PI};
use crate::sampling::ONE_MINUS_EPSILON;

const FRAC_PI_4: f32 = std::f32::consts::FRAC_PI_4;
const FRAC_4_PI: f32 = 4.0 / std::f32::consts::PI;

/// A point uniform on the unit disk by Shirley and Chiu's concentric map (1997): the square
/// [-1, 1]^2 is cut into four triangles by its diagonals and each concentric square ring
/// maps to a circle of radius r = the larger coordinate, with the angle linear along the
/// square's edge: theta = pi/4 * (y / x) in the right and left triangles.
#[inline]
#[must_use]
pub fn sample_uniform_disk_concentric(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    if o == Vec2::ZERO {
        return Vec2::ZERO;
    }
    let (r, theta) = if o.x.abs() > o.y.abs() {
        (o.x, FRAC_PI_4 * (o.y / o.x))
    } else {
        (o.y, std::f32::consts::FRAC_PI_2 - FRAC_PI_4 * (o.x / o.y))
    };
    let (sin, cos) = theta.sin_cos();
    r * Vec2::new(cos, sin)
}

/// The `u` for which [`sample_uniform_disk_concentric`] returns `p` (|p| <= 1).
///
/// In the right/left triangles the point is `r (cos theta, sin theta)` with
/// theta in (-pi/4, pi/4), so `sign(r) = sign(p.x)` and `o.y / o.x = atan(p.y / p.x) * 4/pi`;
/// in the top/bottom ones `o.x / o.y = atan(p.x / p.y) * 4/pi` by the same argument.
#[inline]
#[must_use]
pub fn invert_uniform_disk_concentric(p: Vec2) -> Vec2 {
    let len = p.length();
    let o = if p.x.abs() >= p.y.abs() {
        if p.x == 0.0 {
            return Vec2::splat(0.5);
        }
        let r = len.copysign(p.x);
        Vec2::new(r, r * FRAC_4_PI * (p.y / p.x).atan())
    } else {
        let r = len.copysign(p.y);
        Vec2::new(r * FRAC_4_PI * (p.x / p.y).atan(), r)
    };
    ((o + Vec2::ONE) * 0.5).clamp(Vec2::ZERO, Vec2::splat(ONE_MINUS_EPSILON))
}

/// A point uniform on the unit disk by the polar map: r = sqrt(`u.x`) (the area inside
/// radius r is proportional to r^2), theta = 2 pi `u.y`.
#[inline]
#[must_use]
pub fn sample_uniform_disk_polar(u: Vec2) -> Vec2 {
    let r = u.x.sqrt();
    let (sin, cos) = (std::f32::consts::TAU * u.y).sin_cos();
    r * Vec2::new(cos, sin)
}

/// The `u` for which [`sample_uniform_disk_polar`] returns `p` (|p| <= 1).
#[inline]
#[must_use]
pub fn invert_uniform_disk_polar(p: Vec2) -> Vec2 {
    Vec2::new(p.length_squared().min(ONE_MINUS_EPSILON), azimuth_fraction(p.x, p.y))
}

/// Area pdf of both disk samplers on the unit disk: 1 / pi.
#[inline]
#[must_use]
pub fn uniform_disk_pdf() -> f32 {
    INV_PI
}

#[cfg(test)]
mod tests {
    use super::super::test_points::unit_square;
    use super::*;
    use crate::sampling::chi2::{suite_seed, Chi2Test, RectGrid, SIGNIFICANCE};
    use glam::UVec2;

    fn disk_pdf(p: Vec2) -> f32 {
        if p.length_squared() <= 1.0 {
            uniform_disk_pdf()
        } else {
            0.0
        }
    }

    const GRID: RectGrid = RectGrid {
        min: Vec2::splat(-1.0),
        max: Vec2::splat(1.0),
        bins: UVec2::new(16, 16),
    };

    #[test]
    fn concentric_samples_lie_on_the_disk_and_invert() {
        for u in unit_square() {
            let p = sample_uniform_disk_concentric(u);
            assert!(p.length() <= 1.0 + 1e-6, "{u} -> {p}");
            let v = invert_uniform_disk_concentric(p);
            assert!((v - u).abs().max_element() < 1e-5, "{u} -> {p} -> {v}");
        }
        assert_eq!(invert_uniform_disk_concentric(Vec2::ZERO), Vec2::splat(0.5));
    }

    #[test]
    fn polar_samples_lie_on_the_disk_and_invert() {
        for u in unit_square() {
            let p = sample_uniform_disk_polar(u);
            assert!(p.length() <= 1.0 + 1e-6, "{u} -> {p}");
            let v = invert_uniform_disk_polar(p);
            let du = (v - u).abs();
            let wrapped = Vec2::new(du.x, du.y.min(1.0 - du.y));
            // The angle is undefined at the centre.
            assert!(u.x < 1e-4 || wrapped.max_element() < 2e-4, "{u} -> {p} -> {v}");
        }
    }

    #[test]
    fn chi2_concentric_disk() {
        let report = Chi2Test::new(1_000_000, suite_seed()).with_test_count(2).rect(
            GRID,
            |u, _| Some(sample_uniform_disk_concentric(u)),
            disk_pdf,
        );
        report.assert_passes(SIGNIFICANCE);
        assert!(
            (report.pdf_integral - 1.0).abs() < 1e-5,
            "pdf integral {}",
            report.pdf_integral
        );
    }

    #[test]
    fn chi2_polar_disk() {
        let report = Chi2Test::new(1_000_000, suite_seed()).with_test_count(2).rect(
            GRID,
            |u, _| Some(sample_uniform_disk_polar(u)),
            disk_pdf,
        );
        report.assert_passes(SIGNIFICANCE);
        assert!(
            (report.pdf_integral - 1.0).abs() < 1e-5,
            "pdf integral {}",
            report.pdf_integral
        );
    }
}
