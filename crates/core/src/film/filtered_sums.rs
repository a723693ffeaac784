//! [`FilteredSums`]: one pixel's sums under filter splatting, where every camera sample adds
//! `f(x - c) L` and `f(x - c)` to each pixel `c` the filter `f` covers, and the pixel is the
//! ratio of the two (Mitsuba 3's film; the ratio estimator of a weighted mean).
//!
//! The samples of one sample index (one per pixel) form a group: for pixel `c`, the group of
//! index `s` gives `x_s = sum_j f(x_j - c)` and `y_s = sum_j f(x_j - c) L_j` over the
//! neighbours `j` whose sample reaches `c` ([`FilterGroup`]). Groups of different indices are
//! independent, samples within a group are not identically distributed (each lies in its
//! own pixel), so the groups are the units of the variance estimate: for the ratio
//! `R = sum y_s / sum x_s` of `n` groups, the delta method (Cochran, *Sampling Techniques*,
//! 3rd ed., eqs. 6.9 and 6.13) gives `Var[R] ~= n / (n - 1) sum (y_s - R x_s)^2 / (sum x_s)^2`,
//! expanded into the sums `sum x`, `sum x^2`, `sum y`, `sum x y`, `sum y^2` kept here.
//! (Treating every sample as a unit instead overstates the variance by the spread of the
//! neighbours' means: 31% on the Cornell box at 128x128.)
//!
//! A pixel's sums gather groups that threads, waves or machines may add in any order, so
//! they are kept in fixed point as [`super::SplatSum`] is: each term is rounded once to a
//! multiple of its unit and added as an `i128`, and any order or grouping of the same
//! terms gives the same bits. (A group itself is an `f64` sum in a fixed order, see
//! `super::filter_groups`.) First moments use units of 2^-64 (as splats); the second
//! moments, computed from the group's `f64` sums and only feeding the variance, units of
//! 2^-32, so a term may reach 2^94 (a radiance of about 1e14).

use crate::color::Rgb;

/// Fractional bits of the first moments (`w`, `w L`).
const FIRST_BITS: i32 = 64;
/// Fractional bits of the second moments (`w^2`, `w^2 L`, `(w L)^2`).
const SECOND_BITS: i32 = 32;
/// Terms of this magnitude or more (in their own unit's range) are refused.
const LIMIT: f64 = 4_611_686_018_427_387_904.0; // 2^62

/// The fixed-point value of `v` in units of `2^-bits` (nearest, ties to even), or `None`
/// when `v` is not finite or `|v| >= 2^62 * 2^(64 - bits)`.
#[inline]
fn quantize(v: f64, bits: i32) -> Option<i128> {
    const TWO_52: f64 = 4_503_599_627_370_496.0;
    let scaled = v * 2f64.powi(bits);
    if scaled.abs() < TWO_52 {
        // Adding and removing 2^52 rounds to an integer (to nearest, ties to even) without
        // a library call; the result then converts to i64 exactly.
        let r = if scaled >= 0.0 {
            (scaled + TWO_52) - TWO_52
        } else {
            (scaled - TWO_52) + TWO_52
        };
        return Some(i128::from(r as i64));
    }
    // At 2^52 and above an f64 is an integer: its mantissa shifted by its exponent.
    (scaled.is_finite() && scaled.abs() < LIMIT * 2f64.powi(64)).then(|| {
        let bits = scaled.to_bits();
        let exponent = ((bits >> 52) & 0x7ff) as i32 - 1075;
        let mantissa = i128::from((bits & ((1 << 52) - 1)) | (1 << 52));
        let magnitude = mantissa << exponent;
        if scaled < 0.0 {
            -magnitude
        } else {
            magnitude
        }
    })
}

/// One pixel's share of one sample index: the filter weights and weighted radiance of the
/// samples reaching it, in `f64` (summed in a fixed order, see `super::filter_groups`, and
/// rounded to fixed point once, by [`FilteredSums::add_group`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FilterGroup {
    /// `sum w`.
    weight: f64,
    /// `sum w L` per channel.
    weighted: [f64; 3],
}

