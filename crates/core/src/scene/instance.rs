//! Object instancing: an object's primitives with their own BVH (the bottom level), shared
//! through an `Arc` by every [`Instance`] that places it with a transform. The scene's BVH
//! (the top level) holds instance bounds beside its own primitives. Rays are moved into
//! instance space (the direction unnormalised, so `t` is the same in both spaces) and hits
//! moved back with their error bounds grown by the transform's rounding.

use std::sync::Arc;

use super::Primitive;
use crate::accel::WideBvh;
use crate::material::Material;
use crate::math::{gamma, Bounds3, Ray, Transform, Vec3};
use crate::shape::{ShapeHit, SurfaceInteraction};

/// An object's primitives (in instance space) and their BVH.
#[derive(Debug)]
pub struct ObjectGeometry {
    /// Primitives, referred to by the BVH. None emits.
    pub primitives: Vec<Primitive>,
    bvh: WideBvh,
}

impl ObjectGeometry {
    /// Build the bottom-level BVH over `primitives`, whose materials index `materials`.
    #[must_use]
    pub fn new(primitives: Vec<Primitive>, materials: &[Material]) -> Self {
        let bounds: Vec<Bounds3> = primitives.iter().map(|p| p.shape.bounds()).collect();
        let mut bvh = WideBvh::build(&bounds);
        let primitives = bvh.reorder_by_leaves(primitives);
        bvh.attach_triangles(|i| primitives[i as usize].plain_triangle(materials));
        Self { bvh, primitives }
    }
}

/// One placement of a shared object.
#[derive(Clone, Debug)]
pub struct Instance {
    /// The shared object.
    pub object: Arc<ObjectGeometry>,
    /// World-from-instance transform.
    pub world_from_instance: Transform,
}

impl Instance {
    /// Place `object` by `world_from_instance`.
    #[must_use]
    pub fn new(object: Arc<ObjectGeometry>, world_from_instance: Transform) -> Self {
        Self {
            object,
            world_from_instance,
        }
    }

    /// World-space bounds: the transformed corners of the object's bounds, padded by the
    /// transform's rounding.
    #[must_use]
    pub fn bounds(&self) -> Bounds3 {
        let b = self.object.bvh.bounds();
        let mut w = Bounds3::EMPTY;
        for i in 0..8 {
            let c = Vec3::new(
                if i & 1 == 0 { b.min.x } else { b.max.x },
                if i & 2 == 0 { b.min.y } else { b.max.y },
                if i & 4 == 0 { b.min.z } else { b.max.z },
            );
            w = w.union_point(self.world_from_instance.point(c));
        }
        let pad = gamma(3) * w.min.abs().max(w.max.abs());
        Bounds3 {
            min: w.min - pad,
            max: w.max + pad,
        }
    }

    /// `ray` in instance space; the same `t` names the same point in both spaces.
    #[must_use]
    pub fn local_ray(&self, ray: &Ray) -> Ray {
        let inv = &self.world_from_instance.m_inv;
        Ray::new(inv.transform_point3(ray.o), inv.transform_vector3(ray.d))
    }

    /// Closest hit of a world-space ray within `t_max`: primitive index in the object and
    /// the shape's hit record (for the instance-space ray).
    #[must_use]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<(u32, ShapeHit)> {
        let local = self.local_ray(ray);
        self.object.bvh.closest_hit_triangles(
            &local,
            t_max,
            |i, r, t| self.object.primitives[i as usize].intersect(r, t).map(|h| (h.t, h)),
            |_, h| ShapeHit { t: h.t, data: h.b },
        )
    }

    /// True when a primitive of the instance for which `blocks` holds is hit by `ray`
    /// within `t_max`.
    #[must_use]
    pub fn any_hit(&self, ray: &Ray, t_max: f32, blocks: impl Fn(&Primitive) -> bool) -> bool {
        let local = self.local_ray(ray);
        self.object.bvh.any_hit_triangles(&local, t_max, |i, r, t| {
            let p = &self.object.primitives[i as usize];
            blocks(p) && p.intersect(r, t).is_some()
        })
    }

    /// The world-space interaction for a hit from [`Self::intersect`].
    #[must_use]
    pub fn interaction(&self, ray: &Ray, prim: u32, hit: &ShapeHit) -> SurfaceInteraction {
        let local = self.local_ray(ray);
        let si = self.object.primitives[prim as usize].shape.interaction(&local, hit);
        let t = &self.world_from_instance;
        let (p, p_error) = t.point_with_error(si.intr.p, si.intr.p_error);
        let n = t.normal(si.intr.n).normalize_or_zero();
        let ns = t.normal(si.ns).normalize_or_zero();
        let ns = if ns == Vec3::ZERO { n } else { ns };
        let dpdu = t.vector(si.dpdu);
        let dpdu = crate::math::Frame::from_zx(n, dpdu).x;
        SurfaceInteraction {
            intr: crate::shape::Interaction { p, p_error, n },
            ns,
            dpdu,
            dp_du: t.vector(si.dp_du),
            dp_dv: t.vector(si.dp_dv),
            uv: si.uv,
            wo: -ray.d.normalize(),
            t: si.t,
            mesh: si.mesh,
            unmapped_ns: None,
            // Carried as it is, as pbrt-v4 carries dpdu: under a mirroring instance the
            // normal map's y follows the world-space ns x dpdu.
            bitangent_sign: si.bitangent_sign,
        }
    }
}
