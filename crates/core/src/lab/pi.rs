//! The coconut: estimate pi from uniform random points in the unit square.
//!
//! A point `(x, y)` uniform in `[0, 1)^2` lies inside the quarter disc `x^2 + y^2 < 1`
//! with probability `p = pi / 4`. With `N` points of which `M` fall inside, the estimator
//! is `4 M / N`. `M` is binomial, so the estimator is unbiased and its variance is exact:
//!
//! ```text
//! Var[4 M / N] = 16 p (1 - p) / N = pi (4 - pi) / N ~= 2.697 / N
//! ```
//!
//! Variance times `N` is a constant, [`EXACT_VARIANCE_TIMES_N`]: the standard error falls
//! as `1 / sqrt(N)`. [`pi_trials`] measures that constant by repeating the estimate over
//! independent trials.
//!
//! Every trial draws from its own PCG32 streams chosen by hashing `(seed, trial)`, so a
//! result depends on `(samples, seed, trial)` alone, never on the thread count.

use std::f64::consts::PI;

use rayon::prelude::*;

use crate::sampling::{hash_u64s, Pcg32};

/// `N` times the variance of the `N`-point estimator: `16 p (1 - p)` with `p = pi / 4`,
/// that is `pi (4 - pi) ~= 2.6968`.
pub const EXACT_VARIANCE_TIMES_N: f64 = PI * (4.0 - PI);

/// 2^-32: maps a `u32` to `[0, 1)`.
const INV_2_POW_32: f64 = 1.0 / 4_294_967_296.0;

/// The exact variance of [`estimate_pi`] with `samples` points: `pi (4 - pi) / samples`
/// (infinite for zero samples).
#[must_use]
pub fn exact_variance(samples: u64) -> f64 {
    EXACT_VARIANCE_TIMES_N / samples as f64
}

/// The generator of one coordinate (`axis` 0 for x, 1 for y) in one trial: stream and
/// start both derived from `(seed, trial, axis)`.
fn trial_rng(seed: u64, trial: u64, axis: u64) -> Pcg32 {
    Pcg32::new(hash_u64s(&[seed, trial, axis]), hash_u64s(&[axis, trial, seed]))
}

/// Estimate pi from `samples` uniform random points in the unit square: 4 times the
/// fraction inside the quarter disc. Deterministic in `(samples, seed, trial)`; distinct
/// trials are independent estimates. Zero samples give NaN (no estimate).
#[must_use]
pub fn estimate_pi(samples: u64, seed: u64, trial: u64) -> f64 {
    // Two independent streams, one per coordinate: their LCG steps run side by side
    // instead of one waiting for the other, which halves the time per point.
    let (mut rng_x, mut rng_y) = (trial_rng(seed, trial, 0), trial_rng(seed, trial, 1));
    let mut inside = 0u64;
    for _ in 0..samples {
        // Cell centres of a 2^32 x 2^32 grid: no point lies on the square's edges.
        let x = (f64::from(rng_x.next_u32()) + 0.5) * INV_2_POW_32;
        let y = (f64::from(rng_y.next_u32()) + 0.5) * INV_2_POW_32;
        inside += u64::from(x * x + y * y < 1.0);
    }
    4.0 * inside as f64 / samples as f64
}

/// The estimate of pi repeated over independent trials, and its measured spread.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PiStats {
    /// Points per estimate, `N`.
    pub samples: u64,
    /// Number of independent estimates.
    pub trials: u64,
    /// Mean of the trials' estimates.
    pub mean: f64,
    /// Unbiased sample variance of one estimate across trials (divides by `trials - 1`);
    /// NaN with fewer than two trials. Compare with [`exact_variance`].
    pub variance: f64,
    /// `variance * samples`: about [`EXACT_VARIANCE_TIMES_N`] for every `N`.
    pub variance_times_n: f64,
}

