//! pbrt-v4 `mix` texture: linear interpolation of two textures by a float texture.

use super::{FloatTexture, Texture, TextureContext, TextureValue};

/// `(1 - amount) tex1 + amount tex2`.
#[derive(Clone, Debug, PartialEq)]
pub struct MixTexture<T: TextureValue> {
    /// Value at `amount = 0`.
    pub tex1: Texture<T>,
    /// Value at `amount = 1`.
    pub tex2: Texture<T>,
    /// The interpolation weight.
    pub amount: FloatTexture,
}

impl<T: TextureValue> MixTexture<T> {
    /// The value at `ctx`; a texture with weight 0 is not evaluated (as pbrt-v4).
    #[must_use]
    pub fn evaluate(&self, ctx: &TextureContext) -> T {
        let amt = self.amount.evaluate(ctx);
        let t1 = if amt != 1.0 { self.tex1.evaluate(ctx) } else { T::ZERO };
        let t2 = if amt != 0.0 { self.tex2.evaluate(ctx) } else { T::ZERO };
        t1 * (1.0 - amt) + t2 * amt
    }
}
