//! Layer 3: lights and light selection.
//!
//! [`Light`] is the closed set of light types, one file each. Every light samples incident
//! radiance at a receiver ([`Light::sample_li`]) and reports its power for light selection.
//! Area lights are also found by rays hitting their shape ([`Light::pdf_li`] gives the
//! density of the hit point); infinite lights by rays that leave the scene
//! ([`Light::le`], [`Light::pdf_li_direction`]); delta lights (point, spot, distant) only by
//! sampling. Lights whose reach depends on the scene's size (distant and infinite) learn it
//! in [`Light::preprocess`].

mod diffuse_area;
mod distant;
mod emission;
mod image_infinite;
mod point;
mod sampler;
mod spot;
mod uniform_infinite;

pub use diffuse_area::DiffuseAreaLight;
pub use distant::DistantLight;
pub use emission::LightLeSample;
pub use image_infinite::{EnvMapping, ImageInfiniteLight};
pub use point::PointLight;
pub use sampler::{LightSelection, PowerLightSampler};
pub use spot::{linear_angle_falloff, smooth_step, SpotFalloff, SpotLight};
pub use uniform_infinite::UniformInfiniteLight;

use crate::color::Rgb;
use crate::math::{Bounds3, Vec2, Vec3};
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
    /// The sampled point on the light, for the shadow ray (outside the scene for distant
    /// and infinite lights).
    pub p_light: Interaction,
}

/// The closed set of lights.
#[derive(Clone, Debug)]
pub enum Light {
    /// Uniform emission from a shape's surface.
    DiffuseArea(DiffuseAreaLight),
    /// Isotropic point light.
    Point(PointLight),
    /// Point light emitting into a cone.
    Spot(SpotLight),
    /// Parallel light from one direction.
    Distant(DistantLight),
    /// The same radiance from every direction at infinity.
    UniformInfinite(UniformInfiniteLight),
    /// Radiance at infinity from an environment image.
    ImageInfinite(ImageInfiniteLight),
}

/// `match` on every variant, binding the light to `$l` and evaluating `$body`.
macro_rules! dispatch {
    ($self:expr, $l:ident => $body:expr) => {
        match $self {
            Light::DiffuseArea($l) => $body,
            Light::Point($l) => $body,
            Light::Spot($l) => $body,
            Light::Distant($l) => $body,
            Light::UniformInfinite($l) => $body,
            Light::ImageInfinite($l) => $body,
        }
    };
}

/// Radius of the bounding sphere of `bounds` (0 when empty), as pbrt's `sceneRadius`.
#[must_use]
pub fn scene_radius(bounds: &Bounds3) -> f32 {
    if bounds.is_empty() {
        0.0
    } else {
        0.5 * bounds.diagonal().length()
    }
}

/// Centre of the bounding sphere of `bounds` (the origin when empty), as pbrt's
/// `sceneCenter`.
#[must_use]
pub fn scene_center(bounds: &Bounds3) -> Vec3 {
    if bounds.is_empty() {
        Vec3::ZERO
    } else {
        0.5 * (bounds.min + bounds.max)
    }
}

impl Light {
    /// Sample incident radiance at `receiver` from two uniform numbers (delta lights ignore
    /// them).
    #[must_use]
    pub fn sample_li(&self, receiver: &Interaction, u: Vec2) -> Option<LightLiSample> {
        dispatch!(self, l => l.sample_li(receiver, u))
    }

    /// Density per unit solid angle of [`Self::sample_li`] at `receiver` choosing the point
    /// `p_light` on this light's surface (area lights; 0 for the others).
    #[must_use]
    pub fn pdf_li(&self, receiver: &Interaction, p_light: &Interaction) -> f32 {
        match self {
            Self::DiffuseArea(l) => l.pdf_li(receiver, p_light),
            _ => 0.0,
        }
    }

    /// Density per unit solid angle of [`Self::sample_li`] choosing the direction `w`
    /// towards infinity (infinite lights; 0 for the others).
    #[must_use]
    pub fn pdf_li_direction(&self, w: Vec3) -> f32 {
        match self {
            Self::UniformInfinite(l) => l.pdf_li(w),
            Self::ImageInfinite(l) => l.pdf_li(w),
            _ => 0.0,
        }
    }

    /// Radiance arriving along a ray that leaves the scene in direction `w` (infinite
    /// lights; black for the others).
    #[must_use]
    pub fn le(&self, w: Vec3) -> Rgb {
        match self {
            Self::UniformInfinite(l) => l.le(w),
            Self::ImageInfinite(l) => l.le(w),
            _ => Rgb::BLACK,
        }
    }

    /// Total emitted power (per channel, W), used to choose lights in proportion to it.
    /// For distant and infinite lights it depends on the scene's size, so call
    /// [`Self::preprocess`] first.
    #[must_use]
    pub fn power(&self) -> Rgb {
        dispatch!(self, l => l.power())
    }

    /// Tell the light the bounds of the scene's geometry.
    pub fn preprocess(&mut self, scene_bounds: &Bounds3) {
        match self {
            Self::Distant(l) => l.preprocess(scene_bounds),
            Self::UniformInfinite(l) => l.preprocess(scene_bounds),
            Self::ImageInfinite(l) => l.preprocess(scene_bounds),
            Self::DiffuseArea(_) | Self::Point(_) | Self::Spot(_) => {}
        }
    }

    /// True for lights that can only be reached by sampling them (a single position or
    /// direction).
    #[must_use]
    pub fn is_delta(&self) -> bool {
        matches!(self, Self::Point(_) | Self::Spot(_) | Self::Distant(_))
    }

    /// True for lights at infinity, seen by rays that leave the scene.
    #[must_use]
    pub fn is_infinite(&self) -> bool {
        matches!(self, Self::UniformInfinite(_) | Self::ImageInfinite(_))
    }
}

#[cfg(test)]
mod tests;
