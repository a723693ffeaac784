//! [`RenderSession`]: one render's thread pool, integrator and film, continued wave after
//! wave of sample indices.

use std::ops::Range;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use rayon::prelude::*;

use super::{
    doubling_waves, is_cancelled, tiles_within, RenderError, RenderObserver, RenderOptions, RenderOutput, RenderStats,
    Tile,
};
use crate::film::{Film, Filter, Footprint, PixelStats, Reconstruction, Splat};
use crate::integrator::{Integrator, TraceStats};
use crate::math::{UVec2, Vec2};
use crate::sampling::Sampler;
use crate::scene::Scene;

/// A render in progress: built once (thread pool, integrator, tiles), then advanced by
/// consecutive ranges of sample indices, each continuing the film where the last stopped.
pub struct RenderSession<'s> {
    scene: &'s Scene,
    integrator: Integrator,
    pool: rayon::ThreadPool,
    threads: usize,
    tile_size: u32,
    /// The pixels this session renders (the whole image unless [`Self::set_window`]).
    window: Tile,
    tiles: Vec<Tile>,
    /// Under filter splatting with a window: tiles of the pixels around it whose samples
    /// the filter carries into it; only their filtered samples are kept.
    margin_tiles: Vec<Tile>,
    film: Film,
    /// The first sample index of the next range; `None` until something is rendered.
    next_sample: Option<u32>,
}

/// One tile's share of a wave.
struct TileResult {
    pixels: Vec<PixelStats>,
    /// Under filter splatting, the camera samples (film position, radiance) for the film's
    /// filtered sums, one list per sample index of the wave; empty otherwise.
    filtered: Vec<Vec<Splat>>,
    splats: Vec<Splat>,
    trace: TraceStats,
    nonfinite: u64,
}

impl<'s> RenderSession<'s> {
    /// A session with an empty film.
    pub fn new(scene: &'s Scene, opts: &RenderOptions) -> Result<Self, RenderError> {
        let (w, h) = (scene.film.width, scene.film.height);
        let film = match scene.reconstruction {
            Reconstruction::FilterSampling => Film::new(w, h),
            Reconstruction::FilterSplatting => Film::for_filter_splatting(w, h),
        };
        Self::build(scene, opts, film, None)
    }

    /// A session continuing `film` (e.g. read from a checkpoint), whose next range must
    /// start at `next_sample`.
    pub fn with_film(
        scene: &'s Scene,
        opts: &RenderOptions,
        film: Film,
        next_sample: u32,
    ) -> Result<Self, RenderError> {
        let expected = (scene.film.width, scene.film.height);
        if (film.width(), film.height()) != expected {
            return Err(RenderError::FilmSize {
                expected,
                found: (film.width(), film.height()),
            });
        }
        let name = |splatting: bool| if splatting { "splatting" } else { "sampling" };
        let (wanted, found) = (splatting(scene), film.filtered_sums().is_some());
        if wanted != found {
            return Err(RenderError::FilmReconstruction {
                expected: name(wanted),
                found: name(found),
            });
        }
        Self::build(scene, opts, film, Some(next_sample))
    }

