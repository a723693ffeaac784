//! Layer 5: integrators estimate the radiance arriving along a camera ray.
//!
//! The path tracer's direct-lighting estimator is chosen per render ([`DirectStrategy`]):
//! hemisphere sampling (uniform or cosine), light sampling, BSDF sampling, or both combined
//! by multiple importance sampling. Each is unbiased for every scene it accepts; the
//! strategies that can only find light by hitting it refuse scenes with point-like lights.
//!
//! Light tracing ([`LightPathIntegrator`]) traces paths from the lights and splats their
//! camera connections. Stochastic progressive photon mapping ([`sppm`]) does not work per
//! camera sample and has its own driver, [`sppm::render`]; so has Metropolis light transport
//! ([`mlt::render`]), which runs Markov chains over the bidirectional paths of [`bdpt`].

pub mod bdpt;
mod direct;
mod lightpath;
pub mod mlt;
mod path;
mod roulette;
pub mod sppm;

pub use bdpt::BdptIntegrator;
pub use direct::DirectEstimator;
pub use lightpath::LightPathIntegrator;
pub use path::PathIntegrator;
pub use roulette::roulette;

use crate::color::Rgb;
use crate::film::Splat;
use crate::math::Ray;
use crate::sampling::Sampler;
use crate::scene::{DirectStrategy, IntegratorKind, Scene};

/// Counters gathered while tracing, summed over the render.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TraceStats {
    /// Closest-hit rays traced (camera, continuation and direct-lighting rays).
    pub rays: u64,
    /// Shadow rays traced.
    pub shadow_rays: u64,
}

impl std::ops::AddAssign for TraceStats {
    fn add_assign(&mut self, o: Self) {
        self.rays += o.rays;
        self.shadow_rays += o.shadow_rays;
    }
}

/// Why an integrator cannot render a scene.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum IntegratorError {
    /// The direct-lighting strategy cannot see some of the scene's lights.
    #[error(
        "direct strategy \"{strategy}\" cannot find the scene's {count} point-like light(s) (point, spot, distant): \
         they have no area for a sampled ray to hit, so they would render black; use \"light-area\" or \"mis\""
    )]
    InvisibleLights {
        /// The strategy's name.
        strategy: &'static str,
        /// Number of such lights.
        count: usize,
    },
    /// The integrator does not render per camera sample; its module has its own driver.
    #[error("integrator \"{name}\" is rendered by its own driver (integrator::{name}::render), not per camera sample")]
    OwnDriver {
        /// The integrator's name.
        name: &'static str,
    },
}

/// The closed set of integrators.
#[derive(Clone, Debug)]
pub enum Integrator {
    /// Unidirectional path tracing (direct lighting only is a path of depth one).
    Path(PathIntegrator),
    /// Bidirectional path tracing.
    Bdpt(BdptIntegrator),
    /// Light tracing: every sample is a light path whose camera connections are splats.
    LightPath(LightPathIntegrator),
}

impl Integrator {
    /// Build from the scene's settings; fails when the chosen estimator cannot render the
    /// scene without bias.
    pub fn new(scene: &Scene) -> Result<Self, IntegratorError> {
        let s = &scene.integrator;
        match s.kind {
            IntegratorKind::Bdpt => return Ok(Self::Bdpt(BdptIntegrator::new(scene, &s.bdpt, s.max_depth))),
            IntegratorKind::LightPath => {
                return Ok(Self::LightPath(LightPathIntegrator {
                    max_depth: s.max_depth,
                    russian_roulette: s.russian_roulette,
                }))
            }
            IntegratorKind::Sppm => return Err(IntegratorError::OwnDriver { name: "sppm" }),
            IntegratorKind::Mlt => return Err(IntegratorError::OwnDriver { name: "mlt" }),
            IntegratorKind::Path | IntegratorKind::Direct => {}
        }
        let delta_lights = scene.lights.iter().filter(|l| l.is_delta()).count();
        if s.direct.needs_emitter_hits() && delta_lights > 0 {
            return Err(IntegratorError::InvisibleLights {
                strategy: s.direct.name(),
                count: delta_lights,
            });
        }
        let max_depth = match s.kind {
            IntegratorKind::Path => s.max_depth,
            IntegratorKind::Direct => s.max_depth.min(1),
            IntegratorKind::Bdpt | IntegratorKind::LightPath | IntegratorKind::Sppm | IntegratorKind::Mlt => {
                unreachable!("handled above")
            }
        };
        Ok(Self::Path(PathIntegrator {
            max_depth,
            direct: DirectEstimator {
                strategy: s.direct,
                samples: s.light_samples.max(1),
            },
            russian_roulette: s.russian_roulette,
        }))
    }

    /// Radiance arriving at the camera along `ray`. Contributions to other pixels (light
    /// tracing) are pushed onto `splats` in the order they are made; the path tracer never
    /// pushes.
    pub fn li(
        &self,
        scene: &Scene,
        ray: Ray,
        sampler: &mut Sampler,
        stats: &mut TraceStats,
        splats: &mut Vec<Splat>,
    ) -> Rgb {
        match self {
            Self::Path(p) => {
                let _ = splats;
                p.li(scene, ray, sampler, stats)
            }
            Self::Bdpt(b) => b.li(scene, ray, sampler, stats, splats),
            Self::LightPath(lp) => {
                // The camera ray is not used: everything arrives as splats.
                let _ = ray;
                lp.trace(scene, sampler, stats, &mut |p_film, l| splats.push(Splat { p_film, l }));
                Rgb::BLACK
            }
        }
    }

    /// Whether [`Self::li`] may push splats (the render session then renders one sample
    /// index at a time, so that splats are added in a fixed order with bounded memory).
    #[must_use]
    pub fn splats(&self) -> bool {
        match self {
            Self::Path(_) => false,
            Self::Bdpt(_) => true,
            Self::LightPath(_) => true,
        }
    }
}

/// The strategy names, for messages.
#[must_use]
pub fn strategy_names() -> Vec<&'static str> {
    DirectStrategy::ALL.iter().map(|d| d.name()).collect()
}
