//! pbrt's `diffuse` material: Lambertian reflection, on both sides.

use super::checks::{check_rgb, InvalidParameter};
use super::params::unit;
use crate::bsdf::{Bxdf, DiffuseBxdf};
use crate::texture::{RgbTexture, TextureContext};

/// Lambertian reflection (pbrt `diffuse`).
#[derive(Clone, Debug, PartialEq)]
pub struct DiffuseMaterial {
    /// Albedo, clamped to [0, 1] where evaluated.
    pub reflectance: RgbTexture,
}

impl DiffuseMaterial {
    /// Check the parameters of material `index`.
    pub fn validate(&self, index: usize) -> Result<(), InvalidParameter> {
        check_rgb(index, "reflectance", &self.reflectance)
    }

    /// True when some parameter is a non-constant texture.
    #[must_use]
    pub fn is_textured(&self) -> bool {
        !self.reflectance.is_constant()
    }

    /// The lobe with the textures evaluated at `ctx`.
    #[must_use]
    pub fn bxdf(&self, ctx: &TextureContext) -> Bxdf {
        Bxdf::Diffuse(DiffuseBxdf {
            r: unit(self.reflectance.evaluate(ctx)),
        })
    }
}