    fn build(
        scene: &'s Scene,
        opts: &RenderOptions,
        film: Film,
        next_sample: Option<u32>,
    ) -> Result<Self, RenderError> {
        let threads = opts.threads.unwrap_or_else(rayon::current_num_threads).max(1);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|source| RenderError::ThreadPool { threads, source })?;
        let integrator = Integrator::new(scene)?;
        let tile_size = opts.tile_size.max(1);
        let window = Tile {
            x0: 0,
            y0: 0,
            x1: scene.film.width,
            y1: scene.film.height,
        };
        Ok(Self {
            scene,
            integrator,
            pool,
            threads,
            tile_size,
            window,
            tiles: tiles_within(window, tile_size),
            margin_tiles: Vec::new(),
            film,
            next_sample,
        })
    }

    /// The scene.
    #[must_use]
    pub fn scene(&self) -> &'s Scene {
        self.scene
    }

    /// The integrator, built once for the session.
    #[must_use]
    pub fn integrator(&self) -> &Integrator {
        &self.integrator
    }

    /// The worker threads (for drivers that do not render per camera sample: SPPM, MLT).
    #[must_use]
    pub fn pool(&self) -> &rayon::ThreadPool {
        &self.pool
    }

    /// Number of worker threads.
    #[must_use]
    pub fn threads(&self) -> usize {
        self.threads
    }

    /// The tiles rendered, row by row.
    #[must_use]
    pub fn tiles(&self) -> &[Tile] {
        &self.tiles
    }

    /// Render only the pixels of `window` from now on (e.g. one machine's share of the
    /// image); the other pixels' accumulators are left as they are. The splats of the
    /// window's paths still land on any pixel. Under filter splatting the window's pixels
    /// are rendered whole: the samples of the pixels around it that the filter reaches are
    /// rendered too (as the film of those pixels renders them) and splatted into the
    /// window only, so films of disjoint windows combine into the whole image's bits.
    pub fn set_window(&mut self, window: Tile) -> Result<(), RenderError> {
        let size = (self.film.width(), self.film.height());
        if window.x0 >= window.x1 || window.y0 >= window.y1 || window.x1 > size.0 || window.y1 > size.1 {
            return Err(RenderError::Window { window, size });
        }
        self.window = window;
        self.tiles = tiles_within(window, self.tile_size);
        self.margin_tiles = if splatting(self.scene) {
            margin_around(window, size, self.scene.filter.radius())
                .into_iter()
                .flat_map(|m| tiles_within(m, self.tile_size))
                .collect()
        } else {
            Vec::new()
        };
        Ok(())
    }

    /// The film so far: every completed wave, nothing of a cancelled one.
    #[must_use]
    pub fn film(&self) -> &Film {
        &self.film
    }

    /// The film, ending the session.
    #[must_use]
    pub fn into_film(self) -> Film {
        self.film
    }

    /// The film, for drivers that fill it themselves (SPPM, MLT; their integrator modules
    /// render through [`Self::pool`], check [`RenderObserver::cancel_flag`] between their
    /// work units, report [`RenderObserver::progress`], then call [`Self::mark_rendered`]).
    pub fn film_mut(&mut self) -> &mut Film {
        &mut self.film
    }

    /// Record that a driver rendered sample indices (iterations, passes) `range` into the
    /// film itself: the film's sample count grows and the next range must follow it.
    pub fn mark_rendered(&mut self, range: Range<u32>) -> Result<(), RenderError> {
        if let Some(next) = self.next_sample {
            if range.start != next {
                return Err(RenderError::SampleRange { next, found: range });
            }
        }
        self.film
            .add_samples_per_pixel(u64::from(range.end.saturating_sub(range.start)));
        self.next_sample = Some(range.end.max(range.start));
        Ok(())
    }

    /// The first sample index of the next range (`None` before the first).
    #[must_use]
    pub fn next_sample(&self) -> Option<u32> {
        self.next_sample
    }

    /// Render samples `range` of every pixel, continuing the film, and return a copy of the
    /// film with this call's figures. See [`Self::advance`].
    pub fn render_samples(
        &mut self,
        range: Range<u32>,
        observer: &dyn RenderObserver,
    ) -> Result<RenderOutput, RenderError> {
        let stats = self.advance(range, observer)?;
        Ok(RenderOutput {
            film: self.film.clone(),
            stats,
        })
    }

    /// Render samples `range` of every pixel, continuing the film: each pixel's accumulator
    /// picks up where the last range left it, so consecutive ranges give the same bytes as
    /// one range covering them. `range` must start where the previous one ended.
    ///
    /// Work units are tiles of a wave; a wave is the whole range, one sample index when the
    /// integrator splats, or under filter splatting as many as [`filter_splatting_wave`]
    /// allows (the film takes each index's samples as a group of its own, so the wave size
    /// changes nothing in the result). When the observer's cancel flag is set, the unfinished wave is
    /// dropped and [`RenderError::Cancelled`] returned; [`Self::film`] then holds the
    /// completed waves, and the render can be continued from [`Self::next_sample`].
    pub fn advance(&mut self, range: Range<u32>, observer: &dyn RenderObserver) -> Result<RenderStats, RenderError> {
        if let Some(next) = self.next_sample {
            if range.start != next {
                return Err(RenderError::SampleRange { next, found: range });
            }
        }
        let start = Instant::now();
        let pixels: u64 = self.tiles.iter().map(Tile::pixel_count).sum();
        let total = pixels * u64::from(range.end.saturating_sub(range.start));
        let done = AtomicU64::new(0);
        let mut stats = RenderStats {
            threads: self.threads,
            ..Default::default()
        };
        // Light-path splats land on other tiles' pixels: one sample index per wave, so that
        // they are committed before the next. Filtered camera samples are committed index by
        // index after each wave.
        let len = range.end.saturating_sub(range.start).max(1);
        let wave = if self.integrator.splats() {
            1
        } else if splatting(self.scene) {
            let margin: u64 = self.margin_tiles.iter().map(Tile::pixel_count).sum();
            filter_splatting_wave(len, pixels + margin)
        } else {
            len
        };
        let mut s = range.start;
        while s < range.end {
            let end = s.saturating_add(wave).min(range.end);
            self.wave(s..end, observer, &done, total, &mut stats)?;
            self.next_sample = Some(end);
            s = end;
        }
        stats.elapsed = start.elapsed();
        stats.paths = total;
        Ok(stats)
    }

    /// Render `range` in waves of doubling sample counts ([`doubling_waves`]), calling
    /// `after_wave(film, wave figures)` after each (convergence studies, progressive
    /// output). The film ends bit-identical to one pass; the figures returned are summed.
    pub fn render_in_waves(
        &mut self,
        range: Range<u32>,
        observer: &dyn RenderObserver,
        mut after_wave: impl FnMut(&Film, &RenderStats),
    ) -> Result<RenderStats, RenderError> {
        let mut total = RenderStats {
            threads: self.threads,
            ..Default::default()
        };
        for wave in doubling_waves(range) {
            let s = self.advance(wave, observer)?;
            after_wave(&self.film, &s);
            total.elapsed += s.elapsed;
            total.paths += s.paths;
            total.trace += s.trace;
            total.nonfinite_samples += s.nonfinite_samples;
            total.dropped_splats += s.dropped_splats;
        }
        Ok(total)
    }

    /// One wave: every tile renders `samples`, then the results are committed (pixels and
    /// splats), or dropped if cancelled.
    fn wave(
        &mut self,
        samples: Range<u32>,
        observer: &dyn RenderObserver,
        done: &AtomicU64,
        total: u64,
        stats: &mut RenderStats,
    ) -> Result<(), RenderError> {
        let cancelled = || is_cancelled(observer);
        if cancelled() {
            return Err(RenderError::Cancelled {
                samples_done: self.film.samples_per_pixel(),
            });
        }
        let n = u64::from(samples.end - samples.start);
        let (scene, integrator, film) = (self.scene, &self.integrator, &self.film);
        let splatting = splatting(scene);
        let owned = self.tiles.len();
        let results: Vec<Option<TileResult>> = self.pool.install(|| {
            self.tiles
                .par_iter()
                .chain(self.margin_tiles.par_iter())
                .enumerate()
                .map(|(k, tile)| {
                    if cancelled() {
                        return None;
                    }
                    // Under filter splatting the samples go to the film's filtered sums and
                    // the accumulators stay empty: nothing to continue.
                    let pixels = if splatting {
                        Vec::new()
                    } else {
                        (0..tile.pixel_count() as usize)
                            .map(|i| {
                                let (x, y) = tile.pixel_at(i);
                                *film.pixel(x, y)
                            })
                            .collect()
                    };
                    let r = render_tile(scene, integrator, tile, samples.clone(), pixels);
                    if k < owned {
                        observer.tile_finished(tile, &r.pixels);
                        let work = tile.pixel_count() * n;
                        observer.progress(done.fetch_add(work, Ordering::Relaxed) + work, total);
                    }
                    Some(r)
                })
                .collect()
        });
        let Some(mut results) = results.into_iter().collect::<Option<Vec<_>>>() else {
            return Err(RenderError::Cancelled {
                samples_done: self.film.samples_per_pixel(),
            });
        };
        // The margin's own light-path splats and figures are its owner's.
        let margin = results.split_off(owned);
        for (tile, r) in self.tiles.iter().zip(&results) {
            // (Empty under filter splatting.)
            for (i, p) in r.pixels.iter().enumerate() {
                let (x, y) = tile.pixel_at(i);
                *self.film.pixel_mut(x, y) = *p;
            }
            stats.trace += r.trace;
            stats.nonfinite_samples += r.nonfinite;
        }
        let (film, filter, pool) = (&mut self.film, &self.scene.filter, &self.pool);
        stats.dropped_splats += pool.install(|| commit_splats(film, &results, filter));
        if splatting {
            let w = &self.window;
            let window = Footprint {
                x0: w.x0,
                x1: w.x1,
                y0: w.y0,
                y1: w.y1,
            };
            // One group per sample index, in index order, gathered into one reused list.
            let mut samples: Vec<Splat> = Vec::new();
            for j in 0..n as usize {
                samples.clear();
                samples.extend(
                    results
                        .iter()
                        .chain(&margin)
                        .flat_map(|r| r.filtered[j].iter().copied()),
                );
                // Samples dropped here carried a huge radiance or fell where the filter
                // (narrower than a pixel) reaches no pixel centre: they count like dropped
                // splats.
                stats.dropped_splats += pool.install(|| film.add_filtered(&samples, filter, window));
            }
        }
        self.film.add_samples_per_pixel(n);
        Ok(())
    }
}

