//! Choosing one light per shading point with probability proportional to its power
//! (luminance of the emitted power), so bright lights get the samples, or uniformly
//! ([`LightSelection`]; Mitsuba 3's `Scene::sample_emitter` picks uniformly, and matching
//! it matters where one light's power is a poor guide, e.g. a spot light beside an
//! environment whose power grows with the scene's size).

use super::Light;

/// How lights are chosen for next-event estimation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LightSelection {
    /// In proportion to each light's power (mcrender's default).
    #[default]
    Power,
    /// Every light with the same probability (Mitsuba 3).
    Uniform,
}

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
        Self::with_selection(lights, LightSelection::Power)
    }

    /// Build over `lights` choosing as `selection` says.
    #[must_use]
    pub fn with_selection(lights: &[Light], selection: LightSelection) -> Self {
        let mut weights: Vec<f32> = match selection {
            LightSelection::Power => lights.iter().map(|l| l.power().luminance().max(0.0)).collect(),
            LightSelection::Uniform => vec![1.0; lights.len()],
        };
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::Rgb;
    use crate::light::PointLight;
    use crate::math::Vec3;

    /// Power selection follows the intensities (1 : 3); uniform selection ignores them.
    #[test]
    fn power_and_uniform_selection() {
        let point = |i: f32| {
            Light::Point(PointLight {
                position: Vec3::ZERO,
                intensity: Rgb::splat(i),
            })
        };
        let lights = [point(1.0), point(3.0)];
        let by_power = PowerLightSampler::new(&lights);
        assert!((by_power.pmf(0) - 0.25).abs() < 1e-6 && (by_power.pmf(1) - 0.75).abs() < 1e-6);
        let uniform = PowerLightSampler::with_selection(&lights, LightSelection::Uniform);
        assert_eq!((uniform.pmf(0), uniform.pmf(1)), (0.5, 0.5));
        assert_eq!(uniform.sample(0.49).unwrap().0, 0);
        assert_eq!(uniform.sample(0.51).unwrap().0, 1);
    }
}
