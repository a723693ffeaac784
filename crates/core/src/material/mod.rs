//! Layer 3: materials turn a surface interaction into a BSDF. A [`Material`] holds its
//! parameters as textures ([`crate::texture`]), evaluated at each hit's
//! [`TextureContext`]; [`Material::from_desc`] copies them from the description and
//! [`Material::bsdf`] resolves them (alphas from roughness, conductor indices from a
//! reflectance) per hit. Constant textures give the same BSDF at every hit.

use crate::bsdf::{
    roughness_to_alpha, Bsdf, Bxdf, ConductorBxdf, DielectricBxdf, DiffuseBxdf, DiffuseTransmissionBxdf,
    ThinDielectricBxdf, TrowbridgeReitz,
};
use crate::color::Rgb;
use crate::scene::MaterialDesc;
use crate::shape::SurfaceInteraction;
use crate::texture::{FloatTexture, RgbTexture, TextureContext};

/// The closed set of materials.
#[derive(Clone, Debug, PartialEq)]
pub enum Material {
    /// Lambertian reflection.
    Diffuse {
        /// Albedo (clamped to [0, 1] per hit).
        reflectance: RgbTexture,
    },
    /// Smooth or rough conductor.
    Conductor {
        /// Real part of the index of refraction.
        eta: RgbTexture,
        /// Imaginary part.
        k: RgbTexture,
        /// When given, replaces `eta` and `k` (see [`MaterialDesc::Conductor`]).
        reflectance: Option<RgbTexture>,
        /// Roughness along `dpdu`.
        u_roughness: FloatTexture,
        /// Roughness along the bitangent.
        v_roughness: FloatTexture,
        /// Map roughness to alpha by `sqrt`.
        remap_roughness: bool,
    },
    /// Smooth or rough dielectric interface.
    Dielectric {
        /// Relative index of refraction, inside over outside.
        eta: f32,
        /// Roughness along `dpdu`.
        u_roughness: FloatTexture,
        /// Roughness along the bitangent.
        v_roughness: FloatTexture,
        /// Map roughness to alpha by `sqrt`.
        remap_roughness: bool,
    },
    /// Thin dielectric slab.
    ThinDielectric {
        /// Index of refraction.
        eta: f32,
    },
    /// Lambertian reflection and transmission.
    DiffuseTransmission {
        /// Reflectance (times `scale`, clamped to [0, 1] per hit).
        reflectance: RgbTexture,
        /// Transmittance (times `scale`, clamped to [0, 1] per hit).
        transmittance: RgbTexture,
        /// Factor on both.
        scale: f32,
    },
}

/// Microfacet alpha from a user roughness, remapped as pbrt does when asked.
fn alpha(roughness: f32, remap: bool) -> f32 {
    if remap {
        roughness_to_alpha(roughness)
    } else {
        roughness.max(0.0)
    }
}

impl Material {
    /// The material a (validated) description asks for.
    #[must_use]
    pub fn from_desc(desc: &MaterialDesc) -> Self {
        match desc.clone() {
            MaterialDesc::Diffuse { reflectance } => Self::Diffuse { reflectance },
            MaterialDesc::Conductor {
                eta,
                k,
                reflectance,
                u_roughness,
                v_roughness,
                remap_roughness,
            } => Self::Conductor {
                eta,
                k,
                reflectance,
                u_roughness,
                v_roughness,
                remap_roughness,
            },
            MaterialDesc::Dielectric {
                eta,
                u_roughness,
                v_roughness,
                remap_roughness,
            } => Self::Dielectric {
                eta,
                u_roughness,
                v_roughness,
                remap_roughness,
            },
            MaterialDesc::ThinDielectric { eta } => Self::ThinDielectric { eta },
            MaterialDesc::DiffuseTransmission {
                reflectance,
                transmittance,
                scale,
            } => Self::DiffuseTransmission {
                reflectance,
                transmittance,
                scale,
            },
        }
    }

    /// True when some parameter is a non-constant texture, so [`Self::bsdf`] needs a
    /// texture context with a footprint.
    #[must_use]
    pub fn is_textured(&self) -> bool {
        match self {
            Self::Diffuse { reflectance } => !reflectance.is_constant(),
            Self::Conductor {
                eta,
                k,
                reflectance,
                u_roughness,
                v_roughness,
                ..
            } => {
                !(eta.is_constant()
                    && k.is_constant()
                    && reflectance.as_ref().is_none_or(RgbTexture::is_constant)
                    && u_roughness.is_constant()
                    && v_roughness.is_constant())
            }
            Self::Dielectric {
                u_roughness,
                v_roughness,
                ..
            } => !(u_roughness.is_constant() && v_roughness.is_constant()),
            Self::ThinDielectric { .. } => false,
            Self::DiffuseTransmission {
                reflectance,
                transmittance,
                ..
            } => !(reflectance.is_constant() && transmittance.is_constant()),
        }
    }

