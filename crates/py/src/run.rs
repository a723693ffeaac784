//! Running a render from Python: the GIL is released while the tiles render; the calling
//! thread wakes every 50 ms, takes the GIL briefly to run Python's signal handlers (Ctrl-C
//! raises KeyboardInterrupt there) and to report progress, and on an exception sets the
//! cancel flag, waits for the render to stop and re-raises it.
//!
//! The render is one [`RenderSession`] (as the CLI's), advanced in waves of samples of
//! about a quarter second each; the session checks the cancel flag before each work unit
//! (a tile of a wave), so Ctrl-C stops the render within a fraction of a second, and since
//! consecutive waves continue the session's film, the image is bit-identical to the CLI's.

use std::ops::Range;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use mcrender_core::integrator::mlt::{self, MltSettings};
use mcrender_core::integrator::sppm::{self, SppmSettings};
use mcrender_core::render::{RenderError, RenderOptions, RenderOutput, RenderSession, RenderStats, Tile, Watch};
use mcrender_core::scene::Scene;
use pyo3::exceptions::{PyRuntimeError, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::render_error;

/// How often the waiting thread looks at signals and progress.
const POLL: Duration = Duration::from_millis(50);

/// The time a wave of samples aims at (see [`render_session`]).
const WAVE_SECONDS: f64 = 0.25;

/// The `progress=` argument as passed.
#[derive(FromPyObject)]
pub enum ProgressArg {
    /// True or False.
    Flag(bool),
    /// None or a callable (anything else is a TypeError when used).
    Other(Py<PyAny>),
}

/// Where progress goes: nowhere, a callback `fn(done, total)`, or a tqdm bar.
pub enum Progress {
    /// No progress.
    Off,
    /// `fn(done, total)`, counts in pixel samples.
    Callback(Py<PyAny>),
    /// A `tqdm.auto.tqdm` bar and the count it shows.
    Bar(Py<PyAny>, u64),
}

impl Progress {
    /// From the `progress=` argument: True (a tqdm bar when tqdm is installed, else
    /// nothing), False or None (nothing), or a callable.
    pub fn from_arg(py: Python<'_>, arg: &ProgressArg, total: u64, desc: &str) -> PyResult<Self> {
        match arg {
            ProgressArg::Flag(false) => Ok(Self::Off),
            ProgressArg::Other(f) if f.is_none(py) => Ok(Self::Off),
            ProgressArg::Other(f) if f.bind(py).is_callable() => Ok(Self::Callback(f.clone_ref(py))),
            ProgressArg::Other(_) => Err(PyTypeError::new_err(
                "progress: expected True, False, None or a callable progress(done, total)",
            )),
            ProgressArg::Flag(true) => match py.import("tqdm.auto") {
                Ok(module) => {
                    let kwargs = PyDict::new(py);
                    kwargs.set_item("total", total)?;
                    kwargs.set_item("desc", desc)?;
                    kwargs.set_item("unit", " samples")?;
                    kwargs.set_item("unit_scale", true)?;
                    kwargs.set_item("leave", false)?;
                    let bar = module.getattr("tqdm")?.call((), Some(&kwargs))?;
                    Ok(Self::Bar(bar.unbind(), 0))
                }
                Err(_) => Ok(Self::Off),
            },
        }
    }

    /// Report `done` of `total`.
    fn update(&mut self, py: Python<'_>, done: u64, total: u64) -> PyResult<()> {
        match self {
            Self::Off => Ok(()),
            Self::Callback(f) => f.bind(py).call1((done, total)).map(drop),
            Self::Bar(bar, shown) => {
                if done > *shown {
                    bar.bind(py).call_method1("update", (done - *shown,))?;
                    *shown = done;
                }
                Ok(())
            }
        }
    }

    /// Close a bar.
    fn close(&mut self, py: Python<'_>) -> PyResult<()> {
        if let Self::Bar(bar, _) = self {
            bar.bind(py).call_method0("close")?;
        }
        Ok(())
    }
}

/// Render the sample indices `samples` of the pixels of `window` (default: all) of
/// `scene`, off the GIL, with progress and cancellation as the module doc says.
pub fn render_range(
    py: Python<'_>,
    scene: &Scene,
    opts: &RenderOptions,
    samples: Range<u32>,
    window: Option<Tile>,
    progress: &mut Progress,
) -> PyResult<RenderOutput> {
    let pixels = window.map_or(u64::from(scene.film.width) * u64::from(scene.film.height), |w| {
        w.pixel_count()
    });
    let total = pixels * u64::from(samples.end - samples.start);
    run_off_gil(py, total, progress, |done, cancel| {
        render_session(scene, opts, samples, window, done, cancel)
    })
}

/// Render `scene` with SPPM (its own driver: iterations of camera and photon passes),
/// off the GIL, progress counted in iterations, cancellable between passes (a cancelled
/// render raises, like the others, rather than returning the iterations done).
pub fn render_sppm(
    py: Python<'_>,
    scene: &Scene,
    threads: Option<usize>,
    progress: &ProgressArg,
) -> PyResult<RenderOutput> {
    let settings = SppmSettings::from_scene(scene);
    let total = u64::from(settings.iterations);
    let mut progress = Progress::from_arg(py, progress, total, "mcrender (sppm)")?;
    run_off_gil(py, total, &mut progress, |done, cancel| {
        let start = Instant::now();
        let report = |n: u64, _total: u64| {
            done.fetch_max(n, Ordering::Relaxed);
        };
        let (out, threads) =
            sppm::render_with_threads(scene, &settings, threads, &report, cancel).map_err(|source| {
                RenderError::ThreadPool {
                    threads: threads.unwrap_or(0),
                    source,
                }
            })?;
        if out.iterations < settings.iterations {
            return Err(RenderError::Cancelled {
                samples_done: u64::from(out.iterations),
            });
        }
        Ok(RenderOutput {
            film: out.film,
            stats: RenderStats {
                elapsed: start.elapsed(),
                paths: out.photons,
                trace: out.trace,
                threads,
                ..Default::default()
            },
        })
    })
}

/// Render `scene` with MLT (its own driver: a bootstrap, then Markov chains), off the GIL,
/// progress counted in mutations, cancellable between bootstrap chunks and every few
/// thousand mutations of a chain (a cancelled render raises, like the others).
pub fn render_mlt(
    py: Python<'_>,
    scene: &Scene,
    threads: Option<usize>,
    progress: &ProgressArg,
) -> PyResult<RenderOutput> {
    let settings = MltSettings::from_scene(scene);
    let pixels = u64::from(scene.film.width) * u64::from(scene.film.height);
    let total = u64::from(settings.mutations_per_pixel) * pixels;
    let mut progress = Progress::from_arg(py, progress, total, "mcrender (mlt)")?;
    run_off_gil(py, total, &mut progress, |done, cancel| {
        let start = Instant::now();
        let report = |n: u64, _total: u64| {
            done.fetch_max(n, Ordering::Relaxed);
        };
        let (out, threads) =
            mlt::render_with_threads(scene, &settings, threads, &report, cancel).map_err(|source| {
                RenderError::ThreadPool {
                    threads: threads.unwrap_or(0),
                    source,
                }
            })?;
        if out.cancelled {
            return Err(RenderError::Cancelled {
                samples_done: out.mutations / pixels.max(1),
            });
        }
        Ok(RenderOutput {
            film: out.film,
            stats: RenderStats {
                elapsed: start.elapsed(),
                paths: out.mutations,
                trace: out.trace,
                threads,
                ..Default::default()
            },
        })
    })
}

/// Run `render(done, cancel)` on a thread of its own with the GIL released; meanwhile
/// poll Python's signals and report `done` of `total` every [`POLL`]. An exception from
/// either (KeyboardInterrupt, a failing progress callback) sets `cancel` and is raised once
/// the render has stopped.
fn run_off_gil<F>(py: Python<'_>, total: u64, progress: &mut Progress, render: F) -> PyResult<RenderOutput>
where
    F: FnOnce(&AtomicU64, &AtomicBool) -> Result<RenderOutput, RenderError> + Send,
{
    run_cancellable(py, total, progress, render, render_error)
}

/// [`run_off_gil`] for any work `run(done, cancel)` whose error `E` becomes a Python
/// exception by `to_py` (the estimator lab's comparisons use it too).
pub fn run_cancellable<T, E, F>(
    py: Python<'_>,
    total: u64,
    progress: &mut Progress,
    run: F,
    to_py: impl FnOnce(&E) -> PyErr,
) -> PyResult<T>
where
    T: Send,
    E: Send,
    F: FnOnce(&AtomicU64, &AtomicBool) -> Result<T, E> + Send,
{
    let done = AtomicU64::new(0);
    let cancel = AtomicBool::new(false);
    let (result, interrupted) = py.detach(|| {
        std::thread::scope(|s| {
            let (finished_tx, finished) = mpsc::channel::<()>();
            let (done, cancel) = (&done, &cancel);
            let worker = s.spawn(move || {
                let r = run(done, cancel);
                // The receiver may be gone only if the waiting loop panicked.
                let _ = finished_tx.send(());
                r
            });
            let mut interrupted: Option<PyErr> = None;
            while let Err(mpsc::RecvTimeoutError::Timeout) = finished.recv_timeout(POLL) {
                if interrupted.is_some() {
                    continue;
                }
                let polled = Python::attach(|py| {
                    py.check_signals()?;
                    progress.update(py, done.load(Ordering::Relaxed), total)
                });
                if let Err(e) = polled {
                    cancel.store(true, Ordering::Relaxed);
                    interrupted = Some(e);
                }
            }
            (worker.join(), interrupted)
        })
    });
    let finished = match (result, interrupted) {
        (_, Some(e)) => Err(e),
        (Err(_), None) => Err(PyRuntimeError::new_err("mcrender: the render thread panicked")),
        (Ok(Err(e)), None) => Err(to_py(&e)),
        (Ok(Ok(out)), None) => progress.update(py, total, total).map(|()| out),
    };
    let closed = progress.close(py);
    let out = finished?;
    closed?;
    Ok(out)
}

/// Render `samples` in one session, reporting progress to `done`, stopping when `cancel`
/// is set. The session is advanced in waves of about [`WAVE_SECONDS`] (the first wave one
/// sample per pixel, each later one sized from the time per sample so far, growing at most
/// fourfold): the session's cancel check is per tile of a wave, so this bounds how long
/// Ctrl-C waits, and consecutive waves continue the film exactly.
fn render_session(
    scene: &Scene,
    opts: &RenderOptions,
    samples: Range<u32>,
    window: Option<Tile>,
    done: &AtomicU64,
    cancel: &AtomicBool,
) -> Result<RenderOutput, RenderError> {
    let mut session = RenderSession::new(scene, opts)?;
    if let Some(window) = window {
        session.set_window(window)?;
    }
    let pixels: u64 = session.tiles().iter().map(Tile::pixel_count).sum();
    let mut stats = RenderStats {
        threads: session.threads(),
        ..Default::default()
    };
    let (mut s, mut wave) = (samples.start, 1u32);
    while s < samples.end {
        let end = s.saturating_add(wave).min(samples.end);
        let base = u64::from(s - samples.start) * pixels;
        let watch = Watch {
            progress: |n: u64, _total: u64| {
                done.fetch_max(base + n, Ordering::Relaxed);
            },
            cancel,
        };
        let w = session.advance(s..end, &watch)?;
        let per_sample = w.elapsed.as_secs_f64() / f64::from(end - s);
        let fit = (WAVE_SECONDS / per_sample.max(1e-9)).min(f64::from(u32::MAX)) as u32;
        wave = fit.clamp(1, wave.saturating_mul(4));
        stats.elapsed += w.elapsed;
        stats.paths += w.paths;
        stats.trace += w.trace;
        stats.nonfinite_samples += w.nonfinite_samples;
        stats.dropped_splats += w.dropped_splats;
        s = end;
    }
    Ok(RenderOutput {
        film: session.into_film(),
        stats,
    })
}
