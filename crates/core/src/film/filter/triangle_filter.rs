//! The triangle filter: a separable tent.

use super::FilterSample;
use crate::math::Vec2;
use crate::sampling::{sample_tent, tent_pdf};

/// `max(0, r_x - |x|) max(0, r_y - |y|)`, sampled exactly by two tent warps, so every
/// weight is 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleFilter {
    radius: Vec2,
}

impl TriangleFilter {
    /// A tent of half-widths `radius`.
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

    /// `max(0, r_x - |x|) max(0, r_y - |y|)`.
    #[inline]
    #[must_use]
    pub fn evaluate(&self, p: Vec2) -> f32 {
        let d = (self.radius - p.abs()).max(Vec2::ZERO);
        d.x * d.y
    }

    /// `r_x^2 r_y^2`: each tent has area r^2.
    #[inline]
    #[must_use]
    pub fn integral(&self) -> f32 {
        let r2 = self.radius * self.radius;
        r2.x * r2.y
    }

    /// An offset with a tent distribution in each axis; weight 1.
    #[inline]
    #[must_use]
    pub fn sample(&self, u: Vec2) -> FilterSample {
        let p = Vec2::new(sample_tent(u.x, self.radius.x), sample_tent(u.y, self.radius.y));
        FilterSample { p, weight: 1.0 }
    }

    /// Product of the two tent pdfs.
    #[inline]
    #[must_use]
    pub fn pdf(&self, p: Vec2) -> f32 {
        tent_pdf(p.x, self.radius.x) * tent_pdf(p.y, self.radius.y)
    }
}
