//! Open cylinders around the z axis of their object space, from `z_min` to `z_max`, swept to
//! `phi_max`, placed by an affine transform (pbrt-v4's `cylinder`, section 6.3; Mitsuba 3's
//! `cylinder` is the case `z in [0, length]`, full sweep). Intersection is solved in object
//! space in double precision with the cancellation-free discriminant (pbrt-v4 eq. 6.5); the
//! hit point is reprojected onto the surface, which leaves an error of `gamma(3)` times
//! `|(x, y, 0)|` (pbrt-v4 6.8.5), carried through the transform. The normal points outwards
//! (object space `(x, y, 0)`), flipped by `flip_normals` (pbrt's `ReverseOrientation` xor a
//! handedness-swapping transform, as for spheres).
//!
//! Area sampling is uniform in object space (height and azimuth); the pdf returned is the
//! true world-space density, `1 / (A_obj J(phi))` with the area Jacobian `J` of the
//! transform (Nanson's formula), so non-uniform scales are exact too. The world area is
//! `r (z_max - z_min)` times the integral of `J` over the sweep, integrated numerically once
//! at construction (constant `J`, hence exact, for the usual uniform scales).

use super::{Interaction, ShapeHit, ShapeSample, SurfaceInteraction};
use crate::math::{gamma, Bounds3, Mat3, Ray, Transform, Vec2, Vec3, PI};
use glam::DVec3;

/// Midpoint steps of the numerical integral of the area Jacobian over the sweep.
const AREA_STEPS: u32 = 1024;

/// An open cylinder, possibly cut in azimuth.
#[derive(Clone, Debug)]
pub struct Cylinder {
    radius: f32,
    z_min: f32,
    z_max: f32,
    phi_max: f32,
    /// Boxed so that the `Shape` enum stays small for the triangles that dominate scenes.
    world_from_object: Box<Transform>,
    flip_normals: bool,
    /// `|det|` of the linear part, for the area Jacobian.
    abs_det: f32,
    /// World-space area.
    area: f32,
}

impl Cylinder {
    /// A cylinder of `radius` between heights `z_min` and `z_max` (either order) of object
    /// space, swept from azimuth 0 to `phi_max` radians (clamped to `[0, 2 pi]`);
    /// `flip_normals` makes the normal point inwards.
    #[must_use]
    pub fn new(
        radius: f32,
        z_min: f32,
        z_max: f32,
        phi_max: f32,
        world_from_object: Transform,
        flip_normals: bool,
    ) -> Self {
        let abs_det = Mat3::from_mat4(world_from_object.m).determinant().abs();
        let mut c = Self {
            radius,
            z_min: z_min.min(z_max),
            z_max: z_min.max(z_max),
            phi_max: phi_max.clamp(0.0, 2.0 * PI),
            world_from_object: Box::new(world_from_object),
            flip_normals,
            abs_det,
            area: 0.0,
        };
        // A = r (z_max - z_min) int_0^phi_max J(phi) dphi, by the midpoint rule (spectrally
        // accurate for the full, periodic sweep).
        let h = f64::from(c.phi_max) / f64::from(AREA_STEPS);
        let integral: f64 = (0..AREA_STEPS)
            .map(|i| f64::from(c.jacobian(((f64::from(i) + 0.5) * h) as f32)) * h)
            .sum();
        c.area = (f64::from(radius) * f64::from(c.z_max - c.z_min) * integral) as f32;
        c
    }

    /// Ratio of world to object area at azimuth `phi`: `|det M| |M^-T n|` for the
    /// object-space unit normal `n = (cos phi, sin phi, 0)` and the linear part `M`.
    fn jacobian(&self, phi: f32) -> f32 {
        let n = Vec3::new(phi.cos(), phi.sin(), 0.0);
        self.abs_det * self.world_from_object.normal(n).length()
    }

    /// Object-space area, `phi_max r (z_max - z_min)`.
    fn object_area(&self) -> f32 {
        self.phi_max * self.radius * (self.z_max - self.z_min)
    }

    /// World-space bounds (the transformed object-space box, padded by the transform's
    /// rounding).
    #[must_use]
    pub fn bounds(&self) -> Bounds3 {
        let r = self.radius;
        let mut b = Bounds3::EMPTY;
        for i in 0..8 {
            let c = Vec3::new(
                if i & 1 == 0 { -r } else { r },
                if i & 2 == 0 { -r } else { r },
                if i & 4 == 0 { self.z_min } else { self.z_max },
            );
            b = b.union_point(self.world_from_object.point(c));
        }
        let pad = gamma(3) * b.min.abs().max(b.max.abs());
        Bounds3 {
            min: b.min - pad,
            max: b.max + pad,
        }
    }

    /// Surface area in world space (exact up to the quadrature of the Jacobian).
    #[must_use]
    pub fn area(&self) -> f32 {
        self.area
    }

    /// Whether the object-space point `p` on the infinite cylinder lies on this one.
    fn kept(&self, p: DVec3) -> bool {
        if !(p.z >= f64::from(self.z_min) && p.z <= f64::from(self.z_max)) {
            return false;
        }
        self.phi_max >= 2.0 * PI || p.y.atan2(p.x).rem_euclid(std::f64::consts::TAU) <= f64::from(self.phi_max)
    }

