//! The integrator efficiency report behind `mcrender compare --integrators`: each
//! integrator renders the same scene at equal time (each gets the same budget, spent in
//! waves of one [`RenderSession`], or in iterations of SPPM's own driver) or at equal
//! samples, and a row gives its relative MSE against a reference, the true time and
//! samples it used, and efficiency `1 / (relMSE x time)`.
//!
//! Integrator names are parsed by one function, [`parse_integrator`], from one table,
//! [`INTEGRATORS`]: a name the build knows but cannot render is an error naming it, never
//! skipped. MLT is not progressive (its chains run to the end); at equal time it gets the
//! mutations per pixel that two short calibration renders predict fit in the budget.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crate::color::Rgb;
use crate::film::{Film, FilmStatistics};
use crate::integrator::mlt::{self, MltSettings};
use crate::integrator::sppm::{self, SppmSettings};
use crate::render::{RenderError, RenderOptions, RenderSession, Watch};
use crate::scene::{IntegratorKind, Scene, SceneDescription};

use super::waves::{check_reference, LabError};

/// Every integrator name `compare --integrators` accepts, with its kind; `None` marks a
/// name this build cannot render yet.
pub const INTEGRATORS: &[(&str, Option<IntegratorKind>)] = &[
    ("path", Some(IntegratorKind::Path)),
    ("direct", Some(IntegratorKind::Direct)),
    ("bdpt", Some(IntegratorKind::Bdpt)),
    ("lightpath", Some(IntegratorKind::LightPath)),
    ("sppm", Some(IntegratorKind::Sppm)),
    ("mlt", Some(IntegratorKind::Mlt)),
];

/// The integrator called `name` (one of [`INTEGRATORS`]).
///
/// # Errors
/// A message naming `name` when it is unknown or not available in this build.
pub fn parse_integrator(name: &str) -> Result<IntegratorKind, String> {
    match INTEGRATORS.iter().find(|(n, _)| *n == name) {
        Some((_, Some(kind))) => Ok(*kind),
        Some((n, None)) => Err(format!("{n}: not available in this build")),
        None => Err(format!(
            "unknown integrator \"{name}\" (expected one of {})",
            INTEGRATORS.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", ")
        )),
    }
}

/// The name of `kind` in [`INTEGRATORS`].
#[must_use]
pub fn integrator_name(kind: IntegratorKind) -> &'static str {
    INTEGRATORS
        .iter()
        .find(|(_, k)| *k == Some(kind))
        .map_or("?", |(n, _)| n)
}

/// How much each integrator may spend.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Budget {
    /// The same samples per pixel for each (SPPM: that many iterations, one camera sample
    /// per pixel each).
    Samples(u32),
    /// The same render time for each: waves (iterations) continue while the next one is
    /// predicted, from the measured time per sample so far, to fit in the budget; at
    /// least one sample is always rendered.
    Time(Duration),
}

/// Where the relative MSE's reference came from.
#[derive(Clone, Debug, PartialEq)]
pub enum ReferenceSource {
    /// Given by the caller.
    Given,
    /// A long render of this integrator: [`REFERENCE_FACTOR`] times the budget, with the
    /// seed changed so its noise is independent of the compared renders.
    LongRender(IntegratorKind),
}

/// Without a given reference, the first integrator renders one with this many times the
/// budget (its own error then adds about `1 / REFERENCE_FACTOR` of that integrator's
/// relMSE to every row).
pub const REFERENCE_FACTOR: u32 = 8;

/// One integrator's figures.
#[derive(Clone, Debug)]
pub struct IntegratorRow {
    /// The integrator.
    pub kind: IntegratorKind,
    /// Samples per pixel reached (SPPM: iterations).
    pub samples: u32,
    /// What `samples` counts: `"spp"` or `"iterations"`.
    pub sample_unit: &'static str,
    /// Mean radiance, per-pixel variance (zero for SPPM, which keeps none) and relative
    /// MSE against the reference.
    pub stats: FilmStatistics,
    /// True render time in seconds (scene building and measuring excluded).
    pub seconds: f64,
    /// Rays traced (closest-hit and shadow).
    pub rays: u64,
    /// `1 / (relMSE x time)`.
    pub efficiency: f64,
    /// Efficiency over the best finite efficiency of the report.
    pub relative_efficiency: f64,
    /// The final film.
    pub film: Film,
    /// `(seconds so far, relMSE)` after each wave (iteration).
    pub points: Vec<(f64, f64)>,
}

