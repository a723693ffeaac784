//! What a front end sees of a render while it runs: progress, finished tiles, and the flag
//! it sets to stop the render.

use std::sync::atomic::AtomicBool;

use super::Tile;
use crate::film::PixelStats;

/// Watches a render. Every method is called from worker threads, as work units finish, in
/// no particular order; the defaults do nothing.
pub trait RenderObserver: Sync {
    /// Work done so far in the current call, `(done, total)` in pixel samples.
    fn progress(&self, _done: u64, _total: u64) {}

    /// A tile finished its samples of the current wave; `pixels` are its accumulators so far
    /// (all waves, row-major within the tile; splats not included).
    fn tile_finished(&self, _tile: &Tile, _pixels: &[PixelStats]) {}

    /// A flag checked before each work unit (a tile of a wave): once set, the render stops
    /// and the unfinished wave is dropped (see [`super::RenderSession::advance`]).
    fn cancel_flag(&self) -> Option<&AtomicBool> {
        None
    }
}

/// Whether the observer's cancel flag is set (for drivers checking between work units).
#[must_use]
pub fn is_cancelled(observer: &dyn RenderObserver) -> bool {
    observer
        .cancel_flag()
        .is_some_and(|c| c.load(std::sync::atomic::Ordering::Relaxed))
}

/// Nothing to watch.
impl RenderObserver for () {}

/// An observer that only reports progress to a closure `(done, total)`.
pub struct ProgressFn<F>(pub F);

impl<F: Fn(u64, u64) + Sync> RenderObserver for ProgressFn<F> {
    fn progress(&self, done: u64, total: u64) {
        (self.0)(done, total);
    }
}

/// An observer with a progress closure and a cancellation flag.
pub struct Watch<'a, F> {
    /// Called with `(done, total)`.
    pub progress: F,
    /// Set it to stop the render.
    pub cancel: &'a AtomicBool,
}

impl<F: Fn(u64, u64) + Sync> RenderObserver for Watch<'_, F> {
    fn progress(&self, done: u64, total: u64) {
        (self.progress)(done, total);
    }

    fn cancel_flag(&self) -> Option<&AtomicBool> {
        Some(self.cancel)
    }
}
