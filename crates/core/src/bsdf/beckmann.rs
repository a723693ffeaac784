//! The Beckmann distribution's one-dimensional pieces, for [`super::microfacet`]: Smith's
//! `Lambda`, Mitsuba 3's rational fit of `G1`, and sampling of the visible slopes in the
//! configuration where `alpha = 1`.
//!
//! With `alpha = 1`, slopes `(x, y)` (normal `(-x, -y, 1)`) are independent Gaussians of
//! density `exp(-x^2 - y^2) / pi`. Seen from a direction at angle `theta` in the xz plane,
//! a facet's projected area weighs the slopes by `max(0, cos theta - x sin theta)`, so the
//! visible `x` has density proportional to `(cot theta - x) exp(-x^2)` for `x < cot theta`
//! and `y` stays Gaussian (Heitz and d'Eon 2014). The CDF of `x`, scaled by `2 tan theta`,
//! is `1 + erf(x) + tan theta exp(-x^2) / sqrt(pi)` (as in Jakob's "An improved visible
//! normal sampling routine for the Beckmann distribution", 2014); it is inverted here by
//! safeguarded Newton iterations in double precision.

use crate::math::Vec2;

const INV_SQRT_PI: f64 = 0.564_189_583_547_756_3;

/// Smith's `Lambda` for Beckmann in terms of `alpha tan(theta)` of the direction:
/// `(erf(a) - 1) / 2 + exp(-a^2) / (2 a sqrt(pi))` with `a = 1 / (alpha tan theta)`.
#[must_use]
pub fn lambda(alpha_tan: f32) -> f32 {
    if alpha_tan <= 0.0 {
        return 0.0;
    }
    let a = 1.0 / f64::from(alpha_tan);
    (0.5 * (-libm::erfc(a) + (-a * a).exp() * INV_SQRT_PI / a)) as f32
}

/// Mitsuba 3's `G1` for Beckmann: the rational fit of Walter et al. 2007 (eq. 27),
/// `(3.535 a + 2.181 a^2) / (1 + 2.276 a + 2.577 a^2)` for `a < 1.6`, else 1, with
/// `a = 1 / (alpha tan theta)`.
#[must_use]
pub fn g1_rational(alpha_tan: f32) -> f32 {
    if alpha_tan <= 0.0 {
        return 1.0;
    }
    let a = 1.0 / alpha_tan;
    if a >= 1.6 {
        1.0
    } else {
        (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a)
    }
}

/// The root of an increasing `f` (with derivative `df`) in `[lo, hi]` from the guess `x`:
/// Newton steps, bisection when a step leaves the bracket.
fn invert_increasing(f: impl Fn(f64) -> f64, df: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64, x: f64) -> f64 {
    let mut x = x.clamp(lo, hi);
    for _ in 0..100 {
        let v = f(x);
        if v == 0.0 {
            return x;
        }
        if v > 0.0 {
            hi = x;
        } else {
            lo = x;
        }
        let d = df(x);
        let newton = x - v / d;
        let next = if d > 0.0 && newton >= lo && newton <= hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if (next - x).abs() <= 1e-12 * (1.0 + x.abs()) {
            return next;
        }
        x = next;
    }
    x
}

/// `erf^-1(z)` for `z` in (-1, 1): Giles' single-precision approximation ("Approximating
/// the erfinv function", 2010) refined by Newton steps.
fn erf_inv(z: f64) -> f64 {
    let w = -((1.0 - z) * (1.0 + z)).ln();
    let guess = if w < 5.0 {
        let w = w - 2.5;
        let p = [
            2.810_226_36e-08,
            3.432_739_39e-07,
            -3.523_387_7e-06,
            -4.391_506_54e-06,
            2.185_808_7e-04,
            -1.253_725_03e-03,
            -4.177_681_64e-03,
            2.466_407_27e-01,
            1.501_409_41,
        ];
        p.iter().fold(0.0, |acc, &c| acc * w + c) * z
    } else {
        let w = w.sqrt() - 3.0;
        let p = [
            -2.002_142_57e-04,
            1.009_505_58e-04,
            1.349_343_22e-03,
            -3.673_428_44e-03,
            5.739_507_73e-03,
            -7.622_461_3e-03,
            9.438_870_47e-03,
            1.001_674_06,
            2.832_976_82,
        ];
        p.iter().fold(0.0, |acc, &c| acc * w + c) * z
    };
    invert_increasing(
        |x| libm::erf(x) - z,
        |x| 2.0 * INV_SQRT_PI * (-x * x).exp(),
        -6.0,
        6.0,
        guess,
    )
}

