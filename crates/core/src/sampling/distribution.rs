//! Piecewise-constant 1-D distributions: sample an interval in proportion to a tabulated
//! non-negative function (pdfs of filters, environment-map rows, light selection).

use super::ONE_MINUS_EPSILON;

/// A piecewise-constant density over [`min`, `max`] proportional to `n` tabulated values,
/// one per equal-width bin, sampled by inverting its CDF.
#[derive(Clone, Debug, PartialEq)]
pub struct PiecewiseConstant1D {
    /// The function value of each bin.
    func: Vec<f32>,
    /// Normalised CDF at the `n + 1` bin edges: 0, ..., 1.
    cdf: Vec<f32>,
    /// Density (per unit length of x) in each bin.
    bin_pdf: Vec<f32>,
    /// Integral of the function over [min, max].
    integral: f32,
    min: f32,
    max: f32,
}

impl PiecewiseConstant1D {
    /// The distribution of the step function with `values` on equal bins of [`min`, `max`].
    /// If all values are zero, sampling is uniform (and [`integral`](Self::integral) is 0).
    ///
    /// # Panics
    /// If `values` is empty, a value is negative or not finite, or `min >= max`.
    #[must_use]
    pub fn new(values: &[f32], min: f32, max: f32) -> Self {
        assert!(!values.is_empty(), "a distribution needs at least one bin");
        assert!(min < max, "empty domain [{min}, {max}]");
        assert!(
            values.iter().all(|v| v.is_finite() && *v >= 0.0),
            "values must be finite and non-negative"
        );
        let n = values.len();
        let width = f64::from(max - min) / n as f64;
        // Running sums in f64: cdf[i] = sum_{j < i} f_j * width.
        let mut sums = Vec::with_capacity(n + 1);
        let mut sum = 0.0f64;
        sums.push(0.0);
        for &v in values {
            sum += f64::from(v) * width;
            sums.push(sum);
        }
        let (cdf, bin_pdf) = if sum > 0.0 {
            let cdf = sums.iter().map(|s| (s / sum) as f32).collect();
            (cdf, values.iter().map(|&v| (f64::from(v) / sum) as f32).collect())
        } else {
            let cdf = (0..=n).map(|i| (i as f64 / n as f64) as f32).collect();
            (cdf, vec![(1.0 / f64::from(max - min)) as f32; n])
        };
        Self {
            func: values.to_vec(),
            cdf,
            bin_pdf,
            integral: sum as f32,
            min,
            max,
        }
    }

    /// Integral of the tabulated function over the domain.
    #[inline]
    #[must_use]
    pub fn integral(&self) -> f32 {
        self.integral
    }

    /// Number of bins.
    #[inline]
    #[must_use]
    pub fn bin_count(&self) -> usize {
        self.func.len()
    }

    /// The tabulated function values.
    #[inline]
    #[must_use]
    pub fn values(&self) -> &[f32] {
        &self.func
    }

    /// The domain `(min, max)`.
    #[inline]
    #[must_use]
    pub fn domain(&self) -> (f32, f32) {
        (self.min, self.max)
    }

    /// A sample `(x, pdf, bin)` for `u` in [0, 1): `x` in [min, max], its density, and the
    /// index of its bin. Bins of zero value are never returned.
    #[inline]
    #[must_use]
    pub fn sample(&self, u: f32) -> (f32, f32, usize) {
        let n = self.func.len();
        // The last edge with cdf <= u; cdf[0] = 0 <= u, and edges of empty bins repeat, so
        // this skips them.
        let bin = (self.cdf.partition_point(|&c| c <= u).max(1) - 1).min(n - 1);
        let (c0, c1) = (self.cdf[bin], self.cdf[bin + 1]);
        let du = if c1 > c0 {
            ((u - c0) / (c1 - c0)).clamp(0.0, ONE_MINUS_EPSILON)
        } else {
            0.0
        };
        let t = (bin as f32 + du) / n as f32;
        (self.min + t * (self.max - self.min), self.bin_pdf[bin], bin)
    }

    /// The density of [`sample`](Self::sample) at `x` (0 outside the domain).
    #[inline]
    #[must_use]
    pub fn pdf(&self, x: f32) -> f32 {
        if !(self.min..=self.max).contains(&x) {
            return 0.0;
        }
        self.bin_pdf[self.bin_of(x)]
    }

