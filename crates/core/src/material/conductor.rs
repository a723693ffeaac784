//! pbrt's `conductor` (and Mitsuba's `conductor` / `roughconductor`): a metal, a mirror
//! or a microfacet surface, with Fresnel from a complex index of refraction per channel.

use super::checks::{check_rgb, check_roughness, InvalidParameter};
use super::params::{alpha, index_from_reflectance};
use crate::bsdf::{Bxdf, ConductorBxdf, MicrofacetStyle};
use crate::texture::{FloatTexture, RgbTexture, TextureContext};

/// A metal (pbrt `conductor`): a mirror, or a microfacet surface when rough.
#[derive(Clone, Debug, PartialEq)]
pub struct ConductorMaterial {
    /// Real part of the index of refraction (relative to the outside), per channel.
    pub eta: RgbTexture,
    /// Imaginary part (absorption), per channel.
    pub k: RgbTexture,
    /// When given, replaces `eta` and `k` as pbrt does: `eta = 1`,
    /// `k = 2 sqrt(r) / sqrt(1 - r)`, the index whose normal-incidence reflectance is
    /// `r` (clamped to [0, 0.9999]).
    pub reflectance: Option<RgbTexture>,
    /// Roughness along the shading tangent (`dpdu`).
    pub u_roughness: FloatTexture,
    /// Roughness along the bitangent.
    pub v_roughness: FloatTexture,
    /// Map roughness to microfacet alpha by `sqrt` (pbrt's `remaproughness`, default
    /// true); otherwise the roughness is alpha itself.
    pub remap_roughness: bool,
    /// Microfacet distribution and masking term (default pbrt-v4's).
    pub microfacet: MicrofacetStyle,
}

impl ConductorMaterial {
    /// Check the parameters of material `index`.
    pub fn validate(&self, index: usize) -> Result<(), InvalidParameter> {
        check_rgb(index, "eta", &self.eta)?;
        check_rgb(index, "k", &self.k)?;
        if let Some(r) = &self.reflectance {
            check_rgb(index, "reflectance", r)?;
        }
        check_roughness(index, &[&self.u_roughness, &self.v_roughness])
    }

    /// True when some parameter is a non-constant texture.
    #[must_use]
    pub fn is_textured(&self) -> bool {
        !(self.eta.is_constant()
            && self.k.is_constant()
            && self.reflectance.as_ref().is_none_or(RgbTexture::is_constant)
            && self.u_roughness.is_constant()
            && self.v_roughness.is_constant())
    }

    /// The lobe with the textures evaluated at `ctx`.
    #[must_use]
    pub fn bxdf(&self, ctx: &TextureContext) -> Bxdf {
        let (eta, k) = match &self.reflectance {
            Some(r) => index_from_reflectance(r.evaluate(ctx)),
            None => (self.eta.evaluate(ctx), self.k.evaluate(ctx)),
        };
        let distrib = self.microfacet.distribution(
            alpha(self.u_roughness.evaluate(ctx), self.remap_roughness),
            alpha(self.v_roughness.evaluate(ctx), self.remap_roughness),
        );
        Bxdf::Conductor(ConductorBxdf { distrib, eta, k })
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_support::bxdf;
    use super::super::MaterialDesc;
    use super::*;
    use crate::bsdf::fresnel::fr_complex;
    use crate::color::Rgb;

    #[test]
    fn conductor_reflectance_becomes_an_index_with_that_normal_reflectance() {
        let r = Rgb::new(0.9, 0.5, 0.0);
        let m = MaterialDesc::Conductor(ConductorMaterial {
            eta: Rgb::splat(0.2).into(),
            k: Rgb::splat(3.0).into(),
            reflectance: Some(r.into()),
            u_roughness: 0.0.into(),
            v_roughness: 0.0.into(),
            remap_roughness: true,
            microfacet: MicrofacetStyle::default(),
        });
        let Bxdf::Conductor(ConductorBxdf { eta, k, .. }) = bxdf(&m) else {
            panic!("{m:?}")
        };
        assert_eq!(eta, Rgb::WHITE);
        let f0 = fr_complex(1.0, eta, k);
        assert!(
            (f0 - r).max_component().abs() < 1e-5 && (r - f0).max_component().abs() < 1e-5,
            "{f0:?}"
        );
    }
}
