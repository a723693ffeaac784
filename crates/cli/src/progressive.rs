//! The render loop of `mcrender render`: one render session advanced in waves sized to end
//! at the next checkpoint (at most [`MAX_WAVE`] each), a checkpoint written between waves
//! every `--checkpoint-every`, and on SIGINT / SIGTERM the image so far (its true sample
//! count on stderr and in the EXR metadata) and a checkpoint, then exit 130 / 143.
//!
//! The waves continue the film, so the image does not depend on how the render was cut
//! into waves, stopped or resumed. A kill -9 loses the work since the last checkpoint: about
//! one interval, as waves are sized to end at the checkpoint times.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{bail, Context, Result};
use mcrender_core::film::Film;
use mcrender_core::render::{RenderError, RenderOptions, RenderOutput, RenderSession, RenderStats, Watch};
use mcrender_core::scene::{Scene, SceneDescription};
use mcrender_formats::image_io::{write_exr_layers_with_metadata, write_image, ImageRgb};

use crate::checkpoint::{self, Checkpoint, Invocation, Resume};
use crate::interrupt;
use crate::render_cmd::{progress_bar, RenderArgs};

/// Longest wave: bounds the work a signal discards (the unfinished wave is dropped).
pub const MAX_WAVE: Duration = Duration::from_secs(5);

/// Default time between checkpoints.
pub const DEFAULT_EVERY: Duration = Duration::from_secs(60);

/// Where a render checkpoints, what identifies it, and the checkpoint it continues.
pub struct Plan {
    /// `--checkpoint`: checkpoints are written periodically only when given.
    pub explicit: Option<PathBuf>,
    /// Where the checkpoint goes (when interrupted without --checkpoint: OUTPUT.ckpt).
    pub path: PathBuf,
    /// The render's fingerprint.
    pub fingerprint: String,
    /// What later checkpoints record as the command to resume.
    pub invocation: Invocation,
    /// The checkpoint continued (a --resume, or the same command run again), checked
    /// against this render's fingerprint.
    pub checkpoint: Option<Checkpoint>,
}

/// Work out the checkpoint of a render writing `output`: the file, the fingerprint, and
/// the checkpoint to continue (refusing one of another render).
pub fn plan(args: &RenderArgs, resume: Option<Resume>, desc: &SceneDescription, output: &Path) -> Result<Plan> {
    let spp = desc.sampler.samples_per_pixel;
    let explicit = args.checkpointing.checkpoint.clone();
    let fallback = {
        let mut name = output.as_os_str().to_owned();
        name.push(".ckpt");
        PathBuf::from(name)
    };
    let path = explicit.clone().unwrap_or(fallback);
    let mut outputs: Vec<&Path> = vec![output, &path];
    outputs.extend(args.variance_output.as_deref());
    let fingerprint = checkpoint::fingerprint(args.scene.scene.as_deref(), desc, &outputs)?;
    let (invocation, checkpoint) = match resume {
        Some(r) => {
            checkpoint::check_fingerprint(&path, &r.checkpoint, &fingerprint, desc)?;
            (r.invocation, Some(r.checkpoint))
        }
        // Re-running the command of a render that was stopped continues it; a checkpoint
        // of another render is never overwritten.
        None => match explicit.as_deref().filter(|p| p.exists()) {
            Some(path) => {
                let ck = checkpoint::read(path).with_context(|| {
                    format!(
                        "--checkpoint \"{}\" exists and is not a usable checkpoint; remove it or choose another file",
                        path.display()
                    )
                })?;
                checkpoint::check_fingerprint(path, &ck, &fingerprint, desc).with_context(|| {
                    format!(
                        "--checkpoint \"{}\" belongs to another render; remove it or choose another file",
                        path.display()
                    )
                })?;
                let done = match &ck.integrator_state {
                    None => format!("{} of {spp} samples per pixel done", ck.film.samples_per_pixel()),
                    Some(s) => format!("saved by {}", s.name),
                };
                eprintln!(
                    "mcrender: continuing the render in checkpoint \"{}\" ({done})",
                    path.display(),
                );
                (Invocation::current()?, Some(ck))
            }
            None => (Invocation::current()?, None),
        },
    };
    Ok(Plan {
        explicit,
        path,
        fingerprint,
        invocation,
        checkpoint,
    })
}

