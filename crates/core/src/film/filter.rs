//! Pixel reconstruction filters. Camera samples are not splatted: each is placed at the
//! pixel centre plus an offset `p` drawn from the filter by importance sampling, and
//! carries the weight `f(p) / (pdf(p) * integral of f)`, so the pixel value is
//! `sum weight * L / sum weight`. The weight is exactly 1 for the box and triangle filters,
//! whose sampling densities are proportional to them, close to 1 for the Gaussian, and
//! about plus or minus 1 for the Mitchell filter, sampled by `|f|` (negative in its lobes).
//! Light-tracing splats use [`Filter::evaluate`] instead ([`super::Splat`]).

mod box_filter;
mod gaussian_filter;
mod mitchell_filter;
mod triangle_filter;

pub use box_filter::BoxFilter;
pub use gaussian_filter::GaussianFilter;
pub use mitchell_filter::MitchellFilter;
pub use triangle_filter::TriangleFilter;

use super::FilterDesc;
use crate::math::Vec2;

/// An offset from the pixel centre drawn from a filter, with its weight.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilterSample {
    /// Offset from the pixel centre, in pixels, inside [-radius, radius].
    pub p: Vec2,
    /// `f(p) / (pdf(p) * integral of f)`: 1 on average, exactly 1 when the sampling
    /// density is proportional to the filter, negative where the filter is.
    pub weight: f32,
}

/// A pixel filter: a closed set of kinds, each in its own file.
#[derive(Clone, Debug, PartialEq)]
pub enum Filter {
    /// Constant over the square.
    Box(BoxFilter),
    /// Separable tent.
    Triangle(TriangleFilter),
    /// Separable truncated Gaussian.
    Gaussian(GaussianFilter),
    /// Separable Mitchell-Netravali cubic, with negative lobes.
    Mitchell(MitchellFilter),
}

/// Forwards a method call to the variant inside a [`Filter`].
macro_rules! dispatch {
    ($self:expr, $f:ident => $call:expr) => {
        match $self {
            Filter::Box($f) => $call,
            Filter::Triangle($f) => $call,
            Filter::Gaussian($f) => $call,
            Filter::Mitchell($f) => $call,
        }
    };
}

impl Filter {
    /// The filter a scene description asks for.
    ///
    /// # Panics
    /// If a radius or the Gaussian's sigma is not positive.
    #[must_use]
    pub fn new(desc: &FilterDesc) -> Self {
        match *desc {
            FilterDesc::Box { radius } => Self::Box(BoxFilter::new(radius)),
            FilterDesc::Triangle { radius } => Self::Triangle(TriangleFilter::new(radius)),
            FilterDesc::Gaussian { radius, sigma } => Self::Gaussian(GaussianFilter::new(radius, sigma)),
            FilterDesc::Mitchell { radius, b, c } => Self::Mitchell(MitchellFilter::new(radius, b, c)),
        }
    }

    /// Half-width of the support in each axis, in pixels.
    #[inline]
    #[must_use]
    pub fn radius(&self) -> Vec2 {
        dispatch!(self, f => f.radius())
    }

    /// The filter's value at offset `p` (zero outside the support).
    #[inline]
    #[must_use]
    pub fn evaluate(&self, p: Vec2) -> f32 {
        dispatch!(self, f => f.evaluate(p))
    }

    /// Integral of [`evaluate`](Self::evaluate) over the plane.
    #[inline]
    #[must_use]
    pub fn integral(&self) -> f32 {
        dispatch!(self, f => f.integral())
    }

    /// An offset drawn with density [`pdf`](Self::pdf) from `u` in [0, 1)^2, with its weight.
    #[inline]
    #[must_use]
    pub fn sample(&self, u: Vec2) -> FilterSample {
        dispatch!(self, f => f.sample(u))
    }

    /// Density per unit area of the offsets [`sample`](Self::sample) returns.
    #[inline]
    #[must_use]
    pub fn pdf(&self, p: Vec2) -> f32 {
        dispatch!(self, f => f.pdf(p))
    }
}

/// Bins of each axis's sampling table of the tabulated filters (Gaussian, Mitchell).
const BINS: usize = 128;
/// Simpson panels per bin when tabulating.
const PANELS_PER_BIN: usize = 8;

/// The sampling table of a separable filter's axis: the average of `g >= 0` over each of
/// [`BINS`] bins of [-radius, radius], by composite Simpson with [`PANELS_PER_BIN`] panels.
fn bin_averages(radius: f32, g: impl Fn(f64) -> f64) -> crate::sampling::PiecewiseConstant1D {
    let r = f64::from(radius);
    let width = 2.0 * r / BINS as f64;
    let h = width / PANELS_PER_BIN as f64;
    let averages: Vec<f32> = (0..BINS)
        .map(|i| {
            let a = -r + width * i as f64;
            let integral: f64 = (0..PANELS_PER_BIN)
                .map(|k| {
                    let t0 = a + h * k as f64;
                    h / 6.0 * (g(t0) + 4.0 * g(t0 + 0.5 * h) + g(t0 + h))
                })
                .sum();
            (integral / width) as f32
        })
        .collect();
    crate::sampling::PiecewiseConstant1D::new(&averages, -radius, radius)
}

#[cfg(test)]
mod tests;
