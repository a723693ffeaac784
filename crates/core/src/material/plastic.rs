//! Mitsuba 3's `plastic` and `roughplastic` (see `bsdf::PlasticBxdf`): a dielectric coat
//! over a diffuse base with the internal scattering summed in closed form; not pbrt's
//! `coateddiffuse`.

use super::checks::{check_positive_eta, check_rgb, invalid, InvalidParameter};
use super::params::unit;
use crate::bsdf::{Bxdf, PlasticBxdf, PlasticCoat};
use crate::texture::{RgbTexture, TextureContext};

/// Mitsuba's plastic.
#[derive(Clone, Debug, PartialEq)]
pub struct PlasticMaterial {
    /// Albedo of the base, in [0, 1] (clamped per hit).
    pub diffuse_reflectance: RgbTexture,
    /// Tint of the coat's reflection (Mitsuba default 1).
    pub specular_reflectance: RgbTexture,
    /// Account for the colour shift of internal scattering (Mitsuba's `nonlinear`).
    pub nonlinear: bool,
    /// Mitsuba's specular sampling weight, `mean(specular) / (mean(diffuse) +
    /// mean(specular))` over the textures, in [0, 1].
    pub specular_sampling_weight: f32,
    /// The coat: index of refraction and roughness, with its precomputed tables.
    pub coat: PlasticCoat,
}

impl PlasticMaterial {
    /// Check the parameters of material `index`.
    pub fn validate(&self, index: usize) -> Result<(), InvalidParameter> {
        check_rgb(index, "diffuse reflectance", &self.diffuse_reflectance)?;
        check_rgb(index, "specular reflectance", &self.specular_reflectance)?;
        check_positive_eta(index, self.coat.eta())?;
        let w = self.specular_sampling_weight;
        if !(0.0..=1.0).contains(&w) {
            return Err(invalid(
                format!("specular sampling weight of material {index}"),
                format!("expected in [0, 1], found {w}"),
            ));
        }
        Ok(())
    }

    /// True when some parameter is a non-constant texture.
    #[must_use]
    pub fn is_textured(&self) -> bool {
        !(self.diffuse_reflectance.is_constant() && self.specular_reflectance.is_constant())
    }

    /// The lobe with the textures evaluated at `ctx`.
    #[must_use]
    pub fn bxdf(&self, ctx: &TextureContext) -> Bxdf {
        Bxdf::Plastic(PlasticBxdf {
            coat: self.coat,
            diffuse: unit(self.diffuse_reflectance.evaluate(ctx)),
            specular: self.specular_reflectance.evaluate(ctx).map(|v| v.max(0.0)),
            nonlinear: self.nonlinear,
            specular_sampling_weight: self.specular_sampling_weight.clamp(0.0, 1.0),
        })
    }
}
