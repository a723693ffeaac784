//! Metropolis light transport (pbrt-v4 `MLTIntegrator`): Markov chains in primary sample
//! space (Kelemen et al. 2002, [`crate::sampling::MltSampler`]) over bidirectional paths,
//! one path depth and one connection strategy per state (multiplexed MLT, Hachisuka et al.
//! 2014, [`contribution`]). It does not work per camera sample, so it has its own driver,
//! [`render`], run inside the caller's rayon pool.
//!
//! 1. **Bootstrap**: `bootstrapsamples x (maxdepth + 1)` independent states, state `i`
//!    serving depth `i mod (maxdepth + 1)`. The mean over the bootstrap of the summed
//!    luminances of each depth, `b = sum_i Y(L_i) / bootstrapsamples`, estimates the
//!    integral of the target `Y(L)` over primary sample space and all depths.
//! 2. **Chains**: `chains` chains share `mutationsperpixel x pixels` mutations. Each starts
//!    from a bootstrap state chosen in proportion to its luminance (so the chain starts in
//!    its stationary distribution, up to the bootstrap's finite size), and at every
//!    mutation splats both the current and the proposed path, weighted by the probability of
//!    moving to each (the expected-value splats of Veach 1997, section 11.5), each divided
//!    by its luminance.
//! 3. **Image**: the splat sums times `b / mutationsperpixel`. Splats are added with their
//!    factor `b`, spread over the pixels the scene's filter covers (as every splat is,
//!    [`Splat`]), and the film counts `mutationsperpixel` samples per pixel, so that
//!    [`Film::mean_image`] is that estimate. Camera subpaths start on the film's sample
//!    bounds ([`contribution`]).
//!
//! MLT is unbiased only in expectation over the normalisation `b` (and the chains' start),
//! so its per-pixel noise is not measured (the film holds splats only). Deterministic
//! whatever the thread count: bootstrap state `i` comes from the random stream `(i, seed)`,
//! chain `c`'s decisions from `(c, seed)` hashed, and the splat sums are fixed point, so
//! the order splats land in does not matter.
//!
//! **Work units and checkpoints.** The render is a [`MltState`] advanced by [`bootstrap`]
//! and then by [`advance`] in steps: a step makes up to a few thousand mutations of each of
//! a handful of running chains (a few per thread, started in index order as others
//! finish). Each chain is a consistent state after any whole mutation and its mutations
//! depend on nothing but its own state, so however the work is cut into steps, stopped
//! (cancel is checked between steps and every few hundred mutations of a chain) and
//! continued, every chain makes the same float operations in the same order, and the fixed
//! point splat sums add to the same bits: a render continued from a saved state
//! ([`MltState::to_bytes`]) is bit-identical to one never stopped, on any thread count.
//! The bootstrap is one unit: a render cancelled during it restarts it.

mod chain;
pub mod contribution;
pub mod state;

use std::sync::atomic::{AtomicBool, Ordering};

use rayon::prelude::*;

use chain::{bootstrap_sampler, choose_start, Chain};
use contribution::{contribution, Buffers, Raster};
pub use state::MltState;
use state::{chain_mutations, total_mutations, ChainSlot};

use super::bdpt::vertex::Context;
use super::BdptIntegrator;
use super::TraceStats;
use crate::film::{Film, Splat};
use crate::scene::{BdptDesc, Scene};

/// MLT settings (pbrt-v4's parameters).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MltSettings {
    /// Maximum number of scattering events of a path (`maxdepth`).
    pub max_depth: u32,
    /// Bootstrap samples per depth (`bootstrapsamples`).
    pub bootstrap_samples: u32,
    /// Markov chains (`chains`).
    pub chains: u32,
    /// Mutations per pixel, over all chains (`mutationsperpixel`).
    pub mutations_per_pixel: u32,
    /// Probability of a large step (`largestepprobability`).
    pub large_step_probability: f32,
    /// Standard deviation of a small step (`sigma`).
    pub sigma: f32,
    /// Roughen near-specular surfaces after a non-specular bounce (`regularize`).
    pub regularize: bool,
    /// Seed of every random stream (the sampler's seed).
    pub seed: u64,
}

impl MltSettings {
    /// The scene's settings.
    #[must_use]
    pub fn from_scene(scene: &Scene) -> Self {
        let m = &scene.integrator.mlt;
        Self {
            max_depth: scene.integrator.max_depth,
            bootstrap_samples: m.bootstrap_samples.max(1),
            chains: m.chains.max(1),
            mutations_per_pixel: m.mutations_per_pixel.max(1),
            large_step_probability: m.large_step_probability,
            sigma: m.sigma,
            regularize: m.regularize,
            seed: scene.sampler.seed,
        }
    }
}

