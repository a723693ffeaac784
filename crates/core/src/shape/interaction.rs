//! Points on surfaces: where a ray hit, with the error bound of the point, the geometric and
//! shading normals, and the helpers that spawn new rays from there without self-intersection.

use crate::math::{offset_ray_origin, Ray, Vec2, Vec3, SHADOW_EPSILON};

/// A point on a surface with its geometric normal and the bound of its rounding error.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Interaction {
    /// The point.
    pub p: Vec3,
    /// Absolute error bound of `p`, per axis.
    pub p_error: Vec3,
    /// Unit geometric normal (zero for points not on a surface, e.g. point lights).
    pub n: Vec3,
}

impl Interaction {
    /// A point in space (no surface): rays leave it unoffset.
    #[must_use]
    pub fn point(p: Vec3) -> Self {
        Self {
            p,
            p_error: Vec3::ZERO,
            n: Vec3::ZERO,
        }
    }

    /// Origin for a ray leaving towards `w`.
    #[inline]
    #[must_use]
    pub fn offset_origin(&self, w: Vec3) -> Vec3 {
        offset_ray_origin(self.p, self.p_error, self.n, w)
    }

    /// A ray leaving in direction `d`.
    #[inline]
    #[must_use]
    pub fn spawn_ray(&self, d: Vec3) -> Ray {
        Ray::new(self.offset_origin(d), d)
    }

    /// A shadow ray towards `other`, to be traced for `t` in `(0, 1 - SHADOW_EPSILON)`:
    /// both ends are offset off their surfaces, so neither end can occlude the ray.
    #[must_use]
    pub fn spawn_ray_to(&self, other: &Interaction) -> (Ray, f32) {
        let pf = self.offset_origin(other.p - self.p);
        let pt = other.offset_origin(pf - other.p);
        (Ray::new(pf, pt - pf), 1.0 - SHADOW_EPSILON)
    }
}

/// Where a hit lies on a triangle mesh: the triangle's index in its mesh and the
/// barycentric weights of its three vertices (all zero for other shapes). Mesh attribute
/// textures interpolate with them.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MeshPoint {
    /// Index of the triangle in its mesh.
    pub triangle: u32,
    /// Barycentric weights of the triangle's vertices, in the mesh's index order.
    pub b: [f32; 3],
}

/// Everything the integrator needs at a ray hit. The default (all zero) is only a place
/// for a caller to write a hit into (the render loop reuses one per path).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SurfaceInteraction {
    /// Point, error bound and geometric normal. The normal's orientation follows the
    /// shape's convention (pbrt's): it decides on which side one-sided lights emit.
    pub intr: Interaction,
    /// Unit shading normal (interpolated vertex normal, or `intr.n`), on the same side as
    /// `intr.n`.
    pub ns: Vec3,
    /// Unit tangent along increasing `u`, for anisotropic shading frames.
    pub dpdu: Vec3,
    /// Unnormalised partial derivative of the point with respect to `u` (pbrt's `dpdu`),
    /// for texture footprints; not used for shading.
    pub dp_du: Vec3,
    /// Unnormalised partial derivative of the point with respect to `v` (pbrt's `dpdv`).
    pub dp_dv: Vec3,
    /// Surface parameterisation.
    pub uv: Vec2,
    /// Unit direction back along the incoming ray.
    pub wo: Vec3,
    /// Ray parameter of the hit.
    pub t: f32,
    /// The triangle and barycentrics of the hit on a mesh.
    pub mesh: MeshPoint,
    /// Set by Mitsuba 3's normal and bump maps: the shading normal before the map moved it
    /// to `ns`. Its divergence from `ns` shadows the light side of the BSDF (Mitsuba's
    /// bump-terminator term, `crate::bsdf::BumpShadowing`); `None` otherwise.
    pub unmapped_ns: Option<Vec3>,
    /// Handedness of the shading frame's bitangent: it is `bitangent_sign * (ns x dpdu)`
    /// (glTF's `TANGENT.w`). Normal maps read their green channel along it. 1 unless a
    /// mesh gives tangents.
    pub bitangent_sign: f32,
}

impl SurfaceInteraction {
    /// The point.
    #[inline]
    #[must_use]
    pub fn p(&self) -> Vec3 {
        self.intr.p
    }

    /// The geometric normal.
    #[inline]
    #[must_use]
    pub fn n(&self) -> Vec3 {
        self.intr.n
    }

    /// A ray leaving in direction `d`.
    #[inline]
    #[must_use]
    pub fn spawn_ray(&self, d: Vec3) -> Ray {
        self.intr.spawn_ray(d)
    }
}
