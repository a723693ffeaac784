//! The cone of directions within angle theta_max of +z, uniformly (for sampling the solid
//! angle subtended by a sphere).

use super::azimuth_fraction;
use crate::math::{safe_sqrt, Vec2, Vec3, INV_2PI};

/// A direction uniform in the cone around +z with cos theta >= `cos_theta_max`: cos theta
/// linear in `u.x` from 1 down to `cos_theta_max` (equal steps in z, equal areas),
/// phi = 2 pi `u.y`.
#[inline]
#[must_use]
pub fn sample_uniform_cone(u: Vec2, cos_theta_max: f32) -> Vec3 {
    let cos_theta = (1.0 - u.x) + u.x * cos_theta_max;
    let sin_theta = safe_sqrt(1.0 - cos_theta * cos_theta);
    let (sin_phi, cos_phi) = (std::f32::consts::TAU * u.y).sin_cos();
    Vec3::new(sin_theta * cos_phi, sin_theta * sin_phi, cos_theta)
}

/// Solid-angle pdf of [`sample_uniform_cone`] inside the cone: 1 / (2 pi (1 - cos theta_max)),
/// the inverse of the cone's solid angle (infinite for a degenerate cone).
#[inline]
#[must_use]
pub fn uniform_cone_pdf(cos_theta_max: f32) -> f32 {
    INV_2PI / (1.0 - cos_theta_max)
}

/// The `u` for which [`sample_uniform_cone`] returns the unit vector `w` inside the cone.
#[inline]
#[must_use]
pub fn invert_uniform_cone(w: Vec3, cos_theta_max: f32) -> Vec2 {
    let ux = if cos_theta_max < 1.0 {
        (1.0 - w.z) / (1.0 - cos_theta_max)
    } else {
        0.0
    };
    Vec2::new(ux, azimuth_fraction(w.x, w.y))
}

#[cfg(test)]
mod tests {
    use super::super::test_points::unit_square;
    use super::*;
    use crate::sampling::chi2::{suite_seed, Chi2Test, SphereGrid, SIGNIFICANCE};

    const COS_THETA_MAX: [f32; 3] = [0.95, 0.3, -0.6];

    #[test]
    fn samples_lie_in_the_cone_and_invert() {
        for cos_max in COS_THETA_MAX {
            for u in unit_square() {
                let w = sample_uniform_cone(u, cos_max);
                assert!((w.length() - 1.0).abs() < 1e-5 && w.z >= cos_max - 1e-6, "{u} -> {w}");
                let v = invert_uniform_cone(w, cos_max);
                let du = (v - u).abs();
                let wrapped = Vec2::new(du.x, du.y.min(1.0 - du.y));
                assert!(w.z > 0.99999 || wrapped.max_element() < 2e-4, "{u} -> {w} -> {v}");
            }
        }
    }

    #[test]
    fn chi2_uniform_cone() {
        for cos_max in COS_THETA_MAX {
            let pdf = |w: Vec3| {
                if w.z >= cos_max {
                    uniform_cone_pdf(cos_max)
                } else {
                    0.0
                }
            };
            // A finer grid in cos theta so the narrow cone covers several rows.
            let grid = SphereGrid {
                cos_theta_bins: 40,
                phi_bins: 20,
            };
            let report = Chi2Test::new(1_000_000, suite_seed())
                .with_test_count(COS_THETA_MAX.len() as u32)
                .sphere(grid, |u, _| Some(sample_uniform_cone(u, cos_max)), pdf);
            report.assert_passes(SIGNIFICANCE);
            assert!(
                (report.pdf_integral - 1.0).abs() < 1e-5,
                "pdf integral {}",
                report.pdf_integral
            );
        }
    }
}