/// A finished MLT render.
#[derive(Clone, Debug)]
pub struct MltOutput {
    /// Splats only, `mutations_per_pixel` samples per pixel (no per-pixel variance).
    pub film: Film,
    /// Rays traced (bootstrap and chains).
    pub trace: TraceStats,
    /// The normalisation `b`: the estimated integral of the luminance over all paths.
    pub b: f64,
    /// Mutations made (fewer than asked when cancelled).
    pub mutations: u64,
    /// Proposals accepted.
    pub accepted: u64,
    /// Whether the render was cancelled (the film then holds the mutations made, with its
    /// sample count scaled down to match, to within rounding).
    pub cancelled: bool,
}

/// Render with MLT on a pool of `threads` threads (`None`: all cores); see [`render`].
///
/// # Errors
/// When the thread pool cannot be created.
pub fn render_with_threads(
    scene: &Scene,
    settings: &MltSettings,
    threads: Option<usize>,
    progress: &(dyn Fn(u64, u64) + Sync),
    cancel: &AtomicBool,
) -> Result<(MltOutput, usize), rayon::ThreadPoolBuildError> {
    let threads = threads.unwrap_or_else(rayon::current_num_threads).max(1);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build()?;
    Ok((pool.install(|| render(scene, settings, progress, cancel)), threads))
}

/// Bootstrap states per work unit.
const BOOTSTRAP_CHUNK: u64 = 1024;
/// Most mutations of one chain in one step (bounds the splats a step holds).
const MAX_STEP: u64 = 4096;
/// Running chains per thread.
const CHAINS_PER_THREAD: usize = 4;

/// Render with MLT in the current rayon pool: [`bootstrap`], then [`advance`] to the end.
/// `progress(done, total)` counts mutations (the bootstrap counts as done at zero); `cancel`
/// is checked between bootstrap chunks and every few hundred mutations of a chain.
pub fn render(
    scene: &Scene,
    settings: &MltSettings,
    progress: &(dyn Fn(u64, u64) + Sync),
    cancel: &AtomicBool,
) -> MltOutput {
    let mut state = MltState::new(scene.film.width, scene.film.height);
    let mut trace = bootstrap(scene, settings, &mut state, cancel);
    if state.is_bootstrapped() {
        trace += advance(scene, settings, &mut state, u64::MAX, progress, cancel);
    }
    MltOutput {
        film: state.film(settings),
        trace,
        b: state.b(),
        mutations: state.mutations(),
        accepted: state.accepted(),
        cancelled: !state.is_finished(),
    }
}

/// The BDPT connection code's settings and scene data for MLT.
fn context<'a>(scene: &'a Scene, settings: &MltSettings) -> Context<'a> {
    let bdpt = BdptIntegrator::new(
        scene,
        &BdptDesc {
            regularize: settings.regularize,
            ..BdptDesc::default()
        },
        settings.max_depth,
    );
    Context {
        scene,
        scene_radius: bdpt.scene_radius,
        regularize: settings.regularize,
    }
}

/// Where the camera subpaths of `state`'s film start (its camera's sample bounds).
fn raster(ctx: &Context<'_>, state: &MltState) -> Raster {
    Raster::new(ctx, state.film.width(), state.film.height())
}

/// The bootstrap of a state not yet bootstrapped: the luminance of `bootstrapsamples x
/// (maxdepth + 1)` independent states, the normalisation `b`, and each chain's start drawn
/// in proportion to the luminances. When `cancel` is set before it ends, the state is left
/// as it was. A bootstrap that finds no light finishes the render (black).
pub fn bootstrap(scene: &Scene, settings: &MltSettings, state: &mut MltState, cancel: &AtomicBool) -> TraceStats {
    let mut trace = TraceStats::default();
    if state.bootstrapped {
        return trace;
    }
    let ctx = context(scene, settings);
    let raster = raster(&ctx, state);
    let depths = u64::from(settings.max_depth) + 1;
    let n_bootstrap = u64::from(settings.bootstrap_samples) * depths;
    let chunks: Vec<(Vec<f32>, TraceStats)> = (0..n_bootstrap.div_ceil(BOOTSTRAP_CHUNK))
        .into_par_iter()
        .map(|chunk| {
            let mut stats = TraceStats::default();
            let mut buffers = Buffers::default();
            if cancel.load(Ordering::Relaxed) {
                return (Vec::new(), stats);
            }
            let start = chunk * BOOTSTRAP_CHUNK;
            let end = (start + BOOTSTRAP_CHUNK).min(n_bootstrap);
            let weights = (start..end)
                .map(|i| {
                    let mut sampler = bootstrap_sampler(i, settings);
                    let depth = (i % depths) as usize;
                    let p = contribution(&ctx, &mut sampler, depth, &raster, &mut buffers, &mut stats);
                    p.l.luminance().max(0.0)
                })
                .collect();
            (weights, stats)
        })
        .collect();
    for (_, stats) in &chunks {
        trace += *stats;
    }
    if cancel.load(Ordering::Relaxed) {
        return trace;
    }
    // The running sums of the luminances, in index order.
    let mut cdf = Vec::with_capacity(n_bootstrap as usize);
    let mut sum = 0.0f64;
    for (weights, _) in chunks {
        for wgt in weights {
            sum += f64::from(wgt);
            cdf.push(sum);
        }
    }
    state.b = sum / f64::from(settings.bootstrap_samples);
    state.chains = (0..u64::from(settings.chains))
        .map(|c| {
            if sum == 0.0 {
                // No path carries light: the image is black.
                ChainSlot::Done
            } else {
                ChainSlot::Pending(choose_start(c, &cdf, settings))
            }
        })
        .collect();
    state.bootstrapped = true;
    trace
}

