//! A thin dielectric slab (pbrt-v4 `ThinDielectricBxDF`), such as a window pane: two
//! parallel smooth interfaces, with all the interreflections inside summed in closed form.
//! Light either reflects specularly or passes straight through (no net refraction):
//! `R' = R + T^2 R / (1 - R^2)`, `T' = 1 - R'`. Both directions are Dirac deltas.

use super::fresnel::fr_dielectric;
use super::{BsdfSample, BxdfFlags};
use crate::color::Rgb;
use crate::math::{sqr, Vec2, Vec3};

/// A thin slab of a dielectric with index `eta` relative to its surroundings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThinDielectricBxdf {
    /// Relative index of refraction of the slab.
    pub eta: f32,
}

impl ThinDielectricBxdf {
    /// Specular reflection and transmission.
    #[must_use]
    pub fn flags(&self) -> BxdfFlags {
        BxdfFlags::REFLECTION | BxdfFlags::TRANSMISSION | BxdfFlags::SPECULAR
    }

    /// Reflectance and transmittance of the slab at `cos_theta`.
    #[must_use]
    pub fn reflectance_transmittance(&self, cos_theta: f32) -> (f32, f32) {
        let mut r = fr_dielectric(cos_theta.abs(), self.eta);
        let mut t = 1.0 - r;
        if r < 1.0 {
            r += sqr(t) * r / (1.0 - sqr(r));
            t = 1.0 - r;
        }
        (r, t)
    }

    /// Zero: both lobes are Dirac deltas.
    #[must_use]
    pub fn f(&self, _wo: Vec3, _wi: Vec3) -> Rgb {
        Rgb::BLACK
    }

    /// The mirror direction with probability `R'`, else straight through.
    #[must_use]
    pub fn sample_f(&self, wo: Vec3, uc: f32, _u: Vec2) -> Option<BsdfSample> {
        let (r, t) = self.reflectance_transmittance(wo.z);
        let cos = wo.z.abs();
        if uc < r / (r + t) {
            Some(BsdfSample {
                f: Rgb::splat(r / cos),
                wi: Vec3::new(-wo.x, -wo.y, wo.z),
                pdf: r / (r + t),
                flags: BxdfFlags::SPECULAR | BxdfFlags::REFLECTION,
                eta: 1.0,
                pdf_is_proportional: false,
            })
        } else {
            Some(BsdfSample {
                f: Rgb::splat(t / cos),
                wi: -wo,
                pdf: t / (r + t),
                flags: BxdfFlags::SPECULAR | BxdfFlags::TRANSMISSION,
                eta: 1.0,
                pdf_is_proportional: false,
            })
        }
    }

    /// Zero: both lobes are Dirac deltas.
    #[must_use]
    pub fn pdf(&self, _wo: Vec3, _wi: Vec3) -> f32 {
        0.0
    }
}