impl FilterGroup {
    /// Add a sample of radiance `l` at filter weight `w` (the products exact in `f64`). A
    /// term that is not finite makes the group one [`FilteredSums::add_group`] refuses.
    #[inline]
    pub fn add(&mut self, l: Rgb, w: f32) {
        let w = f64::from(w);
        self.weight += w;
        for (sum, v) in self.weighted.iter_mut().zip([l.r, l.g, l.b]) {
            *sum += w * f64::from(v);
        }
    }

    /// True when no sample reached the pixel (or only ones that cancel).
    #[must_use]
    pub fn is_zero(&self) -> bool {
        *self == Self::default()
    }
}

/// One pixel's filter-splatting sums over its groups, in fixed point.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct FilteredSums {
    /// `sum x`, `sum x^2` (units 2^-64 and 2^-32).
    weights: [i128; 2],
    /// `sum y` per channel (2^-64).
    weighted: [i128; 3],
    /// `sum x y` per channel (2^-32).
    cross: [i128; 3],
    /// `sum y^2` per channel (2^-32).
    squares: [i128; 3],
}

/// Number of `i128` values [`FilteredSums::to_fixed`] gives.
pub const FILTERED_SUMS_LEN: usize = 11;

impl FilteredSums {
    /// No samples.
    pub const ZERO: Self = Self {
        weights: [0; 2],
        weighted: [0; 3],
        cross: [0; 3],
        squares: [0; 3],
    };

    /// Add one sample index's group, each of its sums and their products rounded once to
    /// fixed point, so that they depend on nothing but the group. Adds nothing and returns
    /// false when a term is not finite or too large.
    pub fn add_group(&mut self, g: &FilterGroup) -> bool {
        let (x, y) = (g.weight, g.weighted);
        let (first, second) = (|v: f64| quantize(v, FIRST_BITS), |v: f64| quantize(v, SECOND_BITS));
        let (Some(qx), Some(x2)) = (first(x), second(x * x)) else {
            return false;
        };
        let mut q = [[0i128; 3]; 3];
        for (q, y) in q.iter_mut().zip(y) {
            let (Some(qy), Some(xy), Some(y2)) = (first(y), second(x * y), second(y * y)) else {
                return false;
            };
            *q = [qy, xy, y2];
        }
        self.weights[0] = self.weights[0].wrapping_add(qx);
        self.weights[1] = self.weights[1].wrapping_add(x2);
        for (c, [qy, xy, y2]) in q.into_iter().enumerate() {
            self.weighted[c] = self.weighted[c].wrapping_add(qy);
            self.cross[c] = self.cross[c].wrapping_add(xy);
            self.squares[c] = self.squares[c].wrapping_add(y2);
        }
        true
    }

    /// Add another pixel's sums (exact, in any order).
    pub fn merge(&mut self, o: &Self) {
        let mut a = self.to_fixed();
        for (x, y) in a.iter_mut().zip(o.to_fixed()) {
            *x = x.wrapping_add(y);
        }
        *self = Self::from_fixed(a);
    }

    /// True when nothing (or only terms that cancel) was added.
    #[must_use]
    pub fn is_zero(&self) -> bool {
        *self == Self::ZERO
    }

    /// `sum w` as `f64`.
    #[must_use]
    pub fn weight_sum(&self) -> f64 {
        to_f64(self.weights[0], FIRST_BITS)
    }

    /// The pixel's estimate `sum(w L) / sum(w)` (black when the weights sum to zero).
    #[must_use]
    pub fn mean(&self) -> Rgb {
        let [r, g, b] = self.mean_f64();
        Rgb::new(r as f32, g as f32, b as f32)
    }

