//! A chi-square goodness-of-fit harness for sampling routines: draw many samples, bin them
//! on a grid, integrate the claimed pdf over every cell, and test observed against expected
//! counts (Pearson's statistic, small cells pooled, p-value from the chi-square
//! distribution). Public, so that the tests of every warp, BSDF, light and filter use it.
//!
//! Three domains: directions on the unit sphere ([`Chi2Test::sphere`], binned in
//! (cos theta, phi), where equal steps give equal solid angles), rectangles in the plane
//! ([`Chi2Test::rect`]) and intervals ([`Chi2Test::interval`]). A sampling routine may fail
//! (return `None`); failures are one more category whose expected count is the samples
//! times `1 - integral of the pdf`, so a pdf must integrate to the success rate. Sample
//! weights are not part of the test; check them separately (as the filter tests do).
//!
//! ```
//! use mcrender_core::sampling::chi2::{Chi2Test, SphereGrid};
//! use mcrender_core::sampling::{cosine_hemisphere_pdf, sample_cosine_hemisphere};
//!
//! let report = Chi2Test::new(100_000, 1).sphere(
//!     SphereGrid::default(),
//!     |u, _| Some(sample_cosine_hemisphere(u)),
//!     |w| cosine_hemisphere_pdf(w.z),
//! );
//! assert!(report.passes(0.01), "{report}");
//! ```

mod integrate;
mod report;
mod stats;

pub use report::{Chi2Report, Histogram};
pub use stats::{
    chi_square_p_value, ln_gamma, pooled_statistic, regularized_gamma_p, regularized_gamma_q, sidak_alpha,
    PooledStatistic,
};

use integrate::{integrate_1d, integrate_2d};

use crate::math::{UVec2, Vec2, Vec3};
use crate::sampling::Pcg32;

/// The significance level our test suites use, before the Sidak correction.
pub const SIGNIFICANCE: f32 = 0.01;

/// Failures a correct sampler may show through rounding, as a fraction of the samples:
/// a sample landing exactly on the domain's edge, say one in 500,000. More failures than
/// this against a pdf integrating to 1 are a defect.
const ROUNDING_FAILURE_RATE: f64 = 1e-5;

/// The seed our test suites use unless [`SEED_VARIABLE`] overrides it.
pub const DEFAULT_SEED: u64 = 0;

/// Environment variable that overrides [`DEFAULT_SEED`], to rerun the suites on other
/// seeds: a correct sampling routine then fails at about the nominal rate.
pub const SEED_VARIABLE: &str = "MCRENDER_CHI2_SEED";

/// The seed for a test suite: [`SEED_VARIABLE`] if it is set to an integer, otherwise
/// [`DEFAULT_SEED`]. Tests stay deterministic by default.
#[must_use]
pub fn suite_seed() -> u64 {
    std::env::var(SEED_VARIABLE)
        .ok()
        .and_then(|s| s.trim().parse().ok())
        .unwrap_or(DEFAULT_SEED)
}

/// Absolute quadrature tolerance per accepted panel, times the number of cells. A cell's
/// probability then errs by about 1e-8 (a few panels' worth), so its expected count errs by
/// `N dp` and the statistic by `N dp^2 / p`: negligible for a million samples even in
/// cells expecting a single sample.
const INTEGRATION_TOLERANCE: f64 = 1e-6;
/// Relative slack for samples on the edge of a rectangle or interval grid.
const EDGE_SLACK: f32 = 1e-5;
/// How far from unit length a sampled direction may be.
const UNIT_LENGTH_SLACK: f32 = 1e-3;

/// Settings of a chi-square test: sample count, seed and the size of the suite.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Chi2Test {
    /// Number of samples to draw.
    pub samples: u32,
    /// Seed of the [`Pcg32`] that provides the `u` values (stream 0).
    pub seed: u64,
    /// Number of tests in the suite, for the Sidak correction.
    pub test_count: u32,
    /// Cells expecting fewer samples than this are pooled.
    pub min_expected: f64,
    /// Initial quadrature panels per cell and axis when integrating the pdf. Raise it for
    /// tabulated pdfs to at least two panels per table step (see
    /// [`with_integration_panels`](Self::with_integration_panels)).
    pub integration_panels: u32,
}

/// A (cos theta, phi) grid on the unit sphere: `cos_theta_bins` equal steps of
/// cos theta = z from -1 to 1 times `phi_bins` equal steps of the azimuth from 0 to 2 pi,
/// so all cells have the same solid angle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SphereGrid {
    /// Rows: steps in cos theta (use an even number so z = 0 is a cell border).
    pub cos_theta_bins: u32,
    /// Columns: steps in phi.
    pub phi_bins: u32,
}

