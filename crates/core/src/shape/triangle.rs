//! Triangles: watertight ray intersection (Woop, Benthin and Wald 2013, as in pbrt-v4
//! section 6.5.3) with a conservative bound on the hit distance's error, and uniform
//! sampling by area.

use std::sync::Arc;

use super::{Interaction, ShapeHit, ShapeSample, SurfaceInteraction, TriangleMesh};
use crate::math::{gamma, Bounds3, Frame, Ray, Vec2, Vec3};
use crate::sampling::sample_uniform_triangle;

/// One triangle of a shared mesh. The vertex positions are copied in, so intersection
/// touches only the primitive itself, not the mesh's index and position arrays.
#[derive(Clone, Debug)]
pub struct Triangle {
    /// The mesh (normals and uvs are read from it at hits).
    pub mesh: Arc<TriangleMesh>,
    /// Index of the triangle in the mesh.
    pub index: u32,
    p: [Vec3; 3],
    /// The unit geometric normal `(p0 - p2) x (p1 - p2)`, before any flip (NaN for a
    /// zero-area triangle, which no ray hits): made once here rather than at every hit,
    /// where its square root and division were on the critical path of `geometry_at`.
    n: Vec3,
    /// The unit shading normal when the mesh's three vertex normals of this triangle are
    /// equal (a flat face, as every face of the Cornell box): interpolating them gives that
    /// normal again up to rounding, so `geometry_at` takes it from here instead of reading
    /// the mesh's normals and normalising their blend at every hit.
    flat_ns: Option<Vec3>,
}

/// `a*b - c*d` with one rounding (Kahan's algorithm via fused multiply-add).
#[inline]
fn difference_of_products(a: f32, b: f32, c: f32, d: f32) -> f32 {
    let cd = c * d;
    let err = (-c).mul_add(d, cd);
    let dop = a.mul_add(b, -cd);
    dop + err
}

/// Permute the components of `v` to `(v[x], v[y], v[z])`.
#[inline]
fn permute(v: Vec3, x: usize, y: usize, z: usize) -> Vec3 {
    Vec3::new(v[x], v[y], v[z])
}

impl Triangle {
    /// Triangle `index` of `mesh`.
    #[must_use]
    pub fn new(mesh: Arc<TriangleMesh>, index: u32) -> Self {
        let [a, b, c] = mesh.vertices(index);
        let p = [mesh.positions[a], mesh.positions[b], mesh.positions[c]];
        let n = (p[0] - p[2]).cross(p[1] - p[2]).normalize();
        let flat_ns = mesh.normals.as_ref().and_then(|normals| {
            let (na, nb, nc) = (normals[a], normals[b], normals[c]);
            (na == nb && nb == nc).then(|| na.try_normalize()).flatten()
        });
        Self {
            mesh,
            index,
            p,
            n,
            flat_ns,
        }
    }

    /// Vertex positions (world space).
    #[inline]
    #[must_use]
    pub fn positions(&self) -> [Vec3; 3] {
        self.p
    }

    /// World-space bounds.
    #[must_use]
    pub fn bounds(&self) -> Bounds3 {
        let [p0, p1, p2] = self.positions();
        Bounds3::from_point(p0).union_point(p1).union_point(p2)
    }

    /// Area.
    #[must_use]
    pub fn area(&self) -> f32 {
        let [p0, p1, p2] = self.positions();
        0.5 * (p1 - p0).cross(p2 - p0).length()
    }

