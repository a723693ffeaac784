//! Isotropic point light of radiant intensity `I`: `Li = I / r^2`.

use super::LightLiSample;
use crate::color::Rgb;
use crate::math::{Vec2, Vec3, PI};
use crate::shape::Interaction;

/// A point light.
#[derive(Clone, Debug)]
pub struct PointLight {
    /// World position.
    pub position: Vec3,
    /// Radiant intensity.
    pub intensity: Rgb,
}

impl PointLight {
    /// The single direction to the light; `u` is unused.
    #[must_use]
    pub fn sample_li(&self, receiver: &Interaction, _u: Vec2) -> Option<LightLiSample> {
        let d = self.position - receiver.p;
        let r2 = d.length_squared();
        let wi = d.try_normalize()?;
        Some(LightLiSample {
            l: self.intensity / r2,
            wi,
            pdf: 1.0,
            p_light: Interaction::point(self.position),
        })
    }

    /// `4 pi I`.
    #[must_use]
    pub fn power(&self) -> Rgb {
        self.intensity * (4.0 * PI)
    }
}
