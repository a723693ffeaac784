//! Spheres centred at the origin of their object space, placed by an affine transform,
//! optionally cut to `z_min <= z <= z_max` and `0 <= phi <= phi_max` as pbrt-v4's
//! `sphere` (section 6.2). Intersection is solved in object space in double precision; the
//! hit point is reprojected onto the surface and its error bound carried through the
//! transform (pbrt-v4 6.8.5).

use super::{Interaction, ShapeHit, ShapeSample, SurfaceInteraction};
use crate::math::{gamma, Bounds3, Mat3, Ray, Transform, Vec2, Vec3, PI};
use crate::sampling::sample_uniform_sphere;
use glam::DVec3;

/// A sphere, possibly partial.
#[derive(Clone, Debug)]
pub struct Sphere {
    radius: f32,
    /// The cut, `None` for the full sphere (which skips the clipping tests).
    clip: Option<Box<SphereClip>>,
    /// Boxed so that the `Shape` enum stays small for the triangles that dominate scenes.
    world_from_object: Box<Transform>,
    flip_normals: bool,
    /// `|det|` of the linear part, for the area Jacobian.
    abs_det: f32,
}

/// The part of a sphere kept: heights `z_min..=z_max` and azimuths `0..=phi_max`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereClip {
    /// Lowest height kept.
    pub z_min: f32,
    /// Highest height kept.
    pub z_max: f32,
    /// Largest azimuth kept, in radians (up to 2 pi).
    pub phi_max: f32,
}

impl SphereClip {
    /// The whole sphere of `radius`.
    #[must_use]
    pub fn full(radius: f32) -> Self {
        Self {
            z_min: -radius,
            z_max: radius,
            phi_max: 2.0 * PI,
        }
    }

    /// The polar angles of `z_min` (the larger) and `z_max`.
    fn theta_range(&self, radius: f32) -> (f32, f32) {
        (
            (self.z_min / radius).clamp(-1.0, 1.0).acos(),
            (self.z_max / radius).clamp(-1.0, 1.0).acos(),
        )
    }
}

impl Sphere {
    /// A sphere of `radius` placed by `world_from_object`; `flip_normals` makes the normal
    /// point inwards.
    #[must_use]
    pub fn new(radius: f32, world_from_object: Transform, flip_normals: bool) -> Self {
        Self::partial(radius, SphereClip::full(radius), world_from_object, flip_normals)
    }

    /// The part `clip` of a sphere of `radius` (heights clamped to `[-radius, radius]`, the
    /// azimuth to `[0, 2 pi]`).
    #[must_use]
    pub fn partial(radius: f32, clip: SphereClip, world_from_object: Transform, flip_normals: bool) -> Self {
        let abs_det = Mat3::from_mat4(world_from_object.m).determinant().abs();
        let (z0, z1) = (clip.z_min.min(clip.z_max), clip.z_min.max(clip.z_max));
        let clip = SphereClip {
            z_min: z0.clamp(-radius, radius),
            z_max: z1.clamp(-radius, radius),
            phi_max: clip.phi_max.clamp(0.0, 2.0 * PI),
        };
        let is_full = clip.z_min <= -radius && clip.z_max >= radius && clip.phi_max >= 2.0 * PI;
        Self {
            radius,
            clip: if is_full { None } else { Some(Box::new(clip)) },
            world_from_object: Box::new(world_from_object),
            flip_normals,
            abs_det,
        }
    }

