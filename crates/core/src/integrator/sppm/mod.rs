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
//! as the radii shrink). The per-pixel statistics carried between iterations are an
//! [`SppmState`]; [`iterate`] advances it by one iteration, so a render can be checkpointed
//! between iterations and continued bit-identically. Deterministic whatever the thread count: camera samples come from
//! (seed, pixel, iteration), photons from (seed, iteration, photon index), and deposits are
//! gathered per chunk of photons and added in chunk order.
//!
//! As in pbrt-v4, visible points see only the non-specular part of a BSDF (a coated
//! surface's coat reflects no photons), and light sampling at a visible point is not
//! combined with BSDF sampling.

mod grid;
mod photons;
mod state;
mod visible;

pub use grid::PointGrid;
pub use state::SppmState;

use std::sync::atomic::{AtomicBool, Ordering};

use rayon::prelude::*;

use super::TraceStats;
use crate::color::Rgb;
use crate::film::Film;
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
    let mut state = SppmState::new(scene.film.width, scene.film.height, settings);
    let mut trace = TraceStats::default();
    while state.iterations_done() < settings.iterations {
        match iterate(scene, settings, &mut state, cancel) {
            Some(t) => trace += t,
            None => break,
        }
        progress(u64::from(state.iterations_done()), u64::from(settings.iterations));
        if let Some(f) = observe.as_mut() {
            if !f(state.iterations_done(), &state.film(settings)) {
                break;
            }
        }
    }
    let done = state.iterations_done();
    SppmOutput {
        film: state.film(settings),
        trace,
        photons: u64::from(done) * settings.photons_per_iteration,
        iterations: done,
    }
}

/// Run the next iteration of `state` (camera pass, grid, photon pass, update) in the
/// current rayon pool and return its ray counts. When `cancel` is set before it completes,
/// returns `None` and leaves `state` as it was, so that a render stopped here and
/// continued later is the same as one never stopped.
pub fn iterate(
    scene: &Scene,
    settings: &SppmSettings,
    state: &mut SppmState,
    cancel: &AtomicBool,
) -> Option<TraceStats> {
    let (w, h) = (scene.film.width, scene.film.height);
    assert_eq!(
        (state.width(), state.height()),
        (w, h),
        "SPPM state for another film size"
    );
    let pixel_count = state.pixels.len();
    let iteration = state.iterations_done;
    let cancelled = || cancel.load(Ordering::Relaxed);
    if cancelled() {
        return None;
    }
    let mut trace = TraceStats::default();
    // Camera pass.
    let camera: Vec<(visible::CameraResult, TraceStats)> = (0..h)
        .into_par_iter()
        .flat_map_iter(|y| visible::trace_row(scene, settings, y, iteration))
        .collect();
    if cancelled() {
        return None;
    }
    let mut points = Vec::with_capacity(pixel_count);
    let mut vps = Vec::with_capacity(pixel_count);
    let mut ld = Vec::with_capacity(pixel_count);
    for (i, (c, t)) in camera.into_iter().enumerate() {
        trace += t;
        if let Some(vp) = c.vp {
            points.push((i as u32, vp.p, state.pixels[i].radius));
        }
        vps.push(c.vp);
        ld.push(c.ld);
    }

    // Grid of the visible points.
    let grid = PointGrid::new(&points);

    // Photon pass, deposits gathered per chunk (chunks after a cancel are skipped).
    let chunks = settings.photons_per_iteration.div_ceil(PHOTON_CHUNK);
    let pixels = &state.pixels;
    let deposits: Vec<(Vec<(u32, Rgb)>, TraceStats)> = (0..chunks)
        .into_par_iter()
        .map(|chunk| {
            if cancelled() {
                return Default::default();
            }
            let start = chunk * PHOTON_CHUNK;
            let end = (start + PHOTON_CHUNK).min(settings.photons_per_iteration);
            let radius = |i: u32| pixels[i as usize].radius;
            photons::trace_chunk(scene, settings, iteration, start..end, &grid, &vps, &radius)
        })
        .collect();
    if cancelled() {
        return None;
    }
    let mut phi = vec![Rgb::BLACK; pixel_count];
    let mut m = vec![0u32; pixel_count];
    for (list, t) in deposits {
        trace += t;
        for (i, f) in list {
            phi[i as usize] += f;
            m[i as usize] += 1;
        }
    }

    // Progressive update (alpha = 2/3; Hachisuka and Jensen 2009, eqs. 6 and 10).
    const ALPHA: f32 = 2.0 / 3.0;
    for (i, s) in state.pixels.iter_mut().enumerate() {
        s.ld += ld[i];
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
    state.iterations_done += 1;
    Some(trace)
}
