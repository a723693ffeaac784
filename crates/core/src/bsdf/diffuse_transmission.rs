//! Diffuse reflection and transmission (pbrt-v4 `DiffuseTransmissionBxDF`), for thin
//! translucent surfaces such as paper or leaves: `f = R / pi` on the side of `wo` and
//! `T / pi` on the other side. Each side is sampled with the cosine-weighted hemisphere,
//! the side chosen in proportion to the largest channel of `R` and of `T`.

use super::{same_hemisphere, BsdfSample, BxdfFlags};
use crate::color::Rgb;
use crate::math::{Vec2, Vec3, INV_PI};
use crate::sampling::{cosine_hemisphere_pdf, sample_cosine_hemisphere};

/// Lambertian reflection `r` and Lambertian transmission `t`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiffuseTransmissionBxdf {
    /// Reflectance in [0, 1].
    pub r: Rgb,
    /// Transmittance in [0, 1].
    pub t: Rgb,
}

impl DiffuseTransmissionBxdf {
    /// Probabilities of sampling reflection and transmission.
    fn lobe_probabilities(&self) -> (f32, f32) {
        let (pr, pt) = (self.r.max_component(), self.t.max_component());
        let sum = pr + pt;
        if sum > 0.0 {
            (pr / sum, pt / sum)
        } else {
            (0.0, 0.0)
        }
    }

    /// Diffuse reflection and/or transmission, or nothing when both are black.
    #[must_use]
    pub fn flags(&self) -> BxdfFlags {
        let mut flags = BxdfFlags::NONE;
        if !self.r.is_black() {
            flags = flags | BxdfFlags::DIFFUSE_REFLECTION;
        }
        if !self.t.is_black() {
            flags = flags | BxdfFlags::DIFFUSE | BxdfFlags::TRANSMISSION;
        }
        flags
    }

    /// `R / pi` on the side of `wo`, `T / pi` on the other.
    #[must_use]
    pub fn f(&self, wo: Vec3, wi: Vec3) -> Rgb {
        if same_hemisphere(wo, wi) {
            self.r * INV_PI
        } else {
            self.t * INV_PI
        }
    }

    /// A cosine-weighted direction on the side chosen by `uc`.
    #[must_use]
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample> {
        let (pr, pt) = self.lobe_probabilities();
        if pr + pt == 0.0 {
            return None;
        }
        let mut wi = sample_cosine_hemisphere(u);
        if wi.z == 0.0 {
            return None;
        }
        let reflect = uc < pr;
        // Reflection stays on the side of wo, transmission crosses over.
        if (wo.z < 0.0) == reflect {
            wi.z = -wi.z;
        }
        let (f, p, flags) = if reflect {
            (self.r, pr, BxdfFlags::DIFFUSE_REFLECTION)
        } else {
            (self.t, pt, BxdfFlags::DIFFUSE | BxdfFlags::TRANSMISSION)
        };
        Some(BsdfSample {
            f: f * INV_PI,
            wi,
            pdf: p * cosine_hemisphere_pdf(wi.z.abs()),
            flags,
            eta: 1.0,
            pdf_is_proportional: false,
        })
    }

    /// Density of [`Self::sample_f`].
    #[must_use]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let (pr, pt) = self.lobe_probabilities();
        let p = if same_hemisphere(wo, wi) { pr } else { pt };
        p * cosine_hemisphere_pdf(wi.z.abs())
    }
}
