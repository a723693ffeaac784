//! The outcome of a chi-square test, with a readable histogram for failure messages.

use std::fmt;

use super::stats::sidak_alpha;

/// Observed and expected sample counts on the test's grid, row-major.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Histogram {
    /// Number of rows.
    pub rows: usize,
    /// Number of columns.
    pub cols: usize,
    /// What the rows and columns are, e.g. "rows: cos theta from -1 to 1, columns: phi".
    pub axes: String,
    /// Samples counted in each cell.
    pub observed: Vec<f64>,
    /// Samples the pdf predicts in each cell.
    pub expected: Vec<f64>,
}

/// Outcome of a chi-square goodness-of-fit test: compare [`p_value`](Self::p_value) with
/// the significance level through [`passes`](Self::passes); `Display` prints everything,
/// including the histograms, for failure messages.
#[derive(Clone, Debug, PartialEq)]
pub struct Chi2Report {
    /// Pearson's statistic after pooling small cells.
    pub statistic: f64,
    /// Degrees of freedom: pooled cells minus one.
    pub dof: u32,
    /// Probability of a statistic at least this large if the samples follow the pdf.
    pub p_value: f64,
    /// Number of tests in the suite, for the Sidak correction in [`passes`](Self::passes).
    pub test_count: u32,
    /// Number of samples drawn.
    pub samples: u32,
    /// Samples for which the sampling routine returned `None`.
    pub failed_samples: u32,
    /// Integral of the pdf over the whole domain; the expected fraction of successful
    /// samples.
    pub pdf_integral: f64,
    /// A defect that fails the test whatever the statistic: invalid samples, samples where
    /// the pdf is zero, a negative or NaN pdf, too few samples to test anything.
    pub error: Option<String>,
    /// Counts per cell (without the failed-sample category).
    pub histogram: Histogram,
}

impl Chi2Report {
    /// Whether the samples are consistent with the pdf at level `significance` (e.g. 0.01),
    /// Sidak-corrected for [`test_count`](Self::test_count) tests: no error and
    /// `p_value >= 1 - (1 - significance)^(1 / test_count)`.
    #[must_use]
    pub fn passes(&self, significance: f32) -> bool {
        self.error.is_none() && self.p_value >= self.alpha(significance)
    }

    /// Panics with the full report unless the test [`passes`](Self::passes).
    #[track_caller]
    pub fn assert_passes(&self, significance: f32) {
        assert!(
            self.passes(significance),
            "chi-square test rejected at alpha = {:.3e}:\n{self}",
            self.alpha(significance)
        );
    }

    /// Panics with the full report if the test [`passes`](Self::passes): for tests that
    /// show the harness detects a wrong pdf.
    #[track_caller]
    pub fn assert_rejects(&self, significance: f32) {
        assert!(
            !self.passes(significance),
            "chi-square test unexpectedly passed:\n{self}"
        );
    }

    /// The Sidak-corrected per-test significance level.
    fn alpha(&self, significance: f32) -> f64 {
        sidak_alpha(f64::from(significance), self.test_count)
    }
}

impl fmt::Display for Chi2Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "statistic {:.2} with {} dof, p-value {:.3e} ({} test(s) in the suite)",
            self.statistic, self.dof, self.p_value, self.test_count
        )?;
        let expected_failures = (f64::from(self.samples) * (1.0 - self.pdf_integral)).max(0.0);
        writeln!(
            f,
            "{} samples, {} failed (pdf integral {:.6} predicts {:.1})",
            self.samples, self.failed_samples, self.pdf_integral, expected_failures
        )?;
        if let Some(e) = &self.error {
            writeln!(f, "error: {e}")?;
        }
        let h = &self.histogram;
        if h.observed.is_empty() {
            return Ok(());
        }
        writeln!(f, "{} ({} x {} cells)", h.axes, h.rows, h.cols)?;
        write_table(f, "observed", h, |o, _| format!("{o:.0}"))?;
        write_table(f, "expected", h, |_, e| format!("{e:.0}"))?;
        write_table(f, "residual (o - e) / sqrt(e)", h, |o, e| {
            if e > 0.0 {
                format!("{:+.1}", (o - e) / e.sqrt())
            } else if o > 0.0 {
                "!!".to_owned()
            } else {
                ".".to_owned()
            }
        })?;
        // The cells that contribute most.
        let mut cells: Vec<usize> = (0..h.observed.len()).collect();
        let contribution = |i: usize| {
            let (o, e) = (h.observed[i], h.expected[i]);
            if e > 0.0 {
                (o - e) * (o - e) / e
            } else {
                o * f64::INFINITY
            }
        };
        cells.sort_by(|&a, &b| contribution(b).total_cmp(&contribution(a)));
        write!(f, "largest contributions:")?;
        for &i in cells.iter().take(5) {
            write!(
                f,
                " [{}, {}] {:.0} vs {:.1};",
                i / h.cols,
                i % h.cols,
                h.observed[i],
                h.expected[i]
            )?;
        }
        writeln!(f)
    }
}

/// Maximum number of cells printed on one line.
const MAX_COLUMNS: usize = 20;

/// One table of the histogram, each cell formatted by `cell(observed, expected)`.
fn write_table(
    f: &mut fmt::Formatter<'_>,
    title: &str,
    h: &Histogram,
    cell: impl Fn(f64, f64) -> String,
) -> fmt::Result {
    writeln!(f, "{title}:")?;
    for r in 0..h.rows {
        for (chunk_index, chunk) in (0..h.cols).collect::<Vec<_>>().chunks(MAX_COLUMNS).enumerate() {
            if chunk_index == 0 {
                write!(f, "{r:>4} |")?;
            } else {
                write!(f, "     |")?;
            }
            for &c in chunk {
                let i = r * h.cols + c;
                write!(f, "{:>7}", cell(h.observed[i], h.expected[i]))?;
            }
            writeln!(f)?;
        }
    }
    Ok(())
}
