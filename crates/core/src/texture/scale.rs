//! pbrt-v4 `scale` texture: the product of a texture and a float texture.

use super::{FloatTexture, Texture, TextureContext, TextureValue};

/// `tex * scale`.
#[derive(Clone, Debug, PartialEq)]
pub struct ScaleTexture<T: TextureValue> {
    /// The texture.
    pub tex: Texture<T>,
    /// Its factor.
    pub scale: FloatTexture,
}

impl<T: TextureValue> ScaleTexture<T> {
    /// The value at `ctx`; `tex` is not evaluated where the scale is 0 (as pbrt-v4).
    #[must_use]
    pub fn evaluate(&self, ctx: &TextureContext) -> T {
        let s = self.scale.evaluate(ctx);
        if s == 0.0 {
            return T::ZERO;
        }
        self.tex.evaluate(ctx) * s
    }
}
