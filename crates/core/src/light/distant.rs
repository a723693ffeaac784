//! A distant (directional) light (pbrt-v4 `distant`): radiance arriving from a single
//! direction everywhere, so a surface facing the light receives irradiance equal to the
//! light's radiance value.

use super::LightLiSample;
use crate::color::Rgb;
use crate::math::{Bounds3, Vec2, Vec3, PI};
use crate::shape::Interaction;

/// A distant light.
#[derive(Clone, Debug)]
pub struct DistantLight {
    /// Unit direction from the scene towards the light.
    pub direction: Vec3,
    /// Radiance (the irradiance on a surface facing the light).
    pub radiance: Rgb,
    /// Radius of the scene's bounding sphere, set by [`Self::preprocess`].
    pub scene_radius: f32,
    /// Centre of the scene's bounding sphere, set by [`Self::preprocess`] (where emitted
    /// rays start from, see [`super::Light::sample_le`]).
    pub scene_center: Vec3,
}

impl DistantLight {
    /// Remember the scene's size: shadow rays end outside it, and the power depends on it.
    pub fn preprocess(&mut self, scene_bounds: &Bounds3) {
        self.scene_radius = super::scene_radius(scene_bounds);
        self.scene_center = super::scene_center(scene_bounds);
    }

    /// The single direction to the light; `u` is unused. The shadow-ray end lies outside
    /// the scene.
    #[must_use]
    pub fn sample_li(&self, receiver: &Interaction, _u: Vec2) -> Option<LightLiSample> {
        let wi = self.direction;
        Some(LightLiSample {
            l: self.radiance,
            wi,
            pdf: 1.0,
            p_light: Interaction::point(receiver.p + wi * (2.0 * self.scene_radius)),
        })
    }

    /// `pi r^2 L`: the power crossing a disk of the scene's radius.
    #[must_use]
    pub fn power(&self) -> Rgb {
        self.radiance * (PI * self.scene_radius * self.scene_radius)
    }
}
