//! The 2-D checkerboard (pbrt-v4 section 10.5.1, `Checkerboard()`): squares of unit size in
//! `(s, t)`, `tex1` where `floor(s) + floor(t)` is even, `tex2` where it is odd. Box
//! filtered in closed form: the checker function is convolved with a tent of half-width
//! `1.5 max(|ds/dx|, |ds/dy|)` along s (and likewise along t), as pbrt-v4 does.

use super::Texture;
use super::{TextureContext, TextureMapping, TextureValue};

/// A checkerboard of two textures.
#[derive(Clone, Debug, PartialEq)]
pub struct CheckerboardTexture<T: TextureValue> {
    /// Coordinates.
    pub mapping: TextureMapping,
    /// Texture of the even squares.
    pub tex1: Texture<T>,
    /// Texture of the odd squares.
    pub tex2: Texture<T>,
}

impl<T: TextureValue> CheckerboardTexture<T> {
    /// The filtered value at `ctx`.
    #[must_use]
    pub fn evaluate(&self, ctx: &TextureContext) -> T {
        let w = checkerboard_weight(&self.mapping, ctx);
        let t1 = if w != 1.0 { self.tex1.evaluate(ctx) } else { T::ZERO };
        let t2 = if w != 0.0 { self.tex2.evaluate(ctx) } else { T::ZERO };
        t1 * (1.0 - w) + t2 * w
    }
}

/// Weight of `tex2` at `ctx`: 0 or 1 inside a square, in between where the footprint
/// straddles square edges.
#[must_use]
pub fn checkerboard_weight(mapping: &TextureMapping, ctx: &TextureContext) -> f32 {
    let c = mapping.map(ctx);
    let ds = 1.5 * c.dsdx.abs().max(c.dsdy.abs());
    let dt = 1.5 * c.dtdx.abs().max(c.dtdy.abs());
    0.5 - 0.5 * filtered_square_wave(c.st.x, ds) * filtered_square_wave(c.st.y, dt)
}

/// The square wave `+1` on even unit intervals, `-1` on odd ones, convolved with a tent
/// of half-width `r` (pbrt-v4's `bf`): the second difference of its double integral `d`.
fn filtered_square_wave(x: f32, r: f32) -> f32 {
    if (x - r).floor() == (x + r).floor() {
        return 1.0 - 2.0 * ((x.floor() as i64) & 1) as f32;
    }
    // Double integral of the square wave.
    let d = |x: f32| {
        let y = x / 2.0 - (x / 2.0).floor() - 0.5;
        x / 2.0 + y * (1.0 - 2.0 * y.abs())
    };
    (d(x + r) - 2.0 * d(x) + d(x - r)) / (r * r)
}
