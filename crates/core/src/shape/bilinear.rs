//! Bilinear patches (pbrt-v4 `BilinearPatch`, book section 6.6): the surface
//! `p(u, v) = lerp(u, lerp(v, p00, p01), lerp(v, p10, p11))` over `[0, 1]^2`, curved unless
//! its four corners are coplanar.
//!
//! Intersection follows Reshetov ("Cool Patches", Ray Tracing Gems, 2019; pbrt-v4
//! `IntersectBilinearPatch`): a quadratic in `u` for the `u`-line `lerp(v, pu0, pu1)` that
//! the ray meets, then `v` and `t` from the closest points of the ray and that line. Both
//! roots are tried, so the closer of the two hits of a curved patch is returned. It runs in
//! double precision and accepts `u, v` up to a relative `1e-9` outside `[0, 1]` (clamped
//! back), so neighbouring patches that share an edge overlap by far less than an `f32` ulp
//! instead of leaving cracks.
//!
//! The hit point is re-evaluated in double precision from the (`f32`) hit parameters and
//! rounded once, so it lies within half an ulp per axis of a point of the surface; its error
//! bound is that rounding (plus the double-precision evaluation), far tighter than pbrt-v4's
//! `gamma(6) max |p_ij|`. Hits closer than a relative `1e-10` of the patch's distance are
//! rejected, which spawned rays, offset by that bound, never come near.
//!
//! Area sampling is pbrt-v4's: `(u, v)` from the bilinear density through the corner values
//! of `|dp/du x dp/dv|` (exact for parallelograms, close otherwise), and the exact density
//! `p_uv / |dp/du x dp/dv|` per unit area. The density at a given point needs its `(u, v)`,
//! found by Gauss-Newton iteration from the best point of a coarse grid.

use std::sync::Arc;

use glam::{DVec2, DVec3};

use super::{BilinearMesh, Interaction, ShapeHit, ShapeSample, SurfaceInteraction};
use crate::math::{Bounds3, Frame, Ray, Vec2, Vec3};
use crate::sampling::{bilinear_pdf, sample_bilinear};

/// How far outside `[0, 1]` a hit's `u` or `v` may be (then clamped), so that rays through
/// a shared edge cannot slip between the two patches.
const EDGE_SLACK: f64 = 1e-9;

/// Hits at `t |d|` below this fraction of the largest corner distance from the ray origin
/// are rejected: far above the double-precision error of `t`, far below any spawned ray's
/// offset.
const MIN_RELATIVE_T: f64 = 1e-10;

/// Gauss-Legendre nodes on `[0, 1]` (8 points) and their weights, for the area.
const GAUSS_NODES: [f64; 8] = [
    0.019_855_071_751_231_856,
    0.101_666_761_293_186_63,
    0.237_233_795_041_835_5,
    0.408_282_678_752_175_1,
    0.591_717_321_247_825,
    0.762_766_204_958_164_5,
    0.898_333_238_706_813_4,
    0.980_144_928_248_768_1,
];
const GAUSS_WEIGHTS: [f64; 8] = [
    0.050_614_268_145_188_13,
    0.111_190_517_226_687_24,
    0.156_853_322_938_943_64,
    0.181_341_891_689_181,
    0.181_341_891_689_181,
    0.156_853_322_938_943_64,
    0.111_190_517_226_687_24,
    0.050_614_268_145_188_13,
];

/// One patch of a shared mesh. Holds only the mesh and its index (16 bytes), so the
/// `Shape` enum does not grow for the triangles that dominate scenes.
#[derive(Clone, Debug)]
pub struct BilinearPatch {
    /// The mesh (positions, normals and uvs are read from it).
    pub mesh: Arc<BilinearMesh>,
    /// Index of the patch in the mesh.
    pub index: u32,
}

/// The corners `p00, p10, p01, p11` in double precision.
#[derive(Clone, Copy, Debug)]
struct Corners([DVec3; 4]);

impl Corners {
    /// `p(u, v)`.
    #[inline]
    fn point(&self, uv: DVec2) -> DVec3 {
        let [p00, p10, p01, p11] = self.0;
        p00.lerp(p01, uv.y).lerp(p10.lerp(p11, uv.y), uv.x)
    }

    /// `(dp/du, dp/dv)` at `(u, v)`.
    #[inline]
    fn tangents(&self, uv: DVec2) -> (DVec3, DVec3) {
        let [p00, p10, p01, p11] = self.0;
        let dpdu = p10.lerp(p11, uv.y) - p00.lerp(p01, uv.y);
        let dpdv = p01.lerp(p11, uv.x) - p00.lerp(p10, uv.x);
        (dpdu, dpdv)
    }

    /// `|dp/du x dp/dv|`, the area element.
    #[inline]
    fn jacobian(&self, uv: DVec2) -> f64 {
        let (dpdu, dpdv) = self.tangents(uv);
        dpdu.cross(dpdv).length()
    }
}