/// The report: one row per integrator and where the reference came from.
#[derive(Clone, Debug)]
pub struct IntegratorReport {
    /// The rows, in the order asked.
    pub rows: Vec<IntegratorRow>,
    /// The reference's source.
    pub reference: ReferenceSource,
}

/// Render `base` once per integrator (its other settings unchanged) within `budget` and
/// measure each against `reference` (row-major, the film's size) or, without one, against
/// a long render of the first integrator. `on_start(kind, is_reference)` is called before
/// each render (progress messages). Setting `cancel` stops the comparison within a work
/// unit of the integrator rendering (a tile, an SPPM pass, a stretch of an MLT chain).
///
/// # Errors
/// No integrators, a reference of the wrong size, a scene that cannot render, or
/// [`RenderError::Cancelled`] when cancelled.
pub fn compare_integrators(
    base: &SceneDescription,
    kinds: &[IntegratorKind],
    reference: Option<&[Rgb]>,
    threads: Option<usize>,
    budget: Budget,
    cancel: &AtomicBool,
    mut on_start: impl FnMut(IntegratorKind, bool),
) -> Result<IntegratorReport, LabError> {
    let Some(&first) = kinds.first() else {
        return Err(LabError::Argument(
            "integrators: expected at least one integrator".into(),
        ));
    };
    check_reference(base, reference)?;
    if let Budget::Time(t) = budget {
        if t.is_zero() {
            return Err(LabError::Argument("time budget: expected more than 0 seconds".into()));
        }
    }
    let (owned, source) = match reference {
        Some(_) => (None, ReferenceSource::Given),
        None => {
            on_start(first, true);
            let mut desc = with_kind(base, first);
            desc.sampler.seed = desc.sampler.seed.wrapping_add(0x9e37_79b9);
            desc.integrator.sppm.seed = desc.integrator.sppm.seed.map(|s| s.wrapping_add(0x9e37_79b9));
            let long = match budget {
                Budget::Samples(n) => Budget::Samples(n.saturating_mul(REFERENCE_FACTOR)),
                Budget::Time(t) => Budget::Time(t * REFERENCE_FACTOR),
            };
            let run = render_within(&desc, threads, long, cancel, &|_: &Film| 0.0)?;
            (Some(run.film.mean_image()), ReferenceSource::LongRender(first))
        }
    };
    let reference = reference.or(owned.as_deref()).unwrap_or_default();
    let measure = |f: &Film| FilmStatistics::measure(f, Some(reference)).rel_mse.unwrap_or(f64::NAN);

    let mut rows = Vec::with_capacity(kinds.len());
    for &kind in kinds {
        on_start(kind, false);
        let run = render_within(&with_kind(base, kind), threads, budget, cancel, &measure)?;
        let stats = FilmStatistics::measure(&run.film, Some(reference));
        let seconds = run.time.as_secs_f64();
        rows.push(IntegratorRow {
            kind,
            samples: run.samples,
            sample_unit: match kind {
                IntegratorKind::Sppm => "iterations",
                IntegratorKind::Mlt => "mutations/pixel",
                _ => "spp",
            },
            efficiency: 1.0 / (stats.rel_mse.unwrap_or(f64::NAN) * seconds),
            stats,
            seconds,
            rays: run.rays,
            relative_efficiency: 0.0,
            film: run.film,
            points: run.points,
        });
    }
    let best = rows
        .iter()
        .map(|r| r.efficiency)
        .filter(|e| e.is_finite())
        .fold(0.0, f64::max);
    for r in &mut rows {
        r.relative_efficiency = r.efficiency / best;
    }
    Ok(IntegratorReport {
        rows,
        reference: source,
    })
}

