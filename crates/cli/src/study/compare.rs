//! `mcrender compare`: the efficiency reports (computed by `mcrender_core::lab`).
//!
//! With `--techniques` (the default), each direct-lighting technique renders the same scene
//! with the same samples per pixel; the table gives its mean radiance, average per-pixel
//! variance (from the samples' own second moments), relative MSE against a reference when
//! one is given, render time, efficiency `1 / (variance x time)` and efficiency relative to
//! the best. With `--integrators`, each integrator renders at equal time (`--time-budget`)
//! or equal samples, and efficiency is `1 / (relMSE x time)` against the reference (or,
//! without one, a long render of the first integrator). Both write the same table, JSON,
//! images, contact sheet and log-log convergence plot.

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::time::Duration;

use anyhow::{bail, Result};
use clap::Args;
use mcrender_core::lab::{
    compare_integrators, compare_techniques, integrator_name, parse_integrator, Budget, ReferenceSource,
    REFERENCE_FACTOR,
};
use mcrender_core::scene::{DirectStrategy, IntegratorKind, SamplerKind, SceneDescription};
use mcrender_formats::image_io::ImageRgb;

use super::{film_image, load_reference, write_into};
use crate::lab::plot::{convergence_plot, log_log_plot};
use crate::lab::sheet::contact_sheet;
use crate::scene_args::{parse_strategy, SceneArgs};
use crate::stdout::say;

/// Options of `mcrender compare`.
#[derive(Args, Debug)]
pub struct CompareArgs {
    /// The scene and overrides (--spp sets the samples per pixel of every technique, or
    /// of every integrator without --time-budget: SPPM then runs that many iterations).
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Techniques to compare, comma-separated.
    #[arg(long, value_delimiter = ',', value_parser = parse_strategy,
          default_value = "uniform-hemisphere,cosine-hemisphere,light-area,bsdf,mis")]
    pub techniques: Vec<DirectStrategy>,
    /// Compare integrators instead, comma-separated: path, direct, bdpt, lightpath, sppm, mlt.
    #[arg(long, value_delimiter = ',', value_parser = parse_integrator, conflicts_with = "techniques")]
    pub integrators: Option<Vec<IntegratorKind>>,
    /// With --integrators: give each integrator this many seconds of rendering (equal
    /// time) instead of equal samples.
    #[arg(long, requires = "integrators")]
    pub time_budget: Option<f64>,
    /// Converged reference image (EXR, same resolution) for the relative MSE column and the
    /// convergence plot; without one, techniques plot the estimated variance and
    /// integrators are measured against a long render of the first one.
    #[arg(long)]
    pub reference: Option<PathBuf>,
    /// Print the table as JSON on stdout.
    #[arg(long)]
    pub json: bool,
    /// Directory for the images, the contact sheet and the convergence plot.
    #[arg(short, long, default_value = "compare")]
    pub out_dir: PathBuf,
}

/// One row of either report, as the table, JSON, sheet and plot show it.
struct Row {
    name: &'static str,
    samples: u32,
    sample_unit: &'static str,
    mean: [f32; 3],
    mean_luminance: f32,
    /// `None` when the estimator keeps no per-pixel variance (SPPM).
    variance: Option<f64>,
    rel_mse: Option<f64>,
    seconds: f64,
    rays: u64,
    efficiency: f64,
    relative_efficiency: f64,
    image: ImageRgb,
    /// Convergence points (x, error).
    points: Vec<(f64, f64)>,
}

/// What differs between the two reports.
struct Report {
    /// Name of the first column and of the JSON array.
    kind: &'static str,
    rows: Vec<Row>,
    with_reference: bool,
    /// Extra top-level JSON fields.
    json_extra: serde_json::Map<String, serde_json::Value>,
    /// The plot's x axis when not samples per pixel.
    x_label: Option<&'static str>,
    y_label: &'static str,
    title: String,
    footnote: String,
}

/// Run the command.
pub fn run(args: &CompareArgs) -> Result<()> {
    let (loaded, stem) = args.scene.load()?;
    let mut base = loaded.description;
    args.scene.apply(&mut base)?;
    let reference = match &args.reference {
        Some(p) => Some(load_reference(p, base.film.width, base.film.height)?),
        None => None,
    };
    let report = match &args.integrators {
        Some(kinds) => integrator_report(args, &base, kinds, reference.as_deref(), &stem)?,
        None => technique_report(args, &base, reference.as_deref(), &stem)?,
    };
    write_report(args, &stem, &report)
}

