//! A uniform infinite light (pbrt-v4 `infinite` with `L`): radiance `L` arriving from every
//! direction, from infinitely far away. Sampled uniformly over the sphere (pdf 1 / 4 pi);
//! escaped rays see `L`.

use super::LightLiSample;
use crate::color::Rgb;
use crate::math::{Bounds3, Vec2, Vec3, PI};
use crate::sampling::{sample_uniform_sphere, uniform_sphere_pdf};
use crate::shape::Interaction;

/// A uniform infinite light.
#[derive(Clone, Debug)]
pub struct UniformInfiniteLight {
    /// Radiance from every direction.
    pub radiance: Rgb,
    /// Radius of the scene's bounding sphere, set by [`Self::preprocess`].
    pub scene_radius: f32,
    /// Centre of the scene's bounding sphere, set by [`Self::preprocess`] (where emitted
    /// rays start from, see [`super::Light::sample_le`]).
    pub scene_center: Vec3,
}

impl UniformInfiniteLight {
    /// Remember the scene's size: shadow rays end outside it, and the power depends on it.
    pub fn preprocess(&mut self, scene_bounds: &Bounds3) {
        self.scene_radius = super::scene_radius(scene_bounds);
        self.scene_center = super::scene_center(scene_bounds);
    }

    /// A direction uniform over the sphere.
    #[must_use]
    pub fn sample_li(&self, receiver: &Interaction, u: Vec2) -> Option<LightLiSample> {
        let wi = sample_uniform_sphere(u);
        Some(LightLiSample {
            l: self.radiance,
            wi,
            pdf: uniform_sphere_pdf(),
            p_light: Interaction::point(receiver.p + wi * (2.0 * self.scene_radius)),
        })
    }

    /// Solid-angle density of [`Self::sample_li`] choosing `w`: 1 / (4 pi).
    #[must_use]
    pub fn pdf_li(&self, _w: Vec3) -> f32 {
        uniform_sphere_pdf()
    }

    /// Radiance arriving along a ray that leaves the scene in direction `w`.
    #[must_use]
    pub fn le(&self, _w: Vec3) -> Rgb {
        self.radiance
    }

    /// `4 pi^2 r^2 L`: the radiance integrated over the sphere of directions (4 pi) times
    /// the cross-section of the scene (pi r^2), as pbrt-v4 defines it.
    #[must_use]
    pub fn power(&self) -> Rgb {
        self.radiance * (4.0 * PI * PI * self.scene_radius * self.scene_radius)
    }
}
