//! glTF 2.0's metallic-roughness BRDF, the reference model of the glTF 2.0 specification
//! (Appendix B, "BRDF Implementation"):
//!
//! ```text
//! f = metallic       * F_m(wo.h) S
//!   + (1 - metallic) * [ (1 - F_d(wo.h)) c / pi  +  F_d(wo.h) S ]
//! S   = D(h) G(wo, wi) / (4 |cos theta_o| |cos theta_i|)   (GGX, alpha = roughness^2)
//! F_m = c + (1 - c) (1 - |wo.h|)^5                          (Schlick, F0 = base colour c)
//! F_d = 0.04 + 0.96 (1 - |wo.h|)^5                          (Schlick, F0 = 0.04, ior 1.5)
//! ```
//!
//! `h` is the half vector of `wo` and `wi`, so `f` is reciprocal. The model is the
//! specification's, not an energy-conserving one: the diffuse weight `1 - F_d(wo.h)` does
//! not remove what the specular lobe took at oblique angles, so a white dielectric
//! (`metallic = 0`, `c = 1`) reflects more than it receives away from the normal (albedo
//! 1.27 at `cos theta_o = 0.22`, roughness 0.05; measured in the tests); at normal
//! incidence it stays below 1, and a metal (`metallic = 1`) never exceeds 1.
//!
//! Sampling picks the specular lobe (visible normals of the GGX distribution, as the
//! conductor) with probability `p_s` from the Schlick weights at `cos theta_o`, else the
//! cosine-weighted diffuse lobe; the pdf is the mixture. Below
//! [`super::microfacet::SMOOTH_ALPHA`] the specular lobe is a mirror (a Dirac delta with
//! discrete probability `p_s`). Reflects on both sides, as the other opaque lobes.

use super::fresnel::reflect;
use super::microfacet::Microfacet;
use super::{same_hemisphere, BsdfSample, BxdfFlags};
use crate::color::Rgb;
use crate::math::{Vec2, Vec3, INV_PI};
use crate::sampling::{cosine_hemisphere_pdf, sample_cosine_hemisphere};

/// Normal-incidence reflectance of the dielectric part (index 1.5), as the spec fixes it.
const DIELECTRIC_F0: f32 = 0.04;

/// The glTF metallic-roughness BRDF.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MetallicRoughnessBxdf {
    /// Base colour `c` (the diffuse albedo of the dielectric, the F0 of the metal), in [0, 1].
    pub base_color: Rgb,
    /// Metalness in [0, 1].
    pub metallic: f32,
    /// GGX distribution with `alpha = roughness^2` (isotropic).
    pub distrib: Microfacet,
}

/// `(1 - cos)^5`, Schlick's weight.
fn schlick_weight(cos: f32) -> f32 {
    let m = (1.0 - cos).clamp(0.0, 1.0);
    let m2 = m * m;
    m2 * m2 * m
}

impl MetallicRoughnessBxdf {
    /// A lobe with `alpha = roughness^2` (the glTF convention); inputs clamped to [0, 1].
    #[must_use]
    pub fn new(base_color: Rgb, metallic: f32, roughness: f32) -> Self {
        let r = roughness.clamp(0.0, 1.0);
        Self {
            base_color: base_color.map(|v| v.clamp(0.0, 1.0)),
            metallic: metallic.clamp(0.0, 1.0),
            distrib: Microfacet::trowbridge_reitz(r * r, r * r),
        }
    }

    fn smooth(&self) -> bool {
        self.distrib.effectively_smooth()
    }

    /// The weight of the diffuse term, `(1 - metallic) c`.
    fn diffuse_albedo(&self) -> Rgb {
        self.base_color * (1.0 - self.metallic)
    }

    /// The Fresnel factor of the specular term, `metallic F_m + (1 - metallic) F_d`.
    fn specular_fresnel(&self, cos: f32) -> Rgb {
        let w = schlick_weight(cos);
        let f_m = self.base_color + (Rgb::WHITE - self.base_color) * w;
        let f_d = DIELECTRIC_F0 + (1.0 - DIELECTRIC_F0) * w;
        f_m * self.metallic + Rgb::splat(f_d * (1.0 - self.metallic))
    }

    /// Probability of sampling the specular lobe for `wo`, from the lobes' weights at
    /// `cos theta_o` (1 when the diffuse term is black).
    fn specular_probability(&self, wo: Vec3) -> f32 {
        let cos = wo.z.abs();
        let spec = self.specular_fresnel(cos).average();
        let diff =
            self.diffuse_albedo().average() * (1.0 - DIELECTRIC_F0 - (1.0 - DIELECTRIC_F0) * schlick_weight(cos));
        if diff <= 0.0 {
            1.0
        } else {
            (spec / (spec + diff)).clamp(0.05, 0.95)
        }
    }

