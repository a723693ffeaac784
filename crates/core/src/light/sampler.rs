//! Choosing one light per shading point with probability proportional to its power
//! (luminance of the emitted power), so bright lights get the samples.

use super::Light;

/// A discrete distribution over lights, in proportion to their power.
#[derive(Clone, Debug, Default)]
pub struct PowerLightSampler {
    /// Cumulative probabilities; `cdf[i]` is P(index <= i).
    cdf: Vec<f32>,
    pmf: Vec<f32>,
}

impl PowerLightSampler {
    /// Build over `lights`; all-dark lights get uniform probabilities.
    #[must_use]
    pub fn new(lights: &[Light]) -> Self {
        let mut weights: Vec<f32> = lights.iter().map(|l| l.power().luminance().max(0.0)).collect();
        let total: f32 = weights.iter().sum();
        if !(total > 0.0 && total.is_finite()) {
            weights.iter_mut().for_each(|w| *w = 1.0);
        }
        let total: f32 = weights.iter().sum();
        let pmf: Vec<f32> = weights.iter().map(|w| w / total).collect();
        let mut acc = 0.0;
        let cdf = pmf
            .iter()
            .map(|p| {
                acc += p;
                acc
            })
            .collect();
        Self { cdf, pmf }
    }

    /// Pick a light from a uniform number; returns its index and probability.
    #[must_use]
    pub fn sample(&self, u: f32) -> Option<(usize, f32)> {
        if self.pmf.is_empty() {
            return None;
        }
        let i = self.cdf.partition_point(|&c| c <= u).min(self.pmf.len() - 1);
        // Skip zero-probability entries that rounding could land on.
        let i = (i..self.pmf.len()).find(|&j| self.pmf[j] > 0.0).unwrap_or(i);
        Some((i, self.pmf[i]))
    }

    /// Probability of choosing light `i`.
    #[must_use]
    pub fn pmf(&self, i: usize) -> f32 {
        self.pmf.get(i).copied().unwrap_or(0.0)
    }
}
