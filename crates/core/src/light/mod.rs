//! Layer 3: lights and light selection.

mod diffuse_area;
mod point;
mod sampler;

pub use diffuse_area::DiffuseAreaLight;
pub use point::PointLight;
pub use sampler::PowerLightSampler;

use crate::color::Rgb;
use crate::math::Vec3;
use crate::shape::Interaction;

/// Incident radiance sampled from a light at a receiving point.
#[derive(Clone, Copy, Debug)]
pub struct LightLiSample {
    /// Radiance arriving from the light along `-wi`, unoccluded.
    pub l: Rgb,
    /// Unit direction from the receiver to the light.
    pub wi: Vec3,
    /// Density per unit solid angle at the receiver (1 for delta lights).
    pub pdf: f32,
    /// The sampled point on the light, for the shadow ray.
    pub p_light: Interaction,
}

/// The closed set of lights.
#[derive(Clone, Debug)]
pub enum Light {
    /// Uniform emission from a shape's surface.
    DiffuseArea(DiffuseAreaLight),
    /// Isotropic point light.
    Point(PointLight),
}

impl Light {
    /// Sample incident radiance at `receiver` from two uniform numbers.
    #[must_use]
    pub fn sample_li(&self, receiver: &Interaction, u: crate::math::Vec2) -> Option<LightLiSample> {
        match self {
            Self::DiffuseArea(l) => l.sample_li(receiver, u),
            Self::Point(l) => l.sample_li(receiver),
        }
    }

    /// Density per unit solid angle of [`Self::sample_li`] at `receiver` choosing the point
    /// `p_light` on this light (0 for delta lights).
    #[must_use]
    pub fn pdf_li(&self, receiver: &Interaction, p_light: &Interaction) -> f32 {
        match self {
            Self::DiffuseArea(l) => l.pdf_li(receiver, p_light),
            Self::Point(_) => 0.0,
        }
    }

    /// Total emitted power (per channel, W), used to choose lights in proportion to it.
    #[must_use]
    pub fn power(&self) -> Rgb {
        match self {
            Self::DiffuseArea(l) => l.power(),
            Self::Point(l) => l.power(),
        }
    }

    /// True for lights that can only be reached by sampling them (no area).
    #[must_use]
    pub fn is_delta(&self) -> bool {
        matches!(self, Self::Point(_))
    }
}

#[cfg(test)]
mod tests;
