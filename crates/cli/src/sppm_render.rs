//! The render loop of `mcrender render` for SPPM, which has its own driver (iterations of
//! camera and photon passes, not samples per pixel): iterations run one at a time, the
//! per-pixel SPPM state ([`SppmState`]) is checkpointed between them every
//! `--checkpoint-every` (section `integrator.sppm`), and on SIGINT / SIGTERM the image of
//! the iterations done and a checkpoint are written, then exit 130 / 143. An iteration cut
//! short by a signal is dropped whole, so a resumed render is bit-identical to one never
//! stopped, whatever the thread counts.

use std::path::Path;
use std::time::Instant;

use anyhow::{anyhow, bail, Context, Result};
use mcrender_core::integrator::sppm::{self, SppmSettings, SppmState};
use mcrender_core::integrator::TraceStats;
use mcrender_core::render::{RenderOutput, RenderStats};
use mcrender_core::scene::{Scene, SceneDescription};

use crate::checkpoint::{self, IntegratorState, Resume};
use crate::interrupt;
use crate::progressive::{self, Plan, DEFAULT_EVERY};
use crate::render_cmd::{progress_bar, write_outputs, RenderArgs};

/// The name of SPPM's checkpoint section (`integrator.sppm`).
const STATE_NAME: &str = "sppm";

/// Render `scene` with SPPM, with checkpoints and interruption, and write the outputs.
pub fn render(
    args: &RenderArgs,
    resume: Option<Resume>,
    scene: &Scene,
    desc: &SceneDescription,
    output: &Path,
) -> Result<()> {
    let settings = SppmSettings::from_scene(scene);
    let (w, h) = (desc.film.width, desc.film.height);
    let spp = desc.sampler.samples_per_pixel;
    let Plan {
        explicit,
        path: ck_path,
        fingerprint,
        invocation,
        checkpoint,
    } = progressive::plan(args, resume, desc, output)?;
    let mut state = match checkpoint {
        None => SppmState::new(w, h, &settings),
        Some(ck) => match ck.integrator_state {
            Some(s) if s.name == STATE_NAME => SppmState::from_bytes(&s.bytes, w, h)
                .map_err(|e| anyhow!("checkpoint \"{}\": {e}; nothing was written", ck_path.display()))?,
            _ => bail!(
                "checkpoint \"{}\" holds no SPPM state (it is not an sppm render's); nothing was written",
                ck_path.display()
            ),
        },
    };
    if state.iterations_done() > settings.iterations {
        bail!(
            "checkpoint \"{}\": {} SPPM iterations done, more than the {} asked for",
            ck_path.display(),
            state.iterations_done(),
            settings.iterations
        );
    }
    let every = args.checkpointing.checkpoint_every.unwrap_or(DEFAULT_EVERY);
    let signals = interrupt::install()?;
    let threads = args.scene.threads.unwrap_or_else(rayon::current_num_threads).max(1);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .context("cannot start the render threads")?;
    let bar = progress_bar(u64::from(settings.iterations), args.quiet);
    bar.set_position(u64::from(state.iterations_done()));
    let save = |path: &Path, state: &SppmState| {
        let bytes = IntegratorState {
            name: STATE_NAME.into(),
            bytes: state.to_bytes(),
        };
        checkpoint::write(
            path,
            &fingerprint,
            &invocation,
            spp,
            &state.film(&settings),
            Some(&bytes),
        )
    };
    let first = state.iterations_done();
    let start = Instant::now();
    let (mut trace, mut photons) = (TraceStats::default(), 0u64);
    let mut last_checkpoint = Instant::now();
    while state.iterations_done() < settings.iterations {
        let Some(t) = pool.install(|| sppm::iterate(scene, &settings, &mut state, &signals.cancel)) else {
            break;
        };
        trace += t;
        photons += settings.photons_per_iteration;
        bar.set_position(u64::from(state.iterations_done()));
        if let Some(path) = &explicit {
            let unfinished = state.iterations_done() < settings.iterations;
            if unfinished && last_checkpoint.elapsed() >= every.mul_f64(0.9) {
                save(path, &state)?;
                last_checkpoint = Instant::now();
            }
        }
    }
    bar.finish_and_clear();
    let done = state.iterations_done();
    let film = state.film(&settings);
    if done < settings.iterations {
        if let Some(by) = signals.received() {
            let (done_text, requested) = (done.to_string(), settings.iterations.to_string());
            let meta = [
                ("mcrender.iterations", done_text.as_str()),
                ("mcrender.iterationsRequested", requested.as_str()),
            ];
            progressive::write_partial(&film, output, args.variance_output.as_deref(), &meta)?;
            save(&ck_path, &state)?;
            eprintln!(
                "mcrender: {by} after {done} of {} SPPM iterations: wrote \"{}\" ({done} iterations) and checkpoint \"{}\"; \
                 continue with: mcrender render --resume {}",
                settings.iterations,
                output.display(),
                ck_path.display(),
                ck_path.display()
            );
            return Err(by.into());
        }
    }
    progressive::remove_finished(explicit.as_deref());
    let out = RenderOutput {
        film,
        stats: RenderStats {
            elapsed: start.elapsed(),
            paths: photons,
            trace,
            threads,
            ..Default::default()
        },
    };
    write_outputs(&out, output, args.variance_output.as_deref())?;
    let secs = out.stats.elapsed.as_secs_f64().max(1e-9);
    let continued = if first > 0 {
        format!(" (continued from iteration {first})")
    } else {
        String::new()
    };
    eprintln!(
        "{}: {w}x{h}, SPPM {done} iterations x {} photons{continued} in {secs:.2} s on {threads} threads: {:.2} M photons/s",
        output.display(),
        settings.photons_per_iteration,
        photons as f64 / secs / 1e6,
    );
    Ok(())
}
