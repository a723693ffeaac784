//! The render loop of `mcrender render` for MLT, which has its own driver (a bootstrap,
//! then Markov chains; not samples per pixel): the bootstrap, then steps of mutations sized
//! to end at the next checkpoint (at most [`MAX_WAVE`] each), the MLT state ([`MltState`]:
//! `b`, the chains, the splat sums) checkpointed between them every `--checkpoint-every`
//! (section `integrator.mlt`), and on SIGINT / SIGTERM the image of the mutations made and
//! a checkpoint written, then exit 130 / 143. A chain stopped by a signal stops after a
//! whole mutation and continues from there, so a resumed render is bit-identical to one
//! never stopped, whatever the thread counts.

use std::path::Path;
use std::time::Instant;

use anyhow::{anyhow, bail, Context, Result};
use mcrender_core::integrator::mlt::{self, MltSettings, MltState};
use mcrender_core::render::{RenderOutput, RenderStats};
use mcrender_core::scene::{Scene, SceneDescription};

use crate::checkpoint::{self, IntegratorState, Resume};
use crate::interrupt;
use crate::progressive::{self, Plan, DEFAULT_EVERY, MAX_WAVE};
use crate::render_cmd::{progress_bar, write_outputs, RenderArgs};

/// The name of MLT's checkpoint section (`integrator.mlt`).
const STATE_NAME: &str = "mlt";

/// Mutations of the first step, before the time of one is known.
const FIRST_STEP: u64 = 4096;

/// Render `scene` with MLT, with checkpoints and interruption, and write the outputs.
pub fn render(
    args: &RenderArgs,
    resume: Option<Resume>,
    scene: &Scene,
    desc: &SceneDescription,
    output: &Path,
) -> Result<()> {
    let settings = MltSettings::from_scene(scene);
    let (w, h) = (desc.film.width, desc.film.height);
    let spp = desc.sampler.samples_per_pixel;
    let total = u64::from(settings.mutations_per_pixel) * u64::from(w) * u64::from(h);
    let Plan {
        explicit,
        path: ck_path,
        fingerprint,
        invocation,
        checkpoint,
    } = progressive::plan(args, resume, desc, output)?;
    let mut state = match checkpoint {
        None => MltState::new(w, h),
        Some(ck) => match ck.integrator_state {
            Some(s) if s.name == STATE_NAME => MltState::from_bytes(&s.bytes, w, h, &settings)
                .map_err(|e| anyhow!("checkpoint \"{}\": {e}; nothing was written", ck_path.display()))?,
            _ => bail!(
                "checkpoint \"{}\" holds no MLT state (it is not an mlt render's); nothing was written",
                ck_path.display()
            ),
        },
    };
    let every = args.checkpointing.checkpoint_every.unwrap_or(DEFAULT_EVERY);
    let signals = interrupt::install()?;
    let threads = args.scene.threads.unwrap_or_else(rayon::current_num_threads).max(1);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .context("cannot start the render threads")?;
    let bar = progress_bar(total, args.quiet);
    bar.set_position(state.mutations());
    let save = |path: &Path, state: &MltState| {
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
    let first = state.mutations();
    let start = Instant::now();
    let mut last_checkpoint = Instant::now();
    let due = |last: Instant| last.elapsed() >= every.mul_f64(0.9);
    let mut trace = pool.install(|| mlt::bootstrap(scene, &settings, &mut state, &signals.cancel));
    let mut seconds_per_mutation = None::<f64>;
    while state.is_bootstrapped() && !state.is_finished() && signals.received().is_none() {
        if let Some(path) = &explicit {
            if due(last_checkpoint) {
                save(path, &state)?;
                last_checkpoint = Instant::now();
            }
        }
        // A step that ends at the next checkpoint, or after MAX_WAVE.
        let until_checkpoint = explicit
            .as_ref()
            .map(|_| every.saturating_sub(last_checkpoint.elapsed()));
        let target = until_checkpoint.map_or(MAX_WAVE, |t| t.min(MAX_WAVE)).as_secs_f64();
        let budget = seconds_per_mutation.map_or(FIRST_STEP, |t| ((target / t.max(1e-12)) as u64).max(1));
        let (before, t0) = (state.mutations(), Instant::now());
        trace += pool.install(|| {
            mlt::advance(
                scene,
                &settings,
                &mut state,
                budget,
                &|done, _| bar.set_position(done),
                &signals.cancel,
            )
        });
        let made = state.mutations() - before;
        if made > 0 {
            seconds_per_mutation = Some(t0.elapsed().as_secs_f64() / made as f64);
        }
    }
    bar.finish_and_clear();
    let done = state.mutations();
    if !state.is_finished() {
        if let Some(by) = signals.received() {
            let (done_text, requested) = (done.to_string(), total.to_string());
            let meta = [
                ("mcrender.mutations", done_text.as_str()),
                ("mcrender.mutationsRequested", requested.as_str()),
            ];
            let film = state.film(&settings);
            progressive::write_partial(&film, output, args.variance_output.as_deref(), &meta)?;
            save(&ck_path, &state)?;
            eprintln!(
                "mcrender: {by} after {done} of {total} MLT mutations: wrote \"{}\" ({done} mutations) and checkpoint \"{}\"; \
                 continue with: mcrender render --resume {}",
                output.display(),
                ck_path.display(),
                ck_path.display()
            );
            return Err(by.into());
        }
        bail!("the MLT render stopped after {done} of {total} mutations");
    }
    progressive::remove_finished(explicit.as_deref());
    let out = RenderOutput {
        film: state.film(&settings),
        stats: RenderStats {
            elapsed: start.elapsed(),
            paths: done - first,
            trace,
            threads,
            ..Default::default()
        },
    };
    write_outputs(&out, output, args.variance_output.as_deref())?;
    let secs = out.stats.elapsed.as_secs_f64().max(1e-9);
    let continued = if first > 0 {
        format!(" (continued from mutation {first})")
    } else {
        String::new()
    };
    eprintln!(
        "{}: {w}x{h}, MLT {} mutations per pixel ({} chains, b = {:.4}, {:.1}% accepted){continued} in {secs:.2} s on {threads} threads: {:.2} M mutations/s",
        output.display(),
        settings.mutations_per_pixel,
        settings.chains,
        state.b(),
        100.0 * state.accepted() as f64 / done.max(1) as f64,
        (done - first) as f64 / secs / 1e6,
    );
    Ok(())
}