fn with_kind(base: &SceneDescription, kind: IntegratorKind) -> SceneDescription {
    let mut d = base.clone();
    d.integrator.kind = kind;
    d
}

/// One integrator's render within a budget.
struct Run {
    film: Film,
    samples: u32,
    time: Duration,
    rays: u64,
    points: Vec<(f64, f64)>,
}

/// Whether another step predicted to cost `per_step` fits in `budget` after `elapsed`.
fn fits(budget: Duration, elapsed: Duration, per_step: Duration) -> bool {
    elapsed + per_step <= budget
}

/// Render `desc` within `budget`, measuring after each wave (iteration).
fn render_within(
    desc: &SceneDescription,
    threads: Option<usize>,
    budget: Budget,
    cancel: &AtomicBool,
    measure: &(dyn Fn(&Film) -> f64 + Sync),
) -> Result<Run, LabError> {
    let scene = Scene::build(desc)?;
    match desc.integrator.kind {
        IntegratorKind::Sppm => return render_sppm(&scene, threads, budget, cancel, measure),
        IntegratorKind::Mlt => return render_mlt(&scene, threads, budget, cancel, measure),
        _ => {}
    }
    let opts = RenderOptions {
        threads,
        ..Default::default()
    };
    let mut session = RenderSession::new(&scene, &opts)?;
    let (mut done, mut time, mut rays) = (0u32, Duration::ZERO, 0u64);
    let mut points = Vec::new();
    loop {
        // Waves of 1, 1, 2, 4, ... spp (as `doubling_waves`); under a time budget each is
        // cut to what the measured time per spp predicts fits in the rest.
        let len = match budget {
            Budget::Samples(n) => done.max(1).min(n.saturating_sub(done)),
            Budget::Time(_) if done == 0 => 1,
            Budget::Time(t) => {
                let per = time.as_secs_f64() / f64::from(done);
                let fit = (t.saturating_sub(time).as_secs_f64() / per.max(1e-12)).floor();
                done.min(fit.min(f64::from(u32::MAX)) as u32)
            }
        };
        if len == 0 {
            break;
        }
        let watch = Watch {
            progress: |_, _| {},
            cancel,
        };
        let s = session.advance(done..done + len, &watch)?;
        done += len;
        time += s.elapsed;
        rays += s.trace.rays + s.trace.shadow_rays;
        points.push((time.as_secs_f64(), measure(session.film())));
    }
    Ok(Run {
        film: session.into_film(),
        samples: done,
        time,
        rays,
        points,
    })
}

/// SPPM in iterations of its own driver: `Samples(n)` runs n iterations; `Time` continues
/// while the next iteration (predicted from the mean so far) fits in the budget.
fn render_sppm(
    scene: &Scene,
    threads: Option<usize>,
    budget: Budget,
    cancel: &AtomicBool,
    measure: &(dyn Fn(&Film) -> f64 + Sync),
) -> Result<Run, LabError> {
    let mut settings = SppmSettings::from_scene(scene);
    settings.iterations = match budget {
        Budget::Samples(n) => n.max(1),
        Budget::Time(_) => u32::MAX,
    };
    let threads = threads.unwrap_or_else(rayon::current_num_threads).max(1);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| LabError::Argument(format!("cannot start the render threads: {e}")))?;
    let start = Instant::now();
    // Time spent measuring, excluded from the render time.
    let mut measuring = Duration::ZERO;
    let mut points = Vec::new();
    let mut observe = |done: u32, film: &Film| {
        let t0 = Instant::now();
        let elapsed = start.elapsed().saturating_sub(measuring);
        points.push((elapsed.as_secs_f64(), measure(film)));
        measuring += t0.elapsed();
        match budget {
            Budget::Samples(_) => true,
            Budget::Time(t) => fits(t, elapsed, elapsed / done),
        }
    };
    let observer: sppm::IterationObserver<'_> = &mut observe;
    let out = pool.install(|| sppm::render_observed(scene, &settings, &|_, _| {}, cancel, Some(observer)));
    if cancel.load(Ordering::Relaxed) {
        return Err(cancelled(u64::from(out.iterations)));
    }
    let time = start.elapsed().saturating_sub(measuring);
    Ok(Run {
        film: out.film,
        samples: out.iterations,
        time,
        rays: out.trace.rays + out.trace.shadow_rays,
        points,
    })
}

