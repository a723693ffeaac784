//! The box filter: constant over [-r, r]^2.

use super::FilterSample;
use crate::math::Vec2;

/// 1 on [-radius, radius]^2, 0 elsewhere; sampled uniformly, so every weight is 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoxFilter {
    radius: Vec2,
}

impl BoxFilter {
    /// A box of half-widths `radius`.
    ///
    /// # Panics
    /// If a radius is not positive.
    #[must_use]
    pub fn new(radius: Vec2) -> Self {
        assert!(
            radius.cmpgt(Vec2::ZERO).all(),
            "filter radius must be positive, got {radius}"
        );
        Self { radius }
    }

    /// Half-widths of the support.
    #[inline]
    #[must_use]
    pub fn radius(&self) -> Vec2 {
        self.radius
    }

    /// 1 inside the box, 0 outside.
    #[inline]
    #[must_use]
    pub fn evaluate(&self, p: Vec2) -> f32 {
        if p.abs().cmple(self.radius).all() {
            1.0
        } else {
            0.0
        }
    }

    /// The box's area, 4 r_x r_y.
    #[inline]
    #[must_use]
    pub fn integral(&self) -> f32 {
        4.0 * self.radius.x * self.radius.y
    }

    /// A uniform offset in the box; weight 1.
    #[inline]
    #[must_use]
    pub fn sample(&self, u: Vec2) -> FilterSample {
        FilterSample {
            p: (2.0 * u - Vec2::ONE) * self.radius,
            weight: 1.0,
        }
    }

    /// 1 / area inside the box.
    #[inline]
    #[must_use]
    pub fn pdf(&self, p: Vec2) -> f32 {
        self.evaluate(p) / self.integral()
    }
}
