//! Filter tests: sampling against the pdf (chi-square), weights, integrals.

use super::*;
use crate::math::UVec2;
use crate::sampling::chi2::{suite_seed, Chi2Test, RectGrid, SIGNIFICANCE};
use crate::sampling::Pcg32;

fn filters() -> [(&'static str, Filter); 5] {
    [
        (
            "box",
            Filter::new(&FilterDesc::Box {
                radius: Vec2::new(0.5, 1.5),
            }),
        ),
        (
            "triangle",
            Filter::new(&FilterDesc::Triangle {
                radius: Vec2::new(2.0, 1.0),
            }),
        ),
        ("gaussian", Filter::new(&FilterDesc::default())),
        (
            "wide gaussian",
            Filter::new(&FilterDesc::Gaussian {
                radius: Vec2::new(3.0, 1.0),
                sigma: 1.2,
            }),
        ),
        (
            "mitchell",
            Filter::new(&FilterDesc::Mitchell {
                radius: Vec2::new(2.0, 1.5),
                b: 1.0 / 3.0,
                c: 1.0 / 3.0,
            }),
        ),
    ]
}

/// Draws `n` weighted samples from a fixed stream.
fn samples(filter: &Filter, n: usize) -> Vec<FilterSample> {
    let mut rng = Pcg32::new(11, 12);
    (0..n)
        .map(|_| filter.sample(Vec2::new(rng.next_f32(), rng.next_f32())))
        .collect()
}

/// Integral of `h(p) f(p)` over the support by the midpoint rule on a fine grid.
fn integrate(filter: &Filter, h: impl Fn(Vec2) -> f64) -> f64 {
    let r = filter.radius();
    let n = 1000;
    let cell = 2.0 * r / n as f32;
    let mut sum = 0.0;
    for j in 0..n {
        for i in 0..n {
            let p = -r + (Vec2::new(i as f32, j as f32) + 0.5) * cell;
            sum += h(p) * f64::from(filter.evaluate(p));
        }
    }
    sum * f64::from(cell.x * cell.y)
}

#[test]
fn builds_from_the_description() {
    let f = Filter::new(&FilterDesc::Triangle {
        radius: Vec2::splat(2.0),
    });
    assert!(matches!(f, Filter::Triangle(_)));
    assert_eq!(f.radius(), Vec2::splat(2.0));
    assert_eq!(Filter::new(&FilterDesc::default()).radius(), Vec2::splat(1.5));
}

#[test]
fn values_and_integrals() {
    let (_, b) = &filters()[0];
    assert_eq!(b.evaluate(Vec2::new(0.5, -1.5)), 1.0);
    assert_eq!(b.evaluate(Vec2::new(0.6, 0.0)), 0.0);
    assert_eq!(b.integral(), 3.0);
    let (_, t) = &filters()[1];
    assert_eq!(t.evaluate(Vec2::new(1.0, 0.5)), 0.5);
    assert_eq!(t.evaluate(Vec2::new(0.0, 1.0)), 0.0);
    assert_eq!(t.integral(), 4.0);
    for (name, f) in filters() {
        let numeric = integrate(&f, |_| 1.0);
        assert!(
            (numeric / f64::from(f.integral()) - 1.0).abs() < 1e-3,
            "{name}: {numeric} vs {}",
            f.integral()
        );
        let r = f.radius();
        for p in [Vec2::new(r.x * 1.01, 0.0), Vec2::new(0.0, -r.y * 1.01), r * 2.0] {
            assert_eq!(f.evaluate(p), 0.0, "{name} at {p}");
            assert_eq!(f.pdf(p), 0.0, "{name} at {p}");
        }
    }
    // pbrt-v4's Gaussian: zero at the radius, peak (G(0) - G(r))^2 at the centre.
    let (_, g) = &filters()[2];
    assert_eq!(g.evaluate(Vec2::new(1.5, 0.0)), 0.0);
    let peak = 1.0 / (std::f32::consts::TAU.sqrt() * 0.5) * (1.0 - (-4.5f32).exp());
    assert!((g.evaluate(Vec2::ZERO) - peak * peak).abs() < 1e-5);
}

#[test]
fn box_and_triangle_weights_are_exactly_one() {
    for (name, f) in &filters()[..2] {
        for s in samples(f, 10_000) {
            assert_eq!(s.weight, 1.0, "{name}");
            assert!(s.p.abs().cmple(f.radius()).all(), "{name}: {}", s.p);
            // The sampling density is the normalised filter.
            assert!(
                (f.pdf(s.p) * f.integral() - f.evaluate(s.p)).abs() < 1e-5,
                "{name}: {}",
                s.p
            );
        }
    }
}

#[test]
fn weights_average_to_one_and_reproduce_the_filter() {
    // E[w h(p)] = integral of f h / integral of f for any h: with h = 1 the mean weight,
    // with h = x^2 + y / 2 a moment the weights must get right.
    let n = 1_000_000;
    for (name, f) in filters() {
        let s = samples(&f, n);
        let mean = s.iter().map(|s| f64::from(s.weight)).sum::<f64>() / n as f64;
        assert!((mean - 1.0).abs() < 2e-3, "{name}: mean weight {mean}");
        assert!(s.iter().all(|s| s.weight.is_finite()), "{name}");
        // Only the Mitchell filter has negative lobes, and its weights carry their sign.
        let negative = s.iter().filter(|s| s.weight < 0.0).count();
        assert_eq!(negative > 0, name == "mitchell", "{name}: {negative} negative weights");
        for s in &s {
            assert_eq!(s.weight < 0.0, f.evaluate(s.p) < 0.0, "{name} at {}", s.p);
        }
        let h = |p: Vec2| f64::from(p.x * p.x + 0.5 * p.y + 1.0);
        let estimate = s.iter().map(|s| f64::from(s.weight) * h(s.p)).sum::<f64>() / n as f64;
        let exact = integrate(&f, h) / f64::from(f.integral());
        assert!((estimate / exact - 1.0).abs() < 5e-3, "{name}: {estimate} vs {exact}");
    }
}

/// pbrt-v4's Mitchell filter: `m(0) = (6 - 2B) / 6` per axis at the centre, zero at the
/// radius, negative between half the radius and the radius (for B = C = 1/3), integral
/// `r_x r_y / 4`.
#[test]
fn mitchell_values() {
    let (_, m) = &filters()[4];
    let centre = (6.0 - 2.0 / 3.0) / 6.0;
    assert!((m.evaluate(Vec2::ZERO) - centre * centre).abs() < 1e-6);
    assert!(m.evaluate(Vec2::new(2.0, 0.0)).abs() < 1e-6);
    assert!(m.evaluate(Vec2::new(1.5, 0.0)) < 0.0);
    assert!(m.evaluate(Vec2::new(0.0, 1.0)) < 0.0);
    assert_eq!(m.integral(), 0.75);
}

#[test]
fn gaussian_weights_are_bounded_and_near_one() {
    // Per axis the weight is g(x) / (average of g over x's bin): within a few per cent of 1
    // where g is smooth, between 0 and 2 in the outer bins where g falls linearly to 0.
    for (name, g) in &filters()[2..4] {
        let s = samples(g, 100_000);
        let mut deviation = 0.0;
        for s in &s {
            assert!(s.weight > 0.0 && s.weight <= 4.0, "{name}: {}: {}", s.p, s.weight);
            if s.p.abs().max_element() < 0.5 * g.radius().min_element() {
                assert!((s.weight - 1.0).abs() < 0.08, "{name}: {}: {}", s.p, s.weight);
            }
            deviation += (s.weight - 1.0).abs();
        }
        let mean_deviation = deviation / s.len() as f32;
        assert!(mean_deviation < 0.03, "{name}: mean |w - 1| = {mean_deviation}");
    }
}

#[test]
fn chi2_filters() {
    let list = filters();
    for (name, f) in &list {
        let r = f.radius();
        // The Gaussian's sampling density is a 128 x 128 table: 16 x 16 cells of 8 x 8
        // steps, integrated with two quadrature panels per step.
        let grid = RectGrid {
            min: -r,
            max: r,
            bins: UVec2::new(16, 16),
        };
        let test = Chi2Test::new(1_000_000, suite_seed()).with_test_count(list.len() as u32);
        let report = test
            .with_integration_panels(16)
            .rect(grid, |u, _| Some(f.sample(u).p), |p| f.pdf(p));
        assert!(report.passes(SIGNIFICANCE), "{name}:\n{report}");
        assert!(
            (report.pdf_integral - 1.0).abs() < 1e-5,
            "{name}: pdf integral {}",
            report.pdf_integral
        );
    }
}
