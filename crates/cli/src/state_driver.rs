//! The render loop of `mcrender render` for the integrators with a driver of their own
//! (not samples per pixel: SPPM's iterations, MLT's bootstrap and Markov chains), written
//! once over [`StateRender`], which says what differs between them: the state, one unit of
//! work, and how the image is formed from the state.
//!
//! The loop: continue the checkpoint's state (refusing one of another integrator), run
//! steps of work in a pool of `--threads` threads, checkpoint the state between steps
//! every `--checkpoint-every` (section `integrator.NAME`), and on SIGINT / SIGTERM write the
//! image of the work done and a checkpoint, then exit 130 / 143. A step cut short by a
//! signal leaves the state consistent, so a resumed render is bit-identical to one never
//! stopped, whatever the thread counts.

use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use anyhow::{anyhow, bail, Context, Result};
use mcrender_core::film::Film;
use mcrender_core::integrator::TraceStats;
use mcrender_core::render::{RenderOutput, RenderStats};
use mcrender_core::scene::{Scene, SceneDescription};

use crate::checkpoint::{self, IntegratorState, Resume};
use crate::interrupt;
use crate::progressive::{self, DEFAULT_EVERY};
use crate::render_cmd::{progress_bar, write_outputs, RenderArgs};

/// An integrator whose render is a state advanced in steps, checkpointed between them.
pub trait StateRender: Send {
    /// What is checkpointed: all the render has done so far.
    type State: Send;
    /// The checkpoint section's name (`integrator.NAME`), lower case: `"mlt"`.
    const NAME: &'static str;
    /// The integrator's name in messages: `"MLT"`.
    const LABEL: &'static str;
    /// The unit of work counted, singular: `"mutation"`. Its plural names the EXR metadata
    /// of a partial image (`mcrender.mutations`, `mcrender.mutationsRequested`).
    const UNIT: &'static str;
    /// What the speed on stderr counts, plural: `"photons"` (per second).
    const RATE_UNIT: &'static str;

    /// The state of a `width` x `height` render not yet started.
    fn new_state(&self, width: u32, height: u32) -> Self::State;
    /// The state a checkpoint's section holds, for a `width` x `height` render.
    ///
    /// # Errors
    /// A short description when the bytes are not such a state or one of another render.
    fn restore(&self, bytes: &[u8], width: u32, height: u32) -> Result<Self::State, String>;
    /// The state as the checkpoint's section.
    fn state_bytes(&self, state: &Self::State) -> Vec<u8>;
    /// The image of the work done.
    fn film(&self, state: &Self::State) -> Film;
    /// Units of work done.
    fn done(&self, state: &Self::State) -> u64;
    /// Units of work the render asks for.
    fn total(&self) -> u64;
    /// Whether the render is complete (MLT's can be before [`Self::total`] units, when its
    /// bootstrap finds no light).
    fn is_finished(&self, state: &Self::State) -> bool;
    /// The work before the first step (MLT's bootstrap); none unless overridden. When
    /// `cancel` is set before it ends, the state is left as it was.
    fn start(&mut self, _scene: &Scene, _state: &mut Self::State, _cancel: &AtomicBool) -> TraceStats {
        TraceStats::default()
    }
    /// One step of work in the current rayon pool, sized (where the integrator can) to
    /// take about `seconds`, calling `progress(done)`. Returns `None` when `cancel` cut it
    /// short and it was dropped whole; either way the state is consistent.
    fn step(
        &mut self,
        scene: &Scene,
        state: &mut Self::State,
        seconds: f64,
        progress: &(dyn Fn(u64) + Sync),
        cancel: &AtomicBool,
    ) -> Option<TraceStats>;
    /// The paths (or photons) traced by `units` units of work, for the render's stats.
    fn paths(&self, units: u64) -> u64;
    /// What was rendered, for the summary line: `"SPPM 20 iterations x 20000 photons"`.
    fn describe(&self, state: &Self::State) -> String;
}