/// Add a wave's splats to the film, spread over the pixels `filter` covers (in any order:
/// the film's splat sums are exact; in parallel over bands of rows). Returns the number
/// dropped (reaching no pixel, not finite or huge).
fn commit_splats(film: &mut Film, results: &[TileResult], filter: &Filter) -> u64 {
    let splats: Vec<Splat> = results.iter().flat_map(|r| r.splats.iter().copied()).collect();
    if splats.is_empty() {
        return 0;
    }
    film.add_splats(&splats, filter)
}

/// The strips around `window` (inside the `size` image) holding the pixels whose samples a
/// filter of `radius` carries into the window: a sample in pixel `j` (anywhere in
/// `[j, j + 1)`) reaches the centre `c + 1/2` of pixel `c` when `|j - c| < radius + 1/2`,
/// so `ceil(radius + 1/2)` pixels (the box's edge included) on each side.
fn margin_around(window: Tile, size: (u32, u32), radius: Vec2) -> Vec<Tile> {
    let reach = |r: f32| (r + 0.5).ceil().clamp(0.0, u32::MAX as f32) as u32;
    let (mx, my) = (reach(radius.x), reach(radius.y));
    let outer = Tile {
        x0: window.x0.saturating_sub(mx),
        y0: window.y0.saturating_sub(my),
        x1: window.x1.saturating_add(mx).min(size.0),
        y1: window.y1.saturating_add(my).min(size.1),
    };
    let strips = [
        // Above and below, the whole outer width; left and right, the window's rows.
        (outer.x0, outer.y0, outer.x1, window.y0),
        (outer.x0, window.y1, outer.x1, outer.y1),
        (outer.x0, window.y0, window.x0, window.y1),
        (window.x1, window.y0, outer.x1, window.y1),
    ];
    strips
        .into_iter()
        .filter(|&(x0, y0, x1, y1)| x0 < x1 && y0 < y1)
        .map(|(x0, y0, x1, y1)| Tile { x0, y0, x1, y1 })
        .collect()
}