    /// The `u` for which [`sample`](Self::sample) returns `x`: the CDF at `x`, with `x`
    /// clamped to the domain.
    #[inline]
    #[must_use]
    pub fn invert(&self, x: f32) -> f32 {
        let x = x.clamp(self.min, self.max);
        let bin = self.bin_of(x);
        let t = (x - self.min) / (self.max - self.min) * self.func.len() as f32 - bin as f32;
        let (c0, c1) = (self.cdf[bin], self.cdf[bin + 1]);
        (c0 + t.clamp(0.0, 1.0) * (c1 - c0)).min(ONE_MINUS_EPSILON)
    }

    /// The bin holding `x` in [min, max] (the upper edge belongs to the last bin).
    #[inline]
    fn bin_of(&self, x: f32) -> usize {
        let n = self.func.len();
        (((x - self.min) / (self.max - self.min) * n as f32) as usize).min(n - 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::chi2::{suite_seed, Chi2Test, IntervalGrid, SIGNIFICANCE};
    use crate::sampling::Pcg32;

    const VALUES: [f32; 8] = [0.5, 2.0, 0.0, 0.0, 7.0, 1.0, 0.0, 3.5];

    #[test]
    fn integral_and_pdf() {
        let d = PiecewiseConstant1D::new(&VALUES, -1.0, 3.0);
        assert!((d.integral() - 14.0 * 0.5).abs() < 1e-6);
        assert_eq!(d.bin_count(), 8);
        // Bin 4 covers [1, 1.5): density 7 / 7.
        assert!((d.pdf(1.25) - 1.0).abs() < 1e-6);
        assert_eq!(d.pdf(0.25), 0.0);
        assert_eq!(d.pdf(-1.5), 0.0);
        assert_eq!(d.pdf(3.5), 0.0);
        assert!((d.pdf(3.0) - 0.5).abs() < 1e-6);
    }

    #[test]
    fn samples_avoid_empty_bins_and_invert() {
        let d = PiecewiseConstant1D::new(&VALUES, -1.0, 3.0);
        let mut rng = Pcg32::new(4, 4);
        for u in [0.0, 0.5, ONE_MINUS_EPSILON]
            .into_iter()
            .chain((0..10_000).map(|_| rng.next_f32()))
        {
            let (x, pdf, bin) = d.sample(u);
            assert!((-1.0..=3.0).contains(&x));
            assert!(VALUES[bin] > 0.0, "{u} -> bin {bin}");
            assert_eq!(pdf, d.pdf(x), "{u} -> {x}");
            let v = d.invert(x);
            assert!((v - u).abs() < 1e-5, "{u} -> {x} -> {v}");
        }
    }

    #[test]
    fn all_zero_values_sample_uniformly() {
        let d = PiecewiseConstant1D::new(&[0.0; 4], 0.0, 2.0);
        assert_eq!(d.integral(), 0.0);
        assert_eq!(d.pdf(1.3), 0.5);
        let (x, pdf, bin) = d.sample(0.3);
        assert!((x - 0.6).abs() < 1e-6 && pdf == 0.5 && bin == 1);
        assert!((d.invert(0.6) - 0.3).abs() < 1e-6);
    }

    #[test]
    #[should_panic(expected = "non-negative")]
    fn negative_values_panic() {
        let _ = PiecewiseConstant1D::new(&[1.0, -1.0], 0.0, 1.0);
    }

    #[test]
    fn chi2_piecewise_constant_1d() {
        let d = PiecewiseConstant1D::new(&VALUES, -1.0, 3.0);
        // Cells straddle bin edges (48 cells over 8 bins would not): 20 cells of 0.2.
        let grid = IntervalGrid {
            min: -1.0,
            max: 3.0,
            bins: 20,
        };
        let report = Chi2Test::new(1_000_000, suite_seed()).interval(grid, |u, _| Some(d.sample(u).0), |x| d.pdf(x));
        report.assert_passes(SIGNIFICANCE);
        assert!(
            (report.pdf_integral - 1.0).abs() < 1e-5,
            "pdf integral {}",
            report.pdf_integral
        );
    }
}
