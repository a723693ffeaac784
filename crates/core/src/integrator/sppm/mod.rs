//! Stochastic progressive photon mapping (Hachisuka and Jensen 2009; pbrt-v4
//! `SPPMIntegrator`). It does not fit "radiance per camera sample", so it has its own
//! driver, [`render`], run inside the caller's rayon pool.
//!
//! Each iteration:
//! 1. **Camera pass** ([`visible`]): one camera path per pixel, followed through specular
//!    bounces, adds emission and direct lighting (light sampling) to the pixel's `Ld`, and
//!    stops at the first diffuse (or, at the last bounce, glossy) vertex: the pixel's
//!    *visible point* (position, `wo`, BSDF, throughput).
//! 2. **Grid** ([`grid`]): the visible points bucketed by the cells their search spheres
//!    overlap.
//! 3. **Photon pass** ([`photons`]): `photonsperiteration` photons from the lights
//!    ([`crate::light::Light::sample_le`]); from the second hit on (the first is direct
//!    lighting, already in `Ld`), each deposits `Phi += beta f(wo_vp, wi)` at every visible
//!    point within its radius.
//! 4. **Update** (the progressive radius reduction, alpha = 2/3): with `M` photons found,
//!    `N' = N + alpha M`, `r' = r sqrt(N' / (N + M))`, `tau' = (tau + beta_vp Phi) r'^2 / r^2`.
//!
//! The image is `Ld / iterations + tau / (N_photons pi r^2)`, consistent (the bias vanishes
//! as the radii shrink). Deterministic whatever the thread count: camera samples come from
//! (seed, pixel, iteration), photons from (seed, iteration, photon index), and deposits are
//! gathered per chunk of photons and added in chunk order.
//!
//! As in pbrt-v4, visible points see only the non-specular part of a BSDF (a coated
//! surface's coat reflects no photons), and light sampling at a visible point is not
//! combined with BSDF sampling.

mod grid;
mod photons;
mod visible;

pub use grid::PointGrid;

use std::sync::atomic::{AtomicBool, Ordering};

use rayon::prelude::*;

use super::TraceStats;
use crate::color::Rgb;
use crate::film::Film;
use crate::math::PI;
use crate::scene::Scene;

/// SPPM settings (pbrt-v4's parameters).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SppmSettings {
    /// Camera and photon passes (`numiterations`).
    pub iterations: u32,
    /// Photons per iteration (`photonsperiteration`; pbrt's default is the pixel count).
    pub photons_per_iteration: u64,
    /// Initial search radius (`radius`).
    pub initial_radius: f32,
    /// Seed of the photons and camera samples (`seed`).
    pub seed: u64,
    /// Maximum path depth (`maxdepth`) of camera and photon paths.
    pub max_depth: u32,
}

impl SppmSettings {
    /// The scene's settings with pbrt-v4's defaults resolved: photons per iteration = the
    /// pixel count, seed = the sampler's.
    #[must_use]
    pub fn from_scene(scene: &Scene) -> Self {
        let s = &scene.integrator.sppm;
        Self {
            iterations: s.iterations.max(1),
            photons_per_iteration: s
                .photons_per_iteration
                .unwrap_or(u64::from(scene.film.width) * u64::from(scene.film.height))
                .max(1),
            initial_radius: s.radius,
            seed: s.seed.unwrap_or(scene.sampler.seed),
            max_depth: scene.integrator.max_depth,
        }
    }
}

/// Render with SPPM on a pool of `threads` threads (`None`: all cores); see [`render`].
///
/// # Errors
/// When the thread pool cannot be created.
pub fn render_with_threads(
    scene: &Scene,
    settings: &SppmSettings,
    threads: Option<usize>,
    progress: &(dyn Fn(u64, u64) + Sync),
    cancel: &AtomicBool,
) -> Result<(SppmOutput, usize), rayon::ThreadPoolBuildError> {
    let threads = threads.unwrap_or_else(rayon::current_num_threads).max(1);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build()?;
    Ok((pool.install(|| render(scene, settings, progress, cancel)), threads))
}

/// A finished SPPM render.
#[derive(Clone, Debug)]
pub struct SppmOutput {
    /// One sample per pixel: the SPPM estimate (no per-pixel variance).
    pub film: Film,
    /// Rays traced.
    pub trace: TraceStats,
    /// Photons traced.
    pub photons: u64,
    /// Iterations completed (fewer than asked when cancelled).
    pub iterations: u32,
}

/// What SPPM keeps per pixel across iterations.
#[derive(Clone, Copy, Debug)]
struct PixelState {
    /// Sum over iterations of emission and direct lighting.
    ld: Rgb,
    /// Accumulated flux, scaled as the radius shrinks.
    tau: Rgb,
    /// Search radius.
    radius: f32,
    /// Accumulated photon count.
    n: f32,
}

/// Photons traced per work unit: deposits are gathered per chunk and added in chunk order.
const PHOTON_CHUNK: u64 = 4096;

