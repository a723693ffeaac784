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
//! chain `c`'s decisions from `(c, seed)` hashed, and the chains' splats are added in chain
//! order.

pub mod contribution;

use std::sync::atomic::{AtomicBool, Ordering};

use rayon::prelude::*;

use contribution::{contribution, Buffers, Raster, STREAM_COUNT};

use super::bdpt::vertex::Context;
use super::BdptIntegrator;
use super::TraceStats;
use crate::film::{Film, Splat};
use crate::sampling::{hash_u64s, MltSampler, Pcg32};
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
    /// Whether the render was cancelled (the film then holds the finished chains only,
    /// with its sample count scaled down to match, to within rounding).
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
/// Mutations between two looks at the cancel flag inside a chain.
const CANCEL_CHECK: u64 = 4096;

/// Render with MLT in the current rayon pool. `progress(done, total)` counts mutations
/// (the bootstrap counts as done at zero); `cancel` is checked between bootstrap chunks and
/// every few thousand mutations of a chain.
pub fn render(
    scene: &Scene,
    settings: &MltSettings,
    progress: &(dyn Fn(u64, u64) + Sync),
    cancel: &AtomicBool,
) -> MltOutput {
    let (w, h) = (scene.film.width, scene.film.height);
    let bdpt = BdptIntegrator::new(
        scene,
        &BdptDesc {
            regularize: settings.regularize,
            ..BdptDesc::default()
        },
        settings.max_depth,
    );
    let ctx = Context {
        scene,
        scene_radius: bdpt.scene_radius,
        regularize: settings.regularize,
    };
    let raster = Raster::new(&ctx, w, h);
    let depths = u64::from(settings.max_depth) + 1;
    let mpp = settings.mutations_per_pixel;
    let total = u64::from(mpp) * u64::from(w) * u64::from(h);
    let new_sampler = |index: u64| {
        MltSampler::new(
            index,
            settings.seed,
            settings.sigma,
            settings.large_step_probability,
            STREAM_COUNT,
        )
    };
    let mut out = MltOutput {
        film: Film::new(w, h),
        trace: TraceStats::default(),
        b: 0.0,
        mutations: 0,
        accepted: 0,
        cancelled: false,
    };

    // Bootstrap: the luminance of every state, in index order.
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
                    let mut sampler = new_sampler(i);
                    let depth = (i % depths) as usize;
                    let p = contribution(&ctx, &mut sampler, depth, &raster, &mut buffers, &mut stats);
                    p.l.luminance().max(0.0)
                })
                .collect();
            (weights, stats)
        })
        .collect();
    if cancel.load(Ordering::Relaxed) {
        out.cancelled = true;
        return out;
    }
    let mut cdf = Vec::with_capacity(n_bootstrap as usize);
    let mut sum = 0.0f64;
    for (weights, stats) in chunks {
        out.trace += stats;
        for wgt in weights {
            sum += f64::from(wgt);
            cdf.push(sum);
        }
    }
    out.b = sum / f64::from(settings.bootstrap_samples);
    if sum == 0.0 {
        // No path carries light: the image is black.
        out.film.add_samples_per_pixel(u64::from(mpp));
        return out;
    }
    progress(0, total);

    // Chains, a batch at a time (bounded memory), splats added in chain order.
    let chains = u64::from(settings.chains);
    let batch = (rayon::current_num_threads() as u64 * 4).max(1);
    let b = out.b as f32;
    let mut done = 0u64;
    for first in (0..chains).step_by(batch as usize) {
        if cancel.load(Ordering::Relaxed) {
            break;
        }
        let results: Vec<ChainResult> = (first..(first + batch).min(chains))
            .into_par_iter()
            .map(|c| {
                let mutations = (c + 1) * total / chains - c * total / chains;
                run_chain(&ctx, c, mutations, &cdf, &raster, settings, cancel, &new_sampler)
            })
            .collect();
        if results.iter().any(|r| r.cancelled) {
            break;
        }
        let splats: Vec<Splat> = results
            .iter()
            .flat_map(|r| &r.splats)
            .map(|s| Splat {
                p_film: s.p_film,
                l: s.l * b,
            })
            .collect();
        out.film.add_splats(&splats, &scene.filter);
        for r in results {
            out.trace += r.trace;
            out.mutations += r.mutations;
            out.accepted += r.accepted;
        }
        done = out.mutations;
        progress(done, total);
    }
    out.cancelled = done < total;
    // The film's sample count makes the mean image b / mutationsperpixel times the splat
    // sums (a cancelled render: its share of the mutations).
    let spp = if out.cancelled {
        ((u128::from(mpp) * u128::from(done)).div_ceil(u128::from(total.max(1))) as u64).max(1)
    } else {
        u64::from(mpp)
    };
    out.film.add_samples_per_pixel(spp);
    out
}

