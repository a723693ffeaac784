//! Spheres centred at the origin of their object space, placed by an affine transform.
//! Intersection is solved in object space in double precision; the hit point is reprojected
//! onto the surface and its error bound carried through the transform (pbrt-v4 6.8.5).

use super::{Interaction, ShapeHit, ShapeSample, SurfaceInteraction};
use crate::math::{gamma, Bounds3, Mat3, Ray, Transform, Vec2, Vec3, PI};
use crate::sampling::sample_uniform_sphere;

/// A full sphere.
#[derive(Clone, Debug)]
pub struct Sphere {
    radius: f32,
    /// Boxed so that the `Shape` enum stays small for the triangles that dominate scenes.
    world_from_object: Box<Transform>,
    flip_normals: bool,
    /// `|det|` of the linear part, for the area Jacobian.
    abs_det: f32,
}

impl Sphere {
    /// A sphere of `radius` placed by `world_from_object`; `flip_normals` makes the normal
    /// point inwards.
    #[must_use]
    pub fn new(radius: f32, world_from_object: Transform, flip_normals: bool) -> Self {
        let abs_det = Mat3::from_mat4(world_from_object.m).determinant().abs();
        Self {
            radius,
            world_from_object: Box::new(world_from_object),
            flip_normals,
            abs_det,
        }
    }

    /// World-space bounds (the transformed object-space box).
    #[must_use]
    pub fn bounds(&self) -> Bounds3 {
        let r = self.radius;
        let mut b = Bounds3::EMPTY;
        for i in 0..8 {
            let c = Vec3::new(
                if i & 1 == 0 { -r } else { r },
                if i & 2 == 0 { -r } else { r },
                if i & 4 == 0 { -r } else { r },
            );
            b = b.union_point(self.world_from_object.point(c));
        }
        // Pad by the rounding of the transform.
        let pad = gamma(3) * b.min.abs().max(b.max.abs());
        Bounds3 {
            min: b.min - pad,
            max: b.max + pad,
        }
    }

    /// Surface area in world space; exact for uniform scales, and `|det|^(2/3) 4 pi r^2`
    /// (used only to estimate light power) otherwise.
    #[must_use]
    pub fn area(&self) -> f32 {
        4.0 * PI * self.radius * self.radius * self.abs_det.powf(2.0 / 3.0)
    }

    /// Closest intersection; `data` holds the object-space hit point.
    #[must_use]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        let inv = &self.world_from_object.m_inv;
        let o = inv.transform_point3(ray.o).as_dvec3();
        let d = inv.transform_vector3(ray.d).as_dvec3();
        let r = f64::from(self.radius);
        let a = d.length_squared();
        let b = 2.0 * d.dot(o);
        // Discriminant in the form that avoids cancellation (pbrt-v4 eq. 6.5).
        let v = o - b / (2.0 * a) * d;
        let len = v.length();
        let discrim = 4.0 * a * (r + len) * (r - len);
        if discrim < 0.0 {
            return None;
        }
        let root = discrim.sqrt();
        let q = if b < 0.0 { -0.5 * (b - root) } else { -0.5 * (b + root) };
        let (mut t0, mut t1) = (
            q / a,
            if q != 0.0 {
                (o.length_squared() - r * r) / q
            } else {
                q / a
            },
        );
        if t0 > t1 {
            std::mem::swap(&mut t0, &mut t1);
        }
        let t_max = f64::from(t_max);
        // Reject roots within the rounding error of zero; origins are offset off surfaces.
        let eps = 1e-9 * (o.length() + r) / a.sqrt();
        let t = if t0 > eps { t0 } else { t1 };
        if t <= eps || t >= t_max {
            return None;
        }
        let p = (o + t * d).as_vec3();
        Some(ShapeHit {
            t: t as f32,
            data: p.to_array(),
        })
    }

    /// The surface point for an object-space point on the sphere.
    fn interaction_at(&self, p_obj: Vec3, wo: Vec3, t: f32) -> SurfaceInteraction {
        // Reproject onto the surface; the error is then gamma(5)|p| (pbrt-v4 eq. 6.36).
        let p_obj = p_obj * (self.radius / p_obj.length());
        let err_obj = gamma(5) * p_obj.abs();
        let (p, p_error) = self.world_from_object.point_with_error(p_obj, err_obj);
        let mut n = self.world_from_object.normal(p_obj).normalize();
        if self.flip_normals {
            n = -n;
        }
        let phi = p_obj.y.atan2(p_obj.x).rem_euclid(2.0 * PI);
        let cos_theta = (p_obj.z / self.radius).clamp(-1.0, 1.0);
        // pbrt's parameterisation: u = phi / 2pi, v from the south pole (theta = pi) upwards.
        let uv = Vec2::new(phi / (2.0 * PI), (PI - cos_theta.acos()) / PI);
        let dpdu_obj = Vec3::new(-p_obj.y, p_obj.x, 0.0);
        let dpdu = self.world_from_object.vector(dpdu_obj);
        // pbrt-v4 eq. 6.3-6.4 with phi_max = 2 pi, theta from pi (v = 0) to 0 (v = 1).
        let dp_du = 2.0 * PI * dpdu;
        let r_xy = (p_obj.x * p_obj.x + p_obj.y * p_obj.y).sqrt();
        let (cos_phi, sin_phi) = if r_xy > 0.0 {
            (p_obj.x / r_xy, p_obj.y / r_xy)
        } else {
            (1.0, 0.0)
        };
        let dp_dv = self
            .world_from_object
            .vector(-PI * Vec3::new(p_obj.z * cos_phi, p_obj.z * sin_phi, -r_xy));
        let dpdu = crate::math::Frame::from_zx(n, dpdu).x;
        SurfaceInteraction {
            intr: Interaction { p, p_error, n },
            ns: n,
            dpdu,
            dp_du,
            dp_dv,
            uv,
            wo,
            t,
        }
    }

    /// The interaction for a hit from [`Self::intersect`].
    #[must_use]
    pub fn interaction(&self, ray: &Ray, hit: &ShapeHit) -> SurfaceInteraction {
        self.interaction_at(Vec3::from_array(hit.data), -ray.d.normalize(), hit.t)
    }

    /// Ratio of world to object area around the object-space unit normal `n_obj`:
    /// `|det M| |M^-T n|` for the linear part `M`.
    fn area_jacobian(&self, n_obj: Vec3) -> f32 {
        self.abs_det * self.world_from_object.normal(n_obj).length()
    }

    /// A point uniform by area in object space; the pdf returned is the world-space density.
    #[must_use]
    pub fn sample_area(&self, u: Vec2) -> ShapeSample {
        let n_obj = sample_uniform_sphere(u);
        let si = self.interaction_at(self.radius * n_obj, Vec3::ZERO, 0.0);
        let pdf_obj = 1.0 / (4.0 * PI * self.radius * self.radius);
        ShapeSample {
            intr: si.intr,
            pdf_area: pdf_obj / self.area_jacobian(n_obj),
            uv: si.uv,
        }
    }

    /// World-space density of [`Self::sample_area`] at a point on the sphere.
    #[must_use]
    pub fn pdf_area(&self, intr: &Interaction) -> f32 {
        let n_obj = self
            .world_from_object
            .m_inv
            .transform_point3(intr.p)
            .normalize_or_zero();
        let pdf_obj = 1.0 / (4.0 * PI * self.radius * self.radius);
        pdf_obj / self.area_jacobian(n_obj)
    }
}
