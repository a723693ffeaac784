//! Disks (and annuli and sectors) in the plane `z = height` of their object space, centred
//! on the z axis and placed by an affine transform (pbrt-v4's `Disk`). The hit point's `z`
//! is set exactly to `height`, so the object-space point carries no error beyond the
//! transform's (pbrt-v4 6.8.5). The object-space normal is `+z`, flipped by
//! `ReverseOrientation` xor a handedness-swapping transform, as for spheres.

use super::{Interaction, ShapeHit, ShapeSample, SurfaceInteraction};
use crate::math::{gamma, Bounds3, Mat3, Ray, Transform, Vec2, Vec3, PI};
use crate::sampling::sample_uniform_disk_concentric;

/// A disk of `radius` with an optional hole of `inner_radius`, swept to `phi_max` radians.
#[derive(Clone, Debug)]
pub struct Disk {
    height: f32,
    radius: f32,
    inner_radius: f32,
    phi_max: f32,
    /// Boxed so that the `Shape` enum stays small for the triangles that dominate scenes.
    world_from_object: Box<Transform>,
    /// World-space unit normal (constant over the disk), already flipped if asked.
    n: Vec3,
    /// World area / object area: `|det M| |M^-T z|` for the linear part `M`.
    area_jacobian: f32,
}

impl Disk {
    /// A disk in the plane `z = height` of object space; `phi_max` in radians (clamped to
    /// `[0, 2 pi]`); `flip_normals` makes the normal point to `-z` (object space).
    #[must_use]
    pub fn new(
        height: f32,
        radius: f32,
        inner_radius: f32,
        phi_max: f32,
        world_from_object: Transform,
        flip_normals: bool,
    ) -> Self {
        let abs_det = Mat3::from_mat4(world_from_object.m).determinant().abs();
        let n_world = world_from_object.normal(Vec3::Z);
        let area_jacobian = abs_det * n_world.length();
        let n = n_world.normalize_or_zero();
        Self {
            height,
            radius,
            inner_radius: inner_radius.clamp(0.0, radius),
            phi_max: phi_max.clamp(0.0, 2.0 * PI),
            world_from_object: Box::new(world_from_object),
            n: if flip_normals { -n } else { n },
            area_jacobian,
        }
    }

    /// World-space bounds (the transformed object-space box, padded by the transform's
    /// rounding).
    #[must_use]
    pub fn bounds(&self) -> Bounds3 {
        let r = self.radius;
        let mut b = Bounds3::EMPTY;
        for i in 0..4 {
            let c = Vec3::new(
                if i & 1 == 0 { -r } else { r },
                if i & 2 == 0 { -r } else { r },
                self.height,
            );
            b = b.union_point(self.world_from_object.point(c));
        }
        let pad = gamma(3) * b.min.abs().max(b.max.abs());
        Bounds3 {
            min: b.min - pad,
            max: b.max + pad,
        }
    }

    /// Object-space area.
    fn object_area(&self) -> f32 {
        0.5 * self.phi_max * (self.radius * self.radius - self.inner_radius * self.inner_radius)
    }

    /// Surface area in world space (exact for any affine transform: the disk is planar).
    #[must_use]
    pub fn area(&self) -> f32 {
        self.object_area() * self.area_jacobian
    }