    /// Watertight intersection: the ray is transformed so it runs along +z from the origin,
    /// the triangle is sheared accordingly, and edge functions decide inside/outside with no
    /// gaps between neighbouring triangles.
    #[must_use]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        let [p0, p1, p2] = self.positions();
        if (p2 - p0).cross(p1 - p0).length_squared() == 0.0 {
            return None;
        }
        // Translate to the ray origin, then permute so the largest |d| component is z.
        let kz = ray.d.abs().max_position();
        let kx = if kz == 2 { 0 } else { kz + 1 };
        let ky = if kx == 2 { 0 } else { kx + 1 };
        let d = permute(ray.d, kx, ky, kz);
        let mut p0t = permute(p0 - ray.o, kx, ky, kz);
        let mut p1t = permute(p1 - ray.o, kx, ky, kz);
        let mut p2t = permute(p2 - ray.o, kx, ky, kz);
        // Shear so the ray direction becomes +z.
        let sx = -d.x / d.z;
        let sy = -d.y / d.z;
        let sz = 1.0 / d.z;
        p0t.x += sx * p0t.z;
        p0t.y += sy * p0t.z;
        p1t.x += sx * p1t.z;
        p1t.y += sy * p1t.z;
        p2t.x += sx * p2t.z;
        p2t.y += sy * p2t.z;
        // Edge functions; recomputed in double precision when one is exactly zero.
        let mut e0 = difference_of_products(p1t.x, p2t.y, p1t.y, p2t.x);
        let mut e1 = difference_of_products(p2t.x, p0t.y, p2t.y, p0t.x);
        let mut e2 = difference_of_products(p0t.x, p1t.y, p0t.y, p1t.x);
        if e0 == 0.0 || e1 == 0.0 || e2 == 0.0 {
            let f = |a: f32, b: f32, c: f32, d: f32| (f64::from(a) * f64::from(b) - f64::from(c) * f64::from(d)) as f32;
            e0 = f(p1t.x, p2t.y, p1t.y, p2t.x);
            e1 = f(p2t.x, p0t.y, p2t.y, p0t.x);
            e2 = f(p0t.x, p1t.y, p0t.y, p1t.x);
        }
        if (e0 < 0.0 || e1 < 0.0 || e2 < 0.0) && (e0 > 0.0 || e1 > 0.0 || e2 > 0.0) {
            return None;
        }
        let det = e0 + e1 + e2;
        if det == 0.0 {
            return None;
        }
        // Scaled hit distance, compared against the range before the division.
        p0t.z *= sz;
        p1t.z *= sz;
        p2t.z *= sz;
        let t_scaled = e0 * p0t.z + e1 * p1t.z + e2 * p2t.z;
        if det < 0.0 && (t_scaled >= 0.0 || t_scaled < t_max * det) {
            return None;
        }
        if det > 0.0 && (t_scaled <= 0.0 || t_scaled > t_max * det) {
            return None;
        }
        let inv_det = 1.0 / det;
        let (b0, b1, b2) = (e0 * inv_det, e1 * inv_det, e2 * inv_det);
        let t = t_scaled * inv_det;
        // Reject hits whose distance is not certainly positive (pbrt-v4 eq. 6.29-6.33).
        let max_zt = Vec3::new(p0t.z, p1t.z, p2t.z).abs().max_element();
        let delta_z = gamma(3) * max_zt;
        let max_xt = Vec3::new(p0t.x, p1t.x, p2t.x).abs().max_element();
        let max_yt = Vec3::new(p0t.y, p1t.y, p2t.y).abs().max_element();
        let delta_x = gamma(5) * (max_xt + max_zt);
        let delta_y = gamma(5) * (max_yt + max_zt);
        let delta_e = 2.0 * (gamma(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
        let max_e = Vec3::new(e0, e1, e2).abs().max_element();
        let delta_t = 3.0 * (gamma(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * inv_det.abs();
        // (A NaN distance, from a NaN direction, is no hit either.)
        if t.is_nan() || t <= delta_t {
            return None;
        }
        Some(ShapeHit { t, data: [b0, b1, b2] })
    }

    /// The point, its error bound and geometric normal, the uv and the shading normal at
    /// barycentrics `b`: what [`Self::interaction_at`] and [`Self::sample_area`] share (the
    /// light samples need no tangents). Always inlined: returned through memory, its
    /// fields were written with narrower stores than the caller's 16-byte loads read back,
    /// which stalled each load until the stores retired (failed store-to-load forwarding,
    /// `perf annotate`: 18% of the interaction's samples). Inlined it takes 1.2% more
    /// instructions and 0.93x the time on the Cornell box.
    #[inline(always)]
    fn geometry_at(&self, b: [f32; 3]) -> (Interaction, Vec2, Vec3, [Vec2; 3]) {
        let [p0, p1, p2] = self.positions();
        // The vertex indices are read only for uvs or normals (a mesh without either, such
        // as the Cornell box's, needs nothing from the mesh here).
        let vertices = || self.mesh.vertices(self.index);
        let p = b[0] * p0 + b[1] * p1 + b[2] * p2;
        // Error of the barycentric interpolation (pbrt-v4 eq. 6.30).
        let p_error = gamma(7) * ((b[0] * p0).abs() + (b[1] * p1).abs() + (b[2] * p2).abs());
        let uvs = match &self.mesh.uvs {
            Some(uv) => {
                let [i0, i1, i2] = vertices();
                [uv[i0], uv[i1], uv[i2]]
            }
            None => [Vec2::ZERO, Vec2::X, Vec2::ONE],
        };
        let uv = b[0] * uvs[0] + b[1] * uvs[1] + b[2] * uvs[2];
        // The shading normal: a flat face's, made once, or the blend of the vertex normals;
        // none where the mesh has no normals or their blend is zero. (A `match`: through
        // `Option::or_else`, left out of line, the normal came back through memory and its
        // load waited for the stores, as in this function's comment.)
        let shading = match (self.flat_ns, &self.mesh.normals) {
            (Some(ns), _) => Some(ns),
            (None, Some(normals)) => {
                let [i0, i1, i2] = vertices();
                (b[0] * normals[i0] + b[1] * normals[i1] + b[2] * normals[i2]).try_normalize()
            }
            (None, None) => None,
        };
        let mut n = self.n;
        let ns = match shading {
            // The geometric normal follows the shading normal's side when one is given.
            Some(ns) => {
                if n.dot(ns) < 0.0 {
                    n = -n;
                }
                ns
            }
            None => {
                if self.mesh.flip_normals {
                    n = -n;
                }
                n
            }
        };
        (Interaction { p, p_error, n }, uv, ns, uvs)
    }

    /// The interaction at barycentrics `b` (always inlined, so that
    /// [`Self::interaction_into`] writes the fields in place).
    #[inline(always)]
    fn interaction_at(&self, b: [f32; 3], wo: Vec3, t: f32) -> SurfaceInteraction {
        let (intr, uv, ns, [uv0, uv1, uv2]) = self.geometry_at(b);
        let [p0, p1, p2] = self.positions();
        let n = intr.n;
        // dp/du from the uv parameterisation, falling back to any tangent.
        let duv02 = uv0 - uv2;
        let duv12 = uv1 - uv2;
        let (dp02, dp12) = (p0 - p2, p1 - p2);
        let det = duv02.x * duv12.y - duv02.y * duv12.x;
        let (dp_du, dp_dv) = if det.abs() > 1e-9 {
            (
                (duv12.y * dp02 - duv02.y * dp12) / det,
                (duv02.x * dp12 - duv12.x * dp02) / det,
            )
        } else {
            (Vec3::ZERO, Vec3::ZERO)
        };
        let (dpdu, bitangent_sign) = self
            .shading_tangent(b, ns)
            .unwrap_or((Frame::from_zx(ns, dp_du).x, 1.0));
        // Degenerate uvs: any tangents, as pbrt-v4's CoordinateSystem(n).
        let (dp_du, dp_dv) = if dp_du.cross(dp_dv).length_squared() == 0.0 {
            let f = Frame::from_z(n);
            (f.x, f.y)
        } else {
            (dp_du, dp_dv)
        };
        SurfaceInteraction {
            intr,
            ns,
            dpdu,
            dp_du,
            dp_dv,
            uv,
            wo,
            t,
            mesh: crate::shape::MeshPoint {
                triangle: self.index,
                b,
            },
            unmapped_ns: None,
            bitangent_sign,
        }
    }

    /// The mesh's own tangent at barycentrics `b` (glTF's `TANGENT`), made orthogonal to
    /// `ns`, with the sign of its interpolated handedness; `None` without tangents and
    /// shading normals, or where the interpolated tangent is parallel to `ns`.
    fn shading_tangent(&self, b: [f32; 3], ns: Vec3) -> Option<(Vec3, f32)> {
        let (tangents, _) = self.mesh.tangents.as_ref().zip(self.mesh.normals.as_ref())?;
        let [i0, i1, i2] = self.mesh.vertices(self.index);
        let t = b[0] * tangents[i0] + b[1] * tangents[i1] + b[2] * tangents[i2];
        let x = (t.truncate() - ns * ns.dot(t.truncate())).try_normalize()?;
        Some((x, if t.w < 0.0 { -1.0 } else { 1.0 }))
    }

    /// The interaction for a hit from [`Self::intersect`].
    #[must_use]
    pub fn interaction(&self, ray: &Ray, hit: &ShapeHit) -> SurfaceInteraction {
        self.interaction_at(hit.data, -ray.d.normalize(), hit.t)
    }

    /// [`Self::interaction`], written into `si` in place: `interaction_at` is always
    /// inlined here, so its fields go straight into `si`. (Assigning what a call returns
    /// would build the 144 bytes in a temporary and copy them, because a call that unwinds
    /// must not leave `si` half written.)
    pub fn interaction_into(&self, ray: &Ray, hit: &ShapeHit, si: &mut SurfaceInteraction) {
        *si = self.interaction_at(hit.data, -ray.d.normalize(), hit.t);
    }

    /// A point uniformly distributed by area.
    #[must_use]
    pub fn sample_area(&self, u: Vec2) -> ShapeSample {
        let (intr, uv, _, _) = self.geometry_at(sample_uniform_triangle(u));
        ShapeSample {
            intr,
            pdf_area: 1.0 / self.area(),
            uv,
        }
    }

    /// Density of [`Self::sample_area`]: constant.
    #[must_use]
    pub fn pdf_area(&self, _intr: &Interaction) -> f32 {
        1.0 / self.area()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec4;

    /// The triangle (0,0,0), (1,0,0), (0,1,0) with normals +z and uvs along x and y, so
    /// that dp/du is +x; `tangents` per vertex if given.
    fn triangle(tangents: Option<Vec<Vec4>>) -> Triangle {
        triangle_with_normals(Some(vec![Vec3::Z; 3]), tangents)
    }

    fn triangle_with_normals(normals: Option<Vec<Vec3>>, tangents: Option<Vec<Vec4>>) -> Triangle {
        let mesh = TriangleMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            indices: vec![0, 1, 2],
            normals,
            uvs: Some(vec![Vec2::ZERO, Vec2::X, Vec2::Y]),
            tangents,
            flip_normals: false,
        };
        Triangle::new(Arc::new(mesh), 0)
    }

    fn hit_at(t: &Triangle, x: f32, y: f32) -> SurfaceInteraction {
        let ray = Ray::new(Vec3::new(x, y, 1.0), -Vec3::Z);
        let hit = t.intersect(&ray, f32::INFINITY).expect("the ray hits");
        t.interaction(&ray, &hit)
    }

    #[test]
    fn without_tangents_the_shading_tangent_is_dp_du() {
        let si = hit_at(&triangle(None), 0.2, 0.3);
        assert!((si.dpdu - Vec3::X).length() < 1e-6, "{}", si.dpdu);
        assert_eq!(si.bitangent_sign, 1.0);
    }

    #[test]
    fn given_tangents_are_interpolated_made_orthogonal_to_the_normal_and_keep_their_sign() {
        // Tangents along y with some z (removed against the normal), mirrored bitangent;
        // a vertex's tangent that differs shows the interpolation.
        let t = vec![
            Vec4::new(0.0, 1.0, 0.5, -1.0),
            Vec4::new(0.0, 1.0, 0.5, -1.0),
            Vec4::new(1.0, 1.0, 0.0, -1.0),
        ];
        // At (x, y) the weights are (1 - x - y, x, y): the tangent is (y, 1, (1 - y) / 2).
        for (x, y) in [(0.3, 0.1), (0.1, 0.5)] {
            let si = hit_at(&triangle(Some(t.clone())), x, y);
            let expected = Vec3::new(y, 1.0, 0.0).normalize();
            assert!((si.dpdu - expected).length() < 1e-5, "{} at ({x}, {y})", si.dpdu);
            assert!(si.dpdu.dot(si.ns).abs() < 1e-6);
            assert_eq!(si.bitangent_sign, -1.0);
        }
    }

    #[test]
    fn tangents_along_the_normal_or_without_normals_fall_back_to_dp_du() {
        let along_n = vec![Vec4::new(0.0, 0.0, 1.0, -1.0); 3];
        let si = hit_at(&triangle(Some(along_n)), 0.2, 0.3);
        assert!((si.dpdu - Vec3::X).length() < 1e-6, "{}", si.dpdu);
        assert_eq!(si.bitangent_sign, 1.0);
        let t = triangle_with_normals(None, Some(vec![Vec4::new(0.0, 1.0, 0.0, -1.0); 3]));
        let si = hit_at(&t, 0.2, 0.3);
        assert!((si.dpdu - Vec3::X).length() < 1e-6, "{}", si.dpdu);
        assert_eq!(si.bitangent_sign, 1.0);
    }

    /// Equal vertex normals (a flat face, unnormalised and facing away from the winding's
    /// normal) give the same shading and geometric normals as interpolated unequal ones
    /// that blend to the same direction, and the geometric normal follows their side.
    #[test]
    fn flat_vertex_normals_match_interpolated_ones() {
        let down = Vec3::new(0.0, 0.0, -2.0);
        let flat = triangle_with_normals(Some(vec![down; 3]), None);
        assert!(flat.flat_ns.is_some());
        // Tilted normals whose blend at (1/3, 1/3) is -z: their tilts cancel there.
        let tilted = vec![
            Vec3::new(0.2, 0.1, -1.0),
            Vec3::new(-0.1, 0.1, -1.0),
            Vec3::new(-0.1, -0.2, -1.0),
        ];
        let blended = triangle_with_normals(Some(tilted), None);
        assert!(blended.flat_ns.is_none());
        let (x, y) = (1.0 / 3.0, 1.0 / 3.0);
        let (a, b) = (hit_at(&flat, x, y), hit_at(&blended, x, y));
        assert!((a.ns - Vec3::NEG_Z).length() < 1e-6, "{}", a.ns);
        assert!((a.ns - b.ns).length() < 1e-5, "{} vs {}", a.ns, b.ns);
        assert_eq!(a.intr.n, Vec3::NEG_Z);
        assert_eq!(a.intr.n, b.intr.n);
        // Zero normals cannot be normalised: the geometric normal is used, as before.
        let zero = triangle_with_normals(Some(vec![Vec3::ZERO; 3]), None);
        assert!(zero.flat_ns.is_none());
        assert_eq!(hit_at(&zero, x, y).ns, Vec3::Z);
    }
}