/// Mutations per pixel of MLT's second calibration render (the first has 1): far enough
/// apart that the time per mutation per pixel is not lost in the bootstrap's noise.
const MLT_CALIBRATION: u32 = 5;

/// MLT at `mutations_per_pixel` on its own pool: the film, the time and the rays.
fn mlt_once(
    scene: &Scene,
    threads: Option<usize>,
    mutations_per_pixel: u32,
    cancel: &AtomicBool,
) -> Result<(Film, Duration, u64), LabError> {
    let mut settings = MltSettings::from_scene(scene);
    settings.mutations_per_pixel = mutations_per_pixel.max(1);
    let start = Instant::now();
    let (out, _) = mlt::render_with_threads(scene, &settings, threads, &|_, _| {}, cancel)
        .map_err(|e| LabError::Argument(format!("cannot start the render threads: {e}")))?;
    if out.cancelled {
        let pixels = u64::from(scene.film.width) * u64::from(scene.film.height);
        return Err(cancelled(out.mutations / pixels.max(1)));
    }
    Ok((out.film, start.elapsed(), out.trace.rays + out.trace.shadow_rays))
}

/// MLT: `Samples(n)` renders n mutations per pixel; `Time(t)` first renders 1 and
/// [`MLT_CALIBRATION`] mutations per pixel (not counted) to split the time into the
/// bootstrap's and each mutation per pixel's, then renders what fits in `t` (at least 1:
/// a bootstrap longer than the budget overruns it). One convergence point: MLT's
/// estimate is only complete when its chains are.
fn render_mlt(
    scene: &Scene,
    threads: Option<usize>,
    budget: Budget,
    cancel: &AtomicBool,
    measure: &(dyn Fn(&Film) -> f64 + Sync),
) -> Result<Run, LabError> {
    let mutations = match budget {
        Budget::Samples(n) => n.max(1),
        Budget::Time(t) => {
            let (_, one, _) = mlt_once(scene, threads, 1, cancel)?;
            let (_, more, _) = mlt_once(scene, threads, MLT_CALIBRATION, cancel)?;
            // The slope of two noisy timings can be tiny or negative; never take a mutation
            // per pixel to cost less than a quarter of the calibration's average (which
            // includes the bootstrap), or the render would be asked for millions of them.
            let slope = more.saturating_sub(one).as_secs_f64() / f64::from(MLT_CALIBRATION - 1);
            let floor = more.as_secs_f64() / f64::from(4 * MLT_CALIBRATION);
            let per = slope.max(floor).max(1e-6);
            let bootstrap = one.as_secs_f64() - per;
            let fit = ((t.as_secs_f64() - bootstrap) / per).floor();
            fit.clamp(1.0, f64::from(u32::MAX)) as u32
        }
    };
    let (film, time, rays) = mlt_once(scene, threads, mutations, cancel)?;
    let points = vec![(time.as_secs_f64(), measure(&film))];
    Ok(Run {
        film,
        samples: mutations,
        time,
        rays,
        points,
    })
}

/// The error of a comparison stopped by its cancel flag.
fn cancelled(samples_done: u64) -> LabError {
    LabError::Render(RenderError::Cancelled { samples_done })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_or_missing_ones_are_errors() {
        for (name, kind) in INTEGRATORS {
            match kind {
                Some(k) => {
                    assert_eq!(parse_integrator(name), Ok(*k));
                    assert_eq!(integrator_name(*k), *name);
                }
                None => assert_eq!(
                    parse_integrator(name),
                    Err(format!("{name}: not available in this build"))
                ),
            }
        }
        let e = parse_integrator("photon").unwrap_err();
        assert!(e.contains("\"photon\"") && e.contains("bdpt"), "{e}");
    }

    #[test]
    fn fits_only_what_the_budget_holds() {
        let s = Duration::from_secs;
        assert!(fits(s(10), s(6), s(4)));
        assert!(!fits(s(10), s(7), s(4)));
    }
}
