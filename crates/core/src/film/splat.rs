//! Splats: radiance that lands on a pixel other than the one whose sample produced it
//! (light tracing, bidirectional path tracing).
//!
//! A splat adds to its pixel's splat sum with weight one (a box filter one pixel wide,
//! whatever the scene's filter), and the displayed pixel value is the weighted mean of the
//! pixel's own samples plus `splat_sum / spp`, with `spp` the samples per pixel of the whole
//! image (pbrt-v4 `RGBFilm::AddSplat`, with the splats scaled by `1 / spp` when the image is
//! written): every camera sample is a path from the image, so a splat's estimate is per
//! image sample, not per sample of the pixel it lands on.

use crate::color::Rgb;
use crate::math::Vec2;

/// One contribution to the pixel containing `p_film`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Splat {
    /// Raster position, the space of [`crate::camera::Camera::generate_ray`]'s `p_film`
    /// (pixel `(x, y)` covers `[x, x + 1) x [y, y + 1)`).
    pub p_film: Vec2,
    /// Radiance contributed (already divided by the path's pdf, not yet by the spp).
    pub l: Rgb,
}
