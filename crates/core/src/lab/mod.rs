//! Layer 6: the estimator lab's measurements. Small, self-contained Monte Carlo
//! experiments whose exact answers are known, so that the lecture's laws (the estimate
//! converges; its variance falls as 1/N) can be printed, plotted and tested; renders grown
//! in waves for convergence plots; and the efficiency reports comparing direct-lighting
//! techniques and integrators (shared by the CLI's `compare` and the Python bindings).

pub mod compare;
pub mod integrators;
pub mod pi;
pub mod waves;

pub use compare::{compare_techniques, efficiency, CompareRow};
pub use integrators::{
    compare_integrators, integrator_name, parse_integrator, Budget, IntegratorReport, IntegratorRow, ReferenceSource,
    INTEGRATORS, REFERENCE_FACTOR,
};
pub use pi::{estimate_pi, exact_variance, pi_trials, PiStats, EXACT_VARIANCE_TIMES_N};
pub use waves::{render_in_waves, LabError, Progression};