    /// The BSDF at a hit, in the shading frame of `si.ns` with `si.dpdu` as first tangent,
    /// with the textures evaluated at `ctx`.
    #[must_use]
    pub fn bsdf(&self, si: &SurfaceInteraction, ctx: &TextureContext) -> Bsdf {
        let bxdf = match self {
            Self::Diffuse { reflectance } => Bxdf::Diffuse(DiffuseBxdf {
                r: reflectance.evaluate(ctx).map(|v| v.clamp(0.0, 1.0)),
            }),
            Self::Conductor {
                eta,
                k,
                reflectance,
                u_roughness,
                v_roughness,
                remap_roughness,
            } => {
                let (eta, k) = match reflectance {
                    Some(r) => {
                        // pbrt-v4: the index with eta = 1 whose normal-incidence
                        // reflectance ((eta-1)^2 + k^2) / ((eta+1)^2 + k^2) is r.
                        let r = r.evaluate(ctx).map(|v| v.clamp(0.0, 0.9999));
                        (Rgb::WHITE, r.map(|v| 2.0 * v.sqrt() / (1.0 - v).max(0.0).sqrt()))
                    }
                    None => (eta.evaluate(ctx), k.evaluate(ctx)),
                };
                let distrib = TrowbridgeReitz::new(
                    alpha(u_roughness.evaluate(ctx), *remap_roughness),
                    alpha(v_roughness.evaluate(ctx), *remap_roughness),
                );
                Bxdf::Conductor(ConductorBxdf { distrib, eta, k })
            }
            Self::Dielectric {
                eta,
                u_roughness,
                v_roughness,
                remap_roughness,
            } => Bxdf::Dielectric(DielectricBxdf {
                eta: *eta,
                distrib: TrowbridgeReitz::new(
                    alpha(u_roughness.evaluate(ctx), *remap_roughness),
                    alpha(v_roughness.evaluate(ctx), *remap_roughness),
                ),
            }),
            Self::ThinDielectric { eta } => Bxdf::ThinDielectric(ThinDielectricBxdf { eta: *eta }),
            Self::DiffuseTransmission {
                reflectance,
                transmittance,
                scale,
            } => Bxdf::DiffuseTransmission(DiffuseTransmissionBxdf {
                r: (reflectance.evaluate(ctx) * *scale).map(|v| v.clamp(0.0, 1.0)),
                t: (transmittance.evaluate(ctx) * *scale).map(|v| v.clamp(0.0, 1.0)),
            }),
        };
        Bsdf::new(si.ns, si.dpdu, bxdf)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::fresnel::fr_complex;
    use crate::math::{Vec2, Vec3};
    use crate::shape::Interaction;

    fn hit() -> SurfaceInteraction {
        SurfaceInteraction {
            intr: Interaction {
                p: Vec3::ZERO,
                p_error: Vec3::ZERO,
                n: Vec3::Z,
            },
            ns: Vec3::Z,
            dpdu: Vec3::X,
            dp_du: Vec3::X,
            dp_dv: Vec3::Y,
            uv: Vec2::splat(0.5),
            wo: Vec3::Z,
            t: 1.0,
        }
    }

    fn bxdf(m: &Material) -> Bxdf {
        let si = hit();
        *m.bsdf(&si, &TextureContext::at_point(&si)).bxdf()
    }

    #[test]
    fn conductor_reflectance_becomes_an_index_with_that_normal_reflectance() {
        let r = Rgb::new(0.9, 0.5, 0.0);
        let m = Material::from_desc(&MaterialDesc::Conductor {
            eta: Rgb::splat(0.2).into(),
            k: Rgb::splat(3.0).into(),
            reflectance: Some(r.into()),
            u_roughness: 0.0.into(),
            v_roughness: 0.0.into(),
            remap_roughness: true,
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

    #[test]
    fn roughness_is_remapped_only_when_asked() {
        for (remap, expected) in [(true, 0.5), (false, 0.25)] {
            let m = Material::from_desc(&MaterialDesc::Dielectric {
                eta: 1.5,
                u_roughness: 0.25.into(),
                v_roughness: 0.0.into(),
                remap_roughness: remap,
            });
            let Bxdf::Dielectric(DielectricBxdf { distrib, .. }) = bxdf(&m) else {
                panic!()
            };
            assert_eq!((distrib.alpha_x, distrib.alpha_y), (expected, 0.0));
        }
    }

    #[test]
    fn diffuse_transmission_scales_then_clamps() {
        let m = Material::from_desc(&MaterialDesc::DiffuseTransmission {
            reflectance: Rgb::splat(0.25).into(),
            transmittance: Rgb::new(0.25, 0.5, 0.75).into(),
            scale: 2.0,
        });
        let Bxdf::DiffuseTransmission(DiffuseTransmissionBxdf { r, t }) = bxdf(&m) else {
            panic!()
        };
        assert_eq!((r, t), (Rgb::splat(0.5), Rgb::new(0.5, 1.0, 1.0)));
    }
}
