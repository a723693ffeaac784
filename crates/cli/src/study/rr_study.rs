//! `mcrender rr-study`: Russian roulette settings side by side (the lecture's table): time,
//! mean radiance with its standard error, and error against a reference for each, showing
//! the time saved and that the mean does not move.

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

use anyhow::{bail, Result};
use clap::Args;
use mcrender_core::film::FilmStatistics;
use mcrender_core::scene::RussianRoulette;

use super::{load_reference, render_in_waves};
use crate::scene_args::SceneArgs;
use crate::stdout::say;

/// Options of `mcrender rr-study`.
#[derive(Args, Debug)]
pub struct RrStudyArgs {
    /// The scene and overrides.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Settings, comma-separated: "off", "throughput" (pbrt's rule) or THRESHOLD:PROBABILITY
    /// (stop with PROBABILITY when the throughput's luminance is below THRESHOLD).
    #[arg(long, value_delimiter = ',', value_parser = parse_setting,
          default_value = "off,0.25:0.5,0.5:0.5,0.125:0.9,1:0.9")]
    pub settings: Vec<RussianRoulette>,
    /// Converged reference (EXR, same resolution); without one, a reference is rendered with
    /// Russian roulette off at --reference-spp.
    #[arg(long)]
    pub reference: Option<PathBuf>,
    /// Samples per pixel of the reference rendered when --reference is not given (default: 4x --spp).
    #[arg(long)]
    pub reference_spp: Option<u32>,
}

/// Parse one setting.
pub fn parse_setting(s: &str) -> Result<RussianRoulette, String> {
    match s {
        "off" => Ok(RussianRoulette::Off),
        "throughput" => Ok(RussianRoulette::Throughput),
        "mitsuba" => Ok(RussianRoulette::Delayed { start_depth: 5 }),
        _ => {
            let err =
                || format!("expected off, throughput, mitsuba or THRESHOLD:PROBABILITY (e.g. 0.25:0.5), found \"{s}\"");
            let (t, q) = s.split_once(':').ok_or_else(err)?;
            let (threshold, probability): (f32, f32) = (t.parse().map_err(|_| err())?, q.parse().map_err(|_| err())?);
            if !(threshold.is_finite() && threshold >= 0.0 && (0.0..1.0).contains(&probability)) {
                return Err(format!(
                    "\"{s}\": expected a threshold >= 0 and a probability in [0, 1)"
                ));
            }
            Ok(RussianRoulette::Threshold { threshold, probability })
        }
    }
}

fn describe(rr: RussianRoulette) -> String {
    match rr {
        RussianRoulette::Off => "no RR".into(),
        RussianRoulette::Throughput => "pbrt (throughput)".into(),
        RussianRoulette::Delayed { start_depth } => format!("mitsuba (from bounce {start_depth})"),
        RussianRoulette::Threshold { threshold, probability } => {
            format!("{:.0}% below {threshold}", probability * 100.0)
        }
    }
}

/// Run the command.
pub fn run(args: &RrStudyArgs) -> Result<()> {
    if args.settings.is_empty() {
        bail!("--settings: expected at least one setting");
    }
    let (loaded, _) = args.scene.load()?;
    let mut base = loaded.description;
    args.scene.apply(&mut base)?;
    let (w, h, spp) = (base.film.width, base.film.height, base.sampler.samples_per_pixel);
    let reference = match &args.reference {
        Some(p) => load_reference(p, w, h)?,
        None => {
            let mut r = base.clone();
            r.integrator.russian_roulette = RussianRoulette::Off;
            r.sampler.samples_per_pixel = args.reference_spp.unwrap_or(4 * spp);
            r.sampler.seed = r.sampler.seed.wrapping_add(0x5eed);
            eprintln!(
                "mcrender: rr-study: rendering a reference without roulette at {} spp",
                r.sampler.samples_per_pixel
            );
            render_in_waves(&r, args.scene.threads, &AtomicBool::new(false), |_| 0.0)?
                .film
                .mean_image()
        }
    };
    let ref_mean = reference.iter().map(|c| f64::from(c.luminance())).sum::<f64>() / reference.len().max(1) as f64;

    say!(
        "{:<20}{:>10}{:>10}{:>12}{:>12}{:>14}{:>12}",
        "setting",
        "time (s)",
        "speed-up",
        "mean L",
        "+- (1 se)",
        "rel. MSE",
        "rays"
    );
    let mut base_time = None;
    for &rr in &args.settings {
        let mut desc = base.clone();
        desc.integrator.russian_roulette = rr;
        let prog = render_in_waves(&desc, args.scene.threads, &AtomicBool::new(false), |_| 0.0)?;
        let stats = FilmStatistics::measure(&prog.film, Some(&reference));
        let n = f64::from(w * h);
        let se = (prog
            .film
            .variance_image()
            .iter()
            .map(|v| f64::from(v.luminance()))
            .sum::<f64>()
            / (n * n))
            .sqrt();
        let t = prog.time.as_secs_f64();
        let t0 = *base_time.get_or_insert(t);
        say!(
            "{:<20}{:>10.3}{:>10.2}{:>12.5}{:>12.5}{:>14.4e}{:>12}",
            describe(rr),
            t,
            t0 / t,
            stats.mean.luminance(),
            se,
            stats.rel_mse.unwrap_or(f64::NAN),
            prog.rays
        );
    }
    say!("reference mean L {ref_mean:.5}; speed-up relative to the first row; {spp} spp, {w}x{h}");
    Ok(())
}