/// One chain's splats (not yet scaled by `b`) and figures.
struct ChainResult {
    splats: Vec<Splat>,
    trace: TraceStats,
    mutations: u64,
    accepted: u64,
    cancelled: bool,
}

/// Run chain `index` for `mutations` mutations, starting from a bootstrap state chosen by
/// luminance from `cdf` (the running sums of the bootstrap luminances).
#[allow(clippy::too_many_arguments)]
fn run_chain(
    ctx: &Context<'_>,
    index: u64,
    mutations: u64,
    cdf: &[f64],
    raster: &Raster,
    settings: &MltSettings,
    cancel: &AtomicBool,
    new_sampler: &(dyn Fn(u64) -> MltSampler + Sync),
) -> ChainResult {
    let mut r = ChainResult {
        splats: Vec::with_capacity(2 * mutations as usize),
        trace: TraceStats::default(),
        mutations: 0,
        accepted: 0,
        cancelled: false,
    };
    let mut rng = Pcg32::new(index, hash_u64s(&[settings.seed, 0x6d6c_7400]));
    // The starting state: bootstrap state i with probability Y_i / sum Y.
    let total = *cdf.last().expect("a non-empty bootstrap");
    let u = f64::from(rng.next_f32()) * total;
    let start = cdf.partition_point(|&c| c <= u).min(cdf.len() - 1) as u64;
    let depths = u64::from(settings.max_depth) + 1;
    let depth = (start % depths) as usize;
    let mut sampler = new_sampler(start);
    let mut buffers = Buffers::default();
    let mut current = contribution(ctx, &mut sampler, depth, raster, &mut buffers, &mut r.trace);
    let mut y_current = current.l.luminance().max(0.0);
    for j in 0..mutations {
        if j % CANCEL_CHECK == 0 && j > 0 && cancel.load(Ordering::Relaxed) {
            r.cancelled = true;
            return r;
        }
        sampler.start_iteration();
        let proposed = contribution(ctx, &mut sampler, depth, raster, &mut buffers, &mut r.trace);
        let y_proposed = proposed.l.luminance().max(0.0);
        // Metropolis-Hastings with symmetric proposals; both states are splatted with the
        // probability of the chain being there next (expected values).
        let accept = if y_current > 0.0 {
            (y_proposed / y_current).min(1.0)
        } else {
            1.0
        };
        if accept > 0.0 && y_proposed > 0.0 {
            r.splats.push(Splat {
                p_film: proposed.p_raster,
                l: proposed.l * (accept / y_proposed),
            });
        }
        if accept < 1.0 && y_current > 0.0 {
            r.splats.push(Splat {
                p_film: current.p_raster,
                l: current.l * ((1.0 - accept) / y_current),
            });
        }
        if rng.next_f32() < accept {
            current = proposed;
            y_current = y_proposed;
            sampler.accept();
            r.accepted += 1;
        } else {
            sampler.reject();
        }
        r.mutations += 1;
    }
    r
}
