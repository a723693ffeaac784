//! TEMPORARY stand-in: replaced by the full filter module when the sampling branch merges.

use crate::math::Vec2;
use crate::scene::FilterDesc;

/// Filter sample.
#[derive(Clone, Copy, Debug)]
pub struct FilterSample {
    /// Offset.
    pub p: Vec2,
    /// Weight.
    pub weight: f32,
}

/// Filter.
#[derive(Clone, Debug)]
pub struct Filter {
    radius: Vec2,
    tent: bool,
}

impl Filter {
    /// New.
    #[must_use]
    pub fn new(d: &FilterDesc) -> Self {
        match *d {
            FilterDesc::Box { radius } => Self {
                radius,
                tent: false,
            },
            FilterDesc::Triangle { radius } | FilterDesc::Gaussian { radius, .. } => {
                Self { radius, tent: true }
            }
        }
    }
    /// Sample.
    #[must_use]
    pub fn sample(&self, u: Vec2) -> FilterSample {
        let f = |u: f32, r: f32| {
            if !self.tent {
                return (2.0 * u - 1.0) * r;
            }
            if u < 0.5 {
                -r + r * (2.0 * u).sqrt()
            } else {
                r - r * (2.0 - 2.0 * u).sqrt()
            }
        };
        FilterSample {
            p: Vec2::new(f(u.x, self.radius.x), f(u.y, self.radius.y)),
            weight: 1.0,
        }
    }
}