/// Continue the chains of a bootstrapped `state` by about `budget` mutations (rounded up to
/// whole steps; all that are left when fewer are), each chain's splats added to the state's
/// film scaled by `b`. Stops early, with a consistent state, when `cancel` is set.
/// `progress(done, total)` counts mutations after each step.
pub fn advance(
    scene: &Scene,
    settings: &MltSettings,
    state: &mut MltState,
    budget: u64,
    progress: &(dyn Fn(u64, u64) + Sync),
    cancel: &AtomicBool,
) -> TraceStats {
    let mut trace = TraceStats::default();
    let ctx = context(scene, settings);
    let raster = raster(&ctx, state);
    let (width, height) = (state.film.width(), state.film.height());
    let total = total_mutations(settings, width, height);
    let chains = state.chains.len() as u64;
    let b = state.b as f32;
    let live = rayon::current_num_threads().max(1) * CHAINS_PER_THREAD;
    let mut used = 0u64;
    progress(state.mutations, total);
    while used < budget && !state.is_finished() && !cancel.load(Ordering::Relaxed) {
        // Start chains in index order until `live` of them run.
        let mut running = state
            .chains
            .iter()
            .filter(|c| matches!(c, ChainSlot::Running(_)))
            .count();
        let mut buffers = Buffers::default();
        for (c, slot) in state.chains.iter_mut().enumerate() {
            if running >= live {
                break;
            }
            if let ChainSlot::Pending(start) = *slot {
                let chain = Chain::begin(&ctx, c as u64, start, settings, &raster, &mut buffers, &mut trace);
                *slot = ChainSlot::Running(Box::new(chain));
                running += 1;
            }
        }
        // One step: up to `k` mutations of every running chain, in parallel.
        let k = (budget - used).div_ceil(running.max(1) as u64).clamp(1, MAX_STEP);
        let mut work: Vec<(u64, &mut Chain)> = state
            .chains
            .iter_mut()
            .enumerate()
            .filter_map(|(c, slot)| match slot {
                ChainSlot::Running(chain) => Some((c as u64, &mut **chain)),
                _ => None,
            })
            .collect();
        let steps: Vec<(Vec<Splat>, TraceStats, u64, u64)> = work
            .par_iter_mut()
            .map(|(c, chain)| {
                let (done, accepted) = (chain.done, chain.accepted);
                let n = k.min(chain_mutations(*c, chains, total) - done);
                let mut splats = Vec::with_capacity(2 * n as usize);
                let mut stats = TraceStats::default();
                chain.run(
                    &ctx,
                    n,
                    &raster,
                    &mut Buffers::default(),
                    &mut splats,
                    &mut stats,
                    cancel,
                );
                (splats, stats, chain.done - done, chain.accepted - accepted)
            })
            .collect();
        drop(work);
        for (splats, stats, mutations, accepted) in steps {
            let scaled: Vec<Splat> = splats
                .iter()
                .map(|s| Splat {
                    p_film: s.p_film,
                    l: s.l * b,
                })
                .collect();
            state.film.add_splats(&scaled, &scene.filter);
            trace += stats;
            state.mutations += mutations;
            state.accepted += accepted;
            used += mutations;
        }
        for (c, slot) in state.chains.iter_mut().enumerate() {
            if let ChainSlot::Running(chain) = slot {
                if chain.done == chain_mutations(c as u64, chains, total) {
                    *slot = ChainSlot::Done;
                }
            }
        }
        progress(state.mutations, total);
    }
    trace
}
