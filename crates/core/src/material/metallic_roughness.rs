//! glTF 2.0's metallic-roughness material (the BRDF of the glTF specification's
//! Appendix B, see `bsdf::MetallicRoughnessBxdf`).

use super::checks::{check_non_negative, check_rgb, float_constants, InvalidParameter};
use crate::bsdf::{Bxdf, MetallicRoughnessBxdf};
use crate::texture::{FloatTexture, RgbTexture, TextureContext};

/// glTF's metallic-roughness material.
#[derive(Clone, Debug, PartialEq)]
pub struct MetallicRoughnessMaterial {
    /// Base colour, in [0, 1] (clamped per hit).
    pub base_color: RgbTexture,
    /// Metalness, in [0, 1] (clamped per hit).
    pub metallic: FloatTexture,
    /// Perceptual roughness in [0, 1]; the GGX alpha is its square.
    pub roughness: FloatTexture,
}

impl MetallicRoughnessMaterial {
    /// Check the parameters of material `index`.
    pub fn validate(&self, index: usize) -> Result<(), InvalidParameter> {
        check_rgb(index, "base colour", &self.base_color)?;
        check_non_negative(
            &format!("metallic and roughness of material {index}"),
            &float_constants(&[&self.metallic, &self.roughness]),
        )
    }

    /// True when some parameter is a non-constant texture.
    #[must_use]
    pub fn is_textured(&self) -> bool {
        !(self.base_color.is_constant() && self.metallic.is_constant() && self.roughness.is_constant())
    }

    /// The lobe with the textures evaluated at `ctx`.
    #[must_use]
    pub fn bxdf(&self, ctx: &TextureContext) -> Bxdf {
        Bxdf::MetallicRoughness(MetallicRoughnessBxdf::new(
            self.base_color.evaluate(ctx),
            self.metallic.evaluate(ctx),
            self.roughness.evaluate(ctx),
        ))
    }
}
