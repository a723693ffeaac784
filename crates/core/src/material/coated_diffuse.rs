//! pbrt's `coateddiffuse`: a dielectric coat over a Lambertian base with a scattering
//! slab between them, evaluated stochastically (`bsdf::LayeredBxdf`).

use super::checks::{check_positive_eta, check_rgb, check_roughness, check_slab, InvalidParameter};
use super::params::{coat, slab_at, slab_is_constant, unit};
use crate::bsdf::{Bxdf, DiffuseBxdf, LayeredBxdf};
use crate::texture::{FloatTexture, RgbTexture, TextureContext};

/// A coated diffuse surface (pbrt `coateddiffuse`).
#[derive(Clone, Debug, PartialEq)]
pub struct CoatedDiffuseMaterial {
    /// Albedo of the base, in [0, 1] (clamped per hit).
    pub reflectance: RgbTexture,
    /// Coat roughness along the shading tangent.
    pub u_roughness: FloatTexture,
    /// Coat roughness along the bitangent.
    pub v_roughness: FloatTexture,
    /// As for [`super::ConductorMaterial::remap_roughness`].
    pub remap_roughness: bool,
    /// Slab thickness in mean free paths (pbrt default 0.01).
    pub thickness: FloatTexture,
    /// Index of refraction of the coat (pbrt default 1.5); 0 means 1.
    pub eta: f32,
    /// Single-scattering albedo of the slab (pbrt default 0: absorbing only).
    pub albedo: RgbTexture,
    /// Henyey-Greenstein asymmetry of the slab, in (-1, 1) (pbrt default 0).
    pub g: FloatTexture,
    /// Maximum scattering events of a random walk (pbrt default 10).
    pub max_depth: u32,
    /// Random walks per evaluation (pbrt default 1).
    pub n_samples: u32,
}

impl CoatedDiffuseMaterial {
    /// Check the parameters of material `index`.
    pub fn validate(&self, index: usize) -> Result<(), InvalidParameter> {
        check_rgb(index, "reflectance", &self.reflectance)?;
        check_roughness(index, &[&self.u_roughness, &self.v_roughness])?;
        check_positive_eta(index, self.eta)?;
        check_slab(index, &self.thickness, &self.albedo, &self.g)
    }

    /// True when some parameter is a non-constant texture.
    #[must_use]
    pub fn is_textured(&self) -> bool {
        !(self.reflectance.is_constant()
            && self.u_roughness.is_constant()
            && self.v_roughness.is_constant()
            && slab_is_constant(&self.thickness, &self.albedo, &self.g))
    }

    /// The stochastic layered lobe with the textures evaluated at `ctx`.
    #[must_use]
    pub fn bxdf(&self, ctx: &TextureContext) -> Bxdf {
        let (thickness, albedo, g) = slab_at(&self.thickness, &self.albedo, &self.g, ctx);
        Bxdf::CoatedDiffuse(LayeredBxdf {
            top: coat(
                self.eta,
                self.u_roughness.evaluate(ctx),
                self.v_roughness.evaluate(ctx),
                self.remap_roughness,
            ),
            bottom: DiffuseBxdf {
                r: unit(self.reflectance.evaluate(ctx)),
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
    fn coated_diffuse_parameters_are_textures_evaluated_per_hit() {
        let m = MaterialDesc::CoatedDiffuse(CoatedDiffuseMaterial {
            reflectance: scaled(Rgb::new(0.2, 0.4, 0.6), 2.0),
            u_roughness: scaled(0.1, 2.0),
            v_roughness: 0.3.into(),
            remap_roughness: false,
            thickness: scaled(0.25, 2.0),
            eta: 1.5,
            albedo: scaled(Rgb::splat(0.25), 2.0),
            g: scaled(0.3, -1.0),
            max_depth: 7,
            n_samples: 0,
        });
        assert!(m.is_textured());
        let Bxdf::CoatedDiffuse(b) = bxdf(&m) else { panic!() };
        assert_eq!(b.bottom.r, Rgb::new(0.4, 0.8, 1.0));
        assert_eq!(
            (b.top.eta, b.top.distrib.alpha_x, b.top.distrib.alpha_y),
            (1.5, 0.2, 0.3)
        );
        assert_eq!((b.thickness, b.albedo, b.g), (0.5, Rgb::splat(0.5), -0.3));
        assert_eq!((b.max_depth, b.n_samples), (7, 1));

        // Constants everywhere: no footprint needed.
        let m = MaterialDesc::CoatedDiffuse(CoatedDiffuseMaterial {
            reflectance: Rgb::splat(0.5).into(),
            u_roughness: 0.0.into(),
            v_roughness: 0.0.into(),
            remap_roughness: true,
            thickness: 0.01.into(),
            eta: 1.5,
            albedo: Rgb::BLACK.into(),
            g: 0.0.into(),
            max_depth: 10,
            n_samples: 1,
        });
        assert!(!m.is_textured());
    }
}
