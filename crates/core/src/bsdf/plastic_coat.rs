//! The dielectric coat of Mitsuba 3's `plastic` and `roughplastic`, with what its diffuse
//! term needs precomputed, as Mitsuba does when the plugin is built:
//!
//! * smooth: the diffuse Fresnel reflectance of the inside, `Fdr(1 / eta)`, by the fits
//!   Mitsuba uses (Egan and Hilgeman 1973 for `eta < 1`, d'Eon and Irving 2011 otherwise);
//! * rough: the coat's transmittance `T(mu)` for light arriving at `cos theta = mu`, on 64
//!   points `mu = i / 63` (linearly interpolated), and its internal reflectance
//!   `2 mean(R_int(mu) mu)` over the same points. `T(mu)` is the expectation over normals
//!   visible from the direction of `(1 - F(wi.m)) G1(wt)` (`wt` refracted about `m`),
//!   `R_int(mu)` that of `F(wi.m, 1 / eta) G1(wr)` (`wr` reflected), both by a
//!   Gauss-Legendre product rule on the sampler's square (32 points per axis for
//!   `eta > 1`, 128 otherwise), as Mitsuba's `eval_transmittance`/`eval_reflectance`.
//!
//! The rough tables take a few million microfacet samples; they are computed in parallel
//! and remembered per (distribution, index) for the life of the process, which lets the
//! coat refer to its table by a `&'static` and stay a small `Copy` value.

use super::fresnel::{fr_dielectric, reflect, refract};
use super::microfacet::Microfacet;
use crate::math::quadrature::gauss_legendre_unit;
use crate::math::{Vec2, Vec3};
use rayon::prelude::*;
use std::collections::HashMap;
use std::sync::{Mutex, OnceLock};

/// Points of the rough transmittance table (Mitsuba's `MI_ROUGH_TRANSMITTANCE_RES`).
pub const TABLE_SIZE: usize = 64;

/// A smooth or rough plastic coat of relative index `eta` (inside over outside).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlasticCoat {
    eta: f32,
    kind: CoatKind,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum CoatKind {
    Smooth {
        fdr_int: f32,
    },
    Rough {
        distrib: Microfacet,
        transmittance: &'static [f32; TABLE_SIZE],
        internal_reflectance: f32,
    },
}

/// Mitsuba's diffuse Fresnel reflectance `Fdr(eta)`: the fraction of uniformly diffuse
/// light reflected by a smooth interface of relative index `eta`.
#[must_use]
pub fn fresnel_diffuse_reflectance(eta: f32) -> f32 {
    if eta < 1.0 {
        -1.4399 * eta * eta + 0.7099 * eta + 0.6681 + 0.0636 / eta
    } else {
        let x = 1.0 / eta;
        0.919_317 + x * (-3.4793 + x * (6.753_35 + x * (-7.809_89 + x * (4.985_54 + x * -1.368_81))))
    }
}

impl PlasticCoat {
    /// A smooth coat.
    #[must_use]
    pub fn smooth(eta: f32) -> Self {
        Self {
            eta,
            kind: CoatKind::Smooth {
                fdr_int: fresnel_diffuse_reflectance(1.0 / eta),
            },
        }
    }

    /// A rough coat with microfacet distribution `distrib` (isotropic in Mitsuba; its
    /// masking term should be [`super::Masking::Separable`] to match Mitsuba).
    #[must_use]
    pub fn rough(distrib: Microfacet, eta: f32) -> Self {
        type Key = (super::MicrofacetModel, super::Masking, [u32; 3]);
        static TABLES: OnceLock<Mutex<HashMap<Key, PlasticCoat>>> = OnceLock::new();
        let key = (
            distrib.model,
            distrib.masking,
            [distrib.alpha_x.to_bits(), distrib.alpha_y.to_bits(), eta.to_bits()],
        );
        let tables = TABLES.get_or_init(|| Mutex::new(HashMap::new()));
        if let Some(coat) = tables.lock().ok().and_then(|t| t.get(&key).copied()) {
            return coat;
        }
        let coat = Self::compute_rough(distrib, eta);
        if let Ok(mut t) = tables.lock() {
            t.insert(key, coat);
        }
        coat
    }