    /// Diffuse and, when rough, glossy reflection; specular instead of glossy when smooth.
    #[must_use]
    pub fn flags(&self) -> BxdfFlags {
        let spec = if self.smooth() {
            BxdfFlags::SPECULAR
        } else {
            BxdfFlags::GLOSSY
        };
        let diffuse = if self.diffuse_albedo().is_black() {
            BxdfFlags::NONE
        } else {
            BxdfFlags::DIFFUSE
        };
        spec | diffuse | BxdfFlags::REFLECTION
    }

    /// The diffuse term `(1 - metallic) (1 - F_d(wo.h)) c / pi` (no `1/pi` dropped).
    fn f_diffuse(&self, cos_oh: f32) -> Rgb {
        let f_d = DIELECTRIC_F0 + (1.0 - DIELECTRIC_F0) * schlick_weight(cos_oh);
        self.diffuse_albedo() * ((1.0 - f_d) * INV_PI)
    }

    /// `f(wo, wi)`; for a smooth surface only the diffuse term (the mirror is a delta).
    #[must_use]
    pub fn f(&self, wo: Vec3, wi: Vec3) -> Rgb {
        if !same_hemisphere(wo, wi) {
            return Rgb::BLACK;
        }
        let (cos_o, cos_i) = (wo.z.abs(), wi.z.abs());
        let Some(h) = (wi + wo).try_normalize() else {
            return Rgb::BLACK;
        };
        let cos_oh = wo.dot(h).abs();
        let mut f = self.f_diffuse(cos_oh);
        if !self.smooth() && cos_o > 0.0 && cos_i > 0.0 {
            let s = self.distrib.d(h) * self.distrib.g(wo, wi) / (4.0 * cos_i * cos_o);
            f += self.specular_fresnel(cos_oh) * s;
        }
        f
    }

    /// The specular lobe with probability `p_s` (chosen by `uc`), else the diffuse lobe.
    #[must_use]
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let p_s = self.specular_probability(wo);
        if uc < p_s {
            if self.smooth() {
                let wi = Vec3::new(-wo.x, -wo.y, wo.z);
                let cos = wi.z.abs();
                return Some(BsdfSample {
                    f: self.specular_fresnel(cos) / cos,
                    wi,
                    pdf: p_s,
                    flags: BxdfFlags::SPECULAR | BxdfFlags::REFLECTION,
                    eta: 1.0,
                    pdf_is_proportional: false,
                });
            }
            let wm = self.distrib.sample_wm(wo, u);
            let wi = reflect(wo, wm);
            if !same_hemisphere(wo, wi) || wi.z == 0.0 {
                return None;
            }
            let pdf = self.pdf(wo, wi);
            if !(pdf > 0.0 && pdf.is_finite()) {
                return None;
            }
            return Some(BsdfSample {
                f: self.f(wo, wi),
                wi,
                pdf,
                flags: BxdfFlags::GLOSSY | BxdfFlags::REFLECTION,
                eta: 1.0,
                pdf_is_proportional: false,
            });
        }
        let mut wi = sample_cosine_hemisphere(u);
        if wi.z == 0.0 {
            return None;
        }
        if wo.z < 0.0 {
            wi.z = -wi.z;
        }
        let pdf = self.pdf(wo, wi);
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        Some(BsdfSample {
            f: self.f(wo, wi),
            wi,
            pdf,
            flags: BxdfFlags::DIFFUSE_REFLECTION,
            eta: 1.0,
            pdf_is_proportional: false,
        })
    }

    /// The mixture density `p_s pdf_spec + (1 - p_s) pdf_diffuse` (without the delta of a
    /// smooth surface).
    #[must_use]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if !same_hemisphere(wo, wi) || wo.z == 0.0 {
            return 0.0;
        }
        let p_s = self.specular_probability(wo);
        let mut pdf = (1.0 - p_s) * cosine_hemisphere_pdf(wi.z.abs());
        if !self.smooth() {
            if let Some(mut wm) = (wo + wi).try_normalize() {
                if wm.z < 0.0 {
                    wm = -wm;
                }
                pdf += p_s * self.distrib.pdf(wo, wm) / (4.0 * wo.dot(wm).abs());
            }
        }
        pdf
    }
}

#[cfg(test)]
#[path = "metallic_roughness_tests.rs"]
mod tests;
