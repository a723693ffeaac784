//! Next-event estimation: one light chosen in proportion to power, one point sampled on
//! it, weighted against BSDF sampling by the power heuristic (Veach 1997, eq. 9.13).

use super::TraceStats;
use crate::bsdf::Bsdf;
use crate::color::Rgb;
use crate::sampling::{power_heuristic, Sampler};
use crate::scene::Scene;
use crate::shape::SurfaceInteraction;

/// MIS-weighted estimate of the light reflected towards `si.wo` directly from lights.
pub fn sample_direct_light(
    scene: &Scene,
    si: &SurfaceInteraction,
    bsdf: &Bsdf,
    sampler: &mut Sampler,
    stats: &mut TraceStats,
) -> Rgb {
    // Always draw the same dimensions, so later samples do not shift with the path.
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
    if light.is_delta() {
        return f * ls.l / p_light;
    }
    let p_bsdf = bsdf.pdf(si.wo, ls.wi);
    let w = power_heuristic(1.0, p_light, 1.0, p_bsdf);
    f * ls.l * (w / p_light)
}
