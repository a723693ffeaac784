//! The camera pass of SPPM: one camera path per pixel and iteration, followed through
//! specular bounces, adding emission (seen directly or after specular bounces) and direct
//! lighting (light sampling) to the pixel's sum, and ending at the pixel's visible point.

use super::SppmSettings;
use crate::bsdf::{Bsdf, BxdfFlags};
use crate::color::Rgb;
use crate::integrator::{roulette, DirectEstimator, TraceStats};
use crate::light::Light;
use crate::math::{UVec2, Vec2, Vec3};
use crate::sampling::Sampler;
use crate::scene::{DirectStrategy, RussianRoulette, SamplerDesc, Scene};

/// Where a camera path ended on a diffuse (or glossy) surface.
#[derive(Clone, Copy, Debug)]
pub struct VisiblePoint {
    /// The point.
    pub p: Vec3,
    /// Direction back along the camera path.
    pub wo: Vec3,
    /// The surface's BSDF.
    pub bsdf: Bsdf,
    /// Throughput of the camera path up to the point.
    pub beta: Rgb,
}

/// One pixel's camera path.
#[derive(Clone, Copy, Debug)]
pub struct CameraResult {
    /// Emission and direct lighting found.
    pub ld: Rgb,
    /// Where the path stopped, if on a surface photons can reach.
    pub vp: Option<VisiblePoint>,
}

/// The camera paths of one row of pixels, in pixel order.
pub fn trace_row(scene: &Scene, settings: &SppmSettings, y: u32, iteration: u32) -> Vec<(CameraResult, TraceStats)> {
    let desc = SamplerDesc {
        samples_per_pixel: settings.iterations.max(1),
        seed: settings.seed,
        ..scene.sampler
    };
    let mut sampler = Sampler::new(&desc);
    (0..scene.film.width)
        .map(|x| {
            let mut stats = TraceStats::default();
            sampler.start_pixel_sample(UVec2::new(x, y), iteration);
            let r = trace_pixel(
                scene,
                settings,
                Vec2::new(x as f32 + 0.5, y as f32 + 0.5),
                &mut sampler,
                &mut stats,
            );
            (r, stats)
        })
        .collect()
}

/// Follow one camera path from the pixel whose centre is `centre`.
fn trace_pixel(
    scene: &Scene,
    settings: &SppmSettings,
    centre: Vec2,
    sampler: &mut Sampler,
    stats: &mut TraceStats,
) -> CameraResult {
    let direct = DirectEstimator {
        strategy: DirectStrategy::LightArea,
        samples: 1,
    };
    // A box-filtered film position (SPPM's image is one value per pixel).
    let fs = scene.filter.sample(sampler.get_pixel_2d());
    let mut ray = scene.camera.generate_ray(centre + fs.p, sampler.get_2d());
    let mut beta = Rgb::WHITE * fs.weight;
    let mut ld = Rgb::BLACK;
    let mut depth = 0u32;
    let mut specular_bounce = false;
    loop {
        stats.rays += 1;
        let Some(hit) = scene.intersect(&ray) else {
            // Emission of the infinite lights, in full at the camera and after specular
            // bounces (direct lighting covers the rest).
            if depth == 0 || specular_bounce {
                for &index in &scene.infinite_lights {
                    ld += beta * scene.lights[index as usize].le(ray.d);
                }
            }
            break;
        };
        let si = hit.si;
        if depth == 0 || specular_bounce {
            if let Some(light) = hit.primitive.light {
                if let Light::DiffuseArea(area) = &scene.lights[light as usize] {
                    ld += beta * area.l(si.n(), si.wo);
                }
            }
        }
        let Some(bsdf) = scene.bsdf(hit.primitive.material, &si) else {
            ray = si.spawn_ray(ray.d);
            continue;
        };
        if depth == settings.max_depth {
            break;
        }
        depth += 1;

        // Direct lighting, then possibly the visible point.
        let flags = bsdf.flags();
        if flags.is_non_specular() {
            ld += beta * direct.estimate(scene, &si, &bsdf, sampler, stats);
        }
        let diffuse = flags.contains(BxdfFlags::DIFFUSE);
        let glossy = flags.contains(BxdfFlags::GLOSSY);
        if diffuse || (glossy && depth == settings.max_depth) {
            return CameraResult {
                ld,
                vp: Some(VisiblePoint {
                    p: si.p(),
                    wo: si.wo,
                    bsdf,
                    beta,
                }),
            };
        }
        if depth == settings.max_depth {
            break;
        }

        // Continue through the specular (or glossy) surface.
        let uc = sampler.get_1d();
        let u = sampler.get_2d();
        let Some(bs) = bsdf.sample_f(si.wo, uc, u) else {
            break;
        };
        beta *= bs.f * (bs.wi.dot(si.ns).abs() / bs.pdf);
        specular_bounce = bs.flags.is_specular();
        ray = si.spawn_ray(bs.wi);
        let u_rr = sampler.get_1d();
        match roulette(RussianRoulette::Throughput, beta, depth, u_rr) {
            Some(b) if !b.is_black() => beta = b,
            _ => break,
        }
    }
    CameraResult { ld, vp: None }
}
