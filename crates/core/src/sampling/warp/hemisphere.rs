//! The unit hemisphere around +z: uniform and cosine-weighted.

use super::{azimuth_fraction, disk};
use crate::math::{safe_sqrt, Vec2, Vec3, INV_2PI, INV_PI};

/// A direction uniform over the hemisphere z >= 0, by inversion: z = cos theta = `u.x`
/// (the hemisphere's area between heights z and 1 is 2 pi (1 - z), Archimedes) and
/// phi = 2 pi `u.y`.
#[inline]
#[must_use]
pub fn sample_uniform_hemisphere(u: Vec2) -> Vec3 {
    let z = u.x;
    let r = safe_sqrt(1.0 - z * z);
    let (sin_phi, cos_phi) = (std::f32::consts::TAU * u.y).sin_cos();
    Vec3::new(r * cos_phi, r * sin_phi, z)
}

/// Solid-angle pdf of [`sample_uniform_hemisphere`] on the upper hemisphere: 1 / (2 pi).
#[inline]
#[must_use]
pub fn uniform_hemisphere_pdf() -> f32 {
    INV_2PI
}

/// The `u` for which [`sample_uniform_hemisphere`] returns the unit vector `w` (z >= 0).
#[inline]
#[must_use]
pub fn invert_uniform_hemisphere(w: Vec3) -> Vec2 {
    Vec2::new(w.z, azimuth_fraction(w.x, w.y))
}

/// A cosine-distributed direction on the hemisphere z >= 0 by Malley's method: a uniform
/// point on the unit disk (concentric map) lifted to the hemisphere, z = sqrt(1 - r^2).
#[inline]
#[must_use]
pub fn sample_cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = disk::sample_uniform_disk_concentric(u);
    Vec3::new(d.x, d.y, safe_sqrt(1.0 - d.length_squared()))
}

/// Solid-angle pdf of [`sample_cosine_hemisphere`]: cos theta / pi (zero below the
/// horizon).
#[inline]
#[must_use]
pub fn cosine_hemisphere_pdf(cos_theta: f32) -> f32 {
    cos_theta.max(0.0) * INV_PI
}

/// The `u` for which [`sample_cosine_hemisphere`] returns the unit vector `w` (z >= 0):
/// project to the disk, invert the concentric map.
#[inline]
#[must_use]
pub fn invert_cosine_hemisphere(w: Vec3) -> Vec2 {
    disk::invert_uniform_disk_concentric(Vec2::new(w.x, w.y))
}

#[cfg(test)]
mod tests {
    use super::super::test_points::unit_square;
    use super::*;
    use crate::sampling::chi2::{suite_seed, Chi2Test, SphereGrid, SIGNIFICANCE};

    #[test]
    fn samples_are_unit_vectors_on_the_upper_hemisphere_and_invert() {
        for u in unit_square() {
            for (w, back) in [
                (
                    sample_uniform_hemisphere(u),
                    invert_uniform_hemisphere as fn(Vec3) -> Vec2,
                ),
                (sample_cosine_hemisphere(u), invert_cosine_hemisphere),
            ] {
                assert!((w.length() - 1.0).abs() < 1e-5 && w.z >= 0.0, "{u} -> {w}");
                let v = back(w);
                // The azimuth is undefined at the pole and wraps around at 0 = 1.
                let du = (v - u).abs();
                let wrapped = Vec2::new(du.x, du.y.min(1.0 - du.y));
                assert!(w.z > 0.99999 || wrapped.max_element() < 2e-4, "{u} -> {w} -> {v}");
            }
        }
    }

    #[test]
    fn cosine_pdf_is_zero_below_the_horizon() {
        assert_eq!(cosine_hemisphere_pdf(-0.5), 0.0);
        assert!((cosine_hemisphere_pdf(1.0) - INV_PI).abs() < 1e-7);
    }

    #[test]
    fn chi2_uniform_hemisphere() {
        let pdf = |w: Vec3| {
            if w.z >= 0.0 {
                uniform_hemisphere_pdf()
            } else {
                0.0
            }
        };
        let report = Chi2Test::new(1_000_000, suite_seed()).with_test_count(2).sphere(
            SphereGrid::default(),
            |u, _| Some(sample_uniform_hemisphere(u)),
            pdf,
        );
        report.assert_passes(SIGNIFICANCE);
        assert!(
            (report.pdf_integral - 1.0).abs() < 1e-5,
            "pdf integral {}",
            report.pdf_integral
        );
    }

    #[test]
    fn chi2_cosine_hemisphere() {
        let pdf = |w: Vec3| cosine_hemisphere_pdf(w.z);
        let report = Chi2Test::new(1_000_000, suite_seed()).with_test_count(2).sphere(
            SphereGrid::default(),
            |u, _| Some(sample_cosine_hemisphere(u)),
            pdf,
        );
        report.assert_passes(SIGNIFICANCE);
        assert!(
            (report.pdf_integral - 1.0).abs() < 1e-5,
            "pdf integral {}",
            report.pdf_integral
        );
    }
}
