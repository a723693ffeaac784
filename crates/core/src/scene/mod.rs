//! Layer 4: the render-ready scene. Built from a [`SceneDescription`]: primitives (shape,
//! material, optional light) in a flat array owned by a BVH, materials and lights by index.
//!
//! Surfaces of the `interface` material have no BSDF: [`Scene::bsdf`] returns `None` and
//! the integrators continue rays through them without counting a bounce. Shadow rays
//! ([`Scene::unoccluded_ray`]) pass through them too, so such a surface changes nothing
//! (pbrt-v4's `PathIntegrator` instead lets them block shadow rays and counts emission
//! found through them in full; its `VolPathIntegrator`, for which interfaces exist, lets
//! its shadow rays through as we do).

mod alpha;
mod build;
mod description;
mod instance;

pub use build::{BuildError, MAX_PIXELS, MAX_RESOLUTION, MAX_SCENE_COORDINATE};
pub use description::*;
pub use instance::{Instance, ObjectGeometry};

use crate::accel::WideBvh;
use crate::bsdf::Bsdf;
use crate::camera::Camera;
use crate::film::Filter;
use crate::light::{Light, PowerLightSampler};
use crate::material::Material;
use crate::math::Ray;
use crate::shape::{Interaction, Shape, ShapeHit, SurfaceInteraction};
use crate::texture::TextureContext;

/// A shape with what it is made of.
#[derive(Clone, Debug)]
pub struct Primitive {
    /// Geometry.
    pub shape: Shape,
    /// Index into [`Scene::materials`].
    pub material: u32,
    /// Index into [`Scene::lights`] when the shape emits.
    pub light: Option<u32>,
    /// Alpha cut-out texture; `None` for an opaque shape (see [`Primitive::intersect`]).
    pub alpha: Option<FloatTexture>,
}

impl Primitive {
    /// The vertex positions when the BVH may test this primitive with the precomputed
    /// four-lane triangle test ([`crate::accel::WideBvh::attach_triangles`]): an opaque
    /// triangle (no alpha cut-out) that also blocks shadow rays (not an `interface`).
    #[must_use]
    pub fn plain_triangle(&self, materials: &[Material]) -> Option<[crate::math::Vec3; 3]> {
        match (&self.shape, &self.alpha, materials.get(self.material as usize)) {
            (Shape::Triangle(t), None, Some(m)) if !matches!(m, Material::Interface) => Some(t.positions()),
            _ => None,
        }
    }
}

/// The closest hit of a ray: the surface interaction and what was hit.
#[derive(Clone, Copy, Debug)]
pub struct Hit<'a> {
    /// Geometry at the hit (world space, also inside instances).
    pub si: SurfaceInteraction,
    /// The primitive hit: one of [`Scene::primitives`] or of an instanced object.
    pub primitive: &'a Primitive,
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
    /// How camera samples become pixels.
    pub reconstruction: crate::film::Reconstruction,
    /// Sampler settings.
    pub sampler: SamplerDesc,
    /// Integrator settings.
    pub integrator: IntegratorDesc,
    /// Placed objects; the BVH refers to them after the primitives.
    pub instances: Vec<Instance>,
    /// True when some material is an `interface`, which shadow rays must skip.
    has_interfaces: bool,
    /// True when some material is a normal map (so `intersect` looks for them).
    has_normal_maps: bool,
    bvh: WideBvh,
}