/// Real roots of `a x^2 + b x + c` (a double root twice; the linear root when `a = 0`),
/// with the cancellation-free form `q = -(b + sign(b) sqrt(disc)) / 2`, roots `q / a`, `c / q`.
fn solve_quadratic(a: f64, b: f64, c: f64) -> Option<[f64; 2]> {
    if a == 0.0 {
        return (b != 0.0).then(|| [-c / b; 2]);
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return None;
    }
    let q = -0.5 * (b + disc.sqrt().copysign(b));
    if q == 0.0 {
        return Some([0.0; 2]);
    }
    Some([q / a, c / q])
}

/// Closest hit `(t, u, v)` of the ray `o + t d` with the patch for `t` in
/// `(min_t, t_max)`, by Reshetov's method (see the module docs).
fn intersect_corners(o: DVec3, d: DVec3, t_max: f64, c: &Corners) -> Option<(f64, DVec2)> {
    let [p00, p10, p01, p11] = c.0;
    // Quadratic in u: the ray meets the line lerp(v, pu0, pu1) where the ray and the line
    // are coplanar.
    let qn = (p10 - p00).cross(p01 - p11);
    let (e00, e11) = (p01 - p00, p11 - p10);
    let (q00, q10) = (p00 - o, p10 - o);
    let a = qn.dot(d);
    let cc = q00.cross(d).dot(e00);
    let b = q10.cross(d).dot(e11) - (a + cc);
    let roots = solve_quadratic(a, b, cc)?;
    let scale = [p00, p10, p01, p11]
        .iter()
        .map(|p| (*p - o).abs().max_element())
        .fold(0.0, f64::max);
    let min_t = MIN_RELATIVE_T * scale / d.length();
    let range = -EDGE_SLACK..=1.0 + EDGE_SLACK;
    let mut best: Option<(f64, DVec2)> = None;
    for (k, &u) in roots.iter().enumerate() {
        if !range.contains(&u) || (k == 1 && u == roots[0]) {
            continue;
        }
        // v and t from the closest points of the ray and the line pa + v pb.
        let pa = q00.lerp(q10, u);
        let pb = e00.lerp(e11, u);
        let n = d.cross(pb);
        let det = n.dot(n);
        if det == 0.0 {
            continue;
        }
        let n = n.cross(pa);
        let t = n.dot(pb) / det;
        let v = n.dot(d) / det;
        if range.contains(&v) && t > min_t && t < t_max && best.is_none_or(|(tb, _)| t < tb) {
            best = Some((t, DVec2::new(u.clamp(0.0, 1.0), v.clamp(0.0, 1.0))));
        }
    }
    best
}

impl BilinearPatch {
    /// Patch `index` of `mesh`.
    #[must_use]
    pub fn new(mesh: Arc<BilinearMesh>, index: u32) -> Self {
        Self { mesh, index }
    }

    /// The corners `[p00, p10, p01, p11]`.
    #[inline]
    #[must_use]
    pub fn corners(&self) -> [Vec3; 4] {
        self.mesh.vertices(self.index).map(|i| self.mesh.positions[i])
    }

    #[inline]
    fn corners_f64(&self) -> Corners {
        Corners(self.corners().map(|p| p.as_dvec3()))
    }