    /// [`Self::mean`] in `f64` (zero when the weights sum to zero).
    #[must_use]
    pub fn mean_f64(&self) -> [f64; 3] {
        let sw = self.weight_sum();
        if sw == 0.0 {
            return [0.0; 3];
        }
        self.weighted.map(|v| to_f64(v, FIRST_BITS) / sw)
    }

    /// The delta-method variance of [`Self::mean`] per channel over `groups` sample
    /// indices: `n / (n - 1) (sum y^2 - 2 R sum x y + R^2 sum x^2) / (sum x)^2` (clamped at
    /// zero; zero with fewer than two groups).
    #[must_use]
    pub fn variance_of_mean(&self, groups: u64) -> Rgb {
        let sw = self.weight_sum();
        if sw == 0.0 || groups < 2 {
            return Rgb::BLACK;
        }
        let correction = groups as f64 / (groups - 1) as f64;
        let sw2 = to_f64(self.weights[1], SECOND_BITS);
        let v = |c: usize| {
            let r = to_f64(self.weighted[c], FIRST_BITS) / sw;
            let s = to_f64(self.squares[c], SECOND_BITS) - 2.0 * r * to_f64(self.cross[c], SECOND_BITS) + r * r * sw2;
            (correction * s.max(0.0) / (sw * sw)) as f32
        };
        Rgb::new(v(0), v(1), v(2))
    }

    /// The fixed-point integers: `sum x`, `sum x^2`, `sum y` (3), `sum x y` (3),
    /// `sum y^2` (3), for storing a film exactly.
    #[must_use]
    pub fn to_fixed(&self) -> [i128; FILTERED_SUMS_LEN] {
        let mut a = [0; FILTERED_SUMS_LEN];
        a[..2].copy_from_slice(&self.weights);
        a[2..5].copy_from_slice(&self.weighted);
        a[5..8].copy_from_slice(&self.cross);
        a[8..].copy_from_slice(&self.squares);
        a
    }

    /// Sums from [`Self::to_fixed`]'s integers.
    #[must_use]
    pub fn from_fixed(a: [i128; FILTERED_SUMS_LEN]) -> Self {
        Self {
            weights: [a[0], a[1]],
            weighted: [a[2], a[3], a[4]],
            cross: [a[5], a[6], a[7]],
            squares: [a[8], a[9], a[10]],
        }
    }
}

