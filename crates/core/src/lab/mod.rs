//! Layer 6: the estimator lab's measurements. Small, self-contained Monte Carlo
//! experiments whose exact answers are known, so that the lecture's laws (the estimate
//! converges; its variance falls as 1/N) can be printed, plotted and tested.

pub mod pi;

pub use pi::{estimate_pi, exact_variance, pi_trials, PiStats, EXACT_VARIANCE_TIMES_N};
