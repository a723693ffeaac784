//! Gauss-Legendre quadrature on [0, 1]: `n` nodes integrate polynomials of degree up to
//! `2n - 1` exactly (Abramowitz and Stegun 25.4.29). Nodes are the roots of the Legendre
//! polynomial `P_n` found by Newton's method from the usual cosine guesses.

/// Nodes and weights of the `n`-point Gauss-Legendre rule on [0, 1] (weights sum to 1).
#[must_use]
pub fn gauss_legendre_unit(n: usize) -> Vec<(f64, f64)> {
    let mut rule = Vec::with_capacity(n);
    for i in 0..n {
        // Root i of P_n on [-1, 1], from the guess cos(pi (i + 0.75) / (n + 0.5)).
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            // P_n(x) and P_n'(x) by the three-term recurrence.
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let k = k as f64;
                let p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
            let dx = p1 / dp;
            x -= dx;
            if dx.abs() < 1e-15 {
                break;
            }
        }
        let w = 2.0 / ((1.0 - x * x) * dp * dp);
        rule.push((0.5 * (x + 1.0), 0.5 * w));
    }
    rule.reverse();
    rule
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integrates_polynomials_of_degree_2n_minus_1_exactly() {
        for n in [1usize, 2, 5, 32] {
            let rule = gauss_legendre_unit(n);
            assert_eq!(rule.len(), n);
            for degree in 0..2 * n {
                let got: f64 = rule.iter().map(|&(x, w)| w * x.powi(degree as i32)).sum();
                let exact = 1.0 / (degree as f64 + 1.0);
                assert!((got - exact).abs() < 1e-12, "n {n}, degree {degree}: {got} vs {exact}");
            }
        }
        // Not exact beyond: degree 2n.
        let rule = gauss_legendre_unit(2);
        let got: f64 = rule.iter().map(|&(x, w)| w * x.powi(4)).sum();
        assert!((got - 0.2).abs() > 1e-3);
    }
}
