//! Lambertian reflection: `f = R / pi` on the side of `wo`, sampled by the cosine-weighted
//! hemisphere, so `f cos / pdf = R` exactly.

use super::{same_hemisphere, BsdfSample, BxdfFlags};
use crate::color::Rgb;
use crate::math::{Vec2, Vec3, INV_PI};
use crate::sampling::{cosine_hemisphere_pdf, sample_cosine_hemisphere};

/// Lambertian reflector with albedo `r`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiffuseBxdf {
    /// Albedo in [0, 1].
    pub r: Rgb,
}

impl DiffuseBxdf {
    /// Diffuse reflection, or nothing when black.
    #[must_use]
    pub fn flags(&self) -> BxdfFlags {
        if self.r.is_black() {
            BxdfFlags::NONE
        } else {
            BxdfFlags::DIFFUSE_REFLECTION
        }
    }

    /// `R / pi` when `wo` and `wi` are on the same side.
    #[must_use]
    pub fn f(&self, wo: Vec3, wi: Vec3) -> Rgb {
        if same_hemisphere(wo, wi) {
            self.r * INV_PI
        } else {
            Rgb::BLACK
        }
    }

    /// Cosine-weighted direction on the side of `wo`.
    #[must_use]
    pub fn sample_f(&self, wo: Vec3, _uc: f32, u: Vec2) -> Option<BsdfSample> {
        let mut wi = sample_cosine_hemisphere(u);
        if wi.z == 0.0 {
            // On the rim: neither side's hemisphere, where f is zero.
            return None;
        }
        if wo.z < 0.0 {
            wi.z = -wi.z;
        }
        let pdf = cosine_hemisphere_pdf(wi.z.abs());
        Some(BsdfSample {
            f: self.r * INV_PI,
            wi,
            pdf,
            flags: BxdfFlags::DIFFUSE_REFLECTION,
            eta: 1.0,
            pdf_is_proportional: false,
        })
    }

    /// `|cos theta_i| / pi` on the side of `wo`.
    #[must_use]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if same_hemisphere(wo, wi) {
            cosine_hemisphere_pdf(wi.z.abs())
        } else {
            0.0
        }
    }
}
