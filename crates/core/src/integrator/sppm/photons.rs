//! The photon pass of SPPM: photons from the lights, each depositing its flux at the
//! visible points within their radii from its second hit on.

use std::ops::Range;

use super::visible::VisiblePoint;
use super::{PointGrid, SppmSettings};
use crate::bsdf::BxdfFlags;
use crate::color::Rgb;
use crate::integrator::TraceStats;
use crate::math::{Vec2, Vec3};
use crate::sampling::{hash_u64s, mix_bits, Pcg32};
use crate::scene::Scene;

/// Trace photons `range` of `iteration`; returns the deposits `(pixel, beta f)` in the
/// order made.
pub fn trace_chunk(
    scene: &Scene,
    settings: &SppmSettings,
    iteration: u32,
    range: Range<u64>,
    grid: &PointGrid,
    vps: &[Option<VisiblePoint>],
    radius: &(dyn Fn(u32) -> f32 + Sync),
) -> (Vec<(u32, Rgb)>, TraceStats) {
    let mut deposits = Vec::new();
    let mut stats = TraceStats::default();
    for photon in range {
        // Stream and state both from the hash: PCG streams sharing a state are correlated.
        let stream = hash_u64s(&[settings.seed, u64::from(iteration), photon]);
        let mut rng = Pcg32::new(stream, mix_bits(stream));
        trace_photon(scene, settings, &mut rng, grid, vps, radius, &mut deposits, &mut stats);
    }
    (deposits, stats)
}

fn next_2d(rng: &mut Pcg32) -> Vec2 {
    Vec2::new(rng.next_f32(), rng.next_f32())
}

/// Veach's adjoint shading-normal correction `|wo.ns| |wi.ng| / (|wo.ng| |wi.ns|)`.
fn shading_correction(ns: Vec3, ng: Vec3, wo: Vec3, wi: Vec3) -> f32 {
    let den = wo.dot(ng).abs() * wi.dot(ns).abs();
    if den == 0.0 {
        0.0
    } else {
        wo.dot(ns).abs() * wi.dot(ng).abs() / den
    }
}

#[allow(clippy::too_many_arguments)]
fn trace_photon(
    scene: &Scene,
    settings: &SppmSettings,
    rng: &mut Pcg32,
    grid: &PointGrid,
    vps: &[Option<VisiblePoint>],
    radius: &(dyn Fn(u32) -> f32 + Sync),
    deposits: &mut Vec<(u32, Rgb)>,
    stats: &mut TraceStats,
) {
    let u_light = rng.next_f32();
    let (u_pos, u_dir) = (next_2d(rng), next_2d(rng));
    let Some((index, pmf)) = scene.light_sampler.sample(u_light) else {
        return;
    };
    let Some(les) = scene.lights[index].sample_le(u_pos, u_dir) else {
        return;
    };
    let mut beta = les.initial_throughput(pmf);
    let mut ray = les.ray;
    let mut depth = 0u32;
    while depth < settings.max_depth {
        stats.rays += 1;
        let Some(hit) = scene.intersect(&ray) else {
            break;
        };
        let si = hit.si;
        // Borrowed where it was made (moving the BSDF out of the `Option` copies it).
        let bsdf = scene.bsdf(hit.primitive.material, &si);
        let Some(bsdf) = bsdf.as_ref() else {
            ray = si.spawn_ray(ray.d);
            continue;
        };
        // Deposit at the visible points in range (not at the first hit: direct lighting
        // is in the camera pass).
        if depth > 0 {
            let p = si.p();
            for &i in grid.candidates(p) {
                let Some(vp) = &vps[i as usize] else { continue };
                let r = radius(i);
                if (vp.p - p).length_squared() <= r * r {
                    let f = vp.bsdf.f(vp.wo, si.wo);
                    if !f.is_black() {
                        deposits.push((i, beta * f));
                    }
                }
            }
        }
        depth += 1;

        // Sample the BSDF (adjoint: no 1/eta^2 on refraction) and play Russian roulette
        // on the change of throughput (pbrt-v4).
        let uc = rng.next_f32();
        let u = next_2d(rng);
        let Some(bs) = bsdf.sample_f(si.wo, uc, u) else {
            break;
        };
        let eta2 = if bs.flags.contains(BxdfFlags::TRANSMISSION) {
            bs.eta * bs.eta
        } else {
            1.0
        };
        let scale = eta2 * bs.wi.dot(si.ns).abs() * shading_correction(si.ns, si.n(), si.wo, bs.wi) / bs.pdf;
        let beta_new = beta * bs.f * scale;
        let q = (1.0 - beta_new.max_component() / beta.max_component()).max(0.0);
        if rng.next_f32() < q {
            break;
        }
        beta = beta_new / (1.0 - q);
        if beta.is_black() || !beta.is_finite() {
            break;
        }
        ray = si.spawn_ray(bs.wi);
    }
}