/// Run [`estimate_pi`] for trials `0..trials` in parallel (rayon) and summarise them. The
/// result is bit-identical for any thread count: each trial has its own stream and the
/// estimates are summed in trial order.
#[must_use]
pub fn pi_trials(samples: u64, seed: u64, trials: u64) -> PiStats {
    let estimates: Vec<f64> = (0..trials)
        .into_par_iter()
        .map(|trial| estimate_pi(samples, seed, trial))
        .collect();
    let k = trials as f64;
    let mean = estimates.iter().sum::<f64>() / k;
    let variance = if trials < 2 {
        f64::NAN
    } else {
        estimates.iter().map(|e| (e - mean) * (e - mean)).sum::<f64>() / (k - 1.0)
    };
    PiStats {
        samples,
        trials,
        mean,
        variance,
        variance_times_n: variance * samples as f64,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_variance_times_n_is_16_p_one_minus_p() {
        let p = PI / 4.0;
        assert!((EXACT_VARIANCE_TIMES_N - 16.0 * p * (1.0 - p)).abs() < 1e-12);
        assert!((EXACT_VARIANCE_TIMES_N - 2.6968).abs() < 1e-4);
        assert!((exact_variance(100) - EXACT_VARIANCE_TIMES_N / 100.0).abs() < 1e-15);
    }

    #[test]
    fn estimate_converges_within_four_standard_errors_at_a_million_points() {
        let n = 1_000_000;
        let bound = 4.0 * exact_variance(n).sqrt();
        for trial in 0..4 {
            let e = estimate_pi(n, 2024, trial);
            assert!(
                (e - PI).abs() < bound,
                "trial {trial}: {e} is more than {bound} from pi"
            );
        }
    }

    #[test]
    fn estimates_are_multiples_of_four_over_n_in_range() {
        for n in [1u64, 10, 100] {
            for trial in 0..50 {
                let e = estimate_pi(n, 1, trial);
                assert!((0.0..=4.0).contains(&e));
                let m = e * n as f64 / 4.0;
                assert_eq!(m, m.round(), "n = {n}: {e}");
            }
        }
        assert!(estimate_pi(0, 1, 0).is_nan());
    }

    #[test]
    fn same_inputs_give_identical_results_whatever_the_thread_count() {
        assert_eq!(estimate_pi(10_000, 5, 3), estimate_pi(10_000, 5, 3));
        assert_ne!(estimate_pi(10_000, 5, 3), estimate_pi(10_000, 5, 4));
        assert_ne!(estimate_pi(10_000, 5, 3), estimate_pi(10_000, 6, 3));
        let on = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| pi_trials(1000, 9, 64))
        };
        let one = on(1);
        assert_eq!(one, on(2));
        assert_eq!(one, on(3));
    }

    /// The law the lecture shows: variance x N is constant. 800 trials keep each measured
    /// variance within about 5% (relative standard deviation sqrt(2 / (K - 1))).
    #[test]
    fn variance_times_n_is_constant_across_n_and_matches_pi_times_4_minus_pi() {
        let trials = 800;
        let measured: Vec<(u64, f64)> = [100u64, 1000, 10_000, 100_000, 1_000_000]
            .iter()
            .map(|&n| (n, pi_trials(n, 77, trials).variance_times_n))
            .collect();
        for &(n, vn) in &measured {
            let rel = (vn - EXACT_VARIANCE_TIMES_N).abs() / EXACT_VARIANCE_TIMES_N;
            assert!(
                rel < 0.2,
                "N = {n}: variance x N = {vn}, expected {EXACT_VARIANCE_TIMES_N}"
            );
        }
        let lo = measured.iter().map(|m| m.1).fold(f64::INFINITY, f64::min);
        let hi = measured.iter().map(|m| m.1).fold(0.0, f64::max);
        assert!(
            hi / lo < 1.5,
            "variance x N ranges over a factor {}: {measured:?}",
            hi / lo
        );
    }

    #[test]
    fn mean_of_trials_is_unbiased() {
        let s = pi_trials(1000, 3, 2000);
        let standard_error = (exact_variance(1000) / 2000.0).sqrt();
        assert!((s.mean - PI).abs() < 4.0 * standard_error, "{s:?}");
        assert_eq!((s.samples, s.trials), (1000, 2000));
        assert!(pi_trials(1000, 3, 1).variance.is_nan());
    }
}
