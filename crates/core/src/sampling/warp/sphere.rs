//! The unit sphere, uniformly.

use super::azimuth_fraction;
use crate::math::{safe_sqrt, Vec2, Vec3, INV_4PI};

/// A direction uniform over the unit sphere: z = 1 - 2 `u.x` (equal steps in z cut equal
/// areas), phi = 2 pi `u.y`.
#[inline]
#[must_use]
pub fn sample_uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = safe_sqrt(1.0 - z * z);
    let (sin_phi, cos_phi) = (std::f32::consts::TAU * u.y).sin_cos();
    Vec3::new(r * cos_phi, r * sin_phi, z)
}

/// Solid-angle pdf of [`sample_uniform_sphere`]: 1 / (4 pi).
#[inline]
#[must_use]
pub fn uniform_sphere_pdf() -> f32 {
    INV_4PI
}

/// The `u` for which [`sample_uniform_sphere`] returns the unit vector `w`.
#[inline]
#[must_use]
pub fn invert_uniform_sphere(w: Vec3) -> Vec2 {
    Vec2::new(0.5 * (1.0 - w.z), azimuth_fraction(w.x, w.y))
}

#[cfg(test)]
mod tests {
    use super::super::test_points::unit_square;
    use super::*;
    use crate::sampling::chi2::{suite_seed, Chi2Test, SphereGrid, SIGNIFICANCE};

    #[test]
    fn samples_are_unit_vectors_and_invert() {
        for u in unit_square() {
            let w = sample_uniform_sphere(u);
            assert!((w.length() - 1.0).abs() < 1e-5, "{u} -> {w}");
            let v = invert_uniform_sphere(w);
            let du = (v - u).abs();
            let wrapped = Vec2::new(du.x, du.y.min(1.0 - du.y));
            assert!(w.z.abs() > 0.99999 || wrapped.max_element() < 2e-4, "{u} -> {w} -> {v}");
        }
    }

    #[test]
    fn chi2_uniform_sphere() {
        let report = Chi2Test::new(1_000_000, suite_seed()).sphere(
            SphereGrid::default(),
            |u, _| Some(sample_uniform_sphere(u)),
            |_| uniform_sphere_pdf(),
        );
        report.assert_passes(SIGNIFICANCE);
        assert!(
            (report.pdf_integral - 1.0).abs() < 1e-5,
            "pdf integral {}",
            report.pdf_integral
        );
    }
}
