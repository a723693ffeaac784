//! Layer 6: rendering a whole image. A [`RenderSession`] is built once per render (thread
//! pool, integrator, tiles, film) and advanced by consecutive ranges of sample indices
//! (waves, as pbrt-v4 renders), the tiles of each wave rendered in parallel with rayon.
//!
//! Determinism. Every sample draws its random numbers from (seed, pixel, sample index)
//! alone. Each pixel's samples are accumulated in index order, and a wave *continues* the
//! pixel's accumulator from the previous wave rather than summing into a fresh one and
//! merging (floating-point addition does not associate), so a render in waves is
//! bit-identical to one pass, whatever the number of threads or the order tiles finish in.
//!
//! Splats (light-tracing contributions to arbitrary pixels, [`crate::film::Splat`]) are
//! collected per tile and added to the film after the wave. The film keeps splat sums in
//! fixed point ([`crate::film::SplatSum`]), where addition associates, so the order splats
//! arrive in does not matter: any thread count, tile size, split of the render into sample
//! ranges or image windows (rendered on other machines and combined with
//! [`Film::combine_disjoint`]) gives the same bits. When the integrator splats, a wave is
//! one sample index, which bounds the memory held to one sample per pixel's worth of splats.
//!
//! A session can render a window of the image only ([`RenderSession::set_window`]); the
//! other pixels keep empty accumulators, and the splats of the window's paths land anywhere.
//!
//! Cancellation: the observer's flag ([`RenderObserver::cancel_flag`]) is checked before
//! every work unit (a tile of a wave); a cancelled wave is dropped whole, so the film always
//! holds a whole number of samples per pixel and can be checkpointed and continued.

mod observer;
mod session;
mod tiles;
mod waves;

pub use observer::{is_cancelled, ProgressFn, RenderObserver, Watch};
pub use session::RenderSession;
pub use tiles::{tiles, tiles_within, Tile};
pub use waves::doubling_waves;

use std::ops::Range;
use std::time::Duration;

use crate::film::Film;
use crate::integrator::TraceStats;
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
    /// Splats dropped: outside the image or not finite.
    pub dropped_splats: u64,
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

/// Why a render could not run (or did not finish).
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
    /// The cancel flag was set; the film holds the completed waves.
    #[error("render cancelled after {samples_done} samples per pixel")]
    Cancelled {
        /// Samples per pixel in the film.
        samples_done: u64,
    },
    /// A range that does not continue the session's film.
    #[error("sample range {}..{} does not continue the render, which stopped at sample {next}", found.start, found.end)]
    SampleRange {
        /// Where the next range must start.
        next: u32,
        /// The range asked for.
        found: Range<u32>,
    },
    /// A window that is empty or not inside the image.
    #[error("window [{}, {}) x [{}, {}) is empty or not inside the {}x{} image", window.x0, window.x1, window.y0, window.y1, size.0, size.1)]
    Window {
        /// The window asked for.
        window: Tile,
        /// The image size.
        size: (u32, u32),
    },
    /// A film kept for the other reconstruction than the scene's (filter sampling or
    /// splatting).
    #[error("film of filter {found}, but the scene asks for filter {expected}")]
    FilmReconstruction {
        /// The scene's ("sampling" or "splatting").
        expected: &'static str,
        /// The film's.
        found: &'static str,
    },
    /// A film of another size than the scene's.
    #[error("film of {}x{} for a {}x{} image", found.0, found.1, expected.0, expected.1)]
    FilmSize {
        /// The scene's image size.
        expected: (u32, u32),
        /// The film's.
        found: (u32, u32),
    },
}

/// Render the scene in one pass; `progress(done, total)` is called (from worker threads) as
/// tiles finish, with counts in pixel samples.
pub fn render(
    scene: &Scene,
    opts: &RenderOptions,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Result<RenderOutput, RenderError> {
    render_samples(scene, opts, 0..scene.sampler.samples_per_pixel, progress)
}

/// Render only the samples with indices in `samples` of every pixel, in a session of its
/// own. Films of disjoint ranges merge ([`Film::merge`]) into the film of their union up to
/// rounding; for the exact bytes, continue one [`RenderSession`].
pub fn render_samples(
    scene: &Scene,
    opts: &RenderOptions,
    samples: Range<u32>,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Result<RenderOutput, RenderError> {
    let mut session = RenderSession::new(scene, opts)?;
    let stats = session.advance(samples, &ProgressFn(progress))?;
    Ok(RenderOutput {
        film: session.into_film(),
        stats,
    })
}
