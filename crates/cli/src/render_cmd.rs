//! `mcrender render`: load, apply command-line overrides, render with a progress bar,
//! write the image (and optionally the per-pixel variance) atomically.

use std::path::{Path, PathBuf};
use std::time::Duration;

use anyhow::{bail, Context, Result};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use mcrender_core::render::{RenderOptions, RenderOutput};
use mcrender_core::scene::{IntegratorKind, Scene};
use mcrender_formats::image_io::{write_images, ImageRgb};

use crate::builtin;
use crate::mlt_render::MltRender;
use crate::preflight;
use crate::scene_args::SceneArgs;
use crate::sppm_render::SppmRender;

/// Options of `mcrender render`; flags override what the scene file says.
#[derive(Args, Debug, Default, Clone)]
pub struct RenderArgs {
    /// The scene and overrides.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Output image: .png (8-bit sRGB) or .exr (linear float). Default: the file's Film
    /// "filename", else the scene's name with .png.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Also write each pixel's estimated variance (of its mean) to this EXR file.
    #[arg(long)]
    pub variance_output: Option<PathBuf>,
    /// No progress bar.
    #[arg(long, short)]
    pub quiet: bool,
    /// Checkpoint and resume.
    #[command(flatten)]
    pub checkpointing: crate::checkpoint::CheckpointArgs,
}

impl RenderArgs {
    /// What `mcrender` with no arguments does: a quick render of the built-in scene.
    pub fn builtin_default() -> Self {
        Self {
            scene: SceneArgs {
                spp: Some(builtin::DEFAULT_SPP),
                resolution: Some(builtin::DEFAULT_RESOLUTION),
                ..Default::default()
            },
            output: Some(PathBuf::from(builtin::DEFAULT_OUTPUT)),
            ..Default::default()
        }
    }
}

/// Run the command.
pub fn run(args: &RenderArgs) -> Result<()> {
    let resume = crate::checkpoint::prepare_resume(args)?;
    let args = resume.as_ref().map_or(args, |r| &r.args).clone();
    let args = &args;
    preflight::check_threads(args.scene.threads)?;
    let (loaded, stem) = args.scene.load()?;
    let image_bytes = loaded.image_bytes;
    let mut desc = loaded.description;
    args.scene.apply(&mut desc)?;
    let output = args
        .output
        .clone()
        .or_else(|| loaded.output_filename.map(PathBuf::from))
        .unwrap_or_else(|| PathBuf::from(format!("{stem}.png")));
    check_extension(&output, &["png", "exr"])?;
    if let Some(v) = &args.variance_output {
        check_extension(v, &["exr"])?;
    }
    preflight::check_before_render(
        &desc,
        image_bytes,
        args.scene.memory_limit(),
        &[
            ("output", Some(&output)),
            ("--variance-output", args.variance_output.as_deref()),
            ("--checkpoint", args.checkpointing.checkpoint.as_deref()),
        ],
    )?;
    let scene = Scene::build(&desc).context("the scene cannot be rendered")?;

    if desc.integrator.kind == IntegratorKind::Sppm {
        let sppm = SppmRender::new(&scene);
        return crate::state_driver::render(sppm, args, resume, &scene, &desc, &output);
    }
    if desc.integrator.kind == IntegratorKind::Mlt {
        let mlt = MltRender::new(&scene, desc.film.width, desc.film.height);
        return crate::state_driver::render(mlt, args, resume, &scene, &desc, &output);
    }
    let (w, h, spp) = (desc.film.width, desc.film.height, desc.sampler.samples_per_pixel);
    let out = crate::progressive::render(args, resume, &scene, &desc, &output)?;

    write_outputs(&out, &output, args.variance_output.as_deref())?;
    print_summary(&out, w, h, spp, &output);
    let dir = output.parent().unwrap_or(Path::new("."));
    let opts = RenderOptions {
        threads: args.scene.threads,
        ..Default::default()
    };
    crate::bdpt_visualize::write_if_requested(&desc, &opts, dir, args.quiet)?;
    Ok(())
}

fn check_extension(path: &Path, allowed: &[&str]) -> Result<()> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    if !allowed.contains(&ext.as_str()) {
        bail!(
            "output file \"{}\": expected extension {}, found \"{ext}\"",
            path.display(),
            allowed.join(" or ")
        );
    }
    Ok(())
}

pub fn progress_bar(total: u64, quiet: bool) -> ProgressBar {
    if quiet {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(total);
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} rendering [{bar:40}] {percent:>3}%  {elapsed_precise} elapsed, ETA {eta_precise}",
        )
        .expect("valid template")
        .progress_chars("=> "),
    );
    bar.enable_steady_tick(Duration::from_millis(200));
    bar
}

/// Write the image (and the variance, if asked for): both files or neither.
pub fn write_outputs(out: &RenderOutput, output: &Path, variance: Option<&Path>) -> Result<()> {
    let (w, h) = (out.film.width(), out.film.height());
    let img = ImageRgb {
        width: w,
        height: h,
        pixels: out.film.mean_image(),
    };
    let var = variance.map(|_| ImageRgb {
        width: w,
        height: h,
        pixels: out.film.variance_image(),
    });
    // Both files or neither.
    let mut images = vec![(output, &img)];
    images.extend(variance.zip(var.as_ref()));
    write_images(&images).context("cannot write the images")?;
    Ok(())
}

fn print_summary(out: &RenderOutput, w: u32, h: u32, spp: u32, output: &Path) {
    let s = &out.stats;
    let secs = s.elapsed.as_secs_f64().max(1e-9);
    let samples = s.paths as f64;
    let rays = (s.trace.rays + s.trace.shadow_rays) as f64;
    eprintln!(
        "{}: {w}x{h}, {spp} spp in {secs:.2} s on {} thread{}: {:.2} M samples/s, {:.2} M paths/s, {:.2} M rays/s{}",
        output.display(),
        s.threads,
        if s.threads == 1 { "" } else { "s" },
        samples / secs / 1e6,
        samples / secs / 1e6,
        rays / secs / 1e6,
        if s.nonfinite_samples > 0 {
            format!(" ({} non-finite samples dropped)", s.nonfinite_samples)
        } else {
            String::new()
        },
    );
}