fn technique_report(
    args: &CompareArgs,
    base: &SceneDescription,
    reference: Option<&[mcrender_core::color::Rgb]>,
    stem: &str,
) -> Result<Report> {
    if args.techniques.is_empty() {
        bail!("--techniques: expected at least one technique");
    }
    let spp = base.sampler.samples_per_pixel;
    if base.sampler.kind != SamplerKind::Independent {
        eprintln!(
            "mcrender: compare: warning: the variance column is estimated from the spread of each pixel's samples, \
             which measures the error only for independent samples; this scene's sampler ({:?}) correlates them, \
             so the column overstates the error (pass --reference for the measured error, or use Sampler \"independent\")",
            base.sampler.kind
        );
    }
    let rows = compare_techniques(
        base,
        &args.techniques,
        reference,
        args.scene.threads,
        &AtomicBool::new(false),
        |t| {
            eprintln!("mcrender: compare: rendering {} at {spp} spp", t.name());
        },
    )?;
    let rows = rows
        .iter()
        .map(|r| Row {
            name: r.technique.name(),
            samples: spp,
            sample_unit: "spp",
            mean: r.stats.mean.to_array(),
            mean_luminance: r.stats.mean.luminance(),
            variance: Some(r.stats.mean_variance),
            rel_mse: r.stats.rel_mse,
            seconds: r.seconds,
            rays: r.rays,
            efficiency: r.efficiency,
            relative_efficiency: r.relative_efficiency,
            image: film_image(&r.progression.film),
            points: r.progression.points.iter().map(|&(n, e)| (f64::from(n), e)).collect(),
        })
        .collect();
    Ok(Report {
        kind: "technique",
        rows,
        with_reference: reference.is_some(),
        json_extra: serde_json::Map::new(),
        x_label: None,
        y_label: if reference.is_some() {
            "relative MSE vs reference"
        } else {
            "mean per-pixel variance"
        },
        title: format!("{stem}: error against samples per pixel"),
        footnote: "variance: average over pixels of the variance of the pixel's luminance estimate; \
                   efficiency = 1 / (variance x time)"
            .into(),
    })
}

fn integrator_report(
    args: &CompareArgs,
    base: &SceneDescription,
    kinds: &[IntegratorKind],
    reference: Option<&[mcrender_core::color::Rgb]>,
    stem: &str,
) -> Result<Report> {
    if kinds.is_empty() {
        bail!("--integrators: expected at least one integrator");
    }
    let budget = match args.time_budget {
        Some(s) if !(s.is_finite() && s > 0.0) => {
            bail!("--time-budget: expected a positive number of seconds, found {s}")
        }
        Some(s) => Budget::Time(Duration::from_secs_f64(s)),
        None => Budget::Samples(base.sampler.samples_per_pixel),
    };
    let budget_text = match budget {
        Budget::Time(t) => format!("{} s each", t.as_secs_f64()),
        Budget::Samples(n) => format!("{n} spp (SPPM: iterations) each"),
    };
    let report = compare_integrators(
        base,
        kinds,
        reference,
        args.scene.threads,
        budget,
        &AtomicBool::new(false),
        |k, long| {
            if long {
                eprintln!(
                    "mcrender: compare: rendering the reference with {} ({REFERENCE_FACTOR}x the budget, another seed)",
                    integrator_name(k)
                );
            } else {
                eprintln!("mcrender: compare: rendering {} ({budget_text})", integrator_name(k));
            }
        },
    )?;
    let reference_text = match (&report.reference, &args.reference) {
        (ReferenceSource::Given, Some(p)) => p.display().to_string(),
        (ReferenceSource::LongRender(k), _) => format!(
            "long render of {} ({REFERENCE_FACTOR}x the budget, another seed)",
            integrator_name(*k)
        ),
        (ReferenceSource::Given, None) => "given".into(),
    };
    let rows = report
        .rows
        .iter()
        .map(|r| Row {
            name: integrator_name(r.kind),
            samples: r.samples,
            sample_unit: r.sample_unit,
            mean: r.stats.mean.to_array(),
            mean_luminance: r.stats.mean.luminance(),
            // SPPM keeps no per-pixel variance, and light tracing and MLT only splat (whose
            // variance the film does not track): no column for them.
            variance: (!matches!(
                r.kind,
                IntegratorKind::Sppm | IntegratorKind::LightPath | IntegratorKind::Mlt
            ))
            .then_some(r.stats.mean_variance),
            rel_mse: r.stats.rel_mse,
            seconds: r.seconds,
            rays: r.rays,
            efficiency: r.efficiency,
            relative_efficiency: r.relative_efficiency,
            image: film_image(&r.film),
            points: r.points.clone(),
        })
        .collect();
    let mut json_extra = serde_json::Map::new();
    json_extra.insert("reference".into(), reference_text.clone().into());
    json_extra.insert(
        "budget".into(),
        match budget {
            Budget::Time(t) => serde_json::json!({ "time_s": t.as_secs_f64() }),
            Budget::Samples(n) => serde_json::json!({ "samples": n }),
        },
    );
    Ok(Report {
        kind: "integrator",
        rows,
        with_reference: true,
        json_extra,
        x_label: Some("render time (s)"),
        y_label: "relative MSE vs reference",
        title: format!("{stem}: error against render time"),
        footnote: format!(
            "budget: {budget_text}; rel. MSE against {reference_text}; efficiency = 1 / (rel. MSE x time); \
             variance: of the pixels' own samples (splats not counted)"
        ),
    })
}

