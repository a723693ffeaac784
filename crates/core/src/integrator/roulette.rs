//! Russian roulette: end a path at random and divide the survivors by their survival
//! probability, so that `E[estimate]` is unchanged while long, dim paths stop early.

use crate::color::Rgb;
use crate::scene::RussianRoulette;

/// The highest survival probability of [`RussianRoulette::Delayed`] (Mitsuba 3's 0.95).
const MAX_SURVIVAL: f32 = 0.95;

/// Play roulette after bounce `depth` with path throughput `beta` and uniform number `u`.
/// Returns `None` when the path stops, otherwise the reweighted throughput.
#[must_use]
pub fn roulette(rule: RussianRoulette, beta: Rgb, depth: u32, u: f32) -> Option<Rgb> {
    let q = match rule {
        RussianRoulette::Off => 0.0,
        // pbrt-v4: from the second bounce, q = 1 - max(beta) once max(beta) < 1.
        RussianRoulette::Throughput => {
            let m = beta.max_component();
            if depth > 1 && m < 1.0 {
                (1.0 - m).max(0.0)
            } else {
                0.0
            }
        }
        // Mitsuba 3: survival min(max(beta), 0.95) from bounce `start_depth` on.
        RussianRoulette::Delayed { start_depth } => {
            if depth >= start_depth {
                1.0 - beta.max_component().min(MAX_SURVIVAL)
            } else {
                0.0
            }
        }
        // The lecture's rule: a fixed q whenever the tentative contribution is small.
        RussianRoulette::Threshold { threshold, probability } => {
            if beta.luminance() < threshold {
                probability
            } else {
                0.0
            }
        }
    };
    if q <= 0.0 {
        return Some(beta);
    }
    if u < q {
        return None;
    }
    Some(beta / (1.0 - q))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roulette_keeps_the_expectation() {
        let beta = Rgb::new(0.2, 0.3, 0.1);
        for rule in [
            RussianRoulette::Throughput,
            RussianRoulette::Delayed { start_depth: 0 },
            RussianRoulette::Threshold {
                threshold: 0.5,
                probability: 0.9,
            },
            RussianRoulette::Threshold {
                threshold: 1.0,
                probability: 0.5,
            },
        ] {
            let n = 100_000;
            let mut sum = [0.0f64; 3];
            for i in 0..n {
                let u = (i as f32 + 0.5) / n as f32;
                if let Some(b) = roulette(rule, beta, 3, u) {
                    for c in 0..3 {
                        sum[c] += f64::from(b[c]);
                    }
                }
            }
            for c in 0..3 {
                let mean = sum[c] / f64::from(n);
                assert!(
                    (mean - f64::from(beta[c])).abs() < 1e-5,
                    "{rule:?}: channel {c}: {mean} vs {}",
                    beta[c]
                );
            }
        }
    }

    #[test]
    fn roulette_plays_only_below_the_threshold() {
        let rule = RussianRoulette::Threshold {
            threshold: 0.25,
            probability: 0.5,
        };
        assert_eq!(roulette(rule, Rgb::splat(0.3), 5, 0.0), Some(Rgb::splat(0.3)));
        assert_eq!(roulette(rule, Rgb::splat(0.2), 5, 0.1), None);
        assert_eq!(
            roulette(RussianRoulette::Off, Rgb::splat(0.01), 50, 0.0),
            Some(Rgb::splat(0.01))
        );
        assert_eq!(
            roulette(RussianRoulette::Throughput, Rgb::splat(0.01), 1, 0.0),
            Some(Rgb::splat(0.01))
        );
    }
}
