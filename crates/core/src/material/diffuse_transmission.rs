//! pbrt's `diffusetransmission`: Lambertian reflection and transmission.

use super::checks::{check_non_negative, check_rgb, InvalidParameter};
use super::params::unit;
use crate::bsdf::{Bxdf, DiffuseTransmissionBxdf};
use crate::texture::{RgbTexture, TextureContext};

/// Lambertian reflection and transmission (pbrt `diffusetransmission`).
#[derive(Clone, Debug, PartialEq)]
pub struct DiffuseTransmissionMaterial {
    /// Reflectance (clamped to [0, 1] after scaling).
    pub reflectance: RgbTexture,
    /// Transmittance (clamped to [0, 1] after scaling).
    pub transmittance: RgbTexture,
    /// Factor applied to both.
    pub scale: f32,
}

impl DiffuseTransmissionMaterial {
    /// Check the parameters of material `index`.
    pub fn validate(&self, index: usize) -> Result<(), InvalidParameter> {
        check_rgb(index, "reflectance", &self.reflectance)?;
        check_rgb(index, "transmittance", &self.transmittance)?;
        check_non_negative(&format!("scale of material {index}"), &[self.scale])
    }

    /// True when some parameter is a non-constant texture.
    #[must_use]
    pub fn is_textured(&self) -> bool {
        !(self.reflectance.is_constant() && self.transmittance.is_constant())
    }

    /// The lobe with the textures evaluated at `ctx`.
    #[must_use]
    pub fn bxdf(&self, ctx: &TextureContext) -> Bxdf {
        Bxdf::DiffuseTransmission(DiffuseTransmissionBxdf {
            r: unit(self.reflectance.evaluate(ctx) * self.scale),
            t: unit(self.transmittance.evaluate(ctx) * self.scale),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_support::bxdf;
    use super::super::MaterialDesc;
    use super::*;
    use crate::color::Rgb;

    #[test]
    fn diffuse_transmission_scales_then_clamps() {
        let m = MaterialDesc::DiffuseTransmission(DiffuseTransmissionMaterial {
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
