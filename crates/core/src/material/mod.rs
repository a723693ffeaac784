//! Layer 3: materials turn a surface interaction into a BSDF. A [`Material`] holds its
//! parameters already resolved (alphas from roughness, conductor indices from a
//! reflectance); [`Material::from_desc`] does that resolution once, at scene build.

use crate::bsdf::{
    roughness_to_alpha, Bsdf, Bxdf, ConductorBxdf, DielectricBxdf, DiffuseBxdf, DiffuseTransmissionBxdf,
    ThinDielectricBxdf, TrowbridgeReitz,
};
use crate::color::Rgb;
use crate::scene::MaterialDesc;
use crate::shape::SurfaceInteraction;

/// The closed set of materials.
#[derive(Clone, Debug, PartialEq)]
pub enum Material {
    /// Lambertian reflection with constant albedo.
    Diffuse {
        /// Albedo.
        reflectance: Rgb,
    },
    /// Smooth or rough conductor.
    Conductor {
        /// Microfacet distribution (alphas along `dpdu` and the bitangent).
        distrib: TrowbridgeReitz,
        /// Real part of the index of refraction.
        eta: Rgb,
        /// Imaginary part.
        k: Rgb,
    },
    /// Smooth or rough dielectric interface.
    Dielectric {
        /// Relative index of refraction, inside over outside.
        eta: f32,
        /// Microfacet distribution.
        distrib: TrowbridgeReitz,
    },
    /// Thin dielectric slab.
    ThinDielectric {
        /// Index of refraction.
        eta: f32,
    },
    /// Lambertian reflection and transmission.
    DiffuseTransmission {
        /// Reflectance in [0, 1].
        reflectance: Rgb,
        /// Transmittance in [0, 1].
        transmittance: Rgb,
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
        match *desc {
            MaterialDesc::Diffuse { reflectance } => Self::Diffuse { reflectance },
            MaterialDesc::Conductor {
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
                        let r = r.map(|v| v.clamp(0.0, 0.9999));
                        (Rgb::WHITE, r.map(|v| 2.0 * v.sqrt() / (1.0 - v).max(0.0).sqrt()))
                    }
                    None => (eta, k),
                };
                Self::Conductor {
                    distrib: TrowbridgeReitz::new(
                        alpha(u_roughness, remap_roughness),
                        alpha(v_roughness, remap_roughness),
                    ),
                    eta,
                    k,
                }
            }
            MaterialDesc::Dielectric {
                eta,
                u_roughness,
                v_roughness,
                remap_roughness,
            } => Self::Dielectric {
                eta,
                distrib: TrowbridgeReitz::new(alpha(u_roughness, remap_roughness), alpha(v_roughness, remap_roughness)),
            },
            MaterialDesc::ThinDielectric { eta } => Self::ThinDielectric { eta },
            MaterialDesc::DiffuseTransmission {
                reflectance,
                transmittance,
                scale,
            } => Self::DiffuseTransmission {
                reflectance: (reflectance * scale).map(|v| v.clamp(0.0, 1.0)),
                transmittance: (transmittance * scale).map(|v| v.clamp(0.0, 1.0)),
            },
        }
    }

    /// The BSDF at a hit, in the shading frame of `si.ns` with `si.dpdu` as first tangent.
    #[must_use]
    pub fn bsdf(&self, si: &SurfaceInteraction) -> Bsdf {
        let bxdf = match *self {
            Self::Diffuse { reflectance } => Bxdf::Diffuse(DiffuseBxdf {
                r: reflectance.map(|v| v.clamp(0.0, 1.0)),
            }),
            Self::Conductor { distrib, eta, k } => Bxdf::Conductor(ConductorBxdf { distrib, eta, k }),
            Self::Dielectric { eta, distrib } => Bxdf::Dielectric(DielectricBxdf { eta, distrib }),
            Self::ThinDielectric { eta } => Bxdf::ThinDielectric(ThinDielectricBxdf { eta }),
            Self::DiffuseTransmission {
                reflectance,
                transmittance,
            } => Bxdf::DiffuseTransmission(DiffuseTransmissionBxdf {
                r: reflectance,
                t: transmittance,
            }),
        };
        Bsdf::new(si.ns, si.dpdu, bxdf)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::fresnel::fr_complex;

    #[test]
    fn conductor_reflectance_becomes_an_index_with_that_normal_reflectance() {
        let r = Rgb::new(0.9, 0.5, 0.0);
        let m = Material::from_desc(&MaterialDesc::Conductor {
            eta: Rgb::splat(0.2),
            k: Rgb::splat(3.0),
            reflectance: Some(r),
            u_roughness: 0.0,
            v_roughness: 0.0,
            remap_roughness: true,
        });
        let Material::Conductor { eta, k, .. } = m else {
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
                u_roughness: 0.25,
                v_roughness: 0.0,
                remap_roughness: remap,
            });
            let Material::Dielectric { distrib, .. } = m else {
                panic!()
            };
            assert_eq!((distrib.alpha_x, distrib.alpha_y), (expected, 0.0));
        }
    }

    #[test]
    fn diffuse_transmission_scales_then_clamps() {
        let m = Material::from_desc(&MaterialDesc::DiffuseTransmission {
            reflectance: Rgb::splat(0.25),
            transmittance: Rgb::new(0.25, 0.5, 0.75),
            scale: 2.0,
        });
        assert_eq!(
            m,
            Material::DiffuseTransmission {
                reflectance: Rgb::splat(0.5),
                transmittance: Rgb::new(0.5, 1.0, 1.0)
            }
        );
    }
}
