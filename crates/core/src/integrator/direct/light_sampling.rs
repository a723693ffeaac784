//! Direct lighting by sampling the lights: choose a light in proportion to its power, a
//! point on it uniformly by area, convert to solid angle (`p_w = p_A r^2 / |cos theta_l|`),
//! and trace a shadow ray. Estimate: `f L_e |cos theta_i| V / p_w`, optionally weighted by
//! the power heuristic against BSDF sampling.

use crate::bsdf::Bsdf;
use crate::color::Rgb;
use crate::integrator::TraceStats;
use crate::sampling::{power_heuristic, Sampler};
use crate::scene::Scene;
use crate::shape::SurfaceInteraction;

/// One light-sampled estimate. With `mis_light_samples = Some(n)`, the sample is weighted
/// against one BSDF sample by the power heuristic with `n` light samples.
pub fn sample_lights(
    scene: &Scene,
    si: &SurfaceInteraction,
    bsdf: &Bsdf,
    mis_light_samples: Option<u32>,
    sampler: &mut Sampler,
    stats: &mut TraceStats,
) -> Rgb {
    // Always draw the same dimensions, so later samples do not shift with the outcome.
    let u_light = sampler.get_1d();
    let u = sampler.get_2d();
    let Some((index, light_prob)) = scene.light_sampler.sample(u_light) else {
        return Rgb::BLACK;
    };
    let light = &scene.lights[index];
    let Some(ls) = light.sample_li(&si.intr, u) else {
        return Rgb::BLACK;
    };
    let f = bsdf.f(si.wo, ls.wi) * ls.wi.dot(si.ns).abs();
    if f.is_black() {
        return Rgb::BLACK;
    }
    stats.shadow_rays += 1;
    if !scene.unoccluded(&si.intr, &ls.p_light) {
        return Rgb::BLACK;
    }
    let p_light = light_prob * ls.pdf;
    let weight = match mis_light_samples {
        Some(n) if !light.is_delta() => power_heuristic(n as f32, p_light, 1.0, bsdf.pdf(si.wo, ls.wi)),
        _ => 1.0,
    };
    f * ls.l * (weight / p_light)
}