/// Render `scene` (described by `desc`, loaded from `args`) to its sample count, with
/// checkpoints and interruption; a resume continues its film. Returns the finished render,
/// or the [`interrupt::Interrupted`] error after writing the partial image and checkpoint.
pub fn render(
    args: &RenderArgs,
    resume: Option<Resume>,
    scene: &Scene,
    desc: &SceneDescription,
    output: &Path,
) -> Result<RenderOutput> {
    let spp = desc.sampler.samples_per_pixel;
    let Plan {
        explicit,
        path: ck_path,
        fingerprint,
        invocation,
        checkpoint,
    } = plan(args, resume, desc, output)?;
    let film = match checkpoint {
        Some(ck) => match ck.integrator_state {
            None => Some(ck.film),
            Some(s) => bail!(
                "checkpoint \"{}\" holds the state of the {} integrator, not of this render's; nothing was written",
                ck_path.display(),
                s.name
            ),
        },
        None => None,
    };
    let every = args.checkpointing.checkpoint_every.unwrap_or(DEFAULT_EVERY);
    let opts = RenderOptions {
        threads: args.scene.threads,
        ..Default::default()
    };
    let signals = interrupt::install()?;
    let mut session = match film {
        Some(f) => {
            let next = u32::try_from(f.samples_per_pixel()).unwrap_or(u32::MAX);
            RenderSession::with_film(scene, &opts, f, next)?
        }
        None => RenderSession::new(scene, &opts)?,
    };
    let pixels = u64::from(desc.film.width) * u64::from(desc.film.height);
    let bar = progress_bar(pixels * u64::from(spp), args.quiet);
    let mut done = session.next_sample().unwrap_or(0);
    bar.set_position(pixels * u64::from(done));
    let mut total = RenderStats {
        threads: session.threads(),
        ..Default::default()
    };
    let (mut last_checkpoint, mut seconds_per_sample) = (Instant::now(), None::<f64>);
    while done < spp {
        let target = wave_seconds(explicit.is_some(), every, last_checkpoint);
        let n = seconds_per_sample.map_or(1, |t| ((target / t.max(1e-9)).floor() as u32).clamp(1, spp - done));
        let base = pixels * u64::from(done);
        let watch = Watch {
            progress: |d, _| bar.set_position(base + d),
            cancel: &signals.cancel,
        };
        match session.advance(done..done + n, &watch) {
            Ok(s) => {
                seconds_per_sample = Some(s.elapsed.as_secs_f64() / f64::from(n));
                add_stats(&mut total, &s);
                done += n;
            }
            Err(RenderError::Cancelled { .. }) => break,
            Err(e) => return Err(e.into()),
        }
        if let Some(path) = &explicit {
            // A little early rather than a wave late.
            if done < spp && last_checkpoint.elapsed() >= every.mul_f64(0.9) {
                checkpoint::write(path, &fingerprint, &invocation, spp, session.film(), None)?;
                last_checkpoint = Instant::now();
            }
        }
    }
    bar.finish_and_clear();
    let film = session.into_film();
    let out = RenderOutput { film, stats: total };
    if done < spp {
        if let Some(by) = signals.received() {
            let done_text = out.film.samples_per_pixel().to_string();
            let requested = spp.to_string();
            let meta = [
                ("mcrender.samplesPerPixel", done_text.as_str()),
                ("mcrender.samplesRequested", requested.as_str()),
            ];
            write_partial(&out.film, output, args.variance_output.as_deref(), &meta)?;
            checkpoint::write(&ck_path, &fingerprint, &invocation, spp, &out.film, None)?;
            eprintln!(
                "mcrender: {by} after {done} of {spp} samples per pixel: wrote \"{}\" ({done} spp) and checkpoint \"{}\"; \
                 continue with: mcrender render --resume {}",
                output.display(),
                ck_path.display(),
                ck_path.display()
            );
            return Err(by.into());
        }
    }
    remove_finished(explicit.as_deref());
    Ok(out)
}

/// How long the next wave (or step) should take, in seconds: until the next checkpoint,
/// `every` after `last_checkpoint`, when `checkpointing`, and at most [`MAX_WAVE`].
pub fn wave_seconds(checkpointing: bool, every: Duration, last_checkpoint: Instant) -> f64 {
    let wave = if checkpointing {
        every.saturating_sub(last_checkpoint.elapsed()).min(MAX_WAVE)
    } else {
        MAX_WAVE
    };
    wave.as_secs_f64()
}

/// A finished render's checkpoint has served its purpose: remove it.
pub fn remove_finished(checkpoint: Option<&Path>) {
    let Some(path) = checkpoint else { return };
    match std::fs::remove_file(path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
            eprintln!(
                "mcrender: warning: cannot remove checkpoint \"{}\": {e}",
                path.display()
            );
        }
        _ => {}
    }
}

fn add_stats(total: &mut RenderStats, s: &RenderStats) {
    total.elapsed += s.elapsed;
    total.paths += s.paths;
    total.trace += s.trace;
    total.nonfinite_samples += s.nonfinite_samples;
    total.dropped_splats += s.dropped_splats;
}

/// The image (and variance) of an unfinished render; EXR files record `meta` in their
/// header (the samples per pixel done and asked for: `mcrender.samplesPerPixel`,
/// `mcrender.samplesRequested`; SPPM's iterations: `mcrender.iterations`,
/// `mcrender.iterationsRequested`; MLT's mutations: `mcrender.mutations`,
/// `mcrender.mutationsRequested`).
pub fn write_partial(film: &Film, output: &Path, variance: Option<&Path>, meta: &[(&str, &str)]) -> Result<()> {
    let (w, h) = (film.width(), film.height());
    let write = |path: &Path, pixels: Vec<mcrender_core::color::Rgb>| -> Result<()> {
        let is_exr = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("exr"));
        if is_exr {
            write_exr_layers_with_metadata(path, w, h, &[("", &pixels)], meta)
        } else {
            write_image(
                path,
                &ImageRgb {
                    width: w,
                    height: h,
                    pixels,
                },
            )
        }
        .with_context(|| format!("cannot write \"{}\"", path.display()))
    };
    write(output, film.mean_image())?;
    if let Some(v) = variance {
        write(v, film.variance_image())?;
    }
    Ok(())
}
