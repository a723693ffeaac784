//! Layer 4: the render-ready scene. Built from a [`SceneDescription`]: primitives (shape,
//! material, optional light) in a flat array owned by a BVH, materials and lights by index.

mod build;
mod description;

pub use build::BuildError;
pub use description::*;

use crate::accel::Bvh;
use crate::camera::Camera;
use crate::film::Filter;
use crate::light::{Light, PowerLightSampler};
use crate::material::Material;
use crate::math::Ray;
use crate::shape::{Interaction, Shape, SurfaceInteraction};

/// A shape with what it is made of.
#[derive(Clone, Debug)]
pub struct Primitive {
    /// Geometry.
    pub shape: Shape,
    /// Index into [`Scene::materials`].
    pub material: u32,
    /// Index into [`Scene::lights`] when the shape emits.
    pub light: Option<u32>,
}

/// The closest hit of a ray: the surface interaction and what was hit.
#[derive(Clone, Copy, Debug)]
pub struct Hit {
    /// Geometry at the hit.
    pub si: SurfaceInteraction,
    /// Index of the primitive hit.
    pub primitive: u32,
}

/// Everything needed to render, ready for queries.
#[derive(Clone, Debug)]
pub struct Scene {
    /// Primitives, referred to by the BVH.
    pub primitives: Vec<Primitive>,
    /// Materials.
    pub materials: Vec<Material>,
    /// Lights (area lights point back at their primitive's shape).
    pub lights: Vec<Light>,
    /// Indices into [`Self::lights`] of the infinite lights, which rays leaving the scene
    /// see.
    pub infinite_lights: Vec<u32>,
    /// Chooses a light per shading point.
    pub light_sampler: PowerLightSampler,
    /// The camera.
    pub camera: Camera,
    /// Pixel filter.
    pub filter: Filter,
    /// Image size.
    pub film: FilmDesc,
    /// Sampler settings.
    pub sampler: SamplerDesc,
    /// Integrator settings.
    pub integrator: IntegratorDesc,
    bvh: Bvh,
}

impl Scene {
    /// Closest hit along `ray` (for `t` in `(0, inf)`).
    #[must_use]
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        let (prim, (shape_hit, _)) = self.bvh.closest_hit(ray, f32::INFINITY, |i, r, t_max| {
            self.primitives[i as usize]
                .shape
                .intersect(r, t_max)
                .map(|h| (h.t, (h, ())))
        })?;
        let si = self.primitives[prim as usize].shape.interaction(ray, &shape_hit);
        Some(Hit { si, primitive: prim })
    }

    /// True when nothing blocks `ray` within `(0, t_max)`.
    #[must_use]
    pub fn unoccluded_ray(&self, ray: &Ray, t_max: f32) -> bool {
        !self.bvh.any_hit(ray, t_max, |i, r, t| {
            self.primitives[i as usize].shape.intersect(r, t).is_some()
        })
    }

    /// True when the segment between two points is free (both ends offset off their
    /// surfaces).
    #[must_use]
    pub fn unoccluded(&self, from: &Interaction, to: &Interaction) -> bool {
        let (ray, t_max) = from.spawn_ray_to(to);
        self.unoccluded_ray(&ray, t_max)
    }
}
