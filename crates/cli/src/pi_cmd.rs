//! `mcrender pi`: the coconut. Estimate pi from N random points in the unit square for
//! each N given, and with `--trials K` measure the variance of the estimate over K
//! independent trials: variance x N stays about pi (4 - pi) ~= 2.697 for every N, the 1/N
//! law of Monte Carlo error.

use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use anyhow::Result;
use clap::Args;
use mcrender_core::lab::{estimate_pi, pi_trials, PiStats, EXACT_VARIANCE_TIMES_N};

use crate::lab::plot::{check_plot_path, log_log_plot, Series};
use crate::stdout::say;

/// The lecture's sample counts: 1, 10, ..., 10^6.
const DEFAULT_SAMPLES: &str = "1,10,100,1000,10000,100000,1000000";

/// Options of `mcrender pi`.
#[derive(Args, Debug)]
pub struct PiArgs {
    /// Numbers of random points, comma-separated; one table row each.
    #[arg(long, value_name = "N,...", value_delimiter = ',', value_parser = parse_samples,
          default_value = DEFAULT_SAMPLES)]
    pub samples: Vec<u64>,
    /// Random seed; the same seed prints the same table.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Independent trials per N (at least 2): adds the mean over trials, the measured
    /// variance of one estimate and variance x N.
    #[arg(long, value_name = "K", value_parser = parse_trials)]
    pub trials: Option<u64>,
    /// Print the table as JSON instead.
    #[arg(long)]
    pub json: bool,
    /// Also write a log-log plot (PNG) of the squared error of one estimate and, with
    /// `--trials`, the measured variance against N, beside the 1/N line.
    #[arg(long, value_name = "FILE.png")]
    pub plot: Option<PathBuf>,
}

fn parse_samples(s: &str) -> Result<u64, String> {
    match s.trim().parse::<u64>() {
        Ok(0) => Err("the number of points must be at least 1".into()),
        Ok(n) => Ok(n),
        Err(_) => Err(format!("expected a positive whole number of points, found \"{s}\"")),
    }
}

fn parse_trials(s: &str) -> Result<u64, String> {
    match s.trim().parse::<u64>() {
        Ok(k) if k >= 2 => Ok(k),
        Ok(_) => Err("at least 2 trials are needed to measure a variance".into()),
        Err(_) => Err(format!("expected a whole number of trials (at least 2), found \"{s}\"")),
    }
}

/// One row of the table.
struct Row {
    samples: u64,
    /// The estimate of trial 0.
    estimate: f64,
    /// Present with `--trials`.
    stats: Option<PiStats>,
}

/// Run the command.
pub fn run(args: &PiArgs) -> Result<()> {
    if let Some(path) = &args.plot {
        check_plot_path(path)?;
    }
    let rows: Vec<Row> = args
        .samples
        .iter()
        .map(|&n| Row {
            samples: n,
            estimate: estimate_pi(n, args.seed, 0),
            stats: args.trials.map(|k| pi_trials(n, args.seed, k)),
        })
        .collect();
    if args.json {
        say!("{}", serde_json::to_string_pretty(&to_json(args, &rows))?);
    } else {
        crate::stdout::write(&table(args, &rows))?;
    }
    if let Some(path) = &args.plot {
        write_plot(path, args, &rows)?;
    }
    Ok(())
}

