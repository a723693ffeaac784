//! The equal-area octahedral mapping between the unit square and the unit sphere (Clarberg,
//! "Fast Equal-Area Mapping of the (Hemi)Sphere using SIMD", 2008), which pbrt-v4 uses for
//! environment maps: the square is folded like an octahedron, the inner diamond
//! `|u| + |v| <= 1` (in `[-1, 1]^2` coordinates) covers the upper hemisphere z >= 0 and the
//! four corner triangles the lower one. Equal areas of the square map to equal solid
//! angles, so a uniform point of the square is a uniform direction (pdf 1 / (4 pi)), and an
//! image in this layout is sampled with the image's own pdf divided by 4 pi.

use crate::math::{safe_sqrt, Vec2, Vec3, PI};

/// The direction of the point `p` of [0, 1]^2 under the equal-area octahedral mapping.
#[inline]
#[must_use]
pub fn equal_area_square_to_sphere(p: Vec2) -> Vec3 {
    let (u, v) = (2.0 * p.x - 1.0, 2.0 * p.y - 1.0);
    let (up, vp) = (u.abs(), v.abs());
    // Signed distance from the diagonal |u| + |v| = 1: positive inside (upper hemisphere).
    let signed_distance = 1.0 - (up + vp);
    let r = 1.0 - signed_distance.abs();
    // Azimuth within the quadrant, from 0 on the u axis to pi/2 on the v axis.
    let phi = if r == 0.0 { 1.0 } else { (vp - up) / r + 1.0 } * (PI / 4.0);
    let z = (1.0 - r * r).copysign(signed_distance);
    let (sin_phi, cos_phi) = phi.sin_cos();
    let s = r * safe_sqrt(2.0 - r * r);
    Vec3::new(cos_phi.copysign(u) * s, sin_phi.copysign(v) * s, z)
}

/// The point of [0, 1]^2 that [`equal_area_square_to_sphere`] maps to the unit vector `w`
/// (exact inverse, by `atan2`, up to rounding).
#[inline]
#[must_use]
pub fn equal_area_sphere_to_square(w: Vec3) -> Vec2 {
    let (x, y, z) = (w.x.abs(), w.y.abs(), w.z.abs());
    // Distance from the centre of the quadrant's triangle: z = 1 - r^2 on either hemisphere.
    let r = safe_sqrt(1.0 - z);
    // Azimuth within the quadrant as a fraction of pi/2.
    let t = if x == 0.0 && y == 0.0 {
        0.0
    } else {
        y.atan2(x) * (2.0 / PI)
    };
    // Upper hemisphere: |v| = r t, |u| = r - |v|.
    let mut vp = r * t;
    let mut up = r - vp;
    if w.z < 0.0 {
        // Lower hemisphere: mirror across the quadrant's diagonal |u| + |v| = 1.
        (up, vp) = (1.0 - vp, 1.0 - up);
    }
    let u = up.copysign(w.x);
    let v = vp.copysign(w.y);
    Vec2::new((0.5 * (u + 1.0)).clamp(0.0, 1.0), (0.5 * (v + 1.0)).clamp(0.0, 1.0))
}

#[cfg(test)]
mod tests {
    use super::super::test_points::unit_square;
    use super::*;
    use crate::sampling::chi2::{suite_seed, Chi2Test, SphereGrid, SIGNIFICANCE};
    use crate::sampling::uniform_sphere_pdf;

    #[test]
    fn square_to_sphere_to_square_round_trips() {
        for p in unit_square() {
            let w = equal_area_square_to_sphere(p);
            assert!((w.length() - 1.0).abs() < 1e-5, "{p} -> {w}");
            let q = equal_area_sphere_to_square(w);
            // The square's boundary is folded: points on it mirrored across an edge's
            // midpoint map to the same direction.
            let on_edge = p.min_element() == 0.0 || p.max_element() >= 1.0 - 1e-6;
            assert!(
                (q - p).abs().max_element() < 2e-4 || (on_edge && (equal_area_square_to_sphere(q) - w).length() < 1e-4),
                "{p} -> {w} -> {q}"
            );
        }
    }

    #[test]
    fn known_points() {
        let cases = [
            (Vec2::new(0.5, 0.5), Vec3::Z),
            (Vec2::new(1.0, 0.5), Vec3::X),
            (Vec2::new(0.5, 1.0), Vec3::Y),
            (Vec2::new(0.0, 0.5), -Vec3::X),
            (Vec2::new(0.5, 0.0), -Vec3::Y),
            (Vec2::new(0.0, 0.0), -Vec3::Z),
            (Vec2::new(1.0, 1.0), -Vec3::Z),
        ];
        for (p, w) in cases {
            let got = equal_area_square_to_sphere(p);
            assert!((got - w).length() < 1e-6, "{p} -> {got}, expected {w}");
        }
    }

    /// Equal area: uniform points of the square land uniformly on the sphere.
    #[test]
    fn chi2_equal_area_square_to_sphere_is_uniform() {
        let report = Chi2Test::new(1_000_000, suite_seed()).with_test_count(2).sphere(
            SphereGrid {
                cos_theta_bins: 20,
                phi_bins: 40,
            },
            |u, _| Some(equal_area_square_to_sphere(u)),
            |_| uniform_sphere_pdf(),
        );
        report.assert_passes(SIGNIFICANCE);
    }

    /// And the inverse: uniform directions land uniformly on the square.
    #[test]
    fn chi2_equal_area_sphere_to_square_is_uniform() {
        use crate::math::UVec2;
        use crate::sampling::chi2::RectGrid;
        use crate::sampling::sample_uniform_sphere;
        let grid = RectGrid {
            min: Vec2::ZERO,
            max: Vec2::ONE,
            bins: UVec2::new(16, 16),
        };
        let report = Chi2Test::new(1_000_000, suite_seed()).with_test_count(2).rect(
            grid,
            |u, _| Some(equal_area_sphere_to_square(sample_uniform_sphere(u))),
            |_| 1.0,
        );
        report.assert_passes(SIGNIFICANCE);
    }
}
