//! Layer 2: BSDFs. Lobes ([`Bxdf`]) are written in the local shading frame (z = shading
//! normal); [`Bsdf`] wraps a lobe with its frame and works on world-space directions.
//!
//! [`Bsdf`] also knows the geometric normal and guards against the light leaks of shading
//! normals (Veach 1997, section 5.3; pbrt-v3 `BSDF::f`): whether a pair of directions is
//! a reflection or a transmission is decided by the geometric normal, and a lobe only
//! contributes when the shading frame agrees.
//!
//! Conventions: `f` excludes the cosine factor; pdfs are per unit solid angle; `wo` and `wi`
//! both point away from the surface.

mod beckmann;
mod bump_shadowing;
mod conductor;
mod dielectric;
mod diffuse;
mod diffuse_transmission;
mod flags;
pub mod fresnel;
mod henyey_greenstein;
mod layered;
mod metallic_roughness;
pub mod microfacet;
mod plastic;
pub mod plastic_coat;
mod thin_dielectric;
mod transport;

pub use bump_shadowing::BumpShadowing;
pub use conductor::ConductorBxdf;
pub use dielectric::DielectricBxdf;
pub use diffuse::DiffuseBxdf;
pub use diffuse_transmission::DiffuseTransmissionBxdf;
pub use flags::BxdfFlags;
pub use henyey_greenstein::{HenyeyGreenstein, PhaseSample};
pub use layered::{CoatedConductorBxdf, CoatedDiffuseBxdf, LayeredBxdf, OpaqueBase};
pub use metallic_roughness::MetallicRoughnessBxdf;
pub use microfacet::{roughness_to_alpha, Masking, Microfacet, MicrofacetModel, MicrofacetStyle};
pub use plastic::PlasticBxdf;
pub use plastic_coat::PlasticCoat;
pub use thin_dielectric::ThinDielectricBxdf;
pub use transport::{ReflTrans, TransportMode};

use crate::color::Rgb;
use crate::math::{Frame, Vec2, Vec3};

/// A sampled direction with its BSDF value and density.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample {
    /// BSDF value `f(wo, wi)` (no cosine).
    pub f: Rgb,
    /// Sampled incident direction (local frame inside a [`Bxdf`], world frame from [`Bsdf`]).
    pub wi: Vec3,
    /// Density of `wi` per unit solid angle (for specular lobes, the discrete probability).
    pub pdf: f32,
    /// Kind of scattering sampled.
    pub flags: BxdfFlags,
    /// For transmission, the relative index of refraction crossed (index on the side of
    /// `wi` over that on the side of `wo`); 1 otherwise. Radiance crossing the interface is
    /// scaled by `1 / eta^2` in `f`; the integrator undoes that for Russian roulette.
    pub eta: f32,
    /// True when `f` and `pdf` are only proportional to the true values (stochastic
    /// lobes such as [`LayeredBxdf`]): `f / pdf` is still the right throughput, but MIS
    /// weights must use [`Bsdf::pdf`] instead of `pdf` (as pbrt-v4's `pdfIsProportional`).
    pub pdf_is_proportional: bool,
}

/// The closed set of lobes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bxdf {
    /// Lambertian reflection.
    Diffuse(DiffuseBxdf),
    /// Smooth or rough (microfacet) conductor.
    Conductor(ConductorBxdf),
    /// Smooth or rough dielectric interface: reflection and refraction.
    Dielectric(DielectricBxdf),
    /// Thin dielectric slab: specular reflection and straight transmission.
    ThinDielectric(ThinDielectricBxdf),
    /// Lambertian reflection and transmission.
    DiffuseTransmission(DiffuseTransmissionBxdf),
    /// A dielectric coat over a Lambertian base (stochastic).
    CoatedDiffuse(CoatedDiffuseBxdf),
    /// A dielectric coat over a conductor (stochastic).
    CoatedConductor(CoatedConductorBxdf),
    /// glTF 2.0's metallic-roughness BRDF.
    MetallicRoughness(MetallicRoughnessBxdf),
    /// Mitsuba 3's plastic: a smooth or rough coat over a diffuse base.
    Plastic(PlasticBxdf),
}