fn to_f64(v: i128, bits: i32) -> f64 {
    v as f64 * 2f64.powi(-bits)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Groups of one to four samples of varied weights (some negative, as Mitchell's lobes
    /// give) and radiance.
    fn groups() -> Vec<Vec<(Rgb, f32)>> {
        (0..300u32)
            .map(|i| {
                (0..=i % 4)
                    .map(|k| {
                        let w = (((i + k) * 37 % 101) as f32 / 100.0) - 0.1;
                        let v = 1.3f32.powi(((i + 3 * k) * 11 % 41) as i32 - 20);
                        (Rgb::new(v, 2.0 * v + 0.5, 0.25), w)
                    })
                    .collect()
            })
            .collect()
    }

    fn group(samples: &[(Rgb, f32)]) -> FilterGroup {
        let mut g = FilterGroup::default();
        samples.iter().for_each(|&(l, w)| g.add(l, w));
        g
    }

    #[test]
    fn mean_and_variance_match_a_float_reference() {
        let gs = groups();
        let mut s = FilteredSums::ZERO;
        gs.iter().for_each(|g| assert!(s.add_group(&group(g))));
        let n = gs.len() as f64;
        let x: Vec<f64> = gs.iter().map(|g| g.iter().map(|&(_, w)| f64::from(w)).sum()).collect();
        let sx: f64 = x.iter().sum();
        for c in 0..3 {
            let y: Vec<f64> = gs
                .iter()
                .map(|g| g.iter().map(|&(l, w)| f64::from(w) * f64::from(l[c])).sum())
                .collect();
            let r = y.iter().sum::<f64>() / sx;
            let var = n / (n - 1.0) * x.iter().zip(&y).map(|(x, y)| (y - r * x).powi(2)).sum::<f64>() / (sx * sx);
            assert!((f64::from(s.mean()[c]) - r).abs() <= 1e-6 * r.abs(), "mean {c}");
            let got = f64::from(s.variance_of_mean(gs.len() as u64)[c]);
            assert!((got - var).abs() <= 1e-5 * var + 1e-12, "variance {c}: {got} vs {var}");
        }
        assert_eq!(s.variance_of_mean(1), Rgb::BLACK);
    }

    #[test]
    fn any_order_and_grouping_of_the_groups_gives_the_same_bits() {
        let gs = groups();
        let mut forward = FilteredSums::ZERO;
        gs.iter().for_each(|g| assert!(forward.add_group(&group(g))));
        let mut backward = FilteredSums::ZERO;
        gs.iter().rev().for_each(|g| assert!(backward.add_group(&group(g))));
        let (mut a, mut b) = (FilteredSums::ZERO, FilteredSums::ZERO);
        gs[..123].iter().for_each(|g| assert!(a.add_group(&group(g))));
        gs[123..].iter().for_each(|g| assert!(b.add_group(&group(g))));
        b.merge(&a);
        assert_eq!(forward, backward);
        assert_eq!(forward, b);
        assert_eq!(FilteredSums::from_fixed(forward.to_fixed()), forward);
    }

    #[test]
    fn constant_radiance_is_exact_and_has_no_variance() {
        let mut s = FilteredSums::ZERO;
        for i in 0..50u32 {
            assert!(s.add_group(&group(&[(Rgb::splat(0.75), (i % 7) as f32 / 8.0 + 0.125)])));
        }
        assert_eq!(s.mean(), Rgb::splat(0.75));
        assert!(s.variance_of_mean(50).max_component() < 1e-12);
    }

    #[test]
    fn quantization_is_exact_rounding_at_every_magnitude() {
        for (v, bits) in [
            (0.3, 64),
            (-0.3, 64),
            (1.5e-19, 64),
            (3.0, 64),
            (-2.5e17, 64),
            (7e25, 32),
            (-1e-9, 32),
        ] {
            let q = quantize(v, bits).unwrap();
            let exact = v * 2f64.powi(bits);
            // Within half a unit below 2^52; an integer (the f64 itself) above.
            assert!((q as f64 - exact).abs() <= 0.5, "{v} at {bits}");
        }
        assert_eq!(quantize(0.5 * 2f64.powi(-64), 64), Some(0));
        assert_eq!(quantize(1.5 * 2f64.powi(-64), 64), Some(2));
        assert_eq!(quantize(-1.5 * 2f64.powi(-64), 64), Some(-2));
        assert_eq!(quantize(2f64.powi(60), 64), Some(1i128 << 124));
        assert_eq!(quantize(-(2f64.powi(60)), 64), Some(-(1i128 << 124)));
        assert_eq!(quantize(2f64.powi(62), 64), None);
        assert_eq!(quantize(f64::NAN, 32), None);
    }

    #[test]
    fn bad_terms_are_refused_whole() {
        let mut s = FilteredSums::ZERO;
        assert!(!s.add_group(&group(&[(Rgb::splat(1.0), 0.5), (Rgb::new(1.0, f32::NAN, 1.0), 0.5)])));
        assert!(!s.add_group(&group(&[(Rgb::splat(1.0), f32::INFINITY)])));
        assert!(s.is_zero());
        // y^2 = 1e30 overflows the second moments' range (2^94 ~ 2e28): the group is
        // refused whole.
        assert!(!s.add_group(&group(&[(Rgb::new(1e15, 1.0, 1.0), 1.0)])));
        assert!(s.is_zero());
        assert!(s.add_group(&group(&[(Rgb::new(1e13, 1.0, 1.0), 1.0)])));
        assert!(!s.is_zero());
    }
}
