//! Splats: radiance that lands on the film at a position of its own rather than at a
//! camera sample of the pixel being rendered (light tracing, bidirectional path tracing's
//! `t = 1` strategies, Metropolis light transport).
//!
//! A splat at raster position `x` with value `L` adds `L f(x - c_j) / F` to the splat sum
//! of every pixel `j` whose filter covers it, `c_j` the pixel's centre, `f` the scene's
//! pixel filter and `F` its integral (pbrt-v4 `RGBFilm::AddSplat`, which divides by `F`
//! when the pixel is read; we divide when adding, which only rounds differently). The
//! displayed pixel is the weighted mean of its own camera samples plus `splat_sum / spp`,
//! with `spp` the samples per pixel of the whole image.
//!
//! **Why this is unbiased for the filtered pixel integral.** Write `L(x)` for the
//! radiance (averaged over the lens) reaching the film point `x` (raster units; the image
//! has `n` pixels of unit area). Pixel `j`'s value is
//!
//! `I_j = integral f(x - c_j) L(x) dx / F`.
//!
//! The camera estimates it by drawing offsets `x - c_j` from the filter with density `p`
//! and weighting each sample by `w = f / (p F)` (`E[w] = 1`, and
//! `E[w L] = integral f L / F = I_j`); the pixel is `sum w L / sum w` ([`super::Filter`]).
//! A camera sample drawn this way is a camera ray whose importance, per unit lens area and
//! solid angle, is `W_j = n We f(x - c_j) / F`, with `We` the importance of a film point
//! chosen uniformly over the `n` pixels ([`crate::camera`]): `I_j = <W_j, L>`, the
//! measurement equation. A light path connected to the lens through film point `x` has
//! the value `We T / pdf` (`T` the throughput of the whole path, `pdf` its density; this
//! is the splat's `L`), whose expectation is `<We g, L>` for any weight `g(x)` applied to
//! it; with `g = n f(x - c_j) / F` that is `I_j`. One light path is traced per camera
//! sample, `n spp` in all, so their average,
//! `(1 / (n spp)) sum_paths n L f(x - c_j) / F = (1 / spp) sum_paths L f(x - c_j) / F`,
//! estimates `I_j` without bias: exactly the pixel's splat sum over `spp`. Two
//! conditions make it hold at every pixel:
//!
//! - The light path must be able to land wherever `f(x - c_j) != 0` for some pixel `j`,
//!   i.e. on the film's *sample bounds* (pixel bounds grown by the filter radius less half
//!   a pixel), so the camera's `We`, `pdf_we` and `sample_wi` accept those points
//!   ([`crate::camera::PerspectiveCamera::sample_bounds`]); splatting with the filter but
//!   cutting the importance at the pixel bounds would darken the border pixels (and a
//!   splat at one pixel with weight one estimates the box-filtered image instead, which
//!   differs from the camera's at every edge).
//! - `We` keeps the normalisation of the pixel bounds (`A` and `n` above) over the wider
//!   bounds: only the support grows.
//!
//! Nothing requires `f >= 0`. For filters with negative lobes (Mitchell, Lanczos) the
//! camera samples `|f|` and carries signed weights, and a splat adds signed amounts
//! `L f / F`: the argument above is linear in `f` and holds as written, and the fixed-point
//! splat sums ([`super::SplatSum`]) are signed integers, exact in any order. A pixel's
//! splat sum can then be negative, as its camera estimate can.
//!
//! In BDPT both estimates meet in one pixel: the camera-side strategies through the pixel's
//! weighted mean, the `t = 1` strategies through its splats. Their MIS weights
//! (`integrator::BdptIntegrator`) use the same `pdf_we` for every strategy and sum
//! to one for every path, and every strategy can produce every path whose film point lies
//! in the support of the pixel's filter, so the sum is the same filtered integral. The
//! only bias left is that of the camera side's ratio estimator `sum w L / sum w`, of order
//! `1 / spp` and zero when every weight is one (box and triangle filters).
//!
//! Determinism: each (splat, pixel) amount is rounded to fixed point on its own, whatever
//! else lands on the pixel, so any order, any thread count and any split of the image into
//! windows (a splat near a window's edge adds to pixels of two windows, and
//! [`super::Film::combine_disjoint`] adds the windows' splat sums) gives the same bits.

use super::{Filter, SplatSum};
use crate::color::Rgb;
use crate::math::{ceil_to_i64, floor_to_i64, Vec2};

/// One contribution to the pixels whose filter covers `p_film`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Splat {
    /// Raster position, the space of [`crate::camera::Camera::generate_ray`]'s `p_film`
    /// (pixel `(x, y)` covers `[x, x + 1) x [y, y + 1)`, its centre at `(x + 0.5, y + 0.5)`).
    pub p_film: Vec2,
    /// Radiance contributed (already divided by the path's pdf, not yet by the spp).
    pub l: Rgb,
}

/// The pixels a splat may touch: columns `x0..x1`, rows `y0..y1` (inside the image).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Footprint {
    /// First column.
    pub x0: u32,
    /// One past the last column.
    pub x1: u32,
    /// First row.
    pub y0: u32,
    /// One past the last row.
    pub y1: u32,
}

impl Splat {
    /// The pixels whose centres lie within the filter's radius of the splat, clipped to a
    /// `width x height` image; `None` when there are none or when the value cannot be
    /// added (not finite, or beyond [`super::MAX_SPLAT`]).
    #[must_use]
    pub fn footprint(&self, filter: &Filter, width: u32, height: u32) -> Option<Footprint> {
        if !SplatSum::accepts(self.l) || !self.p_film.is_finite() {
            return None;
        }
        // Pixel x's centre x + 0.5 within r of p: x in [p - 0.5 - r, p - 0.5 + r].
        let r = filter.radius();
        let (lo, hi) = (self.p_film - Vec2::splat(0.5) - r, self.p_film - Vec2::splat(0.5) + r);
        let clip = |v: i64, n: u32| v.clamp(0, i64::from(n)) as u32;
        let f = Footprint {
            x0: clip(ceil_to_i64(lo.x), width),
            x1: clip(floor_to_i64(hi.x).saturating_add(1), width),
            y0: clip(ceil_to_i64(lo.y), height),
            y1: clip(floor_to_i64(hi.y).saturating_add(1), height),
        };
        (f.x0 < f.x1 && f.y0 < f.y1).then_some(f)
    }

    /// The weight `f(p_film - centre) / integral of f` of pixel `(x, y)` (zero outside the
    /// filter; negative in a filter's negative lobes).
    #[inline]
    #[must_use]
    pub fn weight(&self, filter: &Filter, inv_integral: f32, x: u32, y: u32) -> f32 {
        let centre = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
        filter.evaluate(self.p_film - centre) * inv_integral
    }
}
