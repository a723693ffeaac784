//! The statistics behind the chi-square test: the log-gamma function, the regularized
//! incomplete gamma functions, the chi-square survival function (the p-value), cell pooling
//! and the Sidak correction. All in `f64`.

/// Relative accuracy at which the series and continued fraction stop.
const EPS: f64 = 1e-15;
/// Iteration cap of the series and the continued fraction.
const MAX_ITER: u32 = 10_000;
/// Guard against division by zero in Lentz's algorithm.
const TINY: f64 = 1e-300;

/// Coefficients of the Lanczos approximation with g = 7, n = 9.
const LANCZOS: [f64; 9] = [
    0.999_999_999_999_809_9,
    676.520_368_121_885_1,
    -1_259.139_216_722_402_8,
    771.323_428_777_653_1,
    -176.615_029_162_140_6,
    12.507_343_278_686_905,
    -0.138_571_095_265_720_12,
    9.984_369_578_019_572e-6,
    1.505_632_735_149_311_6e-7,
];

/// ln Gamma(x) for x > 0, by the Lanczos approximation (relative error ~1e-15), with the
/// reflection formula `Gamma(x) Gamma(1 - x) = pi / sin(pi x)` below 1/2.
#[must_use]
pub fn ln_gamma(x: f64) -> f64 {
    use std::f64::consts::PI;
    if x < 0.5 {
        return (PI / (PI * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let t = x + 7.5;
    let a = LANCZOS[1..]
        .iter()
        .enumerate()
        .fold(LANCZOS[0], |acc, (i, c)| acc + c / (x + (i + 1) as f64));
    0.5 * (2.0 * PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// The regularized lower incomplete gamma function `P(a, x) = gamma(a, x) / Gamma(a)`
/// for a > 0, x >= 0.
#[must_use]
pub fn regularized_gamma_p(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        0.0
    } else if x < a + 1.0 {
        gamma_series(a, x)
    } else {
        1.0 - gamma_continued_fraction(a, x)
    }
}

/// The regularized upper incomplete gamma function `Q(a, x) = 1 - P(a, x)`, accurate also
/// when it is tiny.
#[must_use]
pub fn regularized_gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        1.0
    } else if x < a + 1.0 {
        1.0 - gamma_series(a, x)
    } else {
        gamma_continued_fraction(a, x)
    }
}

/// `x^a e^-x / Gamma(a)`, the common prefactor of both expansions.
fn gamma_prefactor(a: f64, x: f64) -> f64 {
    (a * x.ln() - x - ln_gamma(a)).exp()
}

/// P(a, x) by its power series `x^a e^-x / Gamma(a) * sum_n x^n / (a (a+1) ... (a+n))`,
/// which converges quickly for x < a + 1.
fn gamma_series(a: f64, x: f64) -> f64 {
    let mut term = 1.0 / a;
    let mut sum = term;
    let mut ap = a;
    for _ in 0..MAX_ITER {
        ap += 1.0;
        term *= x / ap;
        sum += term;
        if term.abs() < sum.abs() * EPS {
            break;
        }
    }
    sum * gamma_prefactor(a, x)
}

/// Q(a, x) by its continued fraction `1 / (x + 1 - a - 1 (1 - a) / (x + 3 - a - ...))`
/// (the n-th partial numerator is `-n (n - a)`), evaluated with the modified Lentz method;
/// converges quickly for x > a + 1.
fn gamma_continued_fraction(a: f64, x: f64) -> f64 {
    let mut b = x + 1.0 - a;
    let mut c = 1.0 / TINY;
    let mut d = 1.0 / b;
    let mut h = d;
    for i in 1..MAX_ITER {
        let an = -f64::from(i) * (f64::from(i) - a);
        b += 2.0;
        d = an * d + b;
        if d.abs() < TINY {
            d = TINY;
        }
        c = b + an / c;
        if c.abs() < TINY {
            c = TINY;
        }
        d = 1.0 / d;
        let delta = d * c;
        h *= delta;
        if (delta - 1.0).abs() < EPS {
            break;
        }
    }
    h * gamma_prefactor(a, x)
}

/// The chi-square survival function `Pr[X >= statistic]` for `dof` degrees of freedom: the
/// p-value of a chi-square test. Equals `Q(dof / 2, statistic / 2)`.
#[must_use]
pub fn chi_square_p_value(statistic: f64, dof: u32) -> f64 {
    regularized_gamma_q(0.5 * f64::from(dof), 0.5 * statistic)
}

/// The per-test significance level that keeps the probability of at least one false
/// rejection among `test_count` independent tests at `significance` (Sidak correction:
/// `1 - (1 - significance)^(1 / test_count)`, as in Mitsuba's test suite).
#[must_use]
pub fn sidak_alpha(significance: f64, test_count: u32) -> f64 {
    1.0 - (1.0 - significance).powf(1.0 / f64::from(test_count.max(1)))
}

/// Result of [`pooled_statistic`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PooledStatistic {
    /// Pearson's statistic `sum (observed - expected)^2 / expected` over the pooled cells.
    pub statistic: f64,
    /// Number of cells after pooling, minus one.
    pub dof: u32,
}

/// Pearson's chi-square statistic of observed against expected counts, after pooling the
/// cells with small expected counts (standard practice in pbrt and Mitsuba, since the
/// chi-square approximation needs about 5 expected samples per cell).
///
/// Cells are visited in order of increasing expected count and merged into a pool until
/// the pool expects at least `min_expected` samples; the pool then counts as one cell.
/// Cells with zero expected and zero observed count are ignored. Returns `None` when fewer
/// than two cells remain (no degrees of freedom). The caller must reject observed samples
/// in cells of zero expected count before (no pooling can excuse them).
#[must_use]
pub fn pooled_statistic(observed: &[f64], expected: &[f64], min_expected: f64) -> Option<PooledStatistic> {
    assert_eq!(observed.len(), expected.len(), "one expected count per observed count");
    let mut order: Vec<usize> = (0..expected.len())
        .filter(|&i| expected[i] > 0.0 || observed[i] > 0.0)
        .collect();
    order.sort_by(|&i, &j| expected[i].total_cmp(&expected[j]));
    let term = |o: f64, e: f64| (o - e) * (o - e) / e;
    let (mut statistic, mut cells) = (0.0, 0u32);
    let (mut pool_o, mut pool_e) = (0.0, 0.0);
    let mut last = None;
    for i in order {
        pool_o += observed[i];
        pool_e += expected[i];
        if pool_e >= min_expected {
            statistic += term(pool_o, pool_e);
            cells += 1;
            last = Some((pool_o, pool_e));
            pool_o = 0.0;
            pool_e = 0.0;
        }
    }
    if pool_e > 0.0 || pool_o > 0.0 {
        // A tail of cells expecting fewer than `min_expected` samples in total joins the
        // last pooled cell.
        let (o, e) = last?;
        statistic += term(o + pool_o, e + pool_e) - term(o, e);
    }
    (cells >= 2).then(|| PooledStatistic {
        statistic,
        dof: cells - 1,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol * b.abs().max(1e-300)
    }

    #[test]
    fn ln_gamma_matches_known_values() {
        assert!(close(ln_gamma(0.5), 0.5 * std::f64::consts::PI.ln(), 1e-13));
        assert!(close(ln_gamma(10.0), 362_880f64.ln(), 1e-13));
        assert!(close(ln_gamma(1.0).exp(), 1.0, 1e-13));
        assert!(close(ln_gamma(0.1), 2.252_712_651_734_206, 1e-12));
        assert!(close(ln_gamma(100.0), 359.134_205_369_575_4, 1e-13));
    }

    #[test]
    fn incomplete_gamma_matches_closed_forms() {
        for x in [0.01, 0.3, 1.0, 2.5, 7.0, 30.0] {
            // Q(1, x) = e^-x.
            assert!(close(regularized_gamma_q(1.0, x), (-x).exp(), 1e-12), "{x}");
            assert!(close(regularized_gamma_p(1.0, x), 1.0 - (-x).exp(), 1e-12), "{x}");
        }
        // P(1/2, x) = erf(sqrt(x)).
        let erf = [
            (0.25, 0.520_499_877_813_046_5),
            (1.0, 0.842_700_792_949_714_9),
            (4.0, 0.995_322_265_018_952_7),
        ];
        for (x, e) in erf {
            assert!(close(regularized_gamma_p(0.5, x), e, 1e-12), "{x}");
        }
    }

    #[test]
    fn incomplete_gamma_matches_poisson_sums_for_large_integer_a() {
        // Q(n, x) = e^-x sum_{k < n} x^k / k!, summed in log space; n = 100 is the p-value
        // of a 200-dof test, the size of our sphere grids.
        let n = 100;
        for x in [60.0, 95.0, 100.0, 124.7, 160.0] {
            let sum: f64 = (0..n)
                .map(|k| (f64::from(k) * f64::ln(x) - x - ln_gamma(f64::from(k) + 1.0)).exp())
                .sum();
            assert!(close(regularized_gamma_q(f64::from(n), x), sum, 1e-10), "{x}");
        }
    }

    #[test]
    fn p_values_match_chi_square_tables() {
        assert!(close(chi_square_p_value(3.841_458_820_694_124, 1), 0.05, 1e-9));
        assert!(close(chi_square_p_value(23.209_251_158_954_356, 10), 0.01, 1e-9));
        assert!(close(chi_square_p_value(135.806_723_171_026_76, 100), 0.01, 1e-8));
        // Two degrees of freedom: exp(-x / 2).
        assert!(close(chi_square_p_value(9.0, 2), (-4.5f64).exp(), 1e-12));
        assert_eq!(chi_square_p_value(0.0, 5), 1.0);
        assert!(chi_square_p_value(1e4, 5) < 1e-300);
    }

    #[test]
    fn sidak_correction() {
        assert!(close(sidak_alpha(0.01, 1), 0.01, 1e-12));
        let a = sidak_alpha(0.01, 10);
        assert!(close(1.0 - (1.0 - a).powi(10), 0.01, 1e-12));
        assert!(a > 0.001 && a < 0.00101, "{a}");
    }

    #[test]
    fn pooling_merges_small_cells() {
        // Hand-computed: the cells expecting 1, 2 and 3 pool into one (6 expected, 4 seen);
        // 10 vs 12 and 20 vs 17 stay alone.
        let observed = [1.0, 0.0, 3.0, 12.0, 17.0, 0.0];
        let expected = [1.0, 2.0, 3.0, 10.0, 20.0, 0.0];
        let s = pooled_statistic(&observed, &expected, 5.0).unwrap();
        assert_eq!(s.dof, 2);
        let want = 4.0 / 6.0 + 4.0 / 10.0 + 9.0 / 20.0;
        assert!(close(s.statistic, want, 1e-12), "{}", s.statistic);
        assert!(pooled_statistic(&[1.0, 2.0], &[1.0, 2.0], 5.0).is_none());
        // A small tail joins the last pooled cell: (0 + 6 vs 1 + 4), then (5 + 3 vs 4.2 + 4.5)
        // which absorbs the tail (7 vs 4.6).
        let s = pooled_statistic(&[0.0, 6.0, 5.0, 3.0, 7.0], &[1.0, 4.0, 4.2, 4.5, 4.6], 5.0).unwrap();
        assert_eq!(s.dof, 1);
        let want = 1.0 / 5.0 + (15.0f64 - 13.3).powi(2) / 13.3;
        assert!(close(s.statistic, want, 1e-12), "{}", s.statistic);
    }
}