impl Scene {
    /// Closest hit along `ray` (for `t` in `(0, inf)`).
    #[must_use]
    pub fn intersect(&self, ray: &Ray) -> Option<Hit<'_>> {
        let mut si = SurfaceInteraction::default();
        let primitive = self.intersect_into(ray, &mut si)?;
        Some(Hit { si, primitive })
    }

    /// [`Self::intersect`] writing the interaction into `si` (left as it was when nothing
    /// is hit) and returning the primitive hit. For loops that trace ray after ray: the
    /// interaction (about 150 bytes) is built where it stays instead of being moved out
    /// through return values, which cost 4% of a Cornell box render in `memcpy`.
    pub fn intersect_into<'a>(&'a self, ray: &Ray, si: &mut SurfaceInteraction) -> Option<&'a Primitive> {
        let n = self.primitives.len() as u32;
        let (index, (shape_hit, prim)) = self.bvh.closest_hit_triangles(
            ray,
            f32::INFINITY,
            |i, r, t_max| {
                if i < n {
                    self.primitives[i as usize].intersect(r, t_max).map(|h| (h.t, (h, 0)))
                } else {
                    self.instances[(i - n) as usize]
                        .intersect(r, t_max)
                        .map(|(p, h)| (h.t, (h, p)))
                }
            },
            |_, h| (ShapeHit { t: h.t, data: h.b }, 0),
        )?;
        let primitive = if index < n {
            let primitive = &self.primitives[index as usize];
            primitive.shape.interaction_into(ray, &shape_hit, si);
            primitive
        } else {
            let inst = &self.instances[(index - n) as usize];
            *si = inst.interaction(ray, prim, &shape_hit);
            &inst.object.primitives[prim as usize]
        };
        if self.has_normal_maps {
            // Normal and bump maps move the shading frame where the ray lands (bounded:
            // the description has no cycles).
            let mut m = primitive.material;
            for _ in 0..self.materials.len() {
                let Some(mat) = self.materials.get(m as usize) else {
                    break;
                };
                if mat.frame_inner().is_none() {
                    break;
                }
                let ctx = self.texture_context(mat, si);
                match mat.apply_frame(si, &ctx) {
                    Some(inner) => m = inner,
                    None => break,
                }
            }
        }
        Some(primitive)
    }

    /// True when nothing blocks `ray` within `(0, t_max)`; `interface` surfaces and
    /// alpha cut-outs do not.
    #[must_use]
    pub fn unoccluded_ray(&self, ray: &Ray, t_max: f32) -> bool {
        let n = self.primitives.len() as u32;
        let blocks =
            |p: &Primitive| !self.has_interfaces || !matches!(self.materials[p.material as usize], Material::Interface);
        !self.bvh.any_hit_triangles(ray, t_max, |i, r, t| {
            if i < n {
                let p = &self.primitives[i as usize];
                blocks(p) && p.intersect(r, t).is_some()
            } else {
                self.instances[(i - n) as usize].any_hit(r, t, blocks)
            }
        })
    }

    /// The BSDF of material `material` at `si`, following the choices of `mix` materials
    /// (validation rules out cycles); `None` for an `interface`, which rays pass through.
    #[must_use]
    ///
    /// Textured materials are evaluated with the pixel footprint at `si` (pbrt-v4
    /// `Approximate_dp_dxy` from the camera, then `ComputeDifferentials`), at every path
    /// vertex; other materials skip that work.
    pub fn bsdf(&self, material: u32, si: &SurfaceInteraction) -> Option<Bsdf> {
        let m = self.resolve_material(material, si);
        let ctx = self.texture_context(m, si);
        match si.unmapped_ns {
            // A Mitsuba normal or bump map shadows the light side by its tilt.
            Some(before) => m
                .bsdf(si, &ctx)
                .map(|bsdf| bsdf.with_shadowing(crate::bsdf::BumpShadowing::new(before, si.ns))),
            // Returned as made, so it is built in the caller's slot rather than copied there
            // (the 152-byte copy was a `memmove` call at every path vertex).
            None => m.bsdf(si, &ctx),
        }
    }

    /// The texture context of `m` at `si`: with the pixel footprint when `m` is textured.
    fn texture_context(&self, m: &Material, si: &SurfaceInteraction) -> TextureContext {
        if m.is_textured() {
            let (dpdx, dpdy) = self
                .camera
                .approximate_dp_dxy(si.p(), si.n(), self.sampler.samples_per_pixel);
            TextureContext::with_footprint(si, dpdx, dpdy)
        } else {
            TextureContext::at_point(si)
        }
    }

    /// True when material `material` at `si` is an `interface` (no surface), without
    /// building a BSDF.
    #[must_use]
    pub fn passes_through(&self, material: u32, si: &SurfaceInteraction) -> bool {
        self.has_interfaces && matches!(self.resolve_material(material, si), Material::Interface)
    }

    /// The material used at `si`: `material` itself, or what its mixes choose there
    /// (their amounts evaluated at `si`).
    fn resolve_material(&self, material: u32, si: &SurfaceInteraction) -> &Material {
        let mut m = &self.materials[material as usize];
        loop {
            let next = match m {
                Material::Mix(_) => m.mix_choice(si, &self.texture_context(m, si)),
                // (The frame was moved by `intersect`.)
                Material::NormalMap(_) | Material::BumpMap(_) => m.frame_inner(),
                _ => None,
            };
            let Some(next) = next else { break };
            m = &self.materials[next as usize];
        }
        m
    }

    /// True when the segment between two points is free (both ends offset off their
    /// surfaces).
    #[must_use]
    pub fn unoccluded(&self, from: &Interaction, to: &Interaction) -> bool {
        let (ray, t_max) = from.spawn_ray_to(to);
        self.unoccluded_ray(&ray, t_max)
    }
}
