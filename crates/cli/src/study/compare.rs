//! `mcrender compare`: the efficiency report (computed by `mcrender_core::lab::compare`). Each technique renders the same scene with
//! the same samples per pixel; the table gives its mean radiance, average per-pixel
//! variance (from the samples' own second moments), relative MSE against a reference when
//! one is given, render time, efficiency `1 / (variance x time)` and efficiency relative to
//! the best. A contact sheet and a log-log convergence plot are written beside.

use std::path::PathBuf;

use anyhow::{bail, Result};
use clap::Args;
use mcrender_core::lab::{compare_techniques, CompareRow};
use mcrender_core::scene::{DirectStrategy, SamplerKind};

use super::{film_image, load_reference, write_into};
use crate::lab::plot::convergence_plot;
use crate::lab::sheet::contact_sheet;
use crate::scene_args::{parse_strategy, SceneArgs};

/// Options of `mcrender compare`.
#[derive(Args, Debug)]
pub struct CompareArgs {
    /// The scene and overrides (--spp sets the samples per pixel of every technique).
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Techniques to compare, comma-separated.
    #[arg(long, value_delimiter = ',', value_parser = parse_strategy,
          default_value = "uniform-hemisphere,cosine-hemisphere,light-area,bsdf,mis")]
    pub techniques: Vec<DirectStrategy>,
    /// Converged reference image (EXR, same resolution) for the relative MSE column and the
    /// convergence plot; without one, the plot shows the estimated variance.
    #[arg(long)]
    pub reference: Option<PathBuf>,
    /// Print the table as JSON on stdout.
    #[arg(long)]
    pub json: bool,
    /// Directory for the images, the contact sheet and the convergence plot.
    #[arg(short, long, default_value = "compare")]
    pub out_dir: PathBuf,
}

/// Run the command.
pub fn run(args: &CompareArgs) -> Result<()> {
    if args.techniques.is_empty() {
        bail!("--techniques: expected at least one technique");
    }
    let (loaded, stem) = args.scene.load()?;
    let mut base = loaded.description;
    args.scene.apply(&mut base)?;
    let reference = match &args.reference {
        Some(p) => Some(load_reference(p, base.film.width, base.film.height)?),
        None => None,
    };
    let spp = base.sampler.samples_per_pixel;
    if base.sampler.kind != SamplerKind::Independent {
        eprintln!(
            "mcrender: compare: warning: the variance column is estimated from the spread of each pixel's samples, \
             which measures the error only for independent samples; this scene's sampler ({:?}) correlates them, \
             so the column overstates the error (pass --reference for the measured error, or use Sampler \"independent\")",
            base.sampler.kind
        );
    }

    let rows = compare_techniques(&base, &args.techniques, reference.as_deref(), args.scene.threads, |t| {
        eprintln!("mcrender: compare: rendering {} at {spp} spp", t.name());
    })?;
    let mut images = Vec::new();
    let mut series = Vec::new();
    for r in &rows {
        let name = r.technique.name();
        let img = film_image(&r.progression.film);
        write_into(&args.out_dir, &format!("{stem}-{name}.exr"), &img)?;
        images.push((name.to_string(), img));
        series.push((
            name.to_string(),
            r.progression.points.iter().map(|&(n, e)| (f64::from(n), e)).collect(),
        ));
    }

    let columns = images.len().min(3);
    let sheet = contact_sheet(&images, columns)?;
    let sheet_path = write_into(&args.out_dir, "contact-sheet.png", &sheet)?;
    let plot_path = args.out_dir.join("convergence.png");
    let y_label = if reference.is_some() {
        "relative MSE vs reference"
    } else {
        "mean per-pixel variance"
    };
    convergence_plot(
        &plot_path,
        &format!("{stem}: error against samples per pixel"),
        y_label,
        &series,
    )?;

    if args.json {
        let table: Vec<_> = rows
            .iter()
            .map(|r| {
                serde_json::json!({
                    "technique": r.technique.name(),
                    "spp": r.spp,
                    "mean_radiance": r.stats.mean.to_array(),
                    "mean_luminance": r.stats.mean.luminance(),
                    "variance": r.stats.mean_variance,
                    "rel_mse": r.stats.rel_mse,
                    "time_s": r.seconds,
                    "rays": r.rays,
                    "efficiency": r.efficiency,
                    "relative_efficiency": r.relative_efficiency,
                })
            })
            .collect();
        println!(
            "{}",
            serde_json::to_string_pretty(&serde_json::json!({ "scene": stem, "techniques": table }))?
        );
    } else {
        print_table(&rows, spp, reference.is_some());
    }
    eprintln!(
        "mcrender: compare: wrote {} and {}",
        sheet_path.display(),
        plot_path.display()
    );
    Ok(())
}

fn print_table(rows: &[CompareRow], spp: u32, with_reference: bool) {
    println!(
        "{:<20}{:>6}{:>12}{:>14}{:>14}{:>10}{:>14}{:>10}",
        "technique",
        "spp",
        "mean L",
        "variance",
        if with_reference { "rel. MSE" } else { "rel. MSE (-)" },
        "time (s)",
        "efficiency",
        "relative"
    );
    for r in rows {
        println!(
            "{:<20}{:>6}{:>12.5}{:>14.4e}{:>14}{:>10.3}{:>14.4e}{:>10.3}",
            r.technique.name(),
            spp,
            r.stats.mean.luminance(),
            r.stats.mean_variance,
            r.stats.rel_mse.map_or("-".to_string(), |e| format!("{e:.4e}")),
            r.seconds,
            r.efficiency,
            r.relative_efficiency
        );
    }
    println!("variance: average over pixels of the variance of the pixel's luminance estimate; efficiency = 1 / (variance x time)");
}
