//! `mcrender pi`: the coconut. Estimate pi from N random points in the unit square for
//! each N given, and with `--trials K` measure the variance of the estimate over K
//! independent trials: variance x N stays about pi (4 - pi) ~= 2.697 for every N, the 1/N
//! law of Monte Carlo error.

use std::f64::consts::PI;

use anyhow::Result;
use clap::Args;
use mcrender_core::lab::{estimate_pi, pi_trials, PiStats, EXACT_VARIANCE_TIMES_N};

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
        println!("{}", serde_json::to_string_pretty(&to_json(args, &rows))?);
    } else {
        print!("{}", table(args, &rows));
    }
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
