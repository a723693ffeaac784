//! The tent (triangle) distribution on [-r, r], for the triangle pixel filter.

/// A value distributed as the tent `max(0, r - |x|) / r^2` on [-`radius`, `radius`], by
/// inverting its CDF: `F(x) = (x + r)^2 / (2 r^2)` for x <= 0 and
/// `1 - (r - x)^2 / (2 r^2)` for x >= 0.
#[inline]
#[must_use]
pub fn sample_tent(u: f32, radius: f32) -> f32 {
    if u < 0.5 {
        radius * ((2.0 * u).sqrt() - 1.0)
    } else {
        radius * (1.0 - (2.0 * (1.0 - u)).sqrt())
    }
}

/// Pdf of [`sample_tent`]: `max(0, r - |x|) / r^2`.
#[inline]
#[must_use]
pub fn tent_pdf(x: f32, radius: f32) -> f32 {
    (radius - x.abs()).max(0.0) / (radius * radius)
}

/// The `u` for which [`sample_tent`] returns `x` in [-`radius`, `radius`]: the CDF.
#[inline]
#[must_use]
pub fn invert_tent(x: f32, radius: f32) -> f32 {
    let t = (x.abs() / radius).min(1.0);
    // Half the tail mass beyond |x|: (1 - |x|/r)^2 / 2.
    let tail = 0.5 * (1.0 - t) * (1.0 - t);
    if x < 0.0 {
        tail
    } else {
        1.0 - tail
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::chi2::{suite_seed, Chi2Test, IntervalGrid, SIGNIFICANCE};
    use crate::sampling::Pcg32;

    #[test]
    fn samples_lie_in_range_and_invert() {
        let mut rng = Pcg32::new(0, 9);
        let edge = [
            0.0,
            1e-7,
            0.25,
            0.5,
            0.75,
            1.0 - 1e-6,
            crate::sampling::ONE_MINUS_EPSILON,
        ];
        for radius in [0.5, 1.0, 2.5] {
            for u in edge.into_iter().chain((0..10_000).map(|_| rng.next_f32())) {
                let x = sample_tent(u, radius);
                assert!(x.abs() <= radius, "{u} -> {x}");
                let v = invert_tent(x, radius);
                assert!((v - u).abs() < 2e-6, "{u} -> {x} -> {v}");
            }
        }
        assert_eq!(sample_tent(0.5, 1.0), 0.0);
    }

    #[test]
    fn chi2_tent() {
        for radius in [0.5, 2.0] {
            let grid = IntervalGrid {
                min: -radius,
                max: radius,
                bins: 50,
            };
            let report = Chi2Test::new(1_000_000, suite_seed()).with_test_count(2).interval(
                grid,
                |u, _| Some(sample_tent(u, radius)),
                |x| tent_pdf(x, radius),
            );
            report.assert_passes(SIGNIFICANCE);
            assert!(
                (report.pdf_integral - 1.0).abs() < 1e-5,
                "pdf integral {}",
                report.pdf_integral
            );
        }
    }
}