/// Plot the measured variance (with trials) and the squared error of trial 0 against N.
/// A zero value (all trials agreeing, possible for tiny N) has no place on a log axis and
/// is left out with a note.
fn write_plot(path: &Path, args: &PiArgs, rows: &[Row]) -> Result<()> {
    let mut series: Vec<Series> = Vec::new();
    let mut left_out = Vec::new();
    let mut points = |name: &str, value: &dyn Fn(&Row) -> Option<f64>| {
        let pts: Vec<(f64, f64)> = rows
            .iter()
            .filter_map(|r| {
                let v = value(r)?;
                if v > 0.0 {
                    Some((r.samples as f64, v))
                } else {
                    left_out.push(format!("{name} at N = {}", r.samples));
                    None
                }
            })
            .collect();
        if !pts.is_empty() {
            series.push((name.to_string(), pts));
        }
    };
    if let Some(k) = args.trials {
        points(&format!("variance over {k} trials"), &|r: &Row| {
            r.stats.map(|s| s.variance)
        });
    }
    points("squared error of one estimate", &|r: &Row| {
        Some((r.estimate - PI).powi(2))
    });
    for what in &left_out {
        eprintln!("mcrender: the plot leaves out the {what}: zero cannot be shown on a log axis");
    }
    log_log_plot(
        path,
        "Estimating pi: the error falls as 1/N",
        "random points N",
        "variance, squared error",
        &series,
    )?;
    eprintln!("{}: plot written", path.display());
    Ok(())
}

fn table(args: &PiArgs, rows: &[Row]) -> String {
    let mut out = String::new();
    let mut line = |s: String| {
        out.push_str(s.trim_end());
        out.push('\n');
    };
    match args.trials {
        None => line(format!("{:>10}  {:>14}  {:>10}", "N", "estimate of pi", "|error|")),
        Some(k) => line(format!(
            "{:>10}  {:>14}  {:>10}  {:>14}  {:>12}  {:>12}",
            "N",
            "estimate of pi",
            "|error|",
            format!("mean of {k}"),
            "variance",
            "variance x N"
        )),
    }
    for r in rows {
        let head = format!(
            "{:>10}  {:>14.6}  {:>10.6}",
            r.samples,
            r.estimate,
            (r.estimate - PI).abs()
        );
        match &r.stats {
            None => line(head),
            Some(s) => line(format!(
                "{head}  {:>14.6}  {:>12}  {:>12.4}",
                s.mean,
                scientific(s.variance),
                s.variance_times_n
            )),
        }
    }
    if let Some(k) = args.trials {
        line(format!(
            "variance over {k} trials; theory: variance x N = pi (4 - pi) = {EXACT_VARIANCE_TIMES_N:.4} for every N \
             (the variance falls as 1/N)"
        ));
    }
    out
}

/// `v` as `1.234e-05`: four significant digits, a signed two-digit exponent.
fn scientific(v: f64) -> String {
    let s = format!("{v:.3e}");
    match s.split_once('e').map(|(m, e)| (m, e.parse::<i32>())) {
        Some((mantissa, Ok(exp))) => format!("{mantissa}e{exp:+03}"),
        _ => s,
    }
}

fn to_json(args: &PiArgs, rows: &[Row]) -> serde_json::Value {
    let rows: Vec<serde_json::Value> = rows
        .iter()
        .map(|r| {
            let mut v = serde_json::json!({
                "samples": r.samples,
                "estimate": r.estimate,
                "abs_error": (r.estimate - PI).abs(),
            });
            if let Some(s) = &r.stats {
                v["mean"] = s.mean.into();
                v["variance"] = s.variance.into();
                v["variance_times_n"] = s.variance_times_n.into();
            }
            v
        })
        .collect();
    serde_json::json!({
        "seed": args.seed,
        "trials": args.trials,
        "exact_variance_times_n": EXACT_VARIANCE_TIMES_N,
        "rows": rows,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scientific_has_a_signed_two_digit_exponent() {
        assert_eq!(scientific(2.69681), "2.697e+00");
        assert_eq!(scientific(0.000_030_894), "3.089e-05");
        assert_eq!(scientific(1.5e120), "1.500e+120");
        assert_eq!(scientific(f64::NAN), "NaN");
    }

    #[test]
    fn sample_and_trial_parsers_reject_what_cannot_be_measured() {
        assert_eq!(parse_samples("1000"), Ok(1000));
        assert!(parse_samples("0").unwrap_err().contains("at least 1"));
        assert!(parse_samples("-3").unwrap_err().contains("positive whole number"));
        assert_eq!(parse_trials("2"), Ok(2));
        assert!(parse_trials("1").unwrap_err().contains("at least 2"));
        assert!(parse_trials("x").is_err());
    }
}
