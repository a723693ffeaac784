//! Adaptive Simpson quadrature in one and two dimensions, in `f64`, used to turn a pdf into
//! expected cell counts. Robust to the jump discontinuities pdfs have at the edge of their
//! support (hemisphere border, cone edge, disk rim) and to the many small steps of tabulated
//! pdfs: a panel whose two Simpson estimates disagree is halved until they agree.
//!
//! Unlike textbook adaptive Simpson, the tolerance is not halved with the panel: at a jump
//! the disagreement only halves per level, so a halving tolerance would never be met and
//! every jump would be refined to the depth limit, leaving an error of (jump x final panel
//! width) each. With a fixed per-panel tolerance the refinement stops after about
//! log2(jump x width / tol) levels and each accepted panel errs by at most about `tol`.
//!
//! No quadrature from point values can see steps narrower than its initial panels: a
//! staircase sampled at a spacing close to its step width looks smooth, and both Simpson
//! estimates agree on a wrong value (aliasing). So the initial number of panels is the
//! caller's: at least two per step of a tabulated pdf.

/// Maximum number of halvings of an initial panel (2^-40 of it is below `f32` resolution).
const MAX_DEPTH: u32 = 40;

/// Integral of `f` over [a, b], starting from `panels` equal panels, each accepted panel
/// accurate to about `tol` (absolute).
pub(crate) fn integrate_1d(f: &dyn Fn(f64) -> f64, a: f64, b: f64, panels: u32, tol: f64) -> f64 {
    let h = (b - a) / f64::from(panels);
    (0..panels)
        .map(|i| {
            let (x0, x1) = (a + h * f64::from(i), a + h * f64::from(i + 1));
            let (f0, fm, f1) = (f(x0), f(0.5 * (x0 + x1)), f(x1));
            let whole = simpson(x1 - x0, f0, fm, f1);
            refine(f, x0, x1, [f0, fm, f1], whole, tol, MAX_DEPTH)
        })
        .sum()
}

/// Integral of `f(x, y)` over [x0, x1] x [y0, y1]: the outer integral over `y` (panels
/// accurate to about `tol`) of inner integrals over `x` (accurate enough that their errors,
/// integrated over `y`, stay well below `tol`); `panels` initial panels per axis.
pub(crate) fn integrate_2d(f: &dyn Fn(f64, f64) -> f64, x: [f64; 2], y: [f64; 2], panels: u32, tol: f64) -> f64 {
    let inner_tol = 0.01 * tol / (y[1] - y[0]);
    let g = |yv: f64| integrate_1d(&|xv| f(xv, yv), x[0], x[1], panels, inner_tol);
    integrate_1d(&g, y[0], y[1], panels, tol)
}

/// Simpson's rule on a panel of width `h`: `h/6 (f0 + 4 fm + f1)`.
#[inline]
fn simpson(h: f64, f0: f64, fm: f64, f1: f64) -> f64 {
    h / 6.0 * (f0 + 4.0 * fm + f1)
}

/// One step of adaptive Simpson (Lyness 1969): compare the panel estimate `whole` with the
/// sum of its two halves; accept when they agree to `15 tol` (with Richardson's correction
/// `(halves - whole) / 15`), otherwise refine both halves.
fn refine(f: &dyn Fn(f64) -> f64, a: f64, b: f64, fs: [f64; 3], whole: f64, tol: f64, depth: u32) -> f64 {
    let [fa, fm, fb] = fs;
    let m = 0.5 * (a + b);
    let (flm, frm) = (f(0.5 * (a + m)), f(0.5 * (m + b)));
    let left = simpson(m - a, fa, flm, fm);
    let right = simpson(b - m, fm, frm, fb);
    let delta = left + right - whole;
    if depth == 0 || delta.abs() <= 15.0 * tol || !delta.is_finite() {
        return left + right + delta / 15.0;
    }
    refine(f, a, m, [fa, flm, fm], left, tol, depth - 1) + refine(f, m, b, [fm, frm, fb], right, tol, depth - 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integrates_smooth_functions() {
        let v = integrate_1d(&f64::sin, 0.0, std::f64::consts::PI, 4, 1e-12);
        assert!((v - 2.0).abs() < 1e-9, "{v}");
        let v = integrate_2d(&|x, y| x * y * y, [0.0, 2.0], [0.0, 3.0], 4, 1e-12);
        assert!((v - 18.0).abs() < 1e-9, "{v}");
    }

    #[test]
    fn integrates_across_jumps() {
        // A step at an irrational point.
        let c = 1.0 / std::f64::consts::SQRT_2;
        let v = integrate_1d(&|x| if x < c { 1.0 } else { 0.0 }, 0.0, 1.0, 4, 1e-9);
        assert!((v - c).abs() < 1e-8, "{v}");
        // The unit disk inside [-1, 1]^2.
        let v = integrate_2d(
            &|x, y| if x * x + y * y <= 1.0 { 1.0 } else { 0.0 },
            [-1.0, 1.0],
            [-1.0, 1.0],
            4,
            1e-10,
        );
        assert!((v - std::f64::consts::PI).abs() < 1e-6, "{v}");
    }

    #[test]
    fn integrates_staircases_given_enough_panels() {
        // 250 steps of a Gaussian: with 8 panels the samples alias with the steps and
        // the error is ~1e-4 whatever the tolerance; with 2 panels per step it is tiny.
        let n = 250.0;
        let step = |k: f64| (-2.0 * ((k + 0.5) / n * 3.0 - 1.5).powi(2)).exp();
        let f = |x: f64| step(((x + 1.5) / 3.0 * n).floor().min(n - 1.0));
        let exact: f64 = (0..250).map(|k| step(f64::from(k)) * 3.0 / n).sum();
        let v = integrate_1d(&f, -1.5, 1.5, 500, 1e-12);
        assert!((v - exact).abs() < 1e-9, "{}", v - exact);
        let v = integrate_1d(&f, -1.5, 1.5, 8, 1e-10);
        assert!((v - exact).abs() > 1e-5, "aliasing is expected: {}", v - exact);
    }
}
