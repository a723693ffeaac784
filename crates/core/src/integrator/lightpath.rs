//! Light tracing (pbrt-v4 `LightPathIntegrator`; bidirectional path tracing's `t = 1`
//! strategy): each camera sample traces one path from a light instead of from the camera,
//! and at every vertex connects to the camera, adding the contribution as a splat at the
//! film point the connection lands on (spread by the film over the pixels the filter
//! covers, [`crate::film::Splat`]). The camera sample's own value is zero.
//!
//! A path starts with a light chosen by power (`pmf`) and a ray from
//! [`crate::light::Light::sample_le`], carrying `beta = Le |cos| / (pmf pdf_pos pdf_dir)`.
//! A connection from vertex `x` to a lens point found by [`crate::camera::Camera::sample_wi`]
//! adds `beta f(x; wi_cam <- wo) |cos| We / pdf_cam` when unoccluded: the film's
//! measurement estimated by one light path, so a pixel's splats, divided by the samples
//! per pixel, estimate its value (see [`crate::camera`]'s importance normalisation).
//!
//! Paths carry importance, not radiance: the BSDF is evaluated as its adjoint
//! `f*(wo, wi) = f(wi, wo)` (which for refraction means without the radiance's `1/eta^2`,
//! so sampled transmissions are multiplied back by `eta^2`), and shading normals get
//! Veach's adjoint correction `|wo.ns| |wi.ng| / (|wo.ng| |wi.ns|)` (Veach 1997, eq. 5.17),
//! so the estimate matches the path tracer's with interpolated normals too.
//!
//! What light tracing cannot see: a vertex whose BSDF is purely specular has no camera
//! connection (its `f` is a delta), so a mirror or glass seen directly by the camera
//! renders black, and so does an infinite light seen directly (its rays never reach the
//! lens); the same holds in pbrt-v4. Point and spot lights are themselves invisible, as in
//! every renderer.

use super::{roulette, TraceStats};
use crate::bsdf::BxdfFlags;
use crate::color::Rgb;
use crate::light::Light;
use crate::math::{Vec2, Vec3};
use crate::sampling::Sampler;
use crate::scene::{RussianRoulette, Scene};
use crate::shape::{Interaction, SurfaceInteraction};

/// Light tracer settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightPathIntegrator {
    /// Maximum number of scattering events (0: lights seen directly, 1: direct lighting).
    pub max_depth: u32,
    /// When paths end at random.
    pub russian_roulette: RussianRoulette,
}

/// Veach's correction for shading normals in adjoint transport (eq. 5.17):
/// `|wo.ns| |wi.ng| / (|wo.ng| |wi.ns|)`, with `wo` towards the light side of the path and
/// `wi` the direction importance continues in. Zero when `wo` grazes the true surface.
fn shading_normal_correction(si: &SurfaceInteraction, wo: Vec3, wi: Vec3) -> f32 {
    let den = wo.dot(si.n()).abs() * wi.dot(si.ns).abs();
    if den == 0.0 {
        return 0.0;
    }
    wo.dot(si.ns).abs() * wi.dot(si.n()).abs() / den
}

impl LightPathIntegrator {
    /// Trace one light path with the sampler's next dimensions and report each camera
    /// connection to `splat(p_raster, value)`; the value is what the connection adds to
    /// the film (which weights it by the pixel filter and divides splat sums by the samples
    /// per pixel).
    pub fn trace(
        &self,
        scene: &Scene,
        sampler: &mut Sampler,
        stats: &mut TraceStats,
        splat: &mut impl FnMut(Vec2, Rgb),
    ) {
        // Choose a light and a ray leaving it.
        let u_light = sampler.get_1d();
        let u_pos = sampler.get_2d();
        let u_dir = sampler.get_2d();
        let Some((light_index, pmf)) = scene.light_sampler.sample(u_light) else {
            return;
        };
        let light = &scene.lights[light_index];
        let Some(les) = light.sample_le(u_pos, u_dir) else {
            return;
        };

        // Connect the light's own point to the camera (area lights: the only lights a lens
        // can see).
        let u_cam = sampler.get_2d();
        if let Light::DiffuseArea(area) = light {
            if let Some(cs) = scene.camera.sample_wi(les.intr.p, u_cam) {
                let le = area.l(les.intr.n, cs.wi);
                if !le.is_black() {
                    stats.shadow_rays += 1;
                    if scene.unoccluded(&les.intr, &Interaction::point(cs.p_lens)) {
                        let w = cs.wi.dot(les.intr.n).abs() * cs.we / (pmf * les.pdf_pos * cs.pdf);
                        splat(cs.p_raster, le * w);
                    }
                }
            }
        }

        let mut beta = les.initial_throughput(pmf);
        let mut ray = les.ray;
        let mut depth = 0u32;
        loop {
            // Intersect; light paths that leave the scene carry nothing to the camera.
            stats.rays += 1;
            let Some(hit) = scene.intersect(&ray) else {
                break;
            };
            let si = hit.si;

            // Get the BSDF; pass through surfaces without one; stop at the depth limit.
            // Borrowed where it was made (moving the BSDF out of the `Option` copies it).
            let bsdf = scene.bsdf(hit.primitive.material, &si);
            let Some(bsdf) = bsdf.as_ref() else {
                ray = si.spawn_ray(ray.d);
                continue;
            };
            if depth == self.max_depth {
                break;
            }
            depth += 1;

            // Connect the vertex to the camera (not through a delta BSDF).
            let u_cam = sampler.get_2d();
            if bsdf.flags().is_non_specular() {
                if let Some(cs) = scene.camera.sample_wi(si.p(), u_cam) {
                    // The adjoint BSDF: f*(wo, wi) = f(wi, wo).
                    let f =
                        bsdf.f(cs.wi, si.wo) * (cs.wi.dot(si.ns).abs() * shading_normal_correction(&si, si.wo, cs.wi));
                    if !f.is_black() {
                        stats.shadow_rays += 1;
                        if scene.unoccluded(&si.intr, &Interaction::point(cs.p_lens)) {
                            splat(cs.p_raster, beta * f * (cs.we / cs.pdf));
                        }
                    }
                }
            }

            // Sample the BSDF for the direction importance continues in; update beta.
            let uc = sampler.get_1d();
            let u = sampler.get_2d();
            let Some(bs) = bsdf.sample_f(si.wo, uc, u) else {
                break;
            };
            // Undo the radiance's 1/eta^2 on refraction: importance is not scaled.
            let eta2 = if bs.flags.contains(BxdfFlags::TRANSMISSION) {
                bs.eta * bs.eta
            } else {
                1.0
            };
            beta *= bs.f * (eta2 * bs.wi.dot(si.ns).abs() * shading_normal_correction(&si, si.wo, bs.wi) / bs.pdf);
            ray = si.spawn_ray(bs.wi);

            // Russian roulette.
            let u_rr = sampler.get_1d();
            match roulette(self.russian_roulette, beta, depth, u_rr) {
                Some(b) if !b.is_black() => beta = b,
                _ => break,
            }
        }
    }
}
