//! [`SplatSum`]: one pixel's sum of splats, kept as fixed-point integers so that the sum
//! does not depend on the order the splats arrive in.
//!
//! Floating-point addition does not associate: adding the same splats in another order (two
//! threads instead of one, the image split over machines, a render resumed) changes the
//! last bits. Each splat channel is instead rounded once to a multiple of 2^-64 (its own
//! fixed value, whatever came before) and added as an `i128`. Integer addition associates
//! and commutes, so any grouping of the same splats gives the same bits; wrapping addition
//! keeps that true even through an intermediate overflow, and the result is exact whenever
//! the true sum's magnitude stays below 2^63 (about 9.2e18).
//!
//! A splat channel of magnitude at least [`MAX_SPLAT`] (2^62, about 4.6e18) is refused like
//! a non-finite one; below 2^-65 (about 2.7e-20) it rounds to zero. Both are far outside the
//! radiance a splat carries in practice (a pixel value times the samples per pixel).

use crate::color::Rgb;

/// Fractional bits of the fixed-point representation.
const FRACTION_BITS: i32 = 64;

/// Splat channels of this magnitude or more are refused ([`SplatSum::add`] returns false).
pub const MAX_SPLAT: f32 = 4_611_686_018_427_387_904.0; // 2^62

/// The fixed-point sum of a pixel's splats, per channel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct SplatSum {
    fixed: [i128; 3],
}

impl SplatSum {
    /// The empty sum.
    pub const ZERO: Self = Self { fixed: [0; 3] };

    /// A channel's fixed-point value: `v * 2^64` rounded to the nearest integer (ties away
    /// from zero); `None` when `v` is not finite or too large.
    #[must_use]
    pub fn quantize(v: f32) -> Option<i128> {
        if !fits(v) {
            return None;
        }
        // Exact: scaling an f32 by a power of two in f64 neither rounds nor overflows, and
        // the rounded value (below 2^126) converts to i128 exactly.
        Some((f64::from(v) * 2f64.powi(FRACTION_BITS)).round() as i128)
    }

    /// Add a splat's radiance; returns false (and adds nothing) when a channel is not
    /// finite or too large.
    pub fn add(&mut self, l: Rgb) -> bool {
        let (Some(r), Some(g), Some(b)) = (Self::quantize(l.r), Self::quantize(l.g), Self::quantize(l.b)) else {
            return false;
        };
        for (sum, v) in self.fixed.iter_mut().zip([r, g, b]) {
            *sum = sum.wrapping_add(v);
        }
        true
    }

    /// Whether every channel of `l` can be added (finite, below [`MAX_SPLAT`]).
    #[must_use]
    #[inline]
    pub fn accepts(l: Rgb) -> bool {
        // The test `quantize` makes, without its rounding (a library call).
        [l.r, l.g, l.b].into_iter().all(fits)
    }

    /// Add `l w` (a splat's radiance times its filter weight for this pixel, rounded to
    /// `f32` per channel before it is fixed); returns false (and adds nothing) when a
    /// channel of the product is not finite or too large.
    pub fn add_weighted(&mut self, l: Rgb, w: f32) -> bool {
        self.add(Rgb::new(l.r * w, l.g * w, l.b * w))
    }

    /// Add another pixel's sum (exact, in any order).
    pub fn merge(&mut self, other: &Self) {
        for (sum, v) in self.fixed.iter_mut().zip(other.fixed) {
            *sum = sum.wrapping_add(v);
        }
    }

    /// True when no splat (or only ones that cancel) has been added.
    #[must_use]
    pub fn is_zero(&self) -> bool {
        self.fixed == [0; 3]
    }

    /// The sum per channel, rounded to `f64` (to nearest, so equal sums give equal values).
    #[must_use]
    pub fn to_f64(&self) -> [f64; 3] {
        let scale = 2f64.powi(-FRACTION_BITS);
        self.fixed.map(|v| v as f64 * scale)
    }

    /// The fixed-point integers (units of 2^-64), for storing a film exactly.
    #[must_use]
    pub fn to_fixed(&self) -> [i128; 3] {
        self.fixed
    }

    /// A sum from [`Self::to_fixed`]'s integers.
    #[must_use]
    pub fn from_fixed(fixed: [i128; 3]) -> Self {
        Self { fixed }
    }
}

