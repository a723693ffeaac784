//! Layer 6: rendering a whole image. The image is cut into tiles rendered in parallel with
//! rayon. Every sample draws its random numbers from (seed, pixel, sample index) alone and
//! each pixel's samples are accumulated in index order, so the image is bit-identical
//! whatever the number of threads or the order tiles finish in.

mod tiles;

pub use tiles::{tiles, Tile};

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use rayon::prelude::*;

use crate::film::{Film, PixelStats};
use crate::integrator::{Integrator, TraceStats};
use crate::math::{UVec2, Vec2};
use crate::sampling::Sampler;
use crate::scene::Scene;

/// How to render.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RenderOptions {
    /// Worker threads; `None` = all cores.
    pub threads: Option<usize>,
    /// Tile side in pixels.
    pub tile_size: u32,
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            threads: None,
            tile_size: 16,
        }
    }
}

/// Figures about a finished render.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderStats {
    /// Wall-clock time of the rendering (scene building excluded).
    pub elapsed: Duration,
    /// Camera paths traced (pixels x samples per pixel).
    pub paths: u64,
    /// Closest-hit and shadow rays.
    pub trace: TraceStats,
    /// Samples whose value was NaN or infinite; they were dropped, not accumulated.
    pub nonfinite_samples: u64,
    /// Threads used.
    pub threads: usize,
}

/// A finished render: the film (means and variances) and its statistics.
#[derive(Clone, Debug)]
pub struct RenderOutput {
    /// Per-pixel accumulators.
    pub film: Film,
    /// Figures.
    pub stats: RenderStats,
}

/// Why a render could not run.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// The integrator cannot render this scene as configured.
    #[error(transparent)]
    Integrator(#[from] crate::integrator::IntegratorError),
    /// The thread pool could not be created.
    #[error("cannot start {threads} render threads: {source}")]
    ThreadPool {
        /// Requested threads.
        threads: usize,
        /// Cause.
        source: rayon::ThreadPoolBuildError,
    },
}

/// Render the scene; `progress(done, total)` is called (from worker threads) as tiles
/// finish, with counts in pixels.
pub fn render(
    scene: &Scene,
    opts: &RenderOptions,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Result<RenderOutput, RenderError> {
    render_samples(scene, opts, 0..scene.sampler.samples_per_pixel, progress)
}

/// Render only the samples with indices in `samples` of every pixel. Films of disjoint
/// ranges merge ([`Film::merge`]) into exactly the film of their union, so a render can
/// grow in waves (convergence studies, progressive output) and stay deterministic.
pub fn render_samples(
    scene: &Scene,
    opts: &RenderOptions,
    samples: std::ops::Range<u32>,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Result<RenderOutput, RenderError> {
    let threads = opts.threads.unwrap_or_else(rayon::current_num_threads).max(1);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|source| RenderError::ThreadPool { threads, source })?;
    let integrator = Integrator::new(scene)?;
    let (w, h) = (scene.film.width, scene.film.height);
    let tile_list = tiles(w, h, opts.tile_size.max(1));
    let total = u64::from(w) * u64::from(h);
    let done = AtomicU64::new(0);
    let start = Instant::now();

    let results: Vec<(Tile, Vec<PixelStats>, TraceStats, u64)> = pool.install(|| {
        tile_list
            .par_iter()
            .map(|tile| {
                let (pixels, trace, nonfinite) = render_tile(scene, &integrator, tile, samples.clone());
                let n = done.fetch_add(tile.pixel_count(), Ordering::Relaxed) + tile.pixel_count();
                progress(n, total);
                (*tile, pixels, trace, nonfinite)
            })
            .collect()
    });

    let mut film = Film::new(w, h);
    let mut stats = RenderStats {
        threads,
        ..Default::default()
    };
    for (tile, pixels, trace, nonfinite) in results {
        for (i, p) in pixels.into_iter().enumerate() {
            let (x, y) = tile.pixel_at(i);
            *film.pixel_mut(x, y) = p;
        }
        stats.trace += trace;
        stats.nonfinite_samples += nonfinite;
    }
    stats.elapsed = start.elapsed();
    stats.paths = total * u64::from(samples.end.saturating_sub(samples.start));
    Ok(RenderOutput { film, stats })
}

/// Render the given samples of every pixel in a tile, in tile order.
fn render_tile(
    scene: &Scene,
    integrator: &Integrator,
    tile: &Tile,
    samples: std::ops::Range<u32>,
) -> (Vec<PixelStats>, TraceStats, u64) {
    let mut sampler = Sampler::new(&scene.sampler);
    let mut trace = TraceStats::default();
    let mut nonfinite = 0;
    let mut out = Vec::with_capacity(tile.pixel_count() as usize);
    for i in 0..tile.pixel_count() as usize {
        let (x, y) = tile.pixel_at(i);
        let pixel = UVec2::new(x, y);
        let mut acc = PixelStats::default();
        for s in samples.clone() {
            sampler.start_pixel_sample(pixel, s);
            // Offset drawn from the filter: the sample lands at centre + offset with a
            // weight of about one, so nothing is splatted into neighbouring pixels.
            let fs = scene.filter.sample(sampler.get_pixel_2d());
            let p_film = Vec2::new(x as f32 + 0.5, y as f32 + 0.5) + fs.p;
            let ray = scene.camera.generate_ray(p_film, sampler.get_2d());
            let l = integrator.li(scene, ray, &mut sampler, &mut trace);
            if l.is_finite() && fs.weight.is_finite() {
                acc.add(l, fs.weight);
            } else {
                nonfinite += 1;
            }
        }
        out.push(acc);
    }
    (out, trace, nonfinite)
}