macro_rules! dispatch {
    ($self:ident, $b:ident => $e:expr) => {
        match $self {
            Bxdf::Diffuse($b) => $e,
            Bxdf::Conductor($b) => $e,
            Bxdf::Dielectric($b) => $e,
            Bxdf::ThinDielectric($b) => $e,
            Bxdf::DiffuseTransmission($b) => $e,
            Bxdf::CoatedDiffuse($b) => $e,
            Bxdf::CoatedConductor($b) => $e,
            Bxdf::MetallicRoughness($b) => $e,
            Bxdf::Plastic($b) => $e,
        }
    };
}

impl Bxdf {
    /// What kinds of scattering the lobe can do (empty when it is black).
    #[must_use]
    pub fn flags(&self) -> BxdfFlags {
        dispatch!(self, b => b.flags())
    }

    /// `f(wo, wi)` in the local frame.
    #[must_use]
    pub fn f(&self, wo: Vec3, wi: Vec3) -> Rgb {
        dispatch!(self, b => b.f(wo, wi))
    }

    /// Sample `wi` given `wo` (local frame) from two uniform numbers and one more for lobe
    /// selection.
    #[must_use]
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample> {
        dispatch!(self, b => b.sample_f(wo, uc, u))
    }

    /// Density of [`Self::sample_f`] producing `wi`.
    #[must_use]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        dispatch!(self, b => b.pdf(wo, wi))
    }
}

/// A lobe placed in a shading frame, with the geometric normal that guards it against
/// light leaks (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bsdf {
    frame: Frame,
    ng: Vec3,
    bxdf: Bxdf,
    /// `bxdf.flags()`, asked several times per path vertex (a call through the lobe enum
    /// each time); kept in step by every change of the lobe ([`Self::regularize`]).
    flags: BxdfFlags,
    /// Mitsuba's shadowing of the light side under a normal or bump map.
    shadowing: Option<BumpShadowing>,
}

impl Bsdf {
    /// The lobe in the local frame.
    #[must_use]
    pub fn bxdf(&self) -> &Bxdf {
        &self.bxdf
    }

    /// A BSDF with shading normal `ns`, tangent `dpdu` and geometric normal `ng` (either
    /// orientation: only the side of a direction relative to the surface is used).
    #[inline]
    #[must_use]
    pub fn new(ns: Vec3, dpdu: Vec3, ng: Vec3, bxdf: Bxdf) -> Self {
        Self {
            frame: Frame::from_zx(ns, dpdu),
            ng,
            flags: bxdf.flags(),
            bxdf,
            shadowing: None,
        }
    }

    /// The BSDF with Mitsuba 3's shadowing of a normal or bump map ([`BumpShadowing`]):
    /// every value for incident direction `wi` (the side the light comes from when
    /// tracing radiance, as Mitsuba's `wo`) is scaled by the factor; densities are not.
    #[must_use]
    pub fn with_shadowing(mut self, shadowing: BumpShadowing) -> Self {
        self.shadowing = Some(shadowing);
        self
    }

    /// The shadowing factor for incident direction `wi` (1 without a map).
    fn shadow(&self, wi: Vec3) -> f32 {
        self.shadowing.map_or(1.0, |s| s.factor(wi))
    }

    /// True when the geometric surface sees `wo` and `wi` on the same side (a reflection).
    fn reflects_geometrically(&self, wo: Vec3, wi: Vec3) -> bool {
        wo.dot(self.ng) * wi.dot(self.ng) > 0.0
    }

    /// True when the geometric normal and the shading frame agree on whether the world
    /// directions `wo`, `wi` (local `wo_l`, `wi_l`) are a reflection or a transmission.
    fn sides_agree(&self, wo: Vec3, wi: Vec3, wo_l: Vec3, wi_l: Vec3) -> bool {
        self.reflects_geometrically(wo, wi) == same_hemisphere(wo_l, wi_l)
    }

    /// Kinds of scattering.
    #[must_use]
    pub fn flags(&self) -> BxdfFlags {
        debug_assert_eq!(self.flags, self.bxdf.flags());
        self.flags
    }

    /// Roughen the microfacet distributions of conductors, dielectrics and coats (pbrt-v4
    /// `BSDF::Regularize`), turning near-specular lobes into glossy ones that connections
    /// can reach; a biased but consistent-looking trade used by bidirectional methods.
    /// Other lobes are unchanged.
    pub fn regularize(&mut self) {
        match &mut self.bxdf {
            Bxdf::Conductor(c) => c.distrib.regularize(),
            Bxdf::Dielectric(d) => d.distrib.regularize(),
            Bxdf::CoatedDiffuse(l) => l.top.distrib.regularize(),
            Bxdf::CoatedConductor(l) => {
                l.top.distrib.regularize();
                l.bottom.distrib.regularize();
            }
            Bxdf::MetallicRoughness(m) => m.distrib.regularize(),
            // (A rough plastic's coat tables belong to its roughness: left as it is.)
            Bxdf::Diffuse(_) | Bxdf::ThinDielectric(_) | Bxdf::DiffuseTransmission(_) | Bxdf::Plastic(_) => {}
        }
        // A roughened lobe may no longer be specular.
        self.flags = self.bxdf.flags();
    }