impl Default for SphereGrid {
    /// 10 x 20 cells.
    fn default() -> Self {
        Self {
            cos_theta_bins: 10,
            phi_bins: 20,
        }
    }
}

/// A grid of `bins.x` x `bins.y` equal cells over the rectangle `[min, max]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RectGrid {
    /// Lower corner.
    pub min: Vec2,
    /// Upper corner.
    pub max: Vec2,
    /// Cells per axis.
    pub bins: UVec2,
}

/// `bins` equal cells over the interval `[min, max]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IntervalGrid {
    /// Lower end.
    pub min: f32,
    /// Upper end.
    pub max: f32,
    /// Number of cells.
    pub bins: u32,
}

/// Where one sample went.
enum Tally {
    /// Into this cell.
    Cell(usize),
    /// The sampling routine returned `None`.
    Failed,
    /// An invalid sample (NaN, off the domain); the string describes it.
    Invalid(String),
}

impl Chi2Test {
    /// A single test (`test_count` 1) drawing `samples` samples from stream `seed`, pooling
    /// cells that expect fewer than 5 samples, integrating the pdf from 8 x 8 panels per
    /// cell.
    #[must_use]
    pub const fn new(samples: u32, seed: u64) -> Self {
        Self {
            samples,
            seed,
            test_count: 1,
            min_expected: 5.0,
            integration_panels: 8,
        }
    }

    /// The same settings, integrating the pdf from `panels` initial panels per cell and
    /// axis. Adaptive quadrature finds isolated jumps by itself, but it cannot see steps
    /// narrower than its initial panels: a tabulated pdf sampled at about its own step
    /// width aliases into a smooth-looking function with the wrong integral. So for a
    /// tabulated pdf use at least two panels per table step inside a cell.
    #[must_use]
    pub const fn with_integration_panels(self, panels: u32) -> Self {
        Self {
            integration_panels: panels,
            ..self
        }
    }

    /// The same settings in a suite of `test_count` tests.
    #[must_use]
    pub const fn with_test_count(self, test_count: u32) -> Self {
        Self { test_count, ..self }
    }