    /// Closest intersection; `data` holds the object-space hit point.
    #[must_use]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        let inv = &self.world_from_object.m_inv;
        let o = inv.transform_point3(ray.o);
        let d = inv.transform_vector3(ray.d);
        if d.z == 0.0 {
            return None;
        }
        let t = (self.height - o.z) / d.z;
        if !(t > 0.0 && t < t_max) {
            return None;
        }
        let p = o + t * d;
        let dist2 = p.x * p.x + p.y * p.y;
        if dist2 > self.radius * self.radius || dist2 < self.inner_radius * self.inner_radius {
            return None;
        }
        if self.phi_max < 2.0 * PI && p.y.atan2(p.x).rem_euclid(2.0 * PI) > self.phi_max {
            return None;
        }
        Some(ShapeHit {
            t,
            data: [p.x, p.y, self.height],
        })
    }

    /// The surface point for an object-space point on the disk.
    fn interaction_at(&self, p_obj: Vec3, wo: Vec3, t: f32) -> SurfaceInteraction {
        let p_obj = Vec3::new(p_obj.x, p_obj.y, self.height);
        // The object-space point is exact in z and carries no tracked error (pbrt-v4); the
        // transform adds its own rounding.
        let (p, p_error) = self.world_from_object.point_with_error(p_obj, Vec3::ZERO);
        let r_hit = (p_obj.x * p_obj.x + p_obj.y * p_obj.y).sqrt();
        let phi = p_obj.y.atan2(p_obj.x).rem_euclid(2.0 * PI);
        // pbrt's parameterisation: u = phi / phi_max, v = 0 at the rim, 1 at the inner edge.
        let v = if self.radius > self.inner_radius {
            (self.radius - r_hit) / (self.radius - self.inner_radius)
        } else {
            0.0
        };
        let uv = Vec2::new(if self.phi_max > 0.0 { phi / self.phi_max } else { 0.0 }, v);
        let n = self.n;
        let dpdu = self.world_from_object.vector(Vec3::new(-p_obj.y, p_obj.x, 0.0));
        // pbrt-v4 section 6.5.1: dp/du = phi_max (-y, x, 0), dp/dv = (x, y, 0) (r_i - r) / r.
        let dp_du = self.phi_max * dpdu;
        let dp_dv = if r_hit > 0.0 {
            self.world_from_object
                .vector(Vec3::new(p_obj.x, p_obj.y, 0.0) * ((self.inner_radius - self.radius) / r_hit))
        } else {
            Vec3::ZERO
        };
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

    /// A point uniform by area: the concentric map for a full disk, otherwise the polar map
    /// restricted to the annulus sector (pbrt-v4 ignores `innerradius` and `phimax` here;
    /// we sample the surface that is actually intersected).
    #[must_use]
    pub fn sample_area(&self, u: Vec2) -> ShapeSample {
        let pd = if self.inner_radius == 0.0 && self.phi_max >= 2.0 * PI {
            self.radius * sample_uniform_disk_concentric(u)
        } else {
            let (ri2, r2) = (self.inner_radius * self.inner_radius, self.radius * self.radius);
            let r = (ri2 + u.x * (r2 - ri2)).sqrt();
            let phi = u.y * self.phi_max;
            r * Vec2::new(phi.cos(), phi.sin())
        };
        let si = self.interaction_at(pd.extend(self.height), Vec3::ZERO, 0.0);
        ShapeSample {
            intr: si.intr,
            pdf_area: 1.0 / self.area(),
            uv: si.uv,
        }
    }

    /// World-space density of [`Self::sample_area`]: uniform, so `1 / area`.
    #[must_use]
    pub fn pdf_area(&self, _intr: &Interaction) -> f32 {
        1.0 / self.area()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Mat4;
    use crate::sampling::Pcg32;

    fn placed() -> Transform {
        let m = Mat4::from_translation(Vec3::new(0.3, -0.2, 1.5))
            * Mat4::from_rotation_x(0.7)
            * Mat4::from_scale(Vec3::new(1.5, 0.6, 1.0));
        Transform::new(m).unwrap()
    }

    /// Rays from random origins towards random object-space points: a point inside the
    /// annulus sector must be hit at the right distance, one outside must be missed.
    #[test]
    fn rays_hit_exactly_the_annulus_sector() {
        let t = placed();
        let disk = Disk::new(0.4, 1.0, 0.3, 1.5 * PI, t, false);
        let mut rng = Pcg32::new(7, 1);
        let (mut hits, mut misses) = (0, 0);
        for _ in 0..20_000 {
            let target_obj = Vec3::new(2.4 * rng.next_f32() - 1.2, 2.4 * rng.next_f32() - 1.2, 0.4);
            let o = Vec3::new(
                4.0 * rng.next_f32() - 2.0,
                4.0 * rng.next_f32() - 2.0,
                4.0 * rng.next_f32() - 2.0,
            );
            let target = t.point(target_obj);
            let ray = Ray::new(o, target - o);
            let r = target_obj.truncate().length();
            let phi = target_obj.y.atan2(target_obj.x).rem_euclid(2.0 * PI);
            // Skip grazing rays (the hit is ill-conditioned along them) and points within
            // rounding of an edge.
            let d_obj = t.m_inv.transform_vector3(ray.d).normalize();
            if d_obj.z.abs() < 0.05 {
                continue;
            }
            if (r - 1.0).abs() < 1e-3 || (r - 0.3).abs() < 1e-3 || (phi - 1.5 * PI).abs() < 1e-3 || phi < 1e-3 {
                continue;
            }
            let inside = r < 1.0 && r > 0.3 && phi < 1.5 * PI;
            match disk.intersect(&ray, f32::INFINITY) {
                Some(hit) => {
                    assert!(inside, "hit outside at {target_obj}");
                    assert!((hit.t - 1.0).abs() < 1e-3, "t = {}", hit.t);
                    let si = disk.interaction(&ray, &hit);
                    assert!((si.p() - target).length() < 1e-3);
                    // The error bound is what keeps spawned rays off the surface: an origin
                    // offset to either side must be on that side of the plane, checked in f64.
                    let inv = t.m.as_dmat4().inverse();
                    for side in [1.0f32, -1.0] {
                        let o = si.intr.offset_origin(side * si.n());
                        let z = inv.transform_point3(o.as_dvec3()).z - 0.4;
                        assert!(z * f64::from(side) > 0.0, "offset origin on the wrong side: {z}");
                    }
                    assert!((si.uv.x - phi / (1.5 * PI)).abs() < 1e-3);
                    assert!((si.uv.y - (1.0 - r) / 0.7).abs() < 1e-3, "{} {r}", si.uv.y);
                    assert!(disk.bounds().contains(si.p()));
                    hits += 1;
                }
                None => {
                    assert!(!inside, "missed inside at {target_obj}");
                    misses += 1;
                }
            }
            // The segment stopping short of the plane never hits.
            assert!(disk.intersect(&ray, 0.99).is_none());
        }
        assert!(hits > 1000 && misses > 1000, "{hits} {misses}");
    }

    #[test]
    fn normal_is_object_z_flipped_on_request() {
        let t = Transform::new(Mat4::from_rotation_x(0.5)).unwrap();
        let n = t.normal(Vec3::Z).normalize();
        for (flip, sign) in [(false, 1.0), (true, -1.0)] {
            let disk = Disk::new(0.0, 1.0, 0.0, 2.0 * PI, t, flip);
            let ray = Ray::new(n * 2.0, -n);
            let hit = disk.intersect(&ray, f32::INFINITY).unwrap();
            assert!((disk.interaction(&ray, &hit).n() - sign * n).length() < 1e-5);
            assert!((disk.sample_area(Vec2::new(0.3, 0.6)).intr.n - sign * n).length() < 1e-5);
        }
    }

    /// The area includes the Jacobian of the transform; samples land on the disk.
    #[test]
    fn area_and_samples_follow_the_transform() {
        let t = placed();
        let disk = Disk::new(0.4, 1.0, 0.3, 1.5 * PI, t, false);
        // A non-uniform scale (1.5, 0.6) of the xy plane; the rotation keeps areas.
        let expected = 0.5 * 1.5 * PI * (1.0 - 0.09) * 1.5 * 0.6;
        assert!((disk.area() - expected).abs() < 1e-5 * expected);
        let mut rng = Pcg32::new(3, 2);
        for _ in 0..1000 {
            let s = disk.sample_area(Vec2::new(rng.next_f32(), rng.next_f32()));
            let p_obj = t.m_inv.transform_point3(s.intr.p);
            let r = p_obj.truncate().length();
            let phi = p_obj.y.atan2(p_obj.x).rem_euclid(2.0 * PI);
            assert!((p_obj.z - 0.4).abs() < 1e-5 && (0.3 - 1e-5..=1.0 + 1e-5).contains(&r));
            assert!(phi <= 1.5 * PI + 1e-4 || phi > 2.0 * PI - 1e-4);
            assert!((s.pdf_area - 1.0 / expected).abs() < 1e-4 / expected);
            assert_eq!(s.pdf_area, disk.pdf_area(&s.intr));
        }
    }
}