/// Render with SPPM in the current rayon pool; `progress(done, total)` counts iterations;
/// `cancel` is checked between passes (the image of the iterations done is returned).
pub fn render(
    scene: &Scene,
    settings: &SppmSettings,
    progress: &(dyn Fn(u64, u64) + Sync),
    cancel: &AtomicBool,
) -> SppmOutput {
    render_observed(scene, settings, progress, cancel, None)
}

/// What [`render_observed`] calls after each iteration with the iterations done and the
/// image so far; returning `false` stops the render there (a time budget, say).
pub type IterationObserver<'a> = &'a mut (dyn FnMut(u32, &Film) -> bool + Send);

/// [`render`], with `observe` (when given) shown the image after every iteration
/// (convergence studies); the final image is the same bytes as without it.
pub fn render_observed(
    scene: &Scene,
    settings: &SppmSettings,
    progress: &(dyn Fn(u64, u64) + Sync),
    cancel: &AtomicBool,
    mut observe: Option<IterationObserver<'_>>,
) -> SppmOutput {
    let (w, h) = (scene.film.width, scene.film.height);
    let pixel_count = (w * h) as usize;
    let mut state = vec![
        PixelState {
            ld: Rgb::BLACK,
            tau: Rgb::BLACK,
            radius: settings.initial_radius,
            n: 0.0,
        };
        pixel_count
    ];
    let mut trace = TraceStats::default();
    let mut done = 0u32;
    let chunks = settings.photons_per_iteration.div_ceil(PHOTON_CHUNK);
    for iteration in 0..settings.iterations {
        if cancel.load(Ordering::Relaxed) {
            break;
        }
        // Camera pass.
        let camera: Vec<(visible::CameraResult, TraceStats)> = (0..h)
            .into_par_iter()
            .flat_map_iter(|y| visible::trace_row(scene, settings, y, iteration))
            .collect();
        let mut points = Vec::with_capacity(pixel_count);
        let mut vps = Vec::with_capacity(pixel_count);
        for (i, (c, t)) in camera.into_iter().enumerate() {
            state[i].ld += c.ld;
            trace += t;
            if let Some(vp) = c.vp {
                points.push((i as u32, vp.p, state[i].radius));
            }
            vps.push(c.vp);
        }

        // Grid of the visible points.
        let grid = PointGrid::new(&points);

        // Photon pass, deposits gathered per chunk.
        let deposits: Vec<(Vec<(u32, Rgb)>, TraceStats)> = (0..chunks)
            .into_par_iter()
            .map(|chunk| {
                let start = chunk * PHOTON_CHUNK;
                let end = (start + PHOTON_CHUNK).min(settings.photons_per_iteration);
                let radius = |i: u32| state[i as usize].radius;
                photons::trace_chunk(scene, settings, iteration, start..end, &grid, &vps, &radius)
            })
            .collect();
        let mut phi = vec![Rgb::BLACK; pixel_count];
        let mut m = vec![0u32; pixel_count];
        for (list, t) in deposits {
            trace += t;
            for (i, f) in list {
                phi[i as usize] += f;
                m[i as usize] += 1;
            }
        }

        // Progressive update (alpha = 2/3).
        const ALPHA: f32 = 2.0 / 3.0;
        for (i, s) in state.iter_mut().enumerate() {
            let (Some(vp), mi) = (vps[i], m[i]) else { continue };
            if mi == 0 {
                continue;
            }
            let mf = mi as f32;
            let n_new = s.n + ALPHA * mf;
            let r_new = s.radius * (n_new / (s.n + mf)).sqrt();
            s.tau = (s.tau + vp.beta * phi[i]) * (r_new * r_new / (s.radius * s.radius));
            s.n = n_new;
            s.radius = r_new;
        }
        done += 1;
        progress(u64::from(done), u64::from(settings.iterations));
        if let Some(f) = observe.as_mut() {
            if !f(done, &estimate(&state, done, settings, w, h)) {
                break;
            }
        }
    }

    let n_photons = f64::from(done) * settings.photons_per_iteration as f64;
    SppmOutput {
        film: estimate(&state, done, settings, w, h),
        trace,
        photons: n_photons as u64,
        iterations: done,
    }
}

/// The image after `done` iterations: `Ld / done + tau / (N_photons pi r^2)` per pixel.
fn estimate(state: &[PixelState], done: u32, settings: &SppmSettings, w: u32, h: u32) -> Film {
    let mut film = Film::new(w, h);
    let n_photons = f64::from(done) * settings.photons_per_iteration as f64;
    for (i, s) in state.iter().enumerate() {
        let mut l = s.ld / done.max(1) as f32;
        if n_photons > 0.0 {
            let area = f64::from(PI) * f64::from(s.radius) * f64::from(s.radius);
            l += s.tau * (1.0 / (n_photons * area)) as f32;
        }
        let (x, y) = (i as u32 % w, i as u32 / w);
        film.pixel_mut(x, y)
            .add(if l.is_finite() { l } else { Rgb::BLACK }, 1.0);
    }
    film
}
