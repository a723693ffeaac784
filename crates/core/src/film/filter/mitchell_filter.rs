//! The Mitchell-Netravali filter (Mitchell and Netravali 1988; pbrt-v4 `MitchellFilter`):
//! a separable cubic with negative lobes, `m(2x / r_x) m(2y / r_y)` with `m` the
//! one-dimensional kernel of parameters `B` and `C` on [-2, 2].

use super::FilterSample;
use crate::math::Vec2;
use crate::sampling::PiecewiseConstant1D;

/// The Mitchell-Netravali kernel with parameters `b`, `c` at `x` (zero for `|x| > 2`); it
/// integrates to 1 over [-2, 2] for every `b`, `c`.
#[inline]
fn kernel(x: f32, b: f32, c: f32) -> f32 {
    let x = x.abs();
    let v = if x <= 1.0 {
        (12.0 - 9.0 * b - 6.0 * c) * x * x * x + (-18.0 + 12.0 * b + 6.0 * c) * x * x + (6.0 - 2.0 * b)
    } else if x <= 2.0 {
        (-b - 6.0 * c) * x * x * x + (6.0 * b + 30.0 * c) * x * x + (-12.0 * b - 48.0 * c) * x + (8.0 * b + 24.0 * c)
    } else {
        0.0
    };
    v / 6.0
}

/// Separable Mitchell-Netravali filter; negative in its outer lobes for the usual `B`, `C`.
/// Each axis is sampled from a table of the bin averages of `|m|`, so a sample's weight
/// `m(x) / (pdf(x) integral)` carries the sign of the filter there (pbrt-v4 samples the
/// same way, with a 2D table).
#[derive(Clone, Debug, PartialEq)]
pub struct MitchellFilter {
    radius: Vec2,
    b: f32,
    c: f32,
    x: PiecewiseConstant1D,
    y: PiecewiseConstant1D,
}

/// The table of bin averages of `|m(2t / r)|` over [-r, r], by composite Simpson.
fn tabulate(radius: f32, b: f32, c: f32) -> PiecewiseConstant1D {
    let r = f64::from(radius);
    let g = |t: f64| f64::from(kernel((2.0 * t / r) as f32, b, c)).abs();
    super::bin_averages(radius, g)
}

impl MitchellFilter {
    /// A Mitchell filter of half-widths `radius` and parameters `b`, `c` (pbrt's defaults
    /// are radius 2 and `b = c = 1/3`).
    ///
    /// # Panics
    /// If a radius is not positive.
    #[must_use]
    pub fn new(radius: Vec2, b: f32, c: f32) -> Self {
        assert!(
            radius.cmpgt(Vec2::ZERO).all(),
            "filter radius must be positive, got {radius}"
        );
        Self {
            radius,
            b,
            c,
            x: tabulate(radius.x, b, c),
            y: tabulate(radius.y, b, c),
        }
    }

    /// Half-widths of the support.
    #[inline]
    #[must_use]
    pub fn radius(&self) -> Vec2 {
        self.radius
    }

    /// `m(2 p.x / r_x) m(2 p.y / r_y)`; zero outside the support, negative in the lobes.
    #[inline]
    #[must_use]
    pub fn evaluate(&self, p: Vec2) -> f32 {
        if p.abs().cmpgt(self.radius).any() {
            return 0.0;
        }
        kernel(2.0 * p.x / self.radius.x, self.b, self.c) * kernel(2.0 * p.y / self.radius.y, self.b, self.c)
    }

    /// `r_x r_y / 4`: the kernel integrates to 1 over [-2, 2], so each axis to `r / 2`.
    #[inline]
    #[must_use]
    pub fn integral(&self) -> f32 {
        self.radius.x * self.radius.y / 4.0
    }

    /// An offset drawn from the tables of `|m|`, with the signed weight
    /// `f(p) / (pdf(p) integral)`.
    #[inline]
    #[must_use]
    pub fn sample(&self, u: Vec2) -> FilterSample {
        let (x, pdf_x, _) = self.x.sample(u.x);
        let (y, pdf_y, _) = self.y.sample(u.y);
        let wx = kernel(2.0 * x / self.radius.x, self.b, self.c) / (pdf_x * 0.5 * self.radius.x);
        let wy = kernel(2.0 * y / self.radius.y, self.b, self.c) / (pdf_y * 0.5 * self.radius.y);
        FilterSample {
            p: Vec2::new(x, y),
            weight: wx * wy,
        }
    }

    /// Density of [`sample`](Self::sample): product of the tabulated axis densities.
    #[inline]
    #[must_use]
    pub fn pdf(&self, p: Vec2) -> f32 {
        self.x.pdf(p.x) * self.y.pdf(p.y)
    }
}
