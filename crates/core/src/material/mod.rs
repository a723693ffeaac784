//! Layer 3: materials turn a surface interaction into a BSDF.

use crate::bsdf::{Bsdf, Bxdf, DiffuseBxdf};
use crate::color::Rgb;
use crate::shape::SurfaceInteraction;

/// The closed set of materials.
#[derive(Clone, Debug, PartialEq)]
pub enum Material {
    /// Lambertian reflection with constant albedo.
    Diffuse {
        /// Albedo.
        reflectance: Rgb,
    },
}

impl Material {
    /// The BSDF at a hit.
    #[must_use]
    pub fn bsdf(&self, si: &SurfaceInteraction) -> Bsdf {
        match self {
            Self::Diffuse { reflectance } => Bsdf::new(
                si.ns,
                si.dpdu,
                Bxdf::Diffuse(DiffuseBxdf {
                    r: reflectance.map(|v| v.clamp(0.0, 1.0)),
                }),
            ),
        }
    }
}