    /// Tests directions `sample(u, rng)` (`None` for a failed sample) against `pdf`, a
    /// density per unit solid angle, on `grid`. `u` is uniform in [0, 1)^2; `rng` may be
    /// used for further random numbers.
    pub fn sphere(
        &self,
        grid: SphereGrid,
        mut sample: impl FnMut(Vec2, &mut Pcg32) -> Option<Vec3>,
        pdf: impl Fn(Vec3) -> f32,
    ) -> Chi2Report {
        use std::f64::consts::TAU;
        let (rows, cols) = (grid.cos_theta_bins as usize, grid.phi_bins as usize);
        let tally = self.tally(rows * cols, |rng| {
            let u = Vec2::new(rng.next_f32(), rng.next_f32());
            match sample(u, rng) {
                None => Tally::Failed,
                Some(w) if !w.is_finite() || (w.length() - 1.0).abs() > UNIT_LENGTH_SLACK => {
                    Tally::Invalid(format!("direction {w} is not a unit vector"))
                }
                Some(w) => {
                    let row = bin((f64::from(w.z) + 1.0) * 0.5, rows);
                    let phi = f64::from(w.y).atan2(f64::from(w.x)).rem_euclid(TAU);
                    Tally::Cell(row * cols + bin(phi / TAU, cols))
                }
            }
        });
        // Integrand over (phi, z): the area element of the sphere is dz dphi.
        let integrand = |phi: f64, z: f64| {
            let r = (1.0 - z * z).max(0.0).sqrt();
            f64::from(pdf(Vec3::new((r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32)))
        };
        let tol = INTEGRATION_TOLERANCE / (rows * cols) as f64;
        let mut probabilities = Vec::with_capacity(rows * cols);
        for r in 0..rows {
            let z = [edge(-1.0, 1.0, r, rows), edge(-1.0, 1.0, r + 1, rows)];
            for c in 0..cols {
                let phi = [edge(0.0, TAU, c, cols), edge(0.0, TAU, c + 1, cols)];
                probabilities.push(integrate_2d(&integrand, phi, z, self.integration_panels, tol));
            }
        }
        let axes = "rows: cos theta from -1 to 1, columns: phi from 0 to 2 pi".to_owned();
        self.finish(
            tally,
            &probabilities,
            Histogram {
                rows,
                cols,
                axes,
                ..Histogram::default()
            },
        )
    }

    /// Tests points `sample(u, rng)` (`None` for a failed sample) against `pdf`, a density
    /// per unit area, on `grid`. Samples outside the rectangle are errors.
    pub fn rect(
        &self,
        grid: RectGrid,
        mut sample: impl FnMut(Vec2, &mut Pcg32) -> Option<Vec2>,
        pdf: impl Fn(Vec2) -> f32,
    ) -> Chi2Report {
        let (cols, rows) = (grid.bins.x as usize, grid.bins.y as usize);
        let extent = grid.max - grid.min;
        let slack = extent * EDGE_SLACK;
        let tally = self.tally(rows * cols, |rng| {
            let u = Vec2::new(rng.next_f32(), rng.next_f32());
            match sample(u, rng) {
                None => Tally::Failed,
                Some(p) if !p.is_finite() || p.cmplt(grid.min - slack).any() || p.cmpgt(grid.max + slack).any() => {
                    Tally::Invalid(format!("point {p} is outside the grid [{}, {}]", grid.min, grid.max))
                }
                Some(p) => {
                    let (tx, ty) = (fraction(p.x, grid.min.x, extent.x), fraction(p.y, grid.min.y, extent.y));
                    Tally::Cell(bin(ty, rows) * cols + bin(tx, cols))
                }
            }
        });
        let integrand = |x: f64, y: f64| f64::from(pdf(Vec2::new(x as f32, y as f32)));
        let tol = INTEGRATION_TOLERANCE / (rows * cols) as f64;
        let (min, max) = (grid.min.as_dvec2(), grid.max.as_dvec2());
        let mut probabilities = Vec::with_capacity(rows * cols);
        for r in 0..rows {
            let y = [edge(min.y, max.y, r, rows), edge(min.y, max.y, r + 1, rows)];
            for c in 0..cols {
                let x = [edge(min.x, max.x, c, cols), edge(min.x, max.x, c + 1, cols)];
                probabilities.push(integrate_2d(&integrand, x, y, self.integration_panels, tol));
            }
        }
        let axes = format!(
            "rows: y from {} to {}, columns: x from {} to {}",
            grid.min.y, grid.max.y, grid.min.x, grid.max.x
        );
        self.finish(
            tally,
            &probabilities,
            Histogram {
                rows,
                cols,
                axes,
                ..Histogram::default()
            },
        )
    }

    /// Tests values `sample(u, rng)` (`None` for a failed sample) against `pdf`, a density
    /// on the line, on `grid`. Values outside the interval are errors.
    pub fn interval(
        &self,
        grid: IntervalGrid,
        mut sample: impl FnMut(f32, &mut Pcg32) -> Option<f32>,
        pdf: impl Fn(f32) -> f32,
    ) -> Chi2Report {
        let cols = grid.bins as usize;
        let extent = grid.max - grid.min;
        let slack = extent * EDGE_SLACK;
        let tally = self.tally(cols, |rng| {
            let u = rng.next_f32();
            match sample(u, rng) {
                None => Tally::Failed,
                Some(x) if !x.is_finite() || x < grid.min - slack || x > grid.max + slack => {
                    Tally::Invalid(format!("value {x} is outside the grid [{}, {}]", grid.min, grid.max))
                }
                Some(x) => Tally::Cell(bin(fraction(x, grid.min, extent), cols)),
            }
        });
        let integrand = |x: f64| f64::from(pdf(x as f32));
        let tol = INTEGRATION_TOLERANCE / cols as f64;
        let (min, max) = (f64::from(grid.min), f64::from(grid.max));
        let probabilities: Vec<f64> = (0..cols)
            .map(|c| {
                integrate_1d(
                    &integrand,
                    edge(min, max, c, cols),
                    edge(min, max, c + 1, cols),
                    self.integration_panels,
                    tol,
                )
            })
            .collect();
        let axes = format!("columns: x from {} to {}", grid.min, grid.max);
        self.finish(
            tally,
            &probabilities,
            Histogram {
                rows: 1,
                cols,
                axes,
                ..Histogram::default()
            },
        )
    }

    /// Draws the samples and counts them in `cells` cells, with the failures, the number of
    /// invalid samples and a description of the first.
    fn tally(&self, cells: usize, mut classify: impl FnMut(&mut Pcg32) -> Tally) -> Counts {
        let mut rng = Pcg32::new(0, self.seed);
        let mut counts = Counts {
            cells: vec![0; cells],
            ..Counts::default()
        };
        for _ in 0..self.samples {
            match classify(&mut rng) {
                Tally::Cell(i) => counts.cells[i] += 1,
                Tally::Failed => counts.failed += 1,
                Tally::Invalid(what) => {
                    counts.invalid += 1;
                    counts.first_invalid.get_or_insert(what);
                }
            }
        }
        counts
    }

    /// The statistic and report from the counts and the pdf's integral over every cell.
    fn finish(&self, counts: Counts, probabilities: &[f64], mut histogram: Histogram) -> Chi2Report {
        let n = f64::from(self.samples);
        let pdf_integral: f64 = probabilities.iter().sum();
        histogram.observed = counts.cells.iter().map(|&c| f64::from(c)).collect();
        histogram.expected = probabilities.iter().map(|p| n * p).collect();
        let mut report = Chi2Report {
            statistic: f64::NAN,
            dof: 0,
            p_value: 0.0,
            test_count: self.test_count,
            samples: self.samples,
            failed_samples: counts.failed,
            pdf_integral,
            error: None,
            histogram,
        };
        report.error = self.defect(&counts, &report);
        if report.error.is_some() {
            return report;
        }
        // Failures are one more category; a pdf integrating to slightly more than 1 through
        // quadrature error predicts none.
        let h = &report.histogram;
        let observed: Vec<f64> = h.observed.iter().copied().chain([f64::from(counts.failed)]).collect();
        let expected: Vec<f64> = h
            .expected
            .iter()
            .copied()
            .chain([(n * (1.0 - pdf_integral)).max(0.0)])
            .collect();
        match pooled_statistic(&observed, &expected, self.min_expected) {
            Some(s) => {
                report.statistic = s.statistic;
                report.dof = s.dof;
                report.p_value = chi_square_p_value(s.statistic, s.dof);
            }
            None => report.error = Some("too few samples: fewer than two cells after pooling".to_owned()),
        }
        report
    }

    /// Defects that fail the test regardless of the statistic.
    fn defect(&self, counts: &Counts, report: &Chi2Report) -> Option<String> {
        let h = &report.histogram;
        if let Some(what) = &counts.first_invalid {
            return Some(format!("{} invalid samples, the first: {what}", counts.invalid));
        }
        if let Some(i) = h.expected.iter().position(|e| !(e.is_finite() && *e >= 0.0)) {
            return Some(format!(
                "the pdf integrates to {} in cell [{}, {}]",
                h.expected[i],
                i / h.cols,
                i % h.cols
            ));
        }
        let stray = (0..h.expected.len()).find(|&i| h.expected[i] == 0.0 && h.observed[i] > 0.0);
        if let Some(i) = stray {
            let cell = (i / h.cols, i % h.cols);
            return Some(format!(
                "{} samples in cell {cell:?}, where the pdf is zero",
                h.observed[i]
            ));
        }
        let rounding_failures = ROUNDING_FAILURE_RATE * f64::from(self.samples);
        if f64::from(counts.failed) > rounding_failures && report.pdf_integral > 1.0 - 1e-5 {
            return Some(format!(
                "{} failed samples, but the pdf integrates to {}",
                counts.failed, report.pdf_integral
            ));
        }
        None
    }
}

/// Per-cell sample counts.
#[derive(Default)]
struct Counts {
    cells: Vec<u32>,
    failed: u32,
    invalid: u32,
    first_invalid: Option<String>,
}

/// The cell of `t` in [0, 1] among `n` equal cells (values on the upper edge go to the
/// last cell). In `f64`: in `f32`, `(z + 1) / 2` of a direction just below the horizon
/// rounds to 1/2 and lands in the cell above it, where a reflection pdf may be zero.
#[inline]
fn bin(t: f64, n: usize) -> usize {
    ((t * n as f64).max(0.0) as usize).min(n - 1)
}

/// How far `v` lies along `[min, min + extent]`, as a fraction, in `f64` (for [`bin`]).
#[inline]
fn fraction(v: f32, min: f32, extent: f32) -> f64 {
    (f64::from(v) - f64::from(min)) / f64::from(extent)
}

/// The `i`-th of `n + 1` equally spaced points from `a` to `b`.
#[inline]
fn edge(a: f64, b: f64, i: usize, n: usize) -> f64 {
    a + (b - a) * i as f64 / n as f64
}

#[cfg(test)]
mod tests;
