//! Direct lighting at a path vertex, `L_d = integral f L_e cos dw` over light arriving
//! straight from emitters, estimated with one of five techniques and `N` samples.
//!
//! Paths find light in two ways: the direct estimate at a vertex, and the continuation ray
//! hitting an emitter at the next vertex. The strategy fixes how much of the second counts,
//! so that together they estimate each light path exactly once:
//! - `mis`: `N` light samples MIS-weighted against the continuation (a BSDF sample), which
//!   is weighted against the light samples: the power heuristic with counts `N` and 1
//!   (Veach 1997, eq. 9.13);
//! - `bsdf`: the continuation is one BSDF sample, `N - 1` more are traced here, all `1/N`;
//! - `light-area`, `uniform-hemisphere`, `cosine-hemisphere`: all `N` samples are taken
//!   here and emission found by the continuation does not count.
//!
//! After a specular bounce no direct estimate is possible and the continuation counts fully.

mod emitter_hit;
mod hemisphere;
mod light_sampling;

use emitter_hit::emitted_toward;
use hemisphere::sample_hemisphere;
use light_sampling::sample_lights;

use super::TraceStats;
use crate::bsdf::Bsdf;
use crate::color::Rgb;
use crate::sampling::{power_heuristic, Sampler};
use crate::scene::{DirectStrategy, Scene};
use crate::shape::SurfaceInteraction;

/// A direct-lighting technique and its sample count.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DirectEstimator {
    /// The technique.
    pub strategy: DirectStrategy,
    /// Samples per vertex (at least 1).
    pub samples: u32,
}

impl DirectEstimator {
    /// The direct light reflected towards `si.wo`, less the part the continuation ray will
    /// contribute (see [`Self::continuation_weight`]).
    pub fn estimate(
        &self,
        scene: &Scene,
        si: &SurfaceInteraction,
        bsdf: &Bsdf,
        sampler: &mut Sampler,
        stats: &mut TraceStats,
    ) -> Rgb {
        let n = self.samples;
        let inv_n = 1.0 / n as f32;
        let mut sum = Rgb::BLACK;
        match self.strategy {
            DirectStrategy::Mis => {
                for _ in 0..n {
                    sum += sample_lights(scene, si, bsdf, Some(n), sampler, stats);
                }
            }
            DirectStrategy::LightArea => {
                for _ in 0..n {
                    sum += sample_lights(scene, si, bsdf, None, sampler, stats);
                }
            }
            DirectStrategy::UniformHemisphere | DirectStrategy::CosineHemisphere => {
                let cosine = self.strategy == DirectStrategy::CosineHemisphere;
                for _ in 0..n {
                    sum += sample_hemisphere(scene, si, bsdf, cosine, sampler, stats);
                }
            }
            DirectStrategy::Bsdf => {
                // The continuation ray is the N-th BSDF sample.
                for _ in 1..n {
                    let uc = sampler.get_1d();
                    let u = sampler.get_2d();
                    if let Some(bs) = bsdf.sample_f(si.wo, uc, u) {
                        if !bs.flags.is_specular() {
                            let le = emitted_toward(scene, si, bs.wi, stats);
                            sum += bs.f * le * (bs.wi.dot(si.ns).abs() / bs.pdf);
                        }
                    }
                }
            }
        }
        sum * inv_n
    }

    /// Weight of emission found by the continuation ray after a non-specular bounce whose
    /// BSDF pdf was `p_bsdf`, at an emitter whose light-sampling pdf there is `p_light`.
    #[must_use]
    pub fn continuation_weight(&self, p_bsdf: f32, p_light: f32) -> f32 {
        match self.strategy {
            DirectStrategy::Mis => power_heuristic(1.0, p_bsdf, self.samples as f32, p_light),
            DirectStrategy::Bsdf => 1.0 / self.samples as f32,
            DirectStrategy::LightArea | DirectStrategy::UniformHemisphere | DirectStrategy::CosineHemisphere => 0.0,
        }
    }

    /// True when emission found by the continuation ray can count (so the ray is worth
    /// tracing even when the path ends at the next vertex).
    #[must_use]
    pub fn uses_continuation(&self) -> bool {
        matches!(self.strategy, DirectStrategy::Mis | DirectStrategy::Bsdf)
    }
}
