//! Triangles, uniformly by area, in barycentric coordinates.

use crate::math::Vec2;

/// Barycentrics `[b0, b1, b2]` uniform over a triangle, by Heitz's low-distortion map
/// ("A Low-Distortion Map Between Triangle and Square", 2019; also pbrt-v4): the half of
/// the square with `u.x < u.y` maps linearly onto the half of the triangle with `b0 < b1`
/// (b0 = u.x / 2, b1 = u.y - b0), the other half symmetrically. Both pieces are affine with
/// Jacobian 1/2, so the map is uniform, and it is continuous across the diagonal.
#[inline]
#[must_use]
pub fn sample_uniform_triangle(u: Vec2) -> [f32; 3] {
    let (b0, b1) = if u.x < u.y {
        let b0 = 0.5 * u.x;
        (b0, u.y - b0)
    } else {
        let b1 = 0.5 * u.y;
        (u.x - b1, b1)
    };
    [b0, b1, 1.0 - b0 - b1]
}

/// The `u` for which [`sample_uniform_triangle`] returns the barycentrics `b`.
#[inline]
#[must_use]
pub fn invert_uniform_triangle(b: [f32; 3]) -> Vec2 {
    if b[0] < b[1] {
        // b0 = u.x / 2, b1 = u.y - u.x / 2.
        Vec2::new(2.0 * b[0], b[1] + b[0])
    } else {
        // b1 = u.y / 2, b0 = u.x - u.y / 2.
        Vec2::new(b[0] + b[1], 2.0 * b[1])
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_points::unit_square;
    use super::*;
    use crate::sampling::chi2::{suite_seed, Chi2Test, RectGrid, SIGNIFICANCE};
    use glam::UVec2;

    #[test]
    fn barycentrics_are_valid_and_invert() {
        for u in unit_square() {
            let b = sample_uniform_triangle(u);
            assert!(b.iter().all(|&x| (-1e-6..=1.0).contains(&x)), "{u} -> {b:?}");
            assert!((b.iter().sum::<f32>() - 1.0).abs() < 1e-6);
            let v = invert_uniform_triangle(b);
            assert!((v - u).abs().max_element() < 1e-6, "{u} -> {b:?} -> {v}");
        }
    }

    #[test]
    fn chi2_uniform_triangle_in_the_plane() {
        // An obtuse triangle; p = b0 a + b1 b + b2 c, uniform with density 1 / area inside.
        let (a, b, c) = (Vec2::new(-0.9, -0.8), Vec2::new(0.9, -0.3), Vec2::new(-0.4, 0.9));
        let area = 0.5 * (b - a).perp_dot(c - a).abs();
        let inside = |p: Vec2| {
            let d = [
                (b - a).perp_dot(p - a),
                (c - b).perp_dot(p - b),
                (a - c).perp_dot(p - c),
            ];
            d.iter().all(|&x| x >= 0.0) || d.iter().all(|&x| x <= 0.0)
        };
        let grid = RectGrid {
            min: Vec2::splat(-1.0),
            max: Vec2::splat(1.0),
            bins: UVec2::new(16, 16),
        };
        let report = Chi2Test::new(1_000_000, suite_seed()).rect(
            grid,
            |u, _| {
                let [b0, b1, b2] = sample_uniform_triangle(u);
                Some(b0 * a + b1 * b + b2 * c)
            },
            |p| if inside(p) { 1.0 / area } else { 0.0 },
        );
        report.assert_passes(SIGNIFICANCE);
        assert!(
            (report.pdf_integral - 1.0).abs() < 1e-5,
            "pdf integral {}",
            report.pdf_integral
        );
    }
}
