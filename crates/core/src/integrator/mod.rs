//! Layer 5: integrators estimate the radiance arriving along a camera ray.

mod direct_light;
mod path;

pub use direct_light::sample_direct_light;
pub use path::PathIntegrator;

use crate::color::Rgb;
use crate::math::Ray;
use crate::sampling::Sampler;
use crate::scene::Scene;

/// Counters gathered while tracing, summed over the render.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TraceStats {
    /// Closest-hit rays traced.
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

/// The closed set of integrators.
#[derive(Clone, Debug)]
pub enum Integrator {
    /// Unidirectional path tracing with next-event estimation and MIS.
    Path(PathIntegrator),
}

impl Integrator {
    /// Build from the scene's settings.
    #[must_use]
    pub fn from_scene(scene: &Scene) -> Self {
        Self::Path(PathIntegrator {
            max_depth: scene.integrator.max_depth,
        })
    }

    /// Radiance arriving at the camera along `ray`.
    pub fn li(&self, scene: &Scene, ray: Ray, sampler: &mut Sampler, stats: &mut TraceStats) -> Rgb {
        match self {
            Self::Path(p) => p.li(scene, ray, sampler, stats),
        }
    }
}
