//! Bidirectional path tracing (Veach 1997, chapter 10; pbrt-v4 `BDPTIntegrator`).
//!
//! For every camera sample a camera subpath and a light subpath are traced
//! ([`subpath`]), and every prefix pair, `s` light vertices with `t` camera vertices, is
//! connected into a complete path ([`connect`]): `s = 0` is the camera path hitting an
//! emitter, `s = 1` next-event estimation, `t = 1` light tracing, whose contributions are
//! splatted with the pixel filter around the film point their direction falls on (see
//! [`crate::film::Splat`] for why both meet in one filtered image). Each strategy's contribution is
//! weighted by the power heuristic over all strategies that could have produced the same
//! path ([`mis`]), so their sum is unbiased and low in variance wherever one of them is good.
//!
//! Paths have at most `max_depth` scattering events (`s + t - 2 <= max_depth`), as the
//! path tracer counts them. Layered BSDFs only estimate their density stochastically, so
//! the MIS weights of paths through them are estimates too: the weights of one path's
//! strategies then no longer sum to exactly one, which leaves a small bias of the order of
//! the density estimate's relative error on the light those paths carry (pbrt-v4 has the
//! same limitation).

pub(crate) mod connect;
pub(crate) mod mis;
pub(crate) mod subpath;
pub(crate) mod vertex;

pub use mis::MisMode;

use connect::connect;
use subpath::{camera_subpath, light_subpath};
use vertex::{Context, Vertex};

use super::TraceStats;
use crate::color::Rgb;
use crate::film::Splat;
use crate::light::scene_radius;
use crate::math::{Bounds3, Ray};
use crate::sampling::Sampler;
use crate::scene::{BdptDesc, Scene};

/// Bidirectional path tracer settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BdptIntegrator {
    /// Maximum number of scattering events of a path.
    pub max_depth: u32,
    /// MIS weighting of the strategies.
    pub mis: MisMode,
    /// When set, only the strategy `(s, t)` contributes (for studying the strategies).
    pub strategy: Option<(u32, u32)>,
    /// Radius of the scene's bounding sphere.
    pub scene_radius: f32,
    /// Roughen near-specular BSDFs after a non-specular bounce (biased).
    pub regularize: bool,
}

impl BdptIntegrator {
    /// Settings for `scene`: the bounds of its geometry fix the density of light arriving
    /// from infinity.
    #[must_use]
    pub fn new(scene: &Scene, desc: &BdptDesc, max_depth: u32) -> Self {
        let mut bounds = Bounds3::default();
        for p in &scene.primitives {
            bounds = bounds.union(p.shape.bounds());
        }
        for inst in &scene.instances {
            bounds = bounds.union(inst.bounds());
        }
        Self {
            max_depth,
            mis: if desc.mis { MisMode::Power } else { MisMode::Off },
            strategy: desc.strategy,
            scene_radius: scene_radius(&bounds),
            regularize: desc.regularize,
        }
    }

    /// Radiance along the camera ray `ray`, from the strategies with `t >= 2`; the light
    /// tracing strategies (`t = 1`) push their contributions onto `splats`.
    pub fn li(
        &self,
        scene: &Scene,
        ray: Ray,
        sampler: &mut Sampler,
        stats: &mut TraceStats,
        splats: &mut Vec<Splat>,
    ) -> Rgb {
        let ctx = Context {
            scene,
            scene_radius: self.scene_radius,
            regularize: self.regularize,
        };
        let max_depth = self.max_depth as usize;
        let mut camera: Vec<Vertex> = Vec::with_capacity(max_depth + 2);
        let mut light: Vec<Vertex> = Vec::with_capacity(max_depth + 1);
        camera_subpath(&ctx, ray, sampler, max_depth + 2, &mut camera, stats);
        light_subpath(&ctx, sampler, max_depth + 1, &mut light, stats);

        // Connect every pair of prefixes.
        let mut l = Rgb::BLACK;
        for t in 1..=camera.len() {
            for s in 0..=light.len() {
                let depth = (s + t) as i64 - 2;
                if (s == 1 && t == 1) || depth < 0 || depth > max_depth as i64 {
                    continue;
                }
                // Every strategy is evaluated, so that the random numbers each one draws do
                // not depend on which are kept: the images of the strategies alone then add
                // up to the full image sample by sample.
                let Some(c) = connect(&ctx, &light, &camera, s, t, self.mis, sampler, stats) else {
                    continue;
                };
                if !c.l.is_finite() || self.strategy.is_some_and(|st| st != (s as u32, t as u32)) {
                    continue;
                }
                match c.p_raster {
                    Some(p_film) => splats.push(Splat { p_film, l: c.l }),
                    None => l += c.l,
                }
            }
        }
        l
    }
}