    /// The weights of the bilinear sampling density: `|dp/du x dp/dv|` at the corners.
    fn corner_weights(&self) -> [f32; 4] {
        let c = self.corners_f64();
        [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)].map(|(u, v)| c.jacobian(DVec2::new(u, v)) as f32)
    }

    /// World-space bounds: those of the corners, since the patch lies in their convex hull.
    #[must_use]
    pub fn bounds(&self) -> Bounds3 {
        let [p00, p10, p01, p11] = self.corners();
        Bounds3::from_point(p00)
            .union_point(p10)
            .union_point(p01)
            .union_point(p11)
    }

    /// Area: `|dp/du x dp/dv|` integrated by 8 x 8-point Gauss-Legendre quadrature (exact
    /// for planar patches, where the integrand is linear; pbrt-v4 sums a 3 x 3 triangulation).
    #[must_use]
    pub fn area(&self) -> f32 {
        let c = self.corners_f64();
        let mut sum = 0.0;
        for (&u, &wu) in GAUSS_NODES.iter().zip(&GAUSS_WEIGHTS) {
            for (&v, &wv) in GAUSS_NODES.iter().zip(&GAUSS_WEIGHTS) {
                sum += wu * wv * c.jacobian(DVec2::new(u, v));
            }
        }
        sum as f32
    }

    /// Closest intersection in `(0, t_max)`; `data` holds the patch's `(u, v)`.
    #[must_use]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        let c = self.corners_f64();
        let (t, uv) = intersect_corners(ray.o.as_dvec3(), ray.d.as_dvec3(), f64::from(t_max), &c)?;
        let t = t as f32;
        // Rounding to f32 must not push the hit out of range.
        (t > 0.0 && t < t_max).then_some(ShapeHit {
            t,
            data: [uv.x as f32, uv.y as f32, 0.0],
        })
    }

    /// The interaction at the patch parameters `uv`.
    fn interaction_at(&self, uv: Vec2, wo: Vec3, t: f32) -> SurfaceInteraction {
        let c = self.corners_f64();
        let uvd = uv.as_dvec2();
        let p64 = c.point(uvd);
        let p = p64.as_vec3();
        // p is p(u, v) rounded once; the f64 evaluation adds a few ulps of the corners.
        let max_corner = c.0.iter().map(|q| q.abs().max_element()).fold(0.0, f64::max);
        let p_error = (p.abs() * f32::EPSILON + Vec3::splat((64.0 * f64::EPSILON * max_corner) as f32)) * 1.5;
        let (dpdu, dpdv) = c.tangents(uvd);
        let mut n = match dpdu.cross(dpdv).try_normalize() {
            Some(n) => n.as_vec3(),
            // A collapsed corner: the patch's mean normal.
            None => {
                let [p00, p10, p01, p11] = c.0;
                (p11 - p00).cross(p01 - p10).normalize_or_zero().as_vec3()
            }
        };
        let [i00, i10, i01, i11] = self.mesh.vertices(self.index);
        let bilerp = |a: Vec3, b: Vec3, c: Vec3, d: Vec3| a.lerp(c, uv.y).lerp(b.lerp(d, uv.y), uv.x);
        let shading = self
            .mesh
            .normals
            .as_ref()
            .and_then(|ns| bilerp(ns[i00], ns[i10], ns[i01], ns[i11]).try_normalize());
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
        // Texture coordinates, and dp/ds, dp/dt (s, t the texture coordinates) for the
        // tangent and texture footprints.
        let (uv_tex, dpds, dpdt) = match &self.mesh.uvs {
            Some(uvs) => {
                let [t00, t10, t01, t11] = [i00, i10, i01, i11].map(|i| uvs[i].as_dvec2());
                let st = t00.lerp(t01, uvd.y).lerp(t10.lerp(t11, uvd.y), uvd.x);
                let dst_du = t10.lerp(t11, uvd.y) - t00.lerp(t01, uvd.y);
                let dst_dv = t01.lerp(t11, uvd.x) - t00.lerp(t10, uvd.x);
                // [dp/ds dp/dt] = [dp/du dp/dv] J^-1 with J = d(s, t) / d(u, v).
                let det = dst_du.x * dst_dv.y - dst_dv.x * dst_du.y;
                let (dpds, dpdt) = if det.abs() > 1e-12 {
                    (
                        (dpdu * dst_dv.y - dpdv * dst_du.y) / det,
                        (dpdv * dst_du.x - dpdu * dst_dv.x) / det,
                    )
                } else {
                    (dpdu, dpdv)
                };
                (st.as_vec2(), dpds, dpdt)
            }
            None => (uv, dpdu, dpdv),
        };
        let dpdu = Frame::from_zx(ns, dpds.as_vec3()).x;
        SurfaceInteraction {
            intr: Interaction { p, p_error, n },
            ns,
            dpdu,
            dp_du: dpds.as_vec3(),
            dp_dv: dpdt.as_vec3(),
            uv: uv_tex,
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
        self.interaction_at(Vec2::new(hit.data[0], hit.data[1]), -ray.d.normalize(), hit.t)
    }

    /// A point sampled by pbrt-v4's approximately uniform area sampling (see the module
    /// docs); `pdf_area` is the exact density, 0 where the patch degenerates to a line.
    #[must_use]
    pub fn sample_area(&self, u: Vec2) -> ShapeSample {
        let w = self.corner_weights();
        let uv = sample_bilinear(u, w);
        let jacobian = self.corners_f64().jacobian(uv.as_dvec2()) as f32;
        let pdf_area = if jacobian > 0.0 {
            bilinear_pdf(uv, w) / jacobian
        } else {
            0.0
        };
        let si = self.interaction_at(uv, Vec3::ZERO, 0.0);
        ShapeSample {
            intr: si.intr,
            pdf_area,
            uv: si.uv,
        }
    }

    /// Density of [`Self::sample_area`] at the point `intr.p` of the patch.
    #[must_use]
    pub fn pdf_area(&self, intr: &Interaction) -> f32 {
        let uv = self.invert(intr.p);
        let jacobian = self.corners_f64().jacobian(uv.as_dvec2()) as f32;
        if jacobian > 0.0 {
            bilinear_pdf(uv, self.corner_weights()) / jacobian
        } else {
            0.0
        }
    }

    /// The `(u, v)` in `[0, 1]^2` of the patch point closest to `p`: the best of a 5 x 5 grid,
    /// then Gauss-Newton steps on `|p(u, v) - p|^2`, clamped to the square.
    #[must_use]
    pub fn invert(&self, p: Vec3) -> Vec2 {
        let c = self.corners_f64();
        let p = p.as_dvec3();
        let mut uv = DVec2::splat(0.5);
        let mut best = f64::INFINITY;
        for i in 0..5 {
            for j in 0..5 {
                let g = DVec2::new(f64::from(i), f64::from(j)) / 4.0;
                let d2 = c.point(g).distance_squared(p);
                if d2 < best {
                    best = d2;
                    uv = g;
                }
            }
        }
        for _ in 0..16 {
            let r = c.point(uv) - p;
            let (du, dv) = c.tangents(uv);
            let (a, b, d) = (du.dot(du), du.dot(dv), dv.dot(dv));
            let det = a * d - b * b;
            if det <= 0.0 {
                break;
            }
            let (gu, gv) = (du.dot(r), dv.dot(r));
            let step = DVec2::new(d * gu - b * gv, a * gv - b * gu) / det;
            let next = (uv - step).clamp(DVec2::ZERO, DVec2::ONE);
            let moved = (next - uv).abs().max_element();
            uv = next;
            if moved < 1e-12 {
                break;
            }
        }
        uv.as_vec2()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::chi2::{suite_seed, Chi2Test, RectGrid, SIGNIFICANCE};
    use crate::sampling::Pcg32;
    use crate::shape::{Triangle, TriangleMesh};
    use glam::UVec2;

    fn patch_of(corners: [Vec3; 4]) -> BilinearPatch {
        let mesh = BilinearMesh {
            positions: corners.to_vec(),
            indices: vec![0, 1, 2, 3],
            ..Default::default()
        };
        BilinearPatch::new(Arc::new(mesh), 0)
    }

    /// A strongly curved saddle (z = u + v - 2uv up to a placement), tilted and moved off
    /// the origin.
    fn saddle() -> [Vec3; 4] {
        [
            Vec3::new(0.2, 0.1, 0.3),
            Vec3::new(1.4, -0.1, 1.2),
            Vec3::new(0.1, 1.3, 1.0),
            Vec3::new(1.2, 1.1, 0.2),
        ]
    }

    fn rand_vec(rng: &mut Pcg32, lo: f32, hi: f32) -> Vec3 {
        Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * (hi - lo) + Vec3::splat(lo)
    }

    /// The patch's `n x n` grid, two triangles per cell (the reference geometry), with the
    /// patch parameters of every vertex.
    fn tessellate(corners: [Vec3; 4], n: u32) -> (Arc<TriangleMesh>, Vec<Vec2>) {
        let c = Corners(corners.map(|p| p.as_dvec3()));
        let mut positions = Vec::new();
        let mut params = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let uv = DVec2::new(f64::from(i), f64::from(j)) / f64::from(n);
                positions.push(c.point(uv).as_vec3());
                params.push(uv.as_vec2());
            }
        }
        let mut indices = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let k = j * (n + 1) + i;
                indices.extend([k, k + 1, k + n + 2, k, k + n + 2, k + n + 1]);
            }
        }
        let mesh = TriangleMesh {
            positions,
            indices,
            ..Default::default()
        };
        (Arc::new(mesh), params)
    }

    /// All hits `(t, (u, v))` of a ray with the tessellation, sorted by `t`.
    fn reference_hits(tris: &[Triangle], params: &[Vec2], ray: &Ray) -> Vec<(f32, Vec2)> {
        let mut hits: Vec<(f32, Vec2)> = tris
            .iter()
            .filter_map(|tri| {
                let h = tri.intersect(ray, f32::INFINITY)?;
                let [a, b, c] = tri.mesh.vertices(tri.index);
                let uv = h.data[0] * params[a] + h.data[1] * params[b] + h.data[2] * params[c];
                Some((h.t, uv))
            })
            .collect();
        hits.sort_by(|a, b| a.0.total_cmp(&b.0));
        hits
    }

    /// Random rays towards points in and around the curved patch: each must agree with a
    /// 256 x 256 tessellation about whether it hits, where (t) and at which (u, v), and the
    /// closer of two hits must be returned.
    #[test]
    fn intersection_matches_a_fine_tessellation() {
        let corners = saddle();
        let patch = patch_of(corners);
        let (mesh, params) = tessellate(corners, 256);
        let tris: Vec<Triangle> = (0..mesh.triangle_count() as u32)
            .map(|i| Triangle::new(mesh.clone(), i))
            .collect();
        let c = patch.corners_f64();
        let mut rng = Pcg32::new(11, 3);
        let (mut hits, mut misses, mut double) = (0, 0, 0);
        for _ in 0..400 {
            let target_uv = DVec2::new(f64::from(rng.next_f32()), f64::from(rng.next_f32())) * 1.4 - 0.2;
            let target = c.point(target_uv).as_vec3();
            let o = rand_vec(&mut rng, -2.0, 3.0);
            let ray = Ray::new(o, (target - o) * (0.5 + rng.next_f32()));
            let reference = reference_hits(&tris, &params, &ray);
            // Skip rays within the tessellation error of the boundary or of a tangency.
            let near_edge = |uv: Vec2| uv.min_element() < 0.01 || uv.max_element() > 0.99;
            if reference.iter().any(|h| near_edge(h.1))
                || (target_uv.min_element().abs() < 0.01 || (target_uv.max_element() - 1.0).abs() < 0.01)
            {
                continue;
            }
            let grazing = |uv: Vec2| {
                let (du, dv) = c.tangents(uv.as_dvec2());
                let n = du.cross(dv).normalize().as_vec3();
                n.dot(ray.d.normalize()).abs() < 0.05
            };
            if reference.iter().any(|h| grazing(h.1)) {
                continue;
            }
            let got = patch.intersect(&ray, f32::INFINITY);
            if got.is_some_and(|h| {
                let uv = Vec2::new(h.data[0], h.data[1]);
                near_edge(uv) || grazing(uv)
            }) {
                continue;
            }
            match (got, reference.first()) {
                (Some(hit), Some(&(t_ref, uv_ref))) => {
                    let rel = (hit.t - t_ref).abs() / t_ref;
                    assert!(rel < 1e-3, "t {} vs {t_ref}", hit.t);
                    let uv = Vec2::new(hit.data[0], hit.data[1]);
                    assert!((uv - uv_ref).abs().max_element() < 2e-3, "uv {uv} vs {uv_ref}");
                    let si = patch.interaction(&ray, &hit);
                    assert!((si.p() - ray.at(hit.t)).length() < 1e-4 * hit.t * ray.d.length());
                    assert!(patch.bounds().contains(si.p()));
                    if reference.len() > 1 && reference[1].0 > t_ref * 1.01 {
                        double += 1;
                        // Beyond the first hit, the second one is found.
                        let far = patch.intersect(&ray, 0.5 * (t_ref + reference[1].0) * 3.0);
                        assert!(far.is_some());
                    }
                    hits += 1;
                }
                (None, None) => misses += 1,
                (got, want) => panic!("ray {ray:?}: patch {got:?}, tessellation {want:?}"),
            }
            // A segment ending before the first hit finds nothing.
            if let Some(&(t_ref, _)) = reference.first() {
                assert!(patch.intersect(&ray, 0.99 * t_ref).is_none());
            }
        }
        assert!(
            hits > 100 && misses > 20 && double > 5,
            "{hits} hits, {misses} misses, {double} double"
        );
    }

    /// A ray that crosses the patch twice, checked by hand: the saddle z = x y over the unit
    /// square meets the line (s, 1 - s, 0.2) at s (1 - s) = 0.2.
    #[test]
    fn closest_of_two_hits_is_returned() {
        let patch = patch_of([Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::ONE]);
        let s = [0.5 - 0.1f32.sqrt() * 0.5f32.sqrt() * 1.0, 0.5 + (0.05f32).sqrt()];
        // s (1 - s) = 0.2 has roots 0.5 -+ sqrt(0.05).
        let s = [0.5 - 0.05f32.sqrt(), s[1]];
        let o = Vec3::new(-0.5, 1.5, 0.2);
        let d = Vec3::new(1.0, -1.0, 0.0);
        let hit = patch.intersect(&Ray::new(o, d), f32::INFINITY).unwrap();
        assert!((hit.t - (s[0] + 0.5)).abs() < 1e-5, "{}", hit.t);
        // Reversed, the other root is the closer one.
        let o2 = o + 2.0 * d;
        let hit = patch.intersect(&Ray::new(o2, -d), f32::INFINITY).unwrap();
        assert!((hit.t - (2.0 - s[1] - 0.5)).abs() < 1e-5, "{}", hit.t);
        // Limiting t_max to between the hits still finds the closer one only.
        let t_mid = 0.5 * (s[0] + s[1]) + 0.5;
        assert!(patch.intersect(&Ray::new(o, d), t_mid).is_some());
        assert!(patch.intersect(&Ray::new(o + t_mid * d, d), f32::INFINITY).is_some());
    }

    /// A planar trapezoid is hit exactly where its two triangles are.
    #[test]
    fn planar_patch_equals_its_triangle_pair() {
        let m = glam::Mat4::from_rotation_x(0.6) * glam::Mat4::from_translation(Vec3::new(0.3, -0.2, 0.5));
        let corners = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.5, 1.0, 0.0),
            Vec3::new(1.2, 1.0, 0.0),
        ]
        .map(|p| m.transform_point3(p));
        let patch = patch_of(corners);
        let mesh = Arc::new(TriangleMesh {
            positions: corners.to_vec(),
            indices: vec![0, 1, 3, 0, 3, 2],
            ..Default::default()
        });
        let tris = [Triangle::new(mesh.clone(), 0), Triangle::new(mesh, 1)];
        assert!((patch.area() - tris[0].area() - tris[1].area()).abs() < 1e-5);
        let mut rng = Pcg32::new(5, 8);
        let (mut hits, mut misses) = (0, 0);
        for _ in 0..20_000 {
            let o = rand_vec(&mut rng, -2.0, 3.0);
            let target = m.transform_point3(Vec3::new(2.4 * rng.next_f32() - 0.2, 1.4 * rng.next_f32() - 0.2, 0.0));
            let ray = Ray::new(o, target - o);
            if tris[0]
                .interaction(
                    &ray,
                    &tris[0]
                        .intersect(&ray, f32::INFINITY)
                        .unwrap_or(ShapeHit { t: 1.0, data: [0.3; 3] }),
                )
                .n()
                .dot(ray.d.normalize())
                .abs()
                < 0.05
            {
                // Grazing: the f32 corners are coplanar only up to rounding.
                continue;
            }
            let tri = tris.iter().filter_map(|t| t.intersect(&ray, f32::INFINITY)).next();
            let got = patch.intersect(&ray, f32::INFINITY);
            match (got, tri) {
                (Some(a), Some(b)) => {
                    assert!((a.t - b.t).abs() < 1e-5, "{} {}", a.t, b.t);
                    let si = patch.interaction(&ray, &a);
                    assert!((si.p() - target).length() < 1e-4);
                    hits += 1;
                }
                (None, None) => misses += 1,
                (a, b) => {
                    // Only within rounding of the outline may they disagree.
                    let [p00, p10, p01, p11] = corners;
                    let dist = [(p00, p10), (p10, p11), (p11, p01), (p01, p00)]
                        .iter()
                        .map(|&(a, b)| {
                            let e = b - a;
                            let s = ((target - a).dot(e) / e.length_squared()).clamp(0.0, 1.0);
                            (target - (a + s * e)).length()
                        })
                        .fold(f32::INFINITY, f32::min);
                    assert!(dist < 1e-5, "patch {a:?}, triangles {b:?} at {target}");
                }
            }
        }
        assert!(hits > 5000 && misses > 5000, "{hits} {misses}");
    }

    /// A 2 x 2 grid of curved patches over a bumpy height field: rays aimed at points of the
    /// shared edges (and the shared centre vertex) never pass between the patches.
    #[test]
    fn shared_edges_are_watertight() {
        let h = |i: usize, j: usize| [[0.0, 0.7, -0.2], [0.5, -0.6, 0.9], [-0.3, 0.8, 0.1]][j][i];
        let mut positions = Vec::new();
        for j in 0..3 {
            for i in 0..3 {
                positions.push(Vec3::new(i as f32 * 0.7 + 0.31, j as f32 * 0.9 - 0.17, h(i, j) + 1.3));
            }
        }
        let mut indices = Vec::new();
        for j in 0..2 {
            for i in 0..2 {
                let k = (3 * j + i) as u32;
                indices.extend([k, k + 1, k + 3, k + 4]);
            }
        }
        let mesh = Arc::new(BilinearMesh {
            positions: positions.clone(),
            indices,
            ..Default::default()
        });
        let patches: Vec<BilinearPatch> = (0..4).map(|i| BilinearPatch::new(mesh.clone(), i)).collect();
        // The height field's value at (x, y), from the patch over that cell.
        let height = |x: f32, y: f32| -> Option<f32> {
            let (fu, fv) = ((x - 0.31) / 0.7, (y + 0.17) / 0.9);
            if !(0.0..=2.0).contains(&fu) || !(0.0..=2.0).contains(&fv) {
                return None;
            }
            let (i, j) = ((fu as usize).min(1), (fv as usize).min(1));
            let uv = DVec2::new(f64::from(fu) - i as f64, f64::from(fv) - j as f64);
            Some(patches[2 * j + i].corners_f64().point(uv).z as f32)
        };
        // Shared edges: (1,0)-(1,1)-(1,2) and (0,1)-(1,1)-(2,1) in grid coordinates.
        let edges = [(1, 4), (4, 7), (3, 4), (4, 5)];
        let mut rng = Pcg32::new(21, 4);
        let mut tested = 0;
        for k in 0..40_000 {
            let (a, b) = edges[k % 4];
            let s = if k % 97 == 0 { 1.0 } else { rng.next_f32() };
            let target = if s == 1.0 {
                positions[b]
            } else {
                positions[a].lerp(positions[b], s)
            };
            // From above or below the surface, over the grid, through the edge point and
            // on to a point on the other side: the segment must cross the surface.
            let mut o = Vec3::new(0.31 + 1.4 * rng.next_f32(), -0.17 + 1.8 * rng.next_f32(), 0.0);
            o.z = if k % 2 == 0 {
                2.5 + rng.next_f32()
            } else {
                0.2 - rng.next_f32()
            };
            let beyond = target + 0.05 * (target - o);
            let Some(h_beyond) = height(beyond.x, beyond.y) else {
                continue;
            };
            if (beyond.z - h_beyond) * (o.z - target.z) >= 0.0 {
                continue;
            }
            let ray = Ray::new(o, target - o);
            let hit = patches.iter().filter_map(|p| p.intersect(&ray, 1.05)).next();
            assert!(hit.is_some(), "ray {ray:?} towards {target} slipped through");
            tested += 1;
        }
        assert!(tested > 30_000, "{tested}");
    }

    /// Hit points carry an error bound that keeps spawned rays off the surface: an origin
    /// offset to either side is on that side, and rays leaving the surface do not hit it
    /// again right away.
    #[test]
    fn spawned_rays_do_not_self_intersect() {
        let patch = patch_of(saddle().map(|p| p * 37.0 + Vec3::new(100.0, -60.0, 20.0)));
        let c = patch.corners_f64();
        let mut rng = Pcg32::new(9, 9);
        let mut checked = 0;
        for _ in 0..5_000 {
            let uv = Vec2::new(rng.next_f32(), rng.next_f32());
            let o = rand_vec(&mut rng, -100.0, 200.0);
            let target = c.point(uv.as_dvec2()).as_vec3();
            let ray = Ray::new(o, target - o);
            let Some(hit) = patch.intersect(&ray, f32::INFINITY) else {
                continue;
            };
            let si = patch.interaction(&ray, &hit);
            for side in [1.0f32, -1.0] {
                // Directions into the half-space of that side, not too grazing.
                let w = loop {
                    let w = rand_vec(&mut rng, -1.0, 1.0);
                    let w = w.normalize();
                    if side * w.dot(si.n()) > 0.05 {
                        break w;
                    }
                };
                let spawned = si.spawn_ray(w);
                let org = spawned.o.as_dvec3();
                // The origin is on the requested side of the surface (checked in f64 at the
                // closest surface point).
                let uv0 = patch.invert(spawned.o).as_dvec2();
                let (du, dv) = c.tangents(uv0);
                let n = du.cross(dv).normalize();
                let gap = (org - c.point(uv0)).dot(n) * f64::from(si.n().dot(n.as_vec3()).signum());
                assert!(gap * f64::from(side) > 0.0, "origin on the wrong side: {gap}");
                if let Some(again) = patch.intersect(&spawned, f32::INFINITY) {
                    assert!(again.t > 1e-2, "self-intersection at t = {}", again.t);
                }
                checked += 1;
            }
        }
        assert!(checked > 5000, "{checked}");
    }

    /// Sampled points, mapped back to (u, v), follow the claimed density (per unit area times
    /// the area element), and that density integrates to one.
    #[test]
    fn area_sampling_matches_its_pdf() {
        for (k, corners) in [saddle(), [Vec3::ZERO, Vec3::X * 2.0, Vec3::Y, Vec3::new(0.3, 0.6, 0.8)]]
            .into_iter()
            .enumerate()
        {
            let patch = patch_of(corners);
            let c = patch.corners_f64();
            let grid = RectGrid {
                min: Vec2::ZERO,
                max: Vec2::ONE,
                bins: UVec2::new(12, 12),
            };
            let report = Chi2Test::new(300_000, suite_seed()).with_test_count(2).rect(
                grid,
                |u, _| {
                    let s = patch.sample_area(u);
                    assert!(s.pdf_area > 0.0);
                    assert!((s.pdf_area - patch.pdf_area(&s.intr)).abs() < 1e-3 * s.pdf_area);
                    Some(patch.invert(s.intr.p))
                },
                |uv| {
                    let p = c.point(uv.as_dvec2()).as_vec3();
                    let intr = Interaction::point(p);
                    patch.pdf_area(&intr) * c.jacobian(uv.as_dvec2()) as f32
                },
            );
            assert!(report.passes(SIGNIFICANCE), "patch {k}: {report}");
            assert!((report.pdf_integral - 1.0).abs() < 1e-3, "{}", report.pdf_integral);
        }
    }

    /// The area (Gauss-Legendre) agrees with a 256 x 256 tessellation, and `E[1 / pdf]` over
    /// area samples agrees with both.
    #[test]
    fn area_matches_tessellation_and_pdf() {
        let patch = patch_of(saddle());
        let (mesh, _) = tessellate(saddle(), 256);
        let reference: f64 = (0..mesh.triangle_count() as u32)
            .map(|i| f64::from(Triangle::new(mesh.clone(), i).area()))
            .sum();
        let area = f64::from(patch.area());
        assert!((area - reference).abs() < 1e-4 * reference, "{area} vs {reference}");
        let mut rng = Pcg32::new(4, suite_seed());
        let n = 200_000;
        let (mut sum, mut sum2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let v = 1.0 / f64::from(patch.sample_area(Vec2::new(rng.next_f32(), rng.next_f32())).pdf_area);
            sum += v;
            sum2 += v * v;
        }
        let mean = sum / f64::from(n);
        let sigma = ((sum2 / f64::from(n) - mean * mean) / f64::from(n)).sqrt();
        assert!(
            (mean - reference).abs() < 4.0 * sigma + 1e-4 * reference,
            "{mean} +- {sigma} vs {reference}"
        );
    }

    /// A patch with a collapsed edge (p11 = p10) is the triangle p00 p10 p01: same hits,
    /// same area, finite normals, and samples with a valid density.
    #[test]
    fn collapsed_edge_patch_is_its_triangle() {
        let (a, b, c) = (
            Vec3::new(0.1, 0.2, 1.0),
            Vec3::new(1.3, 0.1, 1.4),
            Vec3::new(0.2, 1.1, 0.8),
        );
        let patch = patch_of([a, b, c, b]);
        let mesh = Arc::new(TriangleMesh {
            positions: vec![a, b, c],
            indices: vec![0, 1, 2],
            ..Default::default()
        });
        let tri = Triangle::new(mesh, 0);
        assert!(
            (patch.area() - tri.area()).abs() < 1e-3 * tri.area(),
            "{} {}",
            patch.area(),
            tri.area()
        );
        let mut rng = Pcg32::new(2, 6);
        let mut hits = 0;
        for _ in 0..5_000 {
            let o = Vec3::new(rng.next_f32(), rng.next_f32(), -1.0);
            let target = Vec3::new(1.6 * rng.next_f32() - 0.1, 1.4 * rng.next_f32() - 0.1, 0.0);
            let ray = Ray::new(o, target - o + Vec3::Z * (1.0 + target.x * 0.1));
            let (got, want) = (patch.intersect(&ray, f32::INFINITY), tri.intersect(&ray, f32::INFINITY));
            if let (Some(g), Some(w)) = (got, want) {
                assert!((g.t - w.t).abs() < 1e-4, "{} {}", g.t, w.t);
                let si = patch.interaction(&ray, &g);
                assert!(si.n().is_finite() && (si.n().length() - 1.0).abs() < 1e-4);
                hits += 1;
            } else if got.is_some() != want.is_some() {
                // Only along the outline (within rounding).
                let p = ray.at(got.or(want).unwrap().t);
                let d = [(a, b), (b, c), (c, a)]
                    .iter()
                    .map(|&(x, y)| {
                        let e = y - x;
                        let s = ((p - x).dot(e) / e.length_squared()).clamp(0.0, 1.0);
                        (p - (x + s * e)).length()
                    })
                    .fold(f32::INFINITY, f32::min);
                assert!(d < 1e-4, "disagreement at {p}, {d} from the outline");
            }
        }
        assert!(hits > 500, "{hits}");
        for _ in 0..1000 {
            let s = patch.sample_area(Vec2::new(rng.next_f32(), rng.next_f32()));
            assert!(s.pdf_area.is_finite() && s.pdf_area >= 0.0 && s.intr.p.is_finite());
        }
    }

    /// Normals: `dp/du x dp/dv`, flipped on request, or on the side of interpolated shading
    /// normals; texture coordinates interpolate bilinearly.
    #[test]
    fn normals_and_texture_coordinates() {
        let corners = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.5)];
        let ray = Ray::new(Vec3::new(0.25, 0.5, 2.0), -Vec3::Z);
        let mut mesh = BilinearMesh {
            positions: corners.to_vec(),
            indices: vec![0, 1, 2, 3],
            ..Default::default()
        };
        let at = |mesh: &BilinearMesh| {
            let p = BilinearPatch::new(Arc::new(mesh.clone()), 0);
            let hit = p.intersect(&ray, f32::INFINITY).unwrap();
            p.interaction(&ray, &hit)
        };
        let si = at(&mesh);
        // z = u v / 2: dp/du = (1, 0, v/2), dp/dv = (0, 1, u/2) at (0.25, 0.5).
        let n = Vec3::new(-0.25, -0.125, 1.0).normalize();
        assert!(
            (si.n() - n).length() < 1e-5 && (si.ns - n).length() < 1e-5,
            "{}",
            si.n()
        );
        assert!((si.uv - Vec2::new(0.25, 0.5)).length() < 1e-5);
        assert!((si.p().z - 0.0625).abs() < 1e-6);
        mesh.flip_normals = true;
        assert!((at(&mesh).n() + n).length() < 1e-5);
        // Shading normals pointing down take the geometric normal with them.
        mesh.normals = Some(vec![-Vec3::Z, -Vec3::Z, -Vec3::Y, -Vec3::Y]);
        mesh.flip_normals = false;
        let si = at(&mesh);
        assert!(
            (si.ns + Vec3::new(0.0, 0.5, 0.5).normalize()).length() < 1e-5,
            "{}",
            si.ns
        );
        assert!((si.n() + n).length() < 1e-5);
        mesh.uvs = Some(vec![
            Vec2::new(1.0, 1.0),
            Vec2::new(3.0, 1.0),
            Vec2::new(1.0, 2.0),
            Vec2::new(3.0, 4.0),
        ]);
        let si = at(&mesh);
        // lerp(0.25, lerp(0.5, uv00, uv01), lerp(0.5, uv10, uv11)) = lerp(0.25, (1, 1.5), (3, 2.5)).
        assert!((si.uv - Vec2::new(1.5, 1.75)).length() < 1e-5, "{}", si.uv);
    }
}
