//! Dielectric interfaces (pbrt-v4 `DielectricBxDF`): glass, water. Reflection and
//! transmission are chosen in proportion to the Fresnel reflectance `R` and `T = 1 - R`.
//!
//! Smooth (alpha below [`super::microfacet::SMOOTH_ALPHA`], or `eta == 1`): a mirror
//! direction with weight `R` and a refracted one with weight `T`; with `eta == 1` light
//! passes straight through. Rough: the microfacet model of Walter et al. 2007 with the
//! generalised half vector `wm = normalize(eta' wi + wo)` (`eta'` is the relative index on
//! the side of `wi` over that of `wo` for transmission, 1 for reflection), the normal
//! sampled from the visible normals of `wo`.
//!
//! `eta` is the index of the inside (the side opposite the shading normal) over the
//! outside. Transmitted radiance is scaled by `1 / eta'^2` (pbrt's `TransportMode::Radiance`;
//! radiance is the only transport mode here), so the BSDF is not symmetric for
//! transmission and the sampled `eta` is `eta'`, for the integrator's Russian roulette.

use super::fresnel::{fr_dielectric, reflect, refract};
use super::microfacet::Microfacet;
use super::{same_hemisphere, BsdfSample, BxdfFlags, ReflTrans, TransportMode};
use crate::color::Rgb;
use crate::math::{sqr, Vec2, Vec3};

/// A smooth or rough dielectric interface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DielectricBxdf {
    /// Relative index of refraction, inside over outside.
    pub eta: f32,
    /// Microfacet roughness.
    pub distrib: Microfacet,
}

impl DielectricBxdf {
    fn is_specular(&self) -> bool {
        self.eta == 1.0 || self.distrib.effectively_smooth()
    }

    /// Reflection and transmission (only transmission when `eta == 1`), specular or glossy.
    #[must_use]
    pub fn flags(&self) -> BxdfFlags {
        let kinds = if self.eta == 1.0 {
            BxdfFlags::TRANSMISSION
        } else {
            BxdfFlags::REFLECTION | BxdfFlags::TRANSMISSION
        };
        kinds
            | if self.is_specular() {
                BxdfFlags::SPECULAR
            } else {
                BxdfFlags::GLOSSY
            }
    }

    /// The generalised half vector of `wo` and `wi` facing +z, the relative index `eta'`
    /// the pair implies, and whether it is a reflection; `None` for degenerate pairs and
    /// pairs only back-facing microfacets could connect.
    fn half_vector(&self, wo: Vec3, wi: Vec3) -> Option<(Vec3, f32, bool)> {
        let (cos_o, cos_i) = (wo.z, wi.z);
        if cos_o == 0.0 || cos_i == 0.0 {
            return None;
        }
        let reflect = cos_o * cos_i > 0.0;
        let etap = if reflect {
            1.0
        } else if cos_o > 0.0 {
            self.eta
        } else {
            1.0 / self.eta
        };
        let mut wm = (wi * etap + wo).try_normalize()?;
        if wm.z < 0.0 {
            wm = -wm;
        }
        // Discard back-facing microfacets.
        if wm.dot(wi) * cos_i < 0.0 || wm.dot(wo) * cos_o < 0.0 {
            return None;
        }
        Some((wm, etap, reflect))
    }

    /// The rough BSDF for radiance; zero when specular.
    #[must_use]
    pub fn f(&self, wo: Vec3, wi: Vec3) -> Rgb {
        self.f_mode(wo, wi, TransportMode::Radiance)
    }

