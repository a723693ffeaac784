//! Direct lighting by sampling directions without regard to lights or BSDF: uniformly over
//! the hemisphere (p = 1 / (2 pi), the inversion method) or cosine-weighted
//! (p = cos theta / pi). Estimate: `f L_e |cos| / p` for the emitter the ray hits.
//!
//! The hemisphere is the one around the shading normal on the side of `wo`; for BSDFs that
//! transmit, both hemispheres are used (each chosen with probability 1/2), so light from
//! behind is not missed.

use super::emitted_toward;
use crate::bsdf::{Bsdf, BxdfFlags};
use crate::color::Rgb;
use crate::integrator::TraceStats;
use crate::math::Frame;
use crate::sampling::{
    cosine_hemisphere_pdf, sample_cosine_hemisphere, sample_uniform_hemisphere, uniform_hemisphere_pdf, Sampler,
};
use crate::scene::Scene;
use crate::shape::SurfaceInteraction;

/// One hemisphere-sampled estimate of direct lighting.
pub fn sample_hemisphere(
    scene: &Scene,
    si: &SurfaceInteraction,
    bsdf: &Bsdf,
    cosine: bool,
    sampler: &mut Sampler,
    stats: &mut TraceStats,
) -> Rgb {
    let u_side = sampler.get_1d();
    let u = sampler.get_2d();
    let both_sides = bsdf.flags().contains(BxdfFlags::TRANSMISSION);
    let wo_side = if si.wo.dot(si.ns) >= 0.0 { 1.0 } else { -1.0 };
    let (side, side_prob) = if both_sides {
        (if u_side < 0.5 { wo_side } else { -wo_side }, 0.5)
    } else {
        (wo_side, 1.0)
    };
    let local = if cosine {
        sample_cosine_hemisphere(u)
    } else {
        sample_uniform_hemisphere(u)
    };
    if local.z <= 0.0 {
        return Rgb::BLACK;
    }
    let pdf = side_prob
        * if cosine {
            cosine_hemisphere_pdf(local.z)
        } else {
            uniform_hemisphere_pdf()
        };
    let wi = Frame::from_z(si.ns * side).from_local(local);
    let f = bsdf.f(si.wo, wi);
    if f.is_black() {
        return Rgb::BLACK;
    }
    let le = emitted_toward(scene, si, wi, stats);
    f * le * (local.z / pdf)
}