/// Whether the scene's film splats its camera samples through the filter.
fn splatting(scene: &Scene) -> bool {
    scene.reconstruction == Reconstruction::FilterSplatting
}

/// Most camera samples a wave of filter splatting holds (20 bytes each). They are listed per
/// tile and gathered one index at a time, so a wave of several indices costs at most 20 MiB
/// beyond the one index per pixel that the preflight's per-pixel figure counts.
const FILTER_WAVE_SAMPLES: u64 = 1 << 20;

/// Sample indices per wave under filter splatting, for a range of `len` indices over
/// `pixels` pixels: as many as [`FILTER_WAVE_SAMPLES`] allows, at least one. Several per
/// wave let a tile take a pixel's samples one after another (the Sobol' sampler reuses
/// the pixel's high index digits across them) and spare the threads a barrier per index.
fn filter_splatting_wave(len: u32, pixels: u64) -> u32 {
    let fits = (FILTER_WAVE_SAMPLES / pixels.max(1)).max(1);
    u32::try_from(fits).map_or(len, |fits| fits.min(len))
}

/// Continue the tile's accumulators (`pixels`, in tile order) with the given samples, or
/// under filter splatting (`pixels` then empty), list the samples for the film's filtered
/// sums.
// `i` walks the tile's pixels; `pixels` is indexed by it only when not splatting (then empty).
#[allow(clippy::needless_range_loop)]
fn render_tile(
    scene: &Scene,
    integrator: &Integrator,
    tile: &Tile,
    samples: Range<u32>,
    mut pixels: Vec<PixelStats>,
) -> TileResult {
    let mut sampler = Sampler::new(&scene.sampler);
    let mut trace = TraceStats::default();
    let mut nonfinite = 0;
    let mut splats = Vec::new();
    let splatting = splatting(scene);
    let mut filtered = if splatting {
        // (Not `vec![..; n]`: a cloned `Vec` does not keep its capacity.)
        samples
            .clone()
            .map(|_| Vec::with_capacity(tile.pixel_count() as usize))
            .collect()
    } else {
        Vec::new()
    };
    for i in 0..tile.pixel_count() as usize {
        let (x, y) = tile.pixel_at(i);
        let pixel = UVec2::new(x, y);
        for (j, s) in samples.clone().enumerate() {
            sampler.start_pixel_sample(pixel, s);
            let u = sampler.get_pixel_2d();
            if splatting {
                // Uniform in the pixel; the film weighs it for every pixel the filter covers.
                let p_film = Vec2::new(x as f32, y as f32) + u;
                let ray = scene.camera.generate_ray(p_film, sampler.get_2d());
                let l = integrator.li(scene, ray, &mut sampler, &mut trace, &mut splats);
                if l.is_finite() {
                    filtered[j].push(Splat { p_film, l });
                } else {
                    nonfinite += 1;
                }
                continue;
            }
            // Offset drawn from the filter: the sample lands at centre + offset with a
            // weight of about one, so nothing is splatted into neighbouring pixels.
            let fs = scene.filter.sample(u);
            let p_film = Vec2::new(x as f32 + 0.5, y as f32 + 0.5) + fs.p;
            let ray = scene.camera.generate_ray(p_film, sampler.get_2d());
            let l = integrator.li(scene, ray, &mut sampler, &mut trace, &mut splats);
            if l.is_finite() && fs.weight.is_finite() {
                pixels[i].add(l, fs.weight);
            } else {
                nonfinite += 1;
            }
        }
    }
    TileResult {
        pixels,
        filtered,
        splats,
        trace,
        nonfinite,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::Rgb;

    #[test]
    fn filter_splatting_waves_hold_a_bounded_number_of_samples() {
        assert_eq!(filter_splatting_wave(128, 256 * 256), 16);
        assert_eq!(filter_splatting_wave(7, 256 * 256), 7);
        assert_eq!(filter_splatting_wave(128, 1024 * 1024), 1);
        assert_eq!(filter_splatting_wave(128, 4096 * 4096), 1);
        assert_eq!(filter_splatting_wave(u32::MAX, 0), 1 << 20);
        assert_eq!(filter_splatting_wave(1, 1), 1);
    }

    /// Splats made by each pixel's sample, deterministic in (pixel, k) and landing far from
    /// the pixel, with magnitudes spread so that the order of float additions would show.
    fn splats_of(x: u32, y: u32, w: u32, h: u32) -> Vec<Splat> {
        (0..3)
            .map(|k| {
                let v = ((x * 31 + y * 17 + k * 7) % 13) as f32;
                Splat {
                    p_film: Vec2::new(((x * 7 + k) % w) as f32 + 0.25, ((y * 5 + k) % h) as f32 + 0.75),
                    l: Rgb::new(1e-3 * v, 10.0f32.powi(v as i32 % 7), 0.1 + v),
                }
            })
            .collect()
    }

    /// The film of committing every pixel's splats, the tiles' results listed in `order`.
    fn splat_film(w: u32, h: u32, tile_size: u32, reverse: bool) -> Film {
        let mut results: Vec<TileResult> = tiles_within(
            Tile {
                x0: 0,
                y0: 0,
                x1: w,
                y1: h,
            },
            tile_size,
        )
        .iter()
        .map(|t| TileResult {
            pixels: vec![PixelStats::default(); t.pixel_count() as usize],
            filtered: Vec::new(),
            splats: (0..t.pixel_count() as usize)
                .flat_map(|i| {
                    let (x, y) = t.pixel_at(i);
                    splats_of(x, y, w, h)
                })
                .collect(),
            trace: TraceStats::default(),
            nonfinite: 0,
        })
        .collect();
        if reverse {
            results.reverse();
        }
        let mut film = Film::new(w, h);
        assert_eq!(commit_splats(&mut film, &results, &gaussian()), 0);
        film
    }

    /// pbrt's default filter: every splat reaches several pixels.
    fn gaussian() -> Filter {
        Filter::new(&crate::scene::FilterDesc::default())
    }

    #[test]
    fn splat_sums_do_not_depend_on_tile_size_or_order() {
        let (w, h) = (11, 7);
        let mut reference = Film::new(w, h);
        for y in 0..h {
            for x in 0..w {
                for s in splats_of(x, y, w, h) {
                    assert!(reference.add_splat(&s, &gaussian()));
                }
            }
        }
        for ts in [1, 3, 4, 16] {
            for reverse in [false, true] {
                let film = splat_film(w, h, ts, reverse);
                assert_eq!(
                    film.splat_sums(),
                    reference.splat_sums(),
                    "tile size {ts}, reversed {reverse}"
                );
            }
        }
    }
}
