//! Layer 2: BSDFs. Lobes ([`Bxdf`]) are written in the local shading frame (z = shading
//! normal); [`Bsdf`] wraps a lobe with its frame and works on world-space directions.
//!
//! Conventions: `f` excludes the cosine factor; pdfs are per unit solid angle; `wo` and `wi`
//! both point away from the surface.

mod conductor;
mod dielectric;
mod diffuse;
mod diffuse_transmission;
mod flags;
pub mod fresnel;
mod henyey_greenstein;
mod layered;
pub mod microfacet;
mod thin_dielectric;
mod transport;

pub use conductor::ConductorBxdf;
pub use dielectric::DielectricBxdf;
pub use diffuse::DiffuseBxdf;
pub use diffuse_transmission::DiffuseTransmissionBxdf;
pub use flags::BxdfFlags;
pub use henyey_greenstein::{HenyeyGreenstein, PhaseSample};
pub use layered::{CoatedConductorBxdf, CoatedDiffuseBxdf, LayeredBxdf, OpaqueBase};
pub use microfacet::{roughness_to_alpha, TrowbridgeReitz};
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

/// A lobe placed in a shading frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bsdf {
    frame: Frame,
    bxdf: Bxdf,
}

impl Bsdf {
    /// The lobe in the local frame.
    #[must_use]
    pub fn bxdf(&self) -> &Bxdf {
        &self.bxdf
    }

    /// A BSDF with shading normal `ns` and tangent `dpdu`.
    #[must_use]
    pub fn new(ns: Vec3, dpdu: Vec3, bxdf: Bxdf) -> Self {
        Self {
            frame: Frame::from_zx(ns, dpdu),
            bxdf,
        }
    }

    /// Kinds of scattering.
    #[must_use]
    pub fn flags(&self) -> BxdfFlags {
        self.bxdf.flags()
    }

    /// `f(wo, wi)` for world-space directions.
    #[must_use]
    pub fn f(&self, wo: Vec3, wi: Vec3) -> Rgb {
        let (wo, wi) = (self.frame.to_local(wo), self.frame.to_local(wi));
        if wo.z == 0.0 {
            return Rgb::BLACK;
        }
        self.bxdf.f(wo, wi)
    }

    /// Sample an incident direction (world space) for outgoing `wo`.
    #[must_use]
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample> {
        let wo = self.frame.to_local(wo);
        if wo.z == 0.0 || self.bxdf.flags().is_empty() {
            return None;
        }
        let bs = self.bxdf.sample_f(wo, uc, u)?;
        if bs.f.is_black() || bs.pdf == 0.0 || bs.wi.z == 0.0 || !bs.pdf.is_finite() {
            return None;
        }
        Some(BsdfSample {
            wi: self.frame.from_local(bs.wi),
            ..bs
        })
    }

    /// Density of [`Self::sample_f`] for world-space directions.
    #[must_use]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let (wo, wi) = (self.frame.to_local(wo), self.frame.to_local(wi));
        if wo.z == 0.0 {
            return 0.0;
        }
        self.bxdf.pdf(wo, wi)
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