    /// World-space bounds (the transformed object-space box).
    #[must_use]
    pub fn bounds(&self) -> Bounds3 {
        let r = self.radius;
        let c = self.clip_or_full();
        let mut b = Bounds3::EMPTY;
        for i in 0..8 {
            let c = Vec3::new(
                if i & 1 == 0 { -r } else { r },
                if i & 2 == 0 { -r } else { r },
                if i & 4 == 0 { c.z_min } else { c.z_max },
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

    /// The cut (the full range for a full sphere).
    fn clip_or_full(&self) -> SphereClip {
        self.clip
            .as_deref()
            .copied()
            .unwrap_or_else(|| SphereClip::full(self.radius))
    }

    /// Object-space area: `phi_max r (z_max - z_min)` (Archimedes: area is uniform in z).
    fn object_area(&self) -> f32 {
        match self.clip.as_deref() {
            None => 4.0 * PI * self.radius * self.radius,
            Some(c) => c.phi_max * self.radius * (c.z_max - c.z_min),
        }
    }

    /// Surface area in world space; exact for uniform scales, and `|det|^(2/3)` times the
    /// object-space area (used only to estimate light power) otherwise.
    #[must_use]
    pub fn area(&self) -> f32 {
        self.object_area() * self.abs_det.powf(2.0 / 3.0)
    }

    /// False when the object-space point `p` on the sphere lies outside the cut.
    fn kept(&self, p: DVec3) -> bool {
        let Some(c) = self.clip.as_deref() else { return true };
        let r = f64::from(self.radius);
        if (f64::from(c.z_min) > -r && p.z < f64::from(c.z_min)) || (f64::from(c.z_max) < r && p.z > f64::from(c.z_max))
        {
            return false;
        }
        let phi = p.y.atan2(p.x).rem_euclid(std::f64::consts::TAU);
        phi <= f64::from(c.phi_max)
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
        // The nearer root in range whose point the cut keeps.
        let t = [t0, t1]
            .into_iter()
            .find(|&t| t > eps && t < t_max && self.kept(o + t * d))?;
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
        // pbrt's parameterisation: u = phi / phi_max, v from theta(z_min) (the south pole
        // for a full sphere) to theta(z_max).
        let c = self.clip_or_full();
        let (theta_min, theta_max) = c.theta_range(self.radius);
        let uv = Vec2::new(
            phi / c.phi_max,
            (cos_theta.acos() - theta_min) / (theta_max - theta_min),
        );
        let dpdu_obj = Vec3::new(-p_obj.y, p_obj.x, 0.0);
        let dpdu = self.world_from_object.vector(dpdu_obj);
        // pbrt-v4 eq. 6.3-6.4.
        let dp_du = c.phi_max * dpdu;
        let r_xy = (p_obj.x * p_obj.x + p_obj.y * p_obj.y).sqrt();
        let (cos_phi, sin_phi) = if r_xy > 0.0 {
            (p_obj.x / r_xy, p_obj.y / r_xy)
        } else {
            (1.0, 0.0)
        };
        let dp_dv = self
            .world_from_object
            .vector((theta_max - theta_min) * Vec3::new(p_obj.z * cos_phi, p_obj.z * sin_phi, -r_xy));
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

    /// Ratio of world to object area around the object-space unit normal `n_obj`:
    /// `|det M| |M^-T n|` for the linear part `M`.
    fn area_jacobian(&self, n_obj: Vec3) -> f32 {
        self.abs_det * self.world_from_object.normal(n_obj).length()
    }

    /// A point uniform by area in object space; the pdf returned is the world-space density.
    /// A partial sphere is sampled over its own part only: height uniform in
    /// `[z_min, z_max]` (area is uniform in z) and azimuth in `[0, phi_max]`, where pbrt-v4
    /// samples the whole sphere.
    #[must_use]
    pub fn sample_area(&self, u: Vec2) -> ShapeSample {
        let n_obj = match self.clip.as_deref() {
            None => sample_uniform_sphere(u),
            Some(c) => {
                let z = (c.z_min + u.x * (c.z_max - c.z_min)) / self.radius;
                let r_xy = (1.0 - z * z).max(0.0).sqrt();
                let phi = u.y * c.phi_max;
                Vec3::new(r_xy * phi.cos(), r_xy * phi.sin(), z)
            }
        };
        let si = self.interaction_at(self.radius * n_obj, Vec3::ZERO, 0.0);
        let pdf_obj = 1.0 / self.object_area();
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
        let pdf_obj = 1.0 / self.object_area();
        pdf_obj / self.area_jacobian(n_obj)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cut(z_min: f32, z_max: f32, phi_max_degrees: f32) -> Sphere {
        let clip = SphereClip {
            z_min,
            z_max,
            phi_max: phi_max_degrees.to_radians(),
        };
        Sphere::partial(1.0, clip, Transform::IDENTITY, false)
    }

    #[test]
    fn cuts_let_rays_through_to_the_part_kept() {
        let up = Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z);
        // Full sphere: the bottom at t = 4.
        assert!(
            (Sphere::new(1.0, Transform::IDENTITY, false)
                .intersect(&up, 100.0)
                .unwrap()
                .t
                - 4.0)
                .abs()
                < 1e-5
        );
        // Upper hemisphere: through the open bottom to the inside of the top, t = 6.
        let h = cut(0.0, 1.0, 360.0);
        assert!((h.intersect(&up, 100.0).unwrap().t - 6.0).abs() < 1e-5);
        assert!(h.intersect(&up, 5.5).is_none(), "t_max before the top");
        // A band |z| <= 0.5: a ray along the axis misses both caps.
        assert!(cut(-0.5, 0.5, 360.0).intersect(&up, 100.0).is_none());
        // phimax 90 degrees: a ray along -x from x = 5 at y = 0.5 meets the sphere at
        // phi ~ 30 degrees (kept) first; one at y = -0.5 (phi ~ -30 = 330 degrees, cut) goes
        // on to phi ~ 210 degrees, also cut, and misses.
        let q = cut(-1.0, 1.0, 90.0);
        let hit = q
            .intersect(&Ray::new(Vec3::new(5.0, 0.5, 0.0), -Vec3::X), 100.0)
            .unwrap();
        assert!((hit.t - (5.0 - 0.75f32.sqrt())).abs() < 1e-5);
        assert!(q
            .intersect(&Ray::new(Vec3::new(5.0, -0.5, 0.0), -Vec3::X), 100.0)
            .is_none());
    }

    #[test]
    fn area_uv_and_samples_follow_the_cut() {
        let s = cut(-0.25, 0.5, 180.0);
        // Archimedes: phi_max r (z_max - z_min).
        assert!((s.area() - PI * 0.75).abs() < 1e-5);
        let (mut sum_z, n) = (0.0f64, 4096);
        for i in 0..n {
            let u = Vec2::new((i as f32 + 0.5) / n as f32, ((i * 37 % n) as f32 + 0.5) / n as f32);
            let sample = s.sample_area(u);
            let p = sample.intr.p;
            assert!((-0.25 - 1e-5..=0.5 + 1e-5).contains(&p.z) && p.y >= -1e-5, "{p}");
            assert!((sample.pdf_area - 1.0 / s.area()).abs() < 1e-4);
            sum_z += f64::from(p.z);
        }
        // Uniform by area means uniform in z: mean height at the middle of the band.
        assert!((sum_z / f64::from(n) - 0.125).abs() < 1e-3, "{}", sum_z / f64::from(n));
        // uv spans [0, 1] over the cut: u = phi / phi_max, v from z_min to z_max.
        let ray = Ray::new(Vec3::new(0.0, 5.0, 0.5), -Vec3::Y);
        let hit = s.intersect(&ray, 100.0).unwrap();
        let si = s.interaction(&ray, &hit);
        assert!(
            (si.uv.x - 0.5).abs() < 1e-4 && (si.uv.y - 1.0).abs() < 1e-4,
            "{:?}",
            si.uv
        );
    }
}
