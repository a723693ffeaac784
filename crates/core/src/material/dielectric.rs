//! pbrt's `dielectric` (and Mitsuba's `dielectric` / `roughdielectric`): glass, water;
//! reflection and refraction, smooth or rough.

use super::checks::{check_positive_eta, check_roughness, InvalidParameter};
use super::params::alpha;
use crate::bsdf::{Bxdf, DielectricBxdf, MicrofacetStyle};
use crate::texture::{FloatTexture, TextureContext};

/// Glass, water (pbrt `dielectric`).
#[derive(Clone, Debug, PartialEq)]
pub struct DielectricMaterial {
    /// Index of refraction of the inside (the side opposite the surface normal) over
    /// the outside; 1 passes light straight through.
    pub eta: f32,
    /// Roughness along the shading tangent.
    pub u_roughness: FloatTexture,
    /// Roughness along the bitangent.
    pub v_roughness: FloatTexture,
    /// As for [`super::ConductorMaterial::remap_roughness`].
    pub remap_roughness: bool,
    /// As for [`super::ConductorMaterial::microfacet`].
    pub microfacet: MicrofacetStyle,
}

impl DielectricMaterial {
    /// Check the parameters of material `index`.
    pub fn validate(&self, index: usize) -> Result<(), InvalidParameter> {
        check_positive_eta(index, self.eta)?;
        check_roughness(index, &[&self.u_roughness, &self.v_roughness])
    }

    /// True when some parameter is a non-constant texture.
    #[must_use]
    pub fn is_textured(&self) -> bool {
        !(self.u_roughness.is_constant() && self.v_roughness.is_constant())
    }

    /// The lobe with the textures evaluated at `ctx`.
    #[must_use]
    pub fn bxdf(&self, ctx: &TextureContext) -> Bxdf {
        Bxdf::Dielectric(DielectricBxdf {
            eta: self.eta,
            distrib: self.microfacet.distribution(
                alpha(self.u_roughness.evaluate(ctx), self.remap_roughness),
                alpha(self.v_roughness.evaluate(ctx), self.remap_roughness),
            ),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_support::bxdf;
    use super::super::MaterialDesc;
    use super::*;

    #[test]
    fn roughness_is_remapped_only_when_asked() {
        for (remap, expected) in [(true, 0.5), (false, 0.25)] {
            let m = MaterialDesc::Dielectric(DielectricMaterial {
                eta: 1.5,
                u_roughness: 0.25.into(),
                v_roughness: 0.0.into(),
                remap_roughness: remap,
                microfacet: MicrofacetStyle::default(),
            });
            let Bxdf::Dielectric(DielectricBxdf { distrib, .. }) = bxdf(&m) else {
                panic!()
            };
            assert_eq!((distrib.alpha_x, distrib.alpha_y), (expected, 0.0));
        }
    }
}