    /// The tables of [`Self::rough`].
    fn compute_rough(distrib: Microfacet, eta: f32) -> Self {
        // Per table point: T(mu) and R_int(mu) mu.
        let rows: Vec<(f32, f64)> = (0..TABLE_SIZE)
            .into_par_iter()
            .map(|i| {
                let mu = (i as f32 / (TABLE_SIZE - 1) as f32).max(1e-6);
                let wi = Vec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu);
                let t = expectation(&distrib, wi, eta, |m| {
                    let (wt, _) = refract(wi, m, eta)?;
                    (wt.z < 0.0 && wt.dot(m) * wt.z > 0.0)
                        .then(|| (1.0 - fr_dielectric(wi.dot(m), eta)) * distrib.g1_separable(wt))
                });
                let r = expectation(&distrib, wi, 1.0 / eta, |m| {
                    let wr = reflect(wi, m);
                    (wr.z > 0.0).then(|| fr_dielectric(wi.dot(m), 1.0 / eta) * distrib.g1_separable(wr))
                });
                (t as f32, r * f64::from(mu))
            })
            .collect();
        let mut transmittance = Box::new([0.0; TABLE_SIZE]);
        for (t, row) in transmittance.iter_mut().zip(&rows) {
            *t = row.0;
        }
        // Kept for the life of the process with the cache entry of `rough` (one per
        // distinct distribution and index).
        let transmittance: &'static [f32; TABLE_SIZE] = Box::leak(transmittance);
        let sum: f64 = rows.iter().map(|r| r.1).sum();
        Self {
            eta,
            kind: CoatKind::Rough {
                distrib,
                transmittance,
                internal_reflectance: (2.0 * sum / TABLE_SIZE as f64) as f32,
            },
        }
    }

    /// Relative index of refraction, inside over outside.
    #[must_use]
    pub fn eta(&self) -> f32 {
        self.eta
    }

    /// The microfacet distribution of a rough coat.
    #[must_use]
    pub fn distribution(&self) -> Option<&Microfacet> {
        match &self.kind {
            CoatKind::Smooth { .. } => None,
            CoatKind::Rough { distrib, .. } => Some(distrib),
        }
    }

    /// What light arriving from outside at `cos theta = cos` lets into the coat: `1 - F`
    /// for a smooth coat, the interpolated table for a rough one.
    #[must_use]
    pub fn transmittance(&self, cos: f32) -> f32 {
        match &self.kind {
            CoatKind::Smooth { .. } => 1.0 - fr_dielectric(cos, self.eta),
            CoatKind::Rough { transmittance, .. } => {
                let x = cos.clamp(0.0, 1.0) * (TABLE_SIZE - 1) as f32;
                let i = (x as usize).min(TABLE_SIZE - 2);
                let t = x - i as f32;
                transmittance[i] * (1.0 - t) + transmittance[i + 1] * t
            }
        }
    }

    /// The fraction of diffuse light inside the coat reflected back down.
    #[must_use]
    pub fn internal_reflectance(&self) -> f32 {
        match &self.kind {
            CoatKind::Smooth { fdr_int } => *fdr_int,
            CoatKind::Rough {
                internal_reflectance, ..
            } => *internal_reflectance,
        }
    }
}

/// `E[g(m)]` over the normals visible from `wi` (with index `eta`: 128 points per axis
/// when `eta <= 1`, 32 otherwise), `g` zero where it gives `None`.
fn expectation(distrib: &Microfacet, wi: Vec3, eta: f32, g: impl Fn(Vec3) -> Option<f32>) -> f64 {
    let rule = gauss_legendre_unit(if eta > 1.0 { 32 } else { 128 });
    let mut sum = 0.0;
    for &(x, wx) in &rule {
        for &(y, wy) in &rule {
            let m = distrib.sample_wm(wi, Vec2::new(x as f32, y as f32));
            if let Some(v) = g(m) {
                sum += wx * wy * f64::from(v);
            }
        }
    }
    sum
}
