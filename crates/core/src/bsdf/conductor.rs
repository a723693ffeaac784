//! Conductors (pbrt-v4 `ConductorBxDF`): a perfect mirror when the surface is smooth, else
//! the Torrance-Sparrow microfacet model over a Trowbridge-Reitz distribution,
//! `f = D(wm) F(wo.wm) G(wo, wi) / (4 |cos theta_o| |cos theta_i|)`, sampled through the
//! visible normals so that `pdf = D_visible(wo, wm) / (4 |wo.wm|)`. The Fresnel term uses
//! a complex index of refraction per RGB channel. Reflects on both sides.

use super::fresnel::{fr_complex, reflect};
use super::microfacet::Microfacet;
use super::{same_hemisphere, BsdfSample, BxdfFlags};
use crate::color::Rgb;
use crate::math::{Vec2, Vec3};

/// A smooth or rough conductor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConductorBxdf {
    /// Microfacet roughness; smooth below [`super::microfacet::SMOOTH_ALPHA`].
    pub distrib: Microfacet,
    /// Real part of the relative index of refraction, per channel.
    pub eta: Rgb,
    /// Absorption coefficient (imaginary part of the index), per channel.
    pub k: Rgb,
}

impl ConductorBxdf {
    /// Specular or glossy reflection.
    #[must_use]
    pub fn flags(&self) -> BxdfFlags {
        if self.distrib.effectively_smooth() {
            BxdfFlags::SPECULAR | BxdfFlags::REFLECTION
        } else {
            BxdfFlags::GLOSSY | BxdfFlags::REFLECTION
        }
    }

    /// The microfacet BRDF; zero for a smooth surface (a Dirac delta is never evaluated).
    #[must_use]
    pub fn f(&self, wo: Vec3, wi: Vec3) -> Rgb {
        if !same_hemisphere(wo, wi) || self.distrib.effectively_smooth() {
            return Rgb::BLACK;
        }
        let (cos_o, cos_i) = (wo.z.abs(), wi.z.abs());
        if cos_i == 0.0 || cos_o == 0.0 {
            return Rgb::BLACK;
        }
        let Some(wm) = (wi + wo).try_normalize() else {
            return Rgb::BLACK;
        };
        let fr = fr_complex(wo.dot(wm).abs(), self.eta, self.k);
        fr * (self.distrib.d(wm) * self.distrib.g(wo, wi) / (4.0 * cos_i * cos_o))
    }

    /// The mirror direction (smooth), or a reflection about a sampled visible normal.
    #[must_use]
    pub fn sample_f(&self, wo: Vec3, _uc: f32, u: Vec2) -> Option<BsdfSample> {
        if self.distrib.effectively_smooth() {
            let wi = Vec3::new(-wo.x, -wo.y, wo.z);
            let cos = wi.z.abs();
            return Some(BsdfSample {
                f: fr_complex(cos, self.eta, self.k) / cos,
                wi,
                pdf: 1.0,
                flags: BxdfFlags::SPECULAR | BxdfFlags::REFLECTION,
                eta: 1.0,
                pdf_is_proportional: false,
            });
        }
        if wo.z == 0.0 {
            return None;
        }
        let wm = self.distrib.sample_wm(wo, u);
        let wi = reflect(wo, wm);
        if !same_hemisphere(wo, wi) {
            return None;
        }
        let pdf = self.distrib.pdf(wo, wm) / (4.0 * wo.dot(wm).abs());
        let (cos_o, cos_i) = (wo.z.abs(), wi.z.abs());
        // (pdf = 0: a normal at the horizon, where D vanishes.)
        if cos_i == 0.0 || cos_o == 0.0 || pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        let fr = fr_complex(wo.dot(wm).abs(), self.eta, self.k);
        Some(BsdfSample {
            f: fr * (self.distrib.d(wm) * self.distrib.g(wo, wi) / (4.0 * cos_i * cos_o)),
            wi,
            pdf,
            flags: BxdfFlags::GLOSSY | BxdfFlags::REFLECTION,
            eta: 1.0,
            pdf_is_proportional: false,
        })
    }

    /// Density of [`Self::sample_f`]; zero for a smooth surface.
    #[must_use]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if !same_hemisphere(wo, wi) || self.distrib.effectively_smooth() {
            return 0.0;
        }
        let Some(mut wm) = (wo + wi).try_normalize() else {
            return 0.0;
        };
        if wm.z < 0.0 {
            wm = -wm;
        }
        self.distrib.pdf(wo, wm) / (4.0 * wo.dot(wm).abs())
    }
}