    /// Closest intersection; `data` holds the object-space hit point.
    #[must_use]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        let inv = &self.world_from_object.m_inv;
        let o = inv.transform_point3(ray.o).as_dvec3();
        let d = inv.transform_vector3(ray.d).as_dvec3();
        let r = f64::from(self.radius);
        // x^2 + y^2 = r^2 along the ray: a t^2 + b t + c = 0. Rays along the axis (a = 0)
        // and NaN or infinite directions fail this test.
        let a = d.x * d.x + d.y * d.y;
        if !(a > 0.0 && a.is_finite()) {
            return None;
        }
        let b = 2.0 * (d.x * o.x + d.y * o.y);
        let c = o.x * o.x + o.y * o.y - r * r;
        // Discriminant from the point of the ray nearest the axis (pbrt-v4 eq. 6.5 in 2D):
        // b^2 - 4ac = 4a (r + |v|)(r - |v|), v = o_xy - b / (2a) d_xy.
        let f = b / (2.0 * a);
        let (vx, vy) = (o.x - f * d.x, o.y - f * d.y);
        let len = (vx * vx + vy * vy).sqrt();
        let discrim = 4.0 * a * (r + len) * (r - len);
        if discrim.is_nan() || discrim < 0.0 {
            return None;
        }
        let root = discrim.sqrt();
        let q = if b < 0.0 { -0.5 * (b - root) } else { -0.5 * (b + root) };
        let (mut t0, mut t1) = (q / a, if q != 0.0 { c / q } else { q / a });
        if t0 > t1 {
            std::mem::swap(&mut t0, &mut t1);
        }
        let t_max = f64::from(t_max);
        // Reject roots within the rounding error of zero; origins are offset off surfaces.
        let eps = 1e-9 * (o.length() + r) / d.length();
        let t = [t0, t1]
            .into_iter()
            .find(|&t| t > eps && t < t_max && self.kept(o + t * d))?;
        let p = (o + t * d).as_vec3();
        Some(ShapeHit {
            t: t as f32,
            data: p.to_array(),
        })
    }

    /// The surface point for an object-space point on (or within rounding of) the cylinder.
    fn interaction_at(&self, p_obj: Vec3, wo: Vec3, t: f32) -> SurfaceInteraction {
        // Reproject onto the surface in x and y; the error is then gamma(3) |(x, y, 0)|
        // (pbrt-v4 6.8.5). The error along z is tangential and does not matter for offsets.
        let r_xy = (p_obj.x * p_obj.x + p_obj.y * p_obj.y).sqrt();
        let s = if r_xy > 0.0 { self.radius / r_xy } else { 1.0 };
        let p_obj = Vec3::new(p_obj.x * s, p_obj.y * s, p_obj.z);
        let radial = Vec3::new(p_obj.x, p_obj.y, 0.0);
        let err_obj = gamma(3) * radial.abs();
        let (p, p_error) = self.world_from_object.point_with_error(p_obj, err_obj);
        let mut n = self.world_from_object.normal(radial).normalize();
        if self.flip_normals {
            n = -n;
        }
        let phi = p_obj.y.atan2(p_obj.x).rem_euclid(2.0 * PI);
        // pbrt's parameterisation: u = phi / phi_max, v = (z - z_min) / (z_max - z_min).
        let uv = Vec2::new(
            if self.phi_max > 0.0 { phi / self.phi_max } else { 0.0 },
            (p_obj.z - self.z_min) / (self.z_max - self.z_min),
        );
        // pbrt-v4 eq. 6.9: dp/du = phi_max (-y, x, 0), dp/dv = (0, 0, z_max - z_min).
        let dpdu = self.world_from_object.vector(Vec3::new(-p_obj.y, p_obj.x, 0.0));
        let dp_du = self.phi_max * dpdu;
        let dp_dv = self
            .world_from_object
            .vector(Vec3::new(0.0, 0.0, self.z_max - self.z_min));
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
            mesh: crate::shape::MeshPoint::default(),
            unmapped_ns: None,
            bitangent_sign: 1.0,
        }
    }

    /// The interaction for a hit from [`Self::intersect`].
    #[must_use]
    pub fn interaction(&self, ray: &Ray, hit: &ShapeHit) -> SurfaceInteraction {
        self.interaction_at(Vec3::from_array(hit.data), -ray.d.normalize(), hit.t)
    }

    /// A point uniform by area in object space: height uniform in `[z_min, z_max]`,
    /// azimuth in `[0, phi_max]`; the pdf returned is the world-space density.
    #[must_use]
    pub fn sample_area(&self, u: Vec2) -> ShapeSample {
        let z = self.z_min + u.x * (self.z_max - self.z_min);
        let phi = u.y * self.phi_max;
        let p_obj = Vec3::new(self.radius * phi.cos(), self.radius * phi.sin(), z);
        let si = self.interaction_at(p_obj, Vec3::ZERO, 0.0);
        ShapeSample {
            intr: si.intr,
            pdf_area: 1.0 / (self.object_area() * self.jacobian(phi)),
            uv: si.uv,
        }
    }

    /// World-space density of [`Self::sample_area`] at a point on the cylinder.
    #[must_use]
    pub fn pdf_area(&self, intr: &Interaction) -> f32 {
        let p_obj = self.world_from_object.m_inv.transform_point3(intr.p);
        let phi = p_obj.y.atan2(p_obj.x);
        1.0 / (self.object_area() * self.jacobian(phi))
    }
}

#[cfg(test)]
#[path = "cylinder_tests.rs"]
mod tests;