    /// The rough BSDF for `mode` (importance skips the `1 / eta'^2` scaling of
    /// transmission); zero when specular.
    #[must_use]
    pub fn f_mode(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Rgb {
        if self.is_specular() {
            return Rgb::BLACK;
        }
        let Some((wm, etap, reflect)) = self.half_vector(wo, wi) else {
            return Rgb::BLACK;
        };
        let fr = fr_dielectric(wo.dot(wm), self.eta);
        let d = &self.distrib;
        let v = if reflect {
            d.d(wm) * d.g(wo, wi) * fr / (4.0 * wi.z * wo.z).abs()
        } else {
            let denom = sqr(wi.dot(wm) + wo.dot(wm) / etap) * wi.z * wo.z;
            d.d(wm) * (1.0 - fr) * d.g(wo, wi) * (wi.dot(wm) * wo.dot(wm) / denom).abs() * radiance_scale(etap, mode)
        };
        Rgb::splat(v)
    }

    /// Sample reflection or transmission in proportion to Fresnel (radiance).
    #[must_use]
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample> {
        self.sample_f_mode(wo, uc, u, TransportMode::Radiance, ReflTrans::All)
    }

    /// Sample among the kinds `allowed` in proportion to their Fresnel weights, for `mode`.
    #[must_use]
    pub fn sample_f_mode(
        &self,
        wo: Vec3,
        uc: f32,
        u: Vec2,
        mode: TransportMode,
        allowed: ReflTrans,
    ) -> Option<BsdfSample> {
        if self.is_specular() {
            let r = fr_dielectric(wo.z, self.eta);
            let (pr, pt) = allowed.probabilities(r, 1.0 - r)?;
            if uc < pr {
                let wi = Vec3::new(-wo.x, -wo.y, wo.z);
                return Some(BsdfSample {
                    f: Rgb::splat(r / wi.z.abs()),
                    wi,
                    pdf: pr,
                    flags: BxdfFlags::SPECULAR | BxdfFlags::REFLECTION,
                    eta: 1.0,
                    pdf_is_proportional: false,
                });
            }
            let (wi, etap) = refract(wo, Vec3::Z, self.eta)?;
            if wi.z == 0.0 {
                return None;
            }
            return Some(BsdfSample {
                f: Rgb::splat((1.0 - r) / wi.z.abs() * radiance_scale(etap, mode)),
                wi,
                pdf: pt,
                flags: BxdfFlags::SPECULAR | BxdfFlags::TRANSMISSION,
                eta: etap,
                pdf_is_proportional: false,
            });
        }
        if wo.z == 0.0 {
            return None;
        }
        let d = &self.distrib;
        let wm = d.sample_wm(wo, u);
        let r = fr_dielectric(wo.dot(wm), self.eta);
        let t = 1.0 - r;
        let (pr, pt) = allowed.probabilities(r, t)?;
        if uc < pr {
            let wi = reflect(wo, wm);
            if !same_hemisphere(wo, wi) {
                return None;
            }
            let pdf = d.pdf(wo, wm) / (4.0 * wo.dot(wm).abs()) * pr;
            if pdf.is_nan() || pdf <= 0.0 {
                // A normal at the horizon, where D vanishes: no sample.
                return None;
            }
            let f = d.d(wm) * d.g(wo, wi) * r / (4.0 * wi.z * wo.z).abs();
            return Some(BsdfSample {
                f: Rgb::splat(f),
                wi,
                pdf,
                flags: BxdfFlags::GLOSSY | BxdfFlags::REFLECTION,
                eta: 1.0,
                pdf_is_proportional: false,
            });
        }
        let (wi, etap) = refract(wo, wm, self.eta)?;
        if same_hemisphere(wo, wi) || wi.z == 0.0 {
            return None;
        }
        let denom = sqr(wi.dot(wm) + wo.dot(wm) / etap);
        let dwm_dwi = wi.dot(wm).abs() / denom;
        let pdf = d.pdf(wo, wm) * dwm_dwi * pt;
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        let f = t
            * d.d(wm)
            * d.g(wo, wi)
            * (wi.dot(wm) * wo.dot(wm) / (wi.z * wo.z * denom)).abs()
            * radiance_scale(etap, mode);
        Some(BsdfSample {
            f: Rgb::splat(f),
            wi,
            pdf,
            flags: BxdfFlags::GLOSSY | BxdfFlags::TRANSMISSION,
            eta: etap,
            pdf_is_proportional: false,
        })
    }

    /// Density of [`Self::sample_f`]; zero when specular.
    #[must_use]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.pdf_mode(wo, wi, ReflTrans::All)
    }

    /// Density of [`Self::sample_f_mode`] restricted to `allowed`; zero when specular.
    #[must_use]
    pub fn pdf_mode(&self, wo: Vec3, wi: Vec3, allowed: ReflTrans) -> f32 {
        if self.is_specular() {
            return 0.0;
        }
        let Some((wm, etap, reflect)) = self.half_vector(wo, wi) else {
            return 0.0;
        };
        let r = fr_dielectric(wo.dot(wm), self.eta);
        let Some((pr, pt)) = allowed.probabilities(r, 1.0 - r) else {
            return 0.0;
        };
        let d = &self.distrib;
        if reflect {
            d.pdf(wo, wm) / (4.0 * wo.dot(wm).abs()) * pr
        } else {
            let denom = sqr(wi.dot(wm) + wo.dot(wm) / etap);
            d.pdf(wo, wm) * (wi.dot(wm).abs() / denom) * pt
        }
    }
}

/// The factor transmitted radiance gets, `1 / eta'^2`; 1 for importance.
fn radiance_scale(etap: f32, mode: TransportMode) -> f32 {
    match mode {
        TransportMode::Radiance => 1.0 / sqr(etap),
        TransportMode::Importance => 1.0,
    }
}
