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

use anyhow::{Context, Result};
use mcrender_core::render::{RenderError, RenderOptions, RenderOutput, RenderSession, RenderStats, Watch};
use mcrender_core::scene::{Scene, SceneDescription};
use mcrender_scene::image_io::{write_exr_layers_with_metadata, write_image, ImageRgb};

use crate::checkpoint::{self, Invocation, Resume};
use crate::interrupt;
use crate::render_cmd::{progress_bar, RenderArgs};

/// Longest wave: bounds the work a signal discards (the unfinished wave is dropped).
pub const MAX_WAVE: Duration = Duration::from_secs(5);

/// Default time between checkpoints.
pub const DEFAULT_EVERY: Duration = Duration::from_secs(60);

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
    let explicit = args.checkpointing.checkpoint.clone();
    let fallback = {
        let mut name = output.as_os_str().to_owned();
        name.push(".ckpt");
        PathBuf::from(name)
    };
    let ck_path = explicit.clone().unwrap_or_else(|| fallback.clone());
    let mut outputs: Vec<&Path> = vec![output, &ck_path];
    outputs.extend(args.variance_output.as_deref());
    let fingerprint = checkpoint::fingerprint(args.scene.scene.as_deref(), desc, &outputs)?;
    let (invocation, film) = match resume {
        Some(r) => {
            checkpoint::check_fingerprint(&ck_path, &r.checkpoint, &fingerprint, desc)?;
            (r.invocation, Some(r.checkpoint.film))
        }
        // Re-running the command of a render that was stopped continues it; a checkpoint
        // of another render is never overwritten.
        None => {
            match explicit.as_deref().filter(|p| p.exists()) {
                Some(path) => {
                    let ck = checkpoint::read(path).with_context(|| {
                    format!("--checkpoint \"{}\" exists and is not a usable checkpoint; remove it or choose another file", path.display())
                })?;
                    checkpoint::check_fingerprint(path, &ck, &fingerprint, desc).with_context(|| {
                        format!(
                            "--checkpoint \"{}\" belongs to another render; remove it or choose another file",
                            path.display()
                        )
                    })?;
                    eprintln!(
                        "mcrender: continuing the render in checkpoint \"{}\" ({} of {spp} samples per pixel done)",
                        path.display(),
                        ck.film.samples_per_pixel()
                    );
                    (Invocation::current()?, Some(ck.film))
                }
                None => (Invocation::current()?, None),
            }
        }
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
        let until_checkpoint = explicit
            .as_ref()
            .map(|_| every.saturating_sub(last_checkpoint.elapsed()));
        let target = until_checkpoint.map_or(MAX_WAVE, |t| t.min(MAX_WAVE)).as_secs_f64();
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
                checkpoint::write(path, &fingerprint, &invocation, spp, session.film())?;
                last_checkpoint = Instant::now();
            }
        }
    }
    bar.finish_and_clear();
    let film = session.into_film();
    let out = RenderOutput { film, stats: total };
    if done < spp {
        if let Some(by) = signals.received() {
            write_partial(&out, output, args.variance_output.as_deref(), spp)?;
            checkpoint::write(&ck_path, &fingerprint, &invocation, spp, &out.film)?;
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
    // Finished: the checkpoint has served its purpose.
    if explicit.is_some() {
        match std::fs::remove_file(&ck_path) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                eprintln!(
                    "mcrender: warning: cannot remove checkpoint \"{}\": {e}",
                    ck_path.display()
                );
            }
            _ => {}
        }
    }
    Ok(out)
}

fn add_stats(total: &mut RenderStats, s: &RenderStats) {
    total.elapsed += s.elapsed;
    total.paths += s.paths;
    total.trace += s.trace;
    total.nonfinite_samples += s.nonfinite_samples;
    total.dropped_splats += s.dropped_splats;
}

/// The image (and variance) of an unfinished render; EXR files record the samples per
/// pixel done and asked for in their header (`mcrender.samplesPerPixel`,
/// `mcrender.samplesRequested`).
fn write_partial(out: &RenderOutput, output: &Path, variance: Option<&Path>, spp: u32) -> Result<()> {
    let (w, h) = (out.film.width(), out.film.height());
    let done = out.film.samples_per_pixel().to_string();
    let requested = spp.to_string();
    let meta = [
        ("mcrender.samplesPerPixel", done.as_str()),
        ("mcrender.samplesRequested", requested.as_str()),
    ];
    let write = |path: &Path, pixels: Vec<mcrender_core::color::Rgb>| -> Result<()> {
        let is_exr = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("exr"));
        if is_exr {
            write_exr_layers_with_metadata(path, w, h, &[("", &pixels)], &meta)
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
    write(output, out.film.mean_image())?;
    if let Some(v) = variance {
        write(v, out.film.variance_image())?;
    }
    Ok(())
}
