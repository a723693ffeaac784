//! Image textures (pbrt-v4 `imagemap`, section 10.4): a MIP-mapped image looked up at the
//! mapped coordinates with `t` flipped (so `t = 0` is the bottom row), then `scale`d,
//! optionally inverted (`1 - v`) and clamped to non-negative values. Float image textures read the first (red) channel, as pbrt-v4's
//! `MIPMap::Texel<Float>` does.

use std::sync::Arc;

use super::{MipFilterOptions, MipMap, TextureContext, TextureMapping};
use crate::color::Rgb;
use crate::math::Vec2;

/// An image on a surface.
#[derive(Clone, Debug, PartialEq)]
pub struct ImageTexture {
    /// Coordinates.
    pub mapping: TextureMapping,
    /// The pyramid, shared by every texture that uses the same image.
    pub mipmap: Arc<MipMap>,
    /// Lookup filter.
    pub filter: MipFilterOptions,
    /// Factor on the looked-up value.
    pub scale: f32,
    /// Return `max(0, 1 - value)` instead of the value.
    pub invert: bool,
}

impl ImageTexture {
    /// The filtered RGB value at `ctx`.
    #[must_use]
    pub fn evaluate_rgb(&self, ctx: &TextureContext) -> Rgb {
        let c = self.mapping.map(ctx);
        let st = Vec2::new(c.st.x, 1.0 - c.st.y);
        let v = self
            .mipmap
            .filter(&self.filter, st, Vec2::new(c.dsdx, c.dtdx), Vec2::new(c.dsdy, c.dtdy))
            * self.scale;
        // Negative values are clamped away in both cases, as pbrt-v4 does.
        if self.invert {
            v.map(|x| (1.0 - x).max(0.0))
        } else {
            v.map(|x| x.max(0.0))
        }
    }
}