/// Render `scene` with `integrator`, with checkpoints and interruption, and write the
/// outputs; returns the [`interrupt::Interrupted`] error after writing the partial image
/// and checkpoint.
pub fn render<R: StateRender>(
    mut integrator: R,
    args: &RenderArgs,
    resume: Option<Resume>,
    scene: &Scene,
    desc: &SceneDescription,
    output: &Path,
) -> Result<()> {
    let r = &mut integrator;
    let (label, units) = (R::LABEL, format!("{}s", R::UNIT));
    let (w, h) = (desc.film.width, desc.film.height);
    let spp = desc.sampler.samples_per_pixel;
    let total = r.total();
    let plan = progressive::plan(args, resume, desc, output)?;
    let (explicit, ck_path) = (&plan.explicit, &plan.path);
    let mut state = match plan.checkpoint {
        None => r.new_state(w, h),
        Some(ck) => match ck.integrator_state {
            Some(s) if s.name == R::NAME => r
                .restore(&s.bytes, w, h)
                .map_err(|e| anyhow!("checkpoint \"{}\": {e}; nothing was written", ck_path.display()))?,
            _ => bail!(
                "checkpoint \"{}\" holds no {label} state (it is not an {} render's); nothing was written",
                ck_path.display(),
                R::NAME
            ),
        },
    };
    if r.done(&state) > total {
        bail!(
            "checkpoint \"{}\": {} {label} {units} done, more than the {total} asked for",
            ck_path.display(),
            r.done(&state),
        );
    }
    let every = args.checkpointing.checkpoint_every.unwrap_or(DEFAULT_EVERY);
    let signals = interrupt::install()?;
    let threads = args.scene.threads.unwrap_or_else(rayon::current_num_threads).max(1);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .context("cannot start the render threads")?;
    let bar = progress_bar(total, args.quiet);
    bar.set_position(r.done(&state));
    let save = |path: &Path, r: &R, state: &R::State| {
        let bytes = IntegratorState {
            name: R::NAME.into(),
            bytes: r.state_bytes(state),
        };
        checkpoint::write(
            path,
            &plan.fingerprint,
            &plan.invocation,
            spp,
            &r.film(state),
            Some(&bytes),
        )
    };
    let first = r.done(&state);
    let start = Instant::now();
    let mut last_checkpoint = Instant::now();
    let mut trace = pool.install(|| r.start(scene, &mut state, &signals.cancel));
    while !r.is_finished(&state) && signals.received().is_none() {
        // A little early rather than a step late.
        if let Some(path) = explicit {
            if last_checkpoint.elapsed() >= every.mul_f64(0.9) {
                save(path, r, &state)?;
                last_checkpoint = Instant::now();
            }
        }
        let seconds = progressive::wave_seconds(explicit.is_some(), every, last_checkpoint);
        let progress = |done| bar.set_position(done);
        let Some(t) = pool.install(|| r.step(scene, &mut state, seconds, &progress, &signals.cancel)) else {
            break;
        };
        trace += t;
        bar.set_position(r.done(&state));
    }
    bar.finish_and_clear();
    let done = r.done(&state);
    if !r.is_finished(&state) {
        if let Some(by) = signals.received() {
            let (done_text, requested) = (done.to_string(), total.to_string());
            let keys = [format!("mcrender.{units}"), format!("mcrender.{units}Requested")];
            let meta = [
                (keys[0].as_str(), done_text.as_str()),
                (keys[1].as_str(), requested.as_str()),
            ];
            progressive::write_partial(&r.film(&state), output, args.variance_output.as_deref(), &meta)?;
            save(ck_path, r, &state)?;
            eprintln!(
                "mcrender: {by} after {done} of {total} {label} {units}: wrote \"{}\" ({done} {units}) and checkpoint \"{}\"; \
                 continue with: mcrender render --resume {}",
                output.display(),
                ck_path.display(),
                ck_path.display()
            );
            return Err(by.into());
        }
        bail!("the {label} render stopped after {done} of {total} {units}");
    }
    progressive::remove_finished(explicit.as_deref());
    let out = RenderOutput {
        film: r.film(&state),
        stats: RenderStats {
            elapsed: start.elapsed(),
            paths: r.paths(done - first),
            trace,
            threads,
            ..Default::default()
        },
    };
    write_outputs(&out, output, args.variance_output.as_deref())?;
    let secs = out.stats.elapsed.as_secs_f64().max(1e-9);
    let continued = if first > 0 {
        format!(" (continued from {} {first})", R::UNIT)
    } else {
        String::new()
    };
    eprintln!(
        "{}: {w}x{h}, {}{continued} in {secs:.2} s on {threads} threads: {:.2} M {}/s",
        output.display(),
        r.describe(&state),
        out.stats.paths as f64 / secs / 1e6,
        R::RATE_UNIT,
    );
    Ok(())
}