    /// `f(wo, wi)` for world-space directions; zero when the geometric normal and the
    /// shading frame disagree on reflection versus transmission (the light-leak guard).
    #[must_use]
    pub fn f(&self, wo: Vec3, wi: Vec3) -> Rgb {
        let (wo_l, wi_l) = (self.frame.to_local(wo), self.frame.to_local(wi));
        if wo_l.z == 0.0 || !self.sides_agree(wo, wi, wo_l, wi_l) {
            return Rgb::BLACK;
        }
        self.bxdf.f(wo_l, wi_l) * self.shadow(wi)
    }

    /// Sample an incident direction (world space) for outgoing `wo`; `None` when the
    /// sampled direction's side of the geometric surface disagrees with the kind of lobe
    /// sampled (reflection or transmission), as [`Self::f`] would be zero there.
    #[must_use]
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample> {
        self.sample_f_mode(wo, uc, u, TransportMode::Radiance)
    }

    /// `f(wo, wi)` for the quantity `mode` carries: radiance as [`Self::f`]; importance
    /// (paths traced from the lights) without the `1 / eta'^2` scaling of refraction
    /// (pbrt-v4 section 9.5.2). Only dielectric interfaces differ; the other lobes are
    /// symmetric, and the layered lobes reflect only, so the scaling cancels on the way
    /// into and out of the coat.
    #[must_use]
    pub fn f_mode(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Rgb {
        match (mode, &self.bxdf) {
            (TransportMode::Importance, Bxdf::Dielectric(d)) => {
                let (wo_l, wi_l) = (self.frame.to_local(wo), self.frame.to_local(wi));
                if wo_l.z == 0.0 || !self.sides_agree(wo, wi, wo_l, wi_l) {
                    return Rgb::BLACK;
                }
                d.f_mode(wo_l, wi_l, mode) * self.shadow(wi)
            }
            _ => self.f(wo, wi),
        }
    }

    /// [`Self::sample_f`] for the quantity `mode` carries (see [`Self::f_mode`]).
    #[must_use]
    pub fn sample_f_mode(&self, wo: Vec3, uc: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        let wo_l = self.frame.to_local(wo);
        if wo_l.z == 0.0 || self.flags().is_empty() {
            return None;
        }
        let bs = match (mode, &self.bxdf) {
            (TransportMode::Importance, Bxdf::Dielectric(d)) => d.sample_f_mode(wo_l, uc, u, mode, ReflTrans::All)?,
            _ => self.bxdf.sample_f(wo_l, uc, u)?,
        };
        if bs.f.is_black() || bs.pdf == 0.0 || bs.wi.z == 0.0 || !bs.pdf.is_finite() {
            return None;
        }
        let wi = self.frame.from_local(bs.wi);
        if self.reflects_geometrically(wo, wi) != bs.flags.contains(BxdfFlags::REFLECTION) {
            return None;
        }
        let f = bs.f * self.shadow(wi);
        Some(BsdfSample { wi, f, ..bs })
    }

    /// Density of [`Self::sample_f`] for world-space directions: zero where the light-leak
    /// guard rejects the pair, as [`Self::sample_f`] never returns such a direction. (The
    /// lobe's density elsewhere is not renormalised for the rejected samples, as in pbrt.)
    #[must_use]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let (wo_l, wi_l) = (self.frame.to_local(wo), self.frame.to_local(wi));
        if wo_l.z == 0.0 || !self.sides_agree(wo, wi, wo_l, wi_l) {
            return 0.0;
        }
        self.bxdf.pdf(wo_l, wi_l)
    }
}

/// True when `a` and `b` (local frame) are on the same side of the surface.
#[inline]
#[must_use]
pub fn same_hemisphere(a: Vec3, b: Vec3) -> bool {
    a.z * b.z > 0.0
}

#[cfg(test)]
pub(crate) mod tests;
