//! Multiple importance sampling weights (Veach 1997, chapter 9) for combining a sample of
//! strategy f with the other strategy g.

/// The balance heuristic `nf pf / (nf pf + ng pg)`: weight of a sample from strategy f,
/// taken `nf` times with density `f_pdf`, when strategy g takes `ng` samples with density
/// `g_pdf` at the same point. 1 if f's density is infinite (a delta distribution), 0 if
/// both densities are zero.
#[inline]
#[must_use]
pub fn balance_heuristic(nf: f32, f_pdf: f32, ng: f32, g_pdf: f32) -> f32 {
    let (f, g) = (nf * f_pdf, ng * g_pdf);
    if f.is_infinite() {
        return 1.0;
    }
    if f == 0.0 {
        return 0.0;
    }
    f / (f + g)
}

/// The power heuristic with exponent 2, `(nf pf)^2 / ((nf pf)^2 + (ng pg)^2)`, usually
/// better than the balance heuristic when one strategy is much better than the other. As
/// pbrt: 1 if `(nf pf)^2` overflows to infinity (a delta distribution), and 0 if both
/// densities are zero (instead of NaN).
#[inline]
#[must_use]
pub fn power_heuristic(nf: f32, f_pdf: f32, ng: f32, g_pdf: f32) -> f32 {
    let (f, g) = (nf * f_pdf, ng * g_pdf);
    let (f2, g2) = (f * f, g * g);
    if f2.is_infinite() {
        return 1.0;
    }
    if f2 == 0.0 {
        return 0.0;
    }
    f2 / (f2 + g2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_of_two_strategies_sum_to_one() {
        for (pf, pg) in [(1.0, 1.0), (0.3, 2.0), (5.0, 0.01), (1e-3, 1e3)] {
            for (nf, ng) in [(1.0, 1.0), (2.0, 1.0)] {
                let b = balance_heuristic(nf, pf, ng, pg) + balance_heuristic(ng, pg, nf, pf);
                let p = power_heuristic(nf, pf, ng, pg) + power_heuristic(ng, pg, nf, pf);
                assert!((b - 1.0).abs() < 1e-6 && (p - 1.0).abs() < 1e-6, "{pf} {pg}");
            }
        }
        assert!((power_heuristic(1.0, 1.0, 1.0, 3.0) - 0.1).abs() < 1e-7);
        assert!((balance_heuristic(1.0, 1.0, 1.0, 3.0) - 0.25).abs() < 1e-7);
    }

    #[test]
    fn degenerate_densities_give_finite_weights() {
        assert_eq!(power_heuristic(1.0, f32::INFINITY, 1.0, 1.0), 1.0);
        assert_eq!(power_heuristic(1.0, f32::INFINITY, 1.0, f32::INFINITY), 1.0);
        // The square overflows although the product does not.
        assert_eq!(power_heuristic(1.0, 1e30, 1.0, 1.0), 1.0);
        assert_eq!(power_heuristic(1.0, 1.0, 1.0, f32::INFINITY), 0.0);
        assert_eq!(power_heuristic(1.0, 0.0, 1.0, 0.0), 0.0);
        assert_eq!(power_heuristic(1.0, 0.0, 1.0, 2.0), 0.0);
        assert_eq!(power_heuristic(1.0, 2.0, 1.0, 0.0), 1.0);
        assert_eq!(balance_heuristic(1.0, f32::INFINITY, 1.0, 1.0), 1.0);
        assert_eq!(balance_heuristic(1.0, 0.0, 1.0, 0.0), 0.0);
        assert_eq!(balance_heuristic(1.0, 1.0, 1.0, f32::INFINITY), 0.0);
    }
}
