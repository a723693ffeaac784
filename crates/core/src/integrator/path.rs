//! Unidirectional path tracing (pbrt-v4 `PathIntegrator`): at every vertex, emission seen
//! by the BSDF-sampled ray (MIS-weighted), next-event estimation, a BSDF-sampled
//! continuation, and Russian roulette. Each block below is one step of the rendering
//! equation `L_o = L_e + integral f L_i cos`.

use super::{sample_direct_light, TraceStats};
use crate::color::Rgb;
use crate::light::Light;
use crate::math::Ray;
use crate::sampling::{power_heuristic, Sampler};
use crate::scene::Scene;
use crate::shape::Interaction;

/// Path tracer settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PathIntegrator {
    /// Maximum number of scattering events (0: emission only, 1: direct lighting).
    pub max_depth: u32,
}

impl PathIntegrator {
    /// Radiance along `ray`.
    pub fn li(&self, scene: &Scene, mut ray: Ray, sampler: &mut Sampler, stats: &mut TraceStats) -> Rgb {
        let mut l = Rgb::BLACK;
        let mut beta = Rgb::WHITE;
        let mut depth = 0u32;
        // The previous vertex and the BSDF pdf of the direction that left it, for MIS.
        let mut specular_bounce = true;
        let mut prev: Interaction = Interaction::point(ray.o);
        let mut prev_bsdf_pdf = 0.0f32;

        loop {
            // Intersect the ray with the scene.
            stats.rays += 1;
            let Some(hit) = scene.intersect(&ray) else {
                break;
            };
            let si = hit.si;
            let prim = &scene.primitives[hit.primitive as usize];

            // Add emission, weighted against the light sampling that could have found it.
            if let Some(light_index) = prim.light {
                if let Light::DiffuseArea(area) = &scene.lights[light_index as usize] {
                    let le = area.l(si.n(), si.wo);
                    if !le.is_black() {
                        if depth == 0 || specular_bounce {
                            l += beta * le;
                        } else {
                            let p_light = scene.light_sampler.pmf(light_index as usize) * area.pdf_li(&prev, &si.intr);
                            l += beta * le * power_heuristic(1.0, prev_bsdf_pdf, 1.0, p_light);
                        }
                    }
                }
            }

            // Get the BSDF; stop at the depth limit.
            let bsdf = scene.materials[prim.material as usize].bsdf(&si);
            if depth == self.max_depth {
                break;
            }
            depth += 1;

            // Sample direct illumination (next-event estimation).
            if bsdf.flags().is_non_specular() {
                l += beta * sample_direct_light(scene, &si, &bsdf, sampler, stats);
            }

            // Sample the BSDF for the next direction; update the throughput.
            let uc = sampler.get_1d();
            let u = sampler.get_2d();
            let Some(bs) = bsdf.sample_f(si.wo, uc, u) else {
                break;
            };
            beta *= bs.f * (bs.wi.dot(si.ns).abs() / bs.pdf);
            specular_bounce = bs.flags.is_specular();
            prev_bsdf_pdf = bs.pdf;
            prev = si.intr;
            ray = si.spawn_ray(bs.wi);

            // Russian roulette: once the throughput is below 1, stop with probability
            // 1 - max(beta) and reweight survivors, which keeps the estimate unbiased.
            let u_rr = sampler.get_1d();
            let max_beta = beta.max_component();
            if max_beta < 1.0 && depth > 1 {
                let q = (1.0 - max_beta).max(0.0);
                if u_rr < q {
                    break;
                }
                beta /= 1.0 - q;
            }
            if beta.is_black() {
                break;
            }
        }
        l
    }
}