/// Sample the slopes of normals visible from a direction with `cos theta = cos_theta`
/// (azimuth 0) on the Beckmann surface of roughness 1; the normal is `(-x, -y, 1)`.
#[must_use]
pub fn sample_visible_slopes(cos_theta: f32, u: Vec2) -> (f32, f32) {
    // Keep away from the infinite tails (probability below 1e-7).
    let u1 = f64::from(u.x).clamp(1e-7, 1.0 - 1e-7);
    let u2 = f64::from(u.y).clamp(1e-7, 1.0 - 1e-7);
    let cos = f64::from(cos_theta).clamp(0.0, 1.0);
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    let y = erf_inv(2.0 * u2 - 1.0);
    if sin < 1e-7 * cos {
        // Normal incidence: every facet faces the viewer, x is Gaussian too.
        return (erf_inv(2.0 * u1 - 1.0) as f32, y as f32);
    }
    let tan = sin / cos.max(1e-300);
    let cot = cos / sin;
    let cdf = |x: f64| 1.0 + libm::erf(x) + tan * INV_SQRT_PI * (-x * x).exp();
    // Beyond |x| = 6 the Gaussian has no mass in double precision.
    let hi = cot.min(6.0);
    let target = u1 * cdf(hi);
    let x = invert_increasing(
        |x| cdf(x) - target,
        |x| 2.0 * INV_SQRT_PI * (-x * x).exp() * (1.0 - x * tan),
        -6.0,
        hi,
        // The solution at normal incidence.
        erf_inv(2.0 * u1 - 1.0).min(hi),
    );
    (x as f32, y as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn erf_inv_inverts_erf() {
        for z in [-0.999_999, -0.9, -0.3, 0.0, 0.2, 0.75, 0.999] {
            assert!((libm::erf(erf_inv(z)) - z).abs() < 1e-12, "{z}");
        }
    }

    #[test]
    fn lambda_matches_its_integral_definition() {
        // Lambda(a) = integral over slopes x > a of (x - a) p(x) dx / a, with p the unit
        // Gaussian slope density exp(-x^2) / sqrt(pi) (Smith), a = 1 / (alpha tan theta).
        for alpha_tan in [0.1f32, 0.5, 1.0, 3.0] {
            let a = 1.0 / f64::from(alpha_tan);
            let (n, top) = (200_000, 10.0);
            let h = (top - a) / f64::from(n);
            let mut sum = 0.0;
            for i in 0..n {
                let x = a + (f64::from(i) + 0.5) * h;
                sum += (x - a) * (-x * x).exp() * INV_SQRT_PI * h;
            }
            let expected = sum / a;
            let got = f64::from(lambda(alpha_tan));
            assert!(
                (got - expected).abs() < 1e-6 * (1.0 + expected),
                "{alpha_tan}: {got} vs {expected}"
            );
        }
        assert_eq!(lambda(0.0), 0.0);
    }

    #[test]
    fn rational_g1_is_within_its_stated_error_of_the_exact_one() {
        for i in 1..400 {
            let alpha_tan = i as f32 * 0.025;
            let exact = 1.0 / (1.0 + lambda(alpha_tan));
            let fit = g1_rational(alpha_tan);
            assert!(
                (fit - exact).abs() <= 0.0036 * exact + 1e-6,
                "{alpha_tan}: {fit} vs {exact}"
            );
        }
    }

    #[test]
    fn slope_cdf_is_inverted() {
        // The sampled x solves CDF(x) = u CDF(cot theta).
        for cos in [0.05f32, 0.4, 0.9, 0.999] {
            let (c, s) = (f64::from(cos), (1.0 - f64::from(cos).powi(2)).sqrt());
            let tan = s / c;
            let cdf = |x: f64| 1.0 + libm::erf(x) + tan * INV_SQRT_PI * (-x * x).exp();
            for u in [0.01f32, 0.3, 0.5, 0.97] {
                let (x, _) = sample_visible_slopes(cos, Vec2::new(u, 0.5));
                let got = cdf(f64::from(x)) / cdf((c / s).min(6.0));
                assert!((got - f64::from(u)).abs() < 1e-5, "cos {cos}, u {u}: {got}");
                assert!(f64::from(x) <= c / s + 1e-6);
            }
        }
    }
}