/// Whether a splat channel can be fixed: finite and below [`MAX_SPLAT`] in magnitude.
#[inline]
fn fits(v: f32) -> bool {
    v.is_finite() && v.abs() < MAX_SPLAT
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Values spread over many magnitudes and both signs, so that float addition in
    /// different orders gives different bits.
    fn values() -> Vec<Rgb> {
        (0..200u32)
            .map(|i| {
                let e = (i * 7 % 121) as i32 - 60;
                let sign = if i % 5 == 0 { -1.0 } else { 1.0 };
                let v = sign * 1.37f32.powi(e) * (1.0 + (i % 13) as f32 / 13.0);
                Rgb::new(v, v * 1e6, v * 1e-6)
            })
            .collect()
    }

    #[test]
    fn any_order_and_grouping_gives_the_same_bits() {
        let vs = values();
        let mut forward = SplatSum::ZERO;
        vs.iter().for_each(|&v| assert!(forward.add(v)));
        let mut backward = SplatSum::ZERO;
        vs.iter().rev().for_each(|&v| assert!(backward.add(v)));
        let (mut left, mut right) = (SplatSum::ZERO, SplatSum::ZERO);
        vs[..77].iter().for_each(|&v| assert!(left.add(v)));
        vs[77..].iter().for_each(|&v| assert!(right.add(v)));
        right.merge(&left);
        assert_eq!(forward, backward);
        assert_eq!(forward, right);
        // The float sums in these two orders do differ (else the test shows nothing).
        let f = |it: &mut dyn Iterator<Item = &Rgb>| it.fold(0.0f64, |s, v| s + f64::from(v.g));
        assert_ne!(f(&mut vs.iter()).to_bits(), f(&mut vs.iter().rev()).to_bits());
    }

    #[test]
    fn sums_are_accurate() {
        let vs = values();
        let mut s = SplatSum::ZERO;
        vs.iter().for_each(|&v| assert!(s.add(v)));
        for c in 0..3 {
            let exact: f64 = vs.iter().map(|v| f64::from(v[c])).sum();
            let scale: f64 = vs.iter().map(|v| f64::from(v[c]).abs()).sum();
            // Each value is rounded to 2^-64 at worst; the f64 reference itself rounds.
            assert!((s.to_f64()[c] - exact).abs() <= 1e-12 * scale, "channel {c}");
        }
        let mut one = SplatSum::ZERO;
        assert!(one.add(Rgb::new(0.25, 3.0, 1e-9)));
        assert_eq!(one.to_f64()[0], 0.25);
        assert_eq!(one.to_f64()[1], 3.0);
    }

    #[test]
    fn non_finite_and_huge_splats_are_refused_whole() {
        let mut s = SplatSum::ZERO;
        assert!(!s.add(Rgb::new(1.0, f32::NAN, 1.0)));
        assert!(!s.add(Rgb::new(1.0, 1.0, f32::INFINITY)));
        assert!(!s.add(Rgb::new(-MAX_SPLAT, 1.0, 1.0)));
        assert!(s.is_zero());
        assert!(s.add(Rgb::splat(MAX_SPLAT * 0.99)));
        assert!(!s.is_zero());
    }

    #[test]
    fn accepts_exactly_what_quantize_takes() {
        let below = f32::from_bits(MAX_SPLAT.to_bits() - 1);
        for v in [
            0.0,
            -0.0,
            1.0,
            below,
            -below,
            MAX_SPLAT,
            -MAX_SPLAT,
            f32::MAX,
            f32::INFINITY,
            f32::NAN,
        ] {
            for l in [Rgb::new(v, 0.5, 0.5), Rgb::new(0.5, v, 0.5), Rgb::new(0.5, 0.5, v)] {
                assert_eq!(SplatSum::accepts(l), SplatSum::quantize(v).is_some(), "{v}");
            }
        }
    }

    #[test]
    fn fixed_point_round_trips() {
        let mut s = SplatSum::ZERO;
        assert!(s.add(Rgb::new(1.5, -2.0, 7e-15)));
        assert_eq!(SplatSum::from_fixed(s.to_fixed()), s);
    }
}