/// Images, contact sheet, convergence plot, and the table (or JSON) on stdout.
fn write_report(args: &CompareArgs, stem: &str, report: &Report) -> Result<()> {
    let mut images = Vec::new();
    let mut series = Vec::new();
    for r in &report.rows {
        write_into(&args.out_dir, &format!("{stem}-{}.exr", r.name), &r.image)?;
        images.push((r.name.to_string(), r.image.clone()));
        series.push((r.name.to_string(), r.points.clone()));
    }
    let columns = images.len().min(3);
    let sheet = contact_sheet(&images, columns)?;
    let sheet_path = write_into(&args.out_dir, "contact-sheet.png", &sheet)?;
    let plot_path = args.out_dir.join("convergence.png");
    match report.x_label {
        Some(x) => log_log_plot(&plot_path, &report.title, x, report.y_label, &series)?,
        None => convergence_plot(&plot_path, &report.title, report.y_label, &series)?,
    };

    if args.json {
        let table: Vec<_> = report
            .rows
            .iter()
            .map(|r| {
                let mut o = serde_json::json!({
                    report.kind: r.name,
                    "spp": r.samples,
                    "mean_radiance": r.mean,
                    "mean_luminance": r.mean_luminance,
                    "variance": r.variance,
                    "rel_mse": r.rel_mse,
                    "time_s": r.seconds,
                    "rays": r.rays,
                    "efficiency": r.efficiency,
                    "relative_efficiency": r.relative_efficiency,
                });
                if report.kind == "integrator" {
                    // Not all integrators count samples per pixel (SPPM: iterations).
                    o.as_object_mut().map(|m| m.remove("spp"));
                    o["samples"] = r.samples.into();
                    o["sample_unit"] = r.sample_unit.into();
                }
                o
            })
            .collect();
        let mut top = serde_json::Map::new();
        top.insert("scene".into(), stem.into());
        top.extend(report.json_extra.clone());
        top.insert(format!("{}s", report.kind), table.into());
        say!("{}", serde_json::to_string_pretty(&serde_json::Value::Object(top))?);
    } else {
        print_table(report)?;
    }
    eprintln!(
        "mcrender: compare: wrote {} and {}",
        sheet_path.display(),
        plot_path.display()
    );
    Ok(())
}

fn print_table(report: &Report) -> Result<()> {
    let dash = || "-".to_string();
    say!(
        "{:<20}{:>14}{:>12}{:>14}{:>14}{:>10}{:>14}{:>10}",
        report.kind,
        "samples",
        "mean L",
        "variance",
        if report.with_reference {
            "rel. MSE"
        } else {
            "rel. MSE (-)"
        },
        "time (s)",
        "efficiency",
        "relative"
    );
    for r in &report.rows {
        say!(
            "{:<20}{:>14}{:>12.5}{:>14}{:>14}{:>10.3}{:>14.4e}{:>10.3}",
            r.name,
            format!(
                "{} {}",
                r.samples,
                match r.sample_unit {
                    "iterations" => "it",
                    "mutations/pixel" => "mpp",
                    unit => unit,
                }
            ),
            r.mean_luminance,
            r.variance.map_or_else(dash, |v| format!("{v:.4e}")),
            r.rel_mse.map_or_else(dash, |e| format!("{e:.4e}")),
            r.seconds,
            r.efficiency,
            r.relative_efficiency
        );
    }
    say!("{}", report.footnote);
    Ok(())
}
