//! Unidirectional path tracing (pbrt-v4 `PathIntegrator`): at every vertex, emission seen
//! by the continuation ray (weighted as the direct-lighting strategy requires; from the
//! infinite lights when the ray leaves the scene), a direct lighting estimate, a
//! BSDF-sampled continuation, and Russian roulette. Each block below is one step of the
//! rendering equation `L_o = L_e + integral f L_i cos`.
//!
//! Surfaces without a BSDF (`interface`) are passed through without counting a bounce.
//! For stochastic BSDFs (layered) the sampled pdf is only proportional to the density, so
//! emission found by the continuation is MIS-weighted with `Bsdf::pdf` instead (pbrt-v4's
//! `pdfIsProportional`).

use super::{roulette, DirectEstimator, TraceStats};
use crate::bsdf::BxdfFlags;
use crate::color::Rgb;
use crate::light::Light;
use crate::math::Ray;
use crate::sampling::Sampler;
use crate::scene::{RussianRoulette, Scene};
use crate::shape::{Interaction, SurfaceInteraction};

/// Path tracer settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathIntegrator {
    /// Maximum number of scattering events (0: emission only, 1: direct lighting).
    pub max_depth: u32,
    /// How direct lighting is estimated at each vertex.
    pub direct: DirectEstimator,
    /// When paths end at random.
    pub russian_roulette: RussianRoulette,
}

impl PathIntegrator {
    /// Radiance along `ray`.
    pub fn li(&self, scene: &Scene, mut ray: Ray, sampler: &mut Sampler, stats: &mut TraceStats) -> Rgb {
        let mut l = Rgb::BLACK;
        let mut beta = Rgb::WHITE;
        let mut depth = 0u32;
        // The previous vertex and the BSDF pdf of the direction that left it, for weighting
        // emission the continuation ray finds.
        let mut specular_bounce = true;
        let mut prev: Interaction = Interaction::point(ray.o);
        let mut prev_bsdf_pdf = 0.0f32;
        // Product of eta^2 over the transmissions so far: undoes the 1/eta^2 radiance
        // scaling in beta for Russian roulette, which should not kill paths inside glass.
        let mut eta_scale = 1.0f32;
        // The current vertex, rewritten in place by every hit.
        let mut si = SurfaceInteraction::default();

        loop {
            // Intersect the ray with the scene.
            stats.rays += 1;
            let Some(prim) = scene.intersect_into(&ray, &mut si) else {
                // The ray left the scene: add the infinite lights' emission, in full at the
                // camera and after specular bounces, otherwise as the direct-lighting strategy
                // weights it.
                for &index in &scene.infinite_lights {
                    let light = &scene.lights[index as usize];
                    let le = light.le(ray.d);
                    if le.is_black() {
                        continue;
                    }
                    if depth == 0 || specular_bounce {
                        l += beta * le;
                    } else {
                        let p_light = scene.light_sampler.pmf(index as usize) * light.pdf_li_direction(ray.d);
                        l += beta * le * self.direct.continuation_weight(prev_bsdf_pdf, p_light);
                    }
                }
                break;
            };
            let si = &si;

            // Add emission: in full at the camera and after specular bounces, otherwise as the
            // direct-lighting strategy weights it.
            if let Some(light_index) = prim.light {
                if let Light::DiffuseArea(area) = &scene.lights[light_index as usize] {
                    let le = area.l(si.n(), si.wo);
                    if !le.is_black() {
                        if depth == 0 || specular_bounce {
                            l += beta * le;
                        } else {
                            let p_light = scene.light_sampler.pmf(light_index as usize) * area.pdf_li(&prev, &si.intr);
                            l += beta * le * self.direct.continuation_weight(prev_bsdf_pdf, p_light);
                        }
                    }
                }
            }

            // Get the BSDF; pass through surfaces without one (`interface`) without counting
            // a bounce; stop at the depth limit.
            // (Borrowed where it was made: moving the 152-byte BSDF out of the `Option` was a
            // `memcpy` call at every vertex.)
            let bsdf = scene.bsdf(prim.material, si);
            let Some(bsdf) = bsdf.as_ref() else {
                ray = si.spawn_ray(ray.d);
                continue;
            };
            if depth == self.max_depth {
                break;
            }
            depth += 1;

            // Estimate direct lighting.
            let non_specular = bsdf.flags().is_non_specular();
            if non_specular {
                l += beta * self.direct.estimate(scene, si, bsdf, sampler, stats);
            }
            // A continuation that ends at the depth limit only matters for the emission it
            // may find: none counts after a non-specular event when the direct strategy
            // ignores continuations, so skip it unless the BSDF also has a specular part
            // (a smooth coat over a diffuse base), whose emission always counts.
            if depth == self.max_depth
                && non_specular
                && !bsdf.flags().is_specular()
                && !self.direct.uses_continuation()
            {
                break;
            }

            // Sample the BSDF for the next direction; update the throughput.
            let uc = sampler.get_1d();
            let u = sampler.get_2d();
            let Some(bs) = bsdf.sample_f(si.wo, uc, u) else {
                break;
            };
            beta *= bs.f * (bs.wi.dot(si.ns).abs() / bs.pdf);
            specular_bounce = bs.flags.is_specular();
            if bs.flags.contains(BxdfFlags::TRANSMISSION) {
                eta_scale *= bs.eta * bs.eta;
            }
            // A stochastic BSDF's sampled pdf is only proportional to the true one: MIS needs
            // the (estimated) density itself, as pbrt-v4's `pdfIsProportional`.
            prev_bsdf_pdf = if bs.pdf_is_proportional {
                bsdf.pdf(si.wo, bs.wi)
            } else {
                bs.pdf
            };
            prev = si.intr;
            ray = si.spawn_ray(bs.wi);

            // Russian roulette, on the throughput without the 1/eta^2 radiance scaling of
            // refraction (pbrt-v4's etaScale), so paths inside glass are not cut short.
            let u_rr = sampler.get_1d();
            match roulette(self.russian_roulette, beta * eta_scale, depth, u_rr) {
                Some(b) if !b.is_black() => beta = b / eta_scale,
                _ => break,
            }
        }
        l
    }
}
