//! Mitsuba 3's `plastic` and `roughplastic`: a dielectric coat ([`PlasticCoat`]) over a
//! Lambertian base, with the internal scattering between them summed in closed form. This
//! is not pbrt's `coateddiffuse` (a stochastic random walk through a slab); it is the model
//! of Mitsuba's `plastic.cpp` and `roughplastic.cpp`:
//!
//! * specular part: the coat's reflection, a Fresnel-weighted mirror (smooth) or the
//!   Torrance-Sparrow lobe `F D G / (4 cos_o cos_i)` (rough), times `specular`;
//! * diffuse part: `d' / pi * (1 / eta^2) * T(cos_o) T(cos_i)`, with `d' = d / (1 - Fdr)`
//!   (or `d / (1 - d Fdr)` when `nonlinear`), `Fdr` the coat's internal diffuse reflectance
//!   and `T` its transmittance (`1 - F` when smooth).
//!
//! Sampling picks the specular part with probability `p_s = (1 - T(cos_o)) w /
//! ((1 - T(cos_o)) w + T(cos_o) (1 - w))`, `w` Mitsuba's specular sampling weight
//! `mean(specular) / (mean(diffuse) + mean(specular))`; the diffuse part by the cosine.
//! Mitsuba's plastic is black seen from behind; this lobe mirrors itself to the side of
//! `wo`, like mcrender's other opaque lobes (the same wherever only front faces are seen).

use super::fresnel::{fr_dielectric, reflect};
use super::plastic_coat::PlasticCoat;
use super::{same_hemisphere, BsdfSample, BxdfFlags};
use crate::color::Rgb;
use crate::math::{sqr, Vec2, Vec3, INV_PI};
use crate::sampling::{cosine_hemisphere_pdf, sample_cosine_hemisphere};

/// A plastic: coat, diffuse base, specular tint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlasticBxdf {
    /// The coat (smooth or rough) and its precomputed terms.
    pub coat: PlasticCoat,
    /// Albedo of the base, in [0, 1].
    pub diffuse: Rgb,
    /// Tint of the coat's reflection (1 for physical realism).
    pub specular: Rgb,
    /// Account for the colour shift of internal scattering (`d / (1 - d Fdr)`).
    pub nonlinear: bool,
    /// Mitsuba's specular sampling weight `w`, in [0, 1].
    pub specular_sampling_weight: f32,
}

/// `w` mirrored to the upper hemisphere.
fn up(w: Vec3) -> Vec3 {
    Vec3::new(w.x, w.y, w.z.abs())
}

impl PlasticBxdf {
    /// Specular (smooth) or glossy reflection, with diffuse reflection.
    #[must_use]
    pub fn flags(&self) -> BxdfFlags {
        let coat = if self.coat.distribution().is_some() {
            BxdfFlags::GLOSSY
        } else {
            BxdfFlags::SPECULAR
        };
        let mut flags = BxdfFlags::NONE;
        if !self.specular.is_black() {
            flags = flags | coat | BxdfFlags::REFLECTION;
        }
        if !self.diffuse.is_black() {
            flags = flags | BxdfFlags::DIFFUSE_REFLECTION;
        }
        flags
    }

    /// Probability of sampling the specular part for `cos_o = |cos theta_o|`.
    fn specular_probability(&self, cos_o: f32) -> f32 {
        let w = self.specular_sampling_weight;
        let r = 1.0 - self.coat.transmittance(cos_o);
        let (ps, pd) = (r * w, (1.0 - r) * (1.0 - w));
        if ps + pd > 0.0 {
            ps / (ps + pd)
        } else {
            0.0
        }
    }

    /// The diffuse part for cosines `cos_o`, `cos_i` (both positive).
    fn diffuse_f(&self, cos_o: f32, cos_i: f32) -> Rgb {
        let fdr = self.coat.internal_reflectance();
        let d = if self.nonlinear {
            self.diffuse.map(|v| v / (1.0 - v * fdr))
        } else {
            self.diffuse * (1.0 / (1.0 - fdr))
        };
        let t = self.coat.transmittance(cos_o) * self.coat.transmittance(cos_i);
        d * (INV_PI * t / sqr(self.coat.eta()))
    }

    /// The glossy part of a rough coat (zero when smooth).
    fn glossy_f(&self, wo: Vec3, wi: Vec3) -> Rgb {
        let Some(distrib) = self.coat.distribution() else {
            return Rgb::BLACK;
        };
        let Some(wm) = (wo + wi).try_normalize() else {
            return Rgb::BLACK;
        };
        let fr = fr_dielectric(wo.dot(wm), self.coat.eta());
        self.specular * (fr * distrib.d(wm) * distrib.g(wo, wi) / (4.0 * wo.z * wi.z))
    }

    /// The BSDF (without the delta of a smooth coat).
    #[must_use]
    pub fn f(&self, wo: Vec3, wi: Vec3) -> Rgb {
        if !same_hemisphere(wo, wi) {
            return Rgb::BLACK;
        }
        let (wo, wi) = (up(wo), up(wi));
        self.diffuse_f(wo.z, wi.z) + self.glossy_f(wo, wi)
    }

    /// The coat's reflection with probability [`Self::specular_probability`], else a
    /// cosine-weighted direction.
    #[must_use]
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let o = up(wo);
        let p_s = self.specular_probability(o.z);
        let side = |w: Vec3| if wo.z < 0.0 { Vec3::new(w.x, w.y, -w.z) } else { w };
        let (wi, flags) = if uc < p_s {
            match self.coat.distribution() {
                None => {
                    let fr = fr_dielectric(o.z, self.coat.eta());
                    return Some(BsdfSample {
                        f: self.specular * (fr / o.z),
                        wi: Vec3::new(-wo.x, -wo.y, wo.z),
                        pdf: p_s,
                        flags: BxdfFlags::SPECULAR | BxdfFlags::REFLECTION,
                        eta: 1.0,
                        pdf_is_proportional: false,
                    });
                }
                Some(d) => (
                    side(reflect(o, d.sample_wm(o, u))),
                    BxdfFlags::GLOSSY | BxdfFlags::REFLECTION,
                ),
            }
        } else {
            (side(sample_cosine_hemisphere(u)), BxdfFlags::DIFFUSE_REFLECTION)
        };
        if !same_hemisphere(wo, wi) {
            return None;
        }
        let pdf = self.pdf(wo, wi);
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        Some(BsdfSample {
            f: self.f(wo, wi),
            wi,
            pdf,
            flags,
            eta: 1.0,
            pdf_is_proportional: false,
        })
    }

    /// The mixture density of [`Self::sample_f`] (without the delta of a smooth coat).
    #[must_use]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if !same_hemisphere(wo, wi) {
            return 0.0;
        }
        let (wo, wi) = (up(wo), up(wi));
        let p_s = self.specular_probability(wo.z);
        let mut pdf = (1.0 - p_s) * cosine_hemisphere_pdf(wi.z);
        if let Some(d) = self.coat.distribution() {
            if let Some(wm) = (wo + wi).try_normalize() {
                pdf += p_s * d.pdf(wo, wm) / (4.0 * wo.dot(wm).abs());
            }
        }
        pdf
    }
}

#[cfg(test)]
#[path = "plastic_tests.rs"]
mod tests;
