//! pbrt's `coatedconductor`: a dielectric coat over a conductor with a scattering slab
//! between them, evaluated stochastically (`bsdf::LayeredBxdf`).

use super::checks::{check_positive_eta, check_rgb, check_roughness, check_slab, InvalidParameter};
use super::params::{alpha, coat, index_from_reflectance, slab_at, slab_is_constant};
use crate::bsdf::{Bxdf, ConductorBxdf, LayeredBxdf, Microfacet};
use crate::texture::{FloatTexture, RgbTexture, TextureContext};

/// A coated metal (pbrt `coatedconductor`).
#[derive(Clone, Debug, PartialEq)]
pub struct CoatedConductorMaterial {
    /// Coat roughness along the shading tangent.
    pub interface_u_roughness: FloatTexture,
    /// Coat roughness along the bitangent.
    pub interface_v_roughness: FloatTexture,
    /// Index of refraction of the coat (pbrt default 1.5); 0 means 1.
    pub interface_eta: f32,
    /// Real part of the conductor's index of refraction, relative to vacuum as pbrt
    /// gives it (divided by the coat's index when the BSDF is built).
    pub conductor_eta: RgbTexture,
    /// Imaginary part, relative to vacuum (divided likewise).
    pub conductor_k: RgbTexture,
    /// When given, replaces `conductor_eta` and `conductor_k` as for
    /// [`super::ConductorMaterial::reflectance`] (relative to the coat).
    pub reflectance: Option<RgbTexture>,
    /// Conductor roughness along the shading tangent.
    pub conductor_u_roughness: FloatTexture,
    /// Conductor roughness along the bitangent.
    pub conductor_v_roughness: FloatTexture,
    /// Remap both roughnesses as for [`super::ConductorMaterial::remap_roughness`].
    pub remap_roughness: bool,
    /// Slab thickness in mean free paths (pbrt default 0.01).
    pub thickness: FloatTexture,
    /// Single-scattering albedo of the slab (pbrt default 0).
    pub albedo: RgbTexture,
    /// Henyey-Greenstein asymmetry of the slab (pbrt default 0).
    pub g: FloatTexture,
    /// Maximum scattering events of a random walk (pbrt default 10).
    pub max_depth: u32,
    /// Random walks per evaluation (pbrt default 1).
    pub n_samples: u32,
}

impl CoatedConductorMaterial {
    /// Check the parameters of material `index`.
    pub fn validate(&self, index: usize) -> Result<(), InvalidParameter> {
        check_roughness(
            index,
            &[
                &self.interface_u_roughness,
                &self.interface_v_roughness,
                &self.conductor_u_roughness,
                &self.conductor_v_roughness,
            ],
        )?;
        check_positive_eta(index, self.interface_eta)?;
        check_rgb(index, "conductor eta", &self.conductor_eta)?;
        check_rgb(index, "conductor k", &self.conductor_k)?;
        if let Some(r) = &self.reflectance {
            check_rgb(index, "reflectance", r)?;
        }
        check_slab(index, &self.thickness, &self.albedo, &self.g)
    }

    /// True when some parameter is a non-constant texture.
    #[must_use]
    pub fn is_textured(&self) -> bool {
        !(self.interface_u_roughness.is_constant()
            && self.interface_v_roughness.is_constant()
            && self.conductor_eta.is_constant()
            && self.conductor_k.is_constant()
            && self.reflectance.as_ref().is_none_or(RgbTexture::is_constant)
            && self.conductor_u_roughness.is_constant()
            && self.conductor_v_roughness.is_constant()
            && slab_is_constant(&self.thickness, &self.albedo, &self.g))
    }

    /// The stochastic layered lobe with the textures evaluated at `ctx`.
    #[must_use]
    pub fn bxdf(&self, ctx: &TextureContext) -> Bxdf {
        let (thickness, albedo, g) = slab_at(&self.thickness, &self.albedo, &self.g, ctx);
        let top = coat(
            self.interface_eta,
            self.interface_u_roughness.evaluate(ctx),
            self.interface_v_roughness.evaluate(ctx),
            self.remap_roughness,
        );
        let (eta, k) = match &self.reflectance {
            Some(r) => index_from_reflectance(r.evaluate(ctx)),
            None => (self.conductor_eta.evaluate(ctx), self.conductor_k.evaluate(ctx)),
        };
        Bxdf::CoatedConductor(LayeredBxdf {
            top,
            // pbrt-v4: the base's index is relative to the coat above it.
            bottom: ConductorBxdf {
                distrib: Microfacet::trowbridge_reitz(
                    alpha(self.conductor_u_roughness.evaluate(ctx), self.remap_roughness),
                    alpha(self.conductor_v_roughness.evaluate(ctx), self.remap_roughness),
                ),
                eta: eta / top.eta,
                k: k / top.eta,
            },
            thickness,
            albedo,
            g,
            max_depth: self.max_depth,
            n_samples: self.n_samples.max(1),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_support::{bxdf, scaled};
    use super::super::MaterialDesc;
    use super::*;
    use crate::color::Rgb;

    #[test]
    fn coated_conductor_parameters_are_textures_evaluated_per_hit() {
        let m = MaterialDesc::CoatedConductor(CoatedConductorMaterial {
            interface_u_roughness: scaled(0.1, 2.0),
            interface_v_roughness: 0.1.into(),
            interface_eta: 2.0,
            conductor_eta: scaled(Rgb::splat(0.5), 2.0),
            conductor_k: scaled(Rgb::splat(2.0), 2.0),
            reflectance: None,
            conductor_u_roughness: scaled(0.2, 2.0),
            conductor_v_roughness: 0.2.into(),
            remap_roughness: false,
            thickness: scaled(0.1, 3.0),
            albedo: Rgb::BLACK.into(),
            g: 0.0.into(),
            max_depth: 10,
            n_samples: 1,
        });
        assert!(m.is_textured());
        let Bxdf::CoatedConductor(b) = bxdf(&m) else { panic!() };
        assert_eq!((b.top.eta, b.top.distrib.alpha_x), (2.0, 0.2));
        // The base's index relative to the coat.
        assert_eq!((b.bottom.eta, b.bottom.k), (Rgb::splat(0.5), Rgb::splat(2.0)));
        assert_eq!((b.bottom.distrib.alpha_x, b.bottom.distrib.alpha_y), (0.4, 0.2));
        assert!((b.thickness - 0.3).abs() < 1e-6);
    }
}
