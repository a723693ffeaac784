//! Linear and bilinear densities on [0, 1] and [0, 1]^2 (pbrt-v4 `SampleLinear`,
//! `SampleBilinear`, section A.4.2 of the book), used to sample bilinear patches by the
//! area at their corners.

use crate::math::Vec2;
use crate::sampling::ONE_MINUS_EPSILON;

/// `x` in [0, 1] with density proportional to `(1 - x) a + x b` (`a, b >= 0`, not both 0),
/// by inverting the CDF `F(x) = x ((2 - x) a + x b) / (a + b)`. The root is taken in the
/// form `2 u (a + b) / (2 a + 2 sqrt(lerp(u, a^2, b^2)))` (pbrt-v4 eq. A.12's rearranged
/// quadratic formula), which stays accurate when `a` or `b` is small.
#[inline]
#[must_use]
pub fn sample_linear(u: f32, a: f32, b: f32) -> f32 {
    if u == 0.0 && a == 0.0 {
        return 0.0;
    }
    let x = u * (a + b) / (a + ((1.0 - u) * a * a + u * b * b).sqrt());
    x.min(ONE_MINUS_EPSILON)
}

/// Density of [`sample_linear`]: `2 ((1 - x) a + x b) / (a + b)` on [0, 1], 0 elsewhere.
#[inline]
#[must_use]
pub fn linear_pdf(x: f32, a: f32, b: f32) -> f32 {
    if !(0.0..=1.0).contains(&x) {
        return 0.0;
    }
    2.0 * ((1.0 - x) * a + x * b) / (a + b)
}

/// The `u` for which [`sample_linear`] returns `x`: the CDF.
#[inline]
#[must_use]
pub fn invert_linear(x: f32, a: f32, b: f32) -> f32 {
    x * (a * (2.0 - x) + b * x) / (a + b)
}

/// A point of [0, 1]^2 with density proportional to the bilinear interpolation of the
/// corner weights `w = [w(0,0), w(1,0), w(0,1), w(1,1)]`: `y` from its marginal (linear with
/// end weights `w0 + w1` and `w2 + w3`), then `x` from the conditional, linear between the
/// weights interpolated at `y`.
#[inline]
#[must_use]
pub fn sample_bilinear(u: Vec2, w: [f32; 4]) -> Vec2 {
    let y = sample_linear(u.y, w[0] + w[1], w[2] + w[3]);
    let x = sample_linear(u.x, lerp(y, w[0], w[2]), lerp(y, w[1], w[3]));
    Vec2::new(x, y)
}

/// Density of [`sample_bilinear`]:
/// `4 ((1-x)(1-y) w0 + x(1-y) w1 + (1-x)y w2 + xy w3) / (w0 + w1 + w2 + w3)`, 1 when all
/// weights are 0, and 0 outside the unit square.
#[inline]
#[must_use]
pub fn bilinear_pdf(p: Vec2, w: [f32; 4]) -> f32 {
    if !(0.0..=1.0).contains(&p.x) || !(0.0..=1.0).contains(&p.y) {
        return 0.0;
    }
    let sum = w[0] + w[1] + w[2] + w[3];
    if sum == 0.0 {
        return 1.0;
    }
    let (x, y) = (p.x, p.y);
    4.0 * ((1.0 - x) * (1.0 - y) * w[0] + x * (1.0 - y) * w[1] + (1.0 - x) * y * w[2] + x * y * w[3]) / sum
}

/// The `u` for which [`sample_bilinear`] returns `p`.
#[inline]
#[must_use]
pub fn invert_bilinear(p: Vec2, w: [f32; 4]) -> Vec2 {
    Vec2::new(
        invert_linear(p.x, lerp(p.y, w[0], w[2]), lerp(p.y, w[1], w[3])),
        invert_linear(p.y, w[0] + w[1], w[2] + w[3]),
    )
}

#[inline]
fn lerp(t: f32, a: f32, b: f32) -> f32 {
    (1.0 - t) * a + t * b
}

#[cfg(test)]
mod tests {
    use super::super::test_points::unit_square;
    use super::*;
    use crate::sampling::chi2::{suite_seed, Chi2Test, RectGrid, SIGNIFICANCE};
    use glam::UVec2;

    const WEIGHTS: [[f32; 4]; 3] = [[1.0, 3.0, 0.5, 2.0], [0.0, 1.0, 1.0, 4.0], [2.0, 2.0, 2.0, 2.0]];

    #[test]
    fn bilinear_samples_invert() {
        for w in WEIGHTS {
            for u in unit_square() {
                let p = sample_bilinear(u, w);
                assert!((0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y), "{u} -> {p}");
                let v = invert_bilinear(p, w);
                assert!((v - u).abs().max_element() < 1e-4, "{w:?}: {u} -> {p} -> {v}");
            }
        }
    }

    #[test]
    fn chi2_bilinear() {
        let grid = RectGrid {
            min: Vec2::ZERO,
            max: Vec2::ONE,
            bins: UVec2::new(16, 16),
        };
        for w in WEIGHTS {
            let report = Chi2Test::new(500_000, suite_seed())
                .with_test_count(WEIGHTS.len() as u32)
                .rect(grid, |u, _| Some(sample_bilinear(u, w)), |p| bilinear_pdf(p, w));
            report.assert_passes(SIGNIFICANCE);
            assert!((report.pdf_integral - 1.0).abs() < 1e-5, "{}", report.pdf_integral);
        }
    }
}
