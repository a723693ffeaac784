//! The Henyey-Greenstein phase function (pbrt-v4 `HGPhaseFunction`, section 11.3.1),
//! `p(cos) = (1 - g^2) / (4 pi (1 + g^2 + 2 g cos)^{3/2})` with `cos = wo . wi` (both
//! pointing away from the scattering point, so `g > 0` scatters forward, towards `-wo`),
//! and its exact inversion sampling (pbrt-v4 eq. 11.14 in `SampleHenyeyGreenstein`).

use crate::math::{safe_sqrt, sqr, Frame, Vec2, Vec3, INV_4PI, PI};

/// A sampled direction with its phase function value, which is also its density.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhaseSample {
    /// Phase function value.
    pub p: f32,
    /// Sampled direction (pointing away).
    pub wi: Vec3,
    /// Density per unit solid angle (equal to `p`).
    pub pdf: f32,
}

/// A Henyey-Greenstein lobe with asymmetry `g` in (-1, 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HenyeyGreenstein {
    /// Mean cosine between the incident and the scattered propagation directions.
    pub g: f32,
}

impl HenyeyGreenstein {
    /// The phase function at `cos_theta = wo . wi`.
    #[must_use]
    pub fn eval_cos(&self, cos_theta: f32) -> f32 {
        let g = self.g;
        let denom = 1.0 + sqr(g) + 2.0 * g * cos_theta;
        INV_4PI * (1.0 - sqr(g)) / (denom * safe_sqrt(denom))
    }

    /// `p(wo, wi)`.
    #[must_use]
    pub fn p(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.eval_cos(wo.dot(wi))
    }

    /// Density of [`Self::sample`]: `p` itself.
    #[must_use]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.p(wo, wi)
    }

    /// Sample `wi` with density `p(wo, .)`; `None` only for a degenerate `wo`.
    #[must_use]
    pub fn sample(&self, wo: Vec3, u: Vec2) -> Option<PhaseSample> {
        let g = self.g;
        let cos_theta = if g.abs() < 1e-3 {
            1.0 - 2.0 * u.x
        } else {
            -1.0 / (2.0 * g) * (1.0 + sqr(g) - sqr((1.0 - sqr(g)) / (1.0 + g - 2.0 * g * u.x)))
        }
        .clamp(-1.0, 1.0);
        let sin_theta = safe_sqrt(1.0 - sqr(cos_theta));
        let phi = 2.0 * PI * u.y;
        let wo = wo.try_normalize()?;
        let local = Vec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta);
        let wi = Frame::from_z(wo).from_local(local);
        let p = self.eval_cos(cos_theta);
        Some(PhaseSample { p, wi, pdf: p })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{sample_uniform_sphere, uniform_sphere_pdf, Pcg32};

    #[test]
    fn integrates_to_one_and_samples_have_mean_cosine_minus_g() {
        let mut rng = Pcg32::new(3, 5);
        for g in [-0.7f32, 0.0, 0.3, 0.9] {
            let hg = HenyeyGreenstein { g };
            let wo = Vec3::new(0.3, -0.2, 0.9).normalize();
            let n = 400_000;
            let (mut integral, mut mean_cos) = (0.0f64, 0.0f64);
            for _ in 0..n {
                let u = Vec2::new(rng.next_f32(), rng.next_f32());
                let w = sample_uniform_sphere(u);
                integral += f64::from(hg.p(wo, w) / uniform_sphere_pdf());
                let s = hg.sample(wo, Vec2::new(rng.next_f32(), rng.next_f32())).unwrap();
                assert!((s.pdf - hg.p(wo, s.wi)).abs() <= 1e-3 * s.pdf, "{s:?}");
                mean_cos += f64::from(s.wi.dot(wo));
            }
            let (integral, mean_cos) = (integral / f64::from(n), mean_cos / f64::from(n));
            // The g = 0.9 integral is the noisiest (a sharp peak): tolerance 3%.
            assert!((integral - 1.0).abs() < 0.03, "g {g}: integral {integral}");
            // pbrt's convention: forward scattering (g > 0) sends light on towards -wo.
            assert!((mean_cos + f64::from(g)).abs() < 0.005, "g {g}: mean cos {mean_cos}");
        }
    }
}
