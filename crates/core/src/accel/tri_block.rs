//! A leaf's triangles precomputed for testing four at a time: the vertex positions in
//! structure-of-arrays form (`p[vertex][axis][lane]`), so the watertight test of
//! [`crate::shape::Triangle::intersect`] (Woop, Benthin and Wald 2013; pbrt-v4 section
//! 6.5.3) runs on the four triangles with one instruction per step. The lane arithmetic is
//! plain fixed-size array code that the compiler vectorises; [`super::simd`] compiles it
//! once for any x86-64 (SSE2, fused multiply-adds through the C library) and once with
//! AVX2 and FMA, chosen at run time.
//!
//! Every step is the scalar test's, in the same order and with the same roundings, so a
//! lane hits exactly when [`crate::shape::Triangle::intersect`] does, at the same distance
//! and barycentrics (the tests compare bit for bit). Closest-hit semantics are kept too:
//! the range check against the shrinking `t_max` is redone lane by lane in leaf order.

use crate::math::{gamma, Ray, Vec3, Vec4};

/// Triangles per block.
pub const LANES: usize = 4;

type F4 = [f32; LANES];

/// Up to four triangles of one leaf (plain data, so a large tree's blocks can sit in a
/// memory map, [`super::paged`]).
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C, align(16))]
pub struct TriBlock {
    /// Positions, `p[vertex][axis][lane]`; zero in unused lanes.
    p: [[F4; 3]; 3],
    /// Bit `i` set when lane `i` holds a triangle of non-zero area (the scalar test rejects
    /// zero-area triangles before anything else, so they are left out here).
    mask: u32,
    /// The leaf's primitives, lane by lane (unused lanes 0): read on a hit, so the hit does
    /// not look them up in the tree's primitive order, a cache miss of its own (8% of
    /// incoherent closest-hit time on a 1M-triangle mesh, `perf annotate`).
    pub prims: [u32; LANES],
    /// The leaf's first entry in the tree's primitive order.
    pub start: u32,
    /// The leaf's primitive count (lanes `0..count` are its primitives, in order).
    pub count: u32,
    /// Zero: fills the block to its alignment, so it has no padding bytes.
    unused: u32,
}

impl TriBlock {
    /// The block of a leaf of `tris.len()` (1 to 4) triangles starting at `start` in the
    /// tree's primitive order, whose primitive indices `prims` lists.
    #[must_use]
    pub fn new(start: u32, prims: &[u32], tris: &[[Vec3; 3]]) -> Self {
        debug_assert!((1..=LANES).contains(&tris.len()));
        debug_assert_eq!(prims.len(), tris.len());
        let mut b = Self {
            p: [[[0.0; LANES]; 3]; 3],
            prims: std::array::from_fn(|i| prims.get(i).copied().unwrap_or(0)),
            mask: 0,
            start,
            count: tris.len() as u32,
            unused: 0,
        };
        for (lane, t) in tris.iter().enumerate() {
            for (v, p) in t.iter().enumerate() {
                for a in 0..3 {
                    b.p[v][a][lane] = p[a];
                }
            }
            // The scalar test's first check, on the same expression.
            if (t[2] - t[0]).cross(t[1] - t[0]).length_squared() != 0.0 {
                b.mask |= 1 << lane;
            }
        }
        b
    }
}

/// The per-ray constants of the triangle test: the axis permutation that makes the
/// direction's largest component z, and the shear taking the direction to +z.
#[derive(Clone, Copy, Debug)]
pub struct RayTriangles {
    k: [usize; 3],
    o: [f32; 3],
    s: [f32; 3],
}

impl RayTriangles {
    /// The constants of `ray` (as in the scalar test).
    #[inline(always)]
    #[must_use]
    pub fn new(ray: &Ray) -> Self {
        let kz = ray.d.abs().max_position();
        // `(kx, ky, kz)` is a rotation of the axes; rotating whole arrays by a match on `kz`
        // takes selects, where indexing a vector by `kx` and `ky` took a branch per index.
        let rotate = |v: Vec3| match kz {
            0 => [v.y, v.z, v.x],
            1 => [v.z, v.x, v.y],
            _ => [v.x, v.y, v.z],
        };
        let k = match kz {
            0 => [1, 2, 0],
            1 => [2, 0, 1],
            _ => [0, 1, 2],
        };
        let d = rotate(ray.d);
        Self {
            k,
            o: rotate(ray.o),
            s: [-d[0] / d[2], -d[1] / d[2], 1.0 / d[2]],
        }
    }
}

/// What the lanes of a block say about one ray: which lanes may hit, and the values the
/// final range check and the hit need.
#[derive(Clone, Copy, Debug)]
pub struct Candidates {
    /// Bit `i`: lane `i` hits within the `t_max` the block was tested with.
    pub mask: u32,
    e: [F4; 3],
    det: F4,
    t_scaled: F4,
}

/// A triangle hit: distance and barycentrics, as [`crate::shape::ShapeHit`] holds them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleHit {
    /// Distance along the ray in units of its direction's length.
    pub t: f32,
    /// Barycentric coordinates of the hit (weights of the three vertices).
    pub b: [f32; 3],
}

impl Candidates {
    /// Whether lane `i` still hits within `t_max` (no greater than the block's), as the
    /// scalar test decides it, and the hit.
    #[inline(always)]
    #[must_use]
    pub fn hit(&self, i: usize, t_max: f32) -> Option<TriangleHit> {
        let (det, t_scaled) = (self.det[i], self.t_scaled[i]);
        if !in_range(det, t_scaled, t_max) {
            return None;
        }
        let inv_det = 1.0 / det;
        Some(TriangleHit {
            t: t_scaled * inv_det,
            b: [self.e[0][i] * inv_det, self.e[1][i] * inv_det, self.e[2][i] * inv_det],
        })
    }
}

/// The scalar test's range check of the scaled distance.
#[inline(always)]
fn in_range(det: f32, t_scaled: f32, t_max: f32) -> bool {
    let m = t_max * det;
    !((det < 0.0) & ((t_scaled >= 0.0) | (t_scaled < m)) | (det > 0.0) & ((t_scaled <= 0.0) | (t_scaled > m)))
}

/// `a*b - c*d` with one rounding (Kahan's algorithm), as the scalar test computes it.
#[inline(always)]
fn difference_of_products(a: f32, b: f32, c: f32, d: f32) -> f32 {
    let cd = c * d;
    let err = (-c).mul_add(d, cd);
    let dop = a.mul_add(b, -cd);
    dop + err
}

/// glam's `max_element` comparison (kept so NaNs fall the same way).
#[inline(always)]
fn max3(a: f32, b: f32, c: f32) -> f32 {
    let max = |a: f32, b: f32| if a > b { a } else { b };
    max(a, max(b, c))
}

#[inline(always)]
fn map4(f: impl Fn(usize) -> f32) -> F4 {
    [f(0), f(1), f(2), f(3)]
}

/// Test the block's triangles against the ray within `(0, t_max)`.
#[allow(clippy::needless_range_loop)] // lane loops read several arrays at the same index
#[inline(always)]
#[must_use]
pub fn test(block: &TriBlock, r: &RayTriangles, t_max: f32) -> Candidates {
    let [kx, ky, kz] = r.k;
    let [sx, sy, sz] = r.s;
    // Translate to the origin, permute, shear (x += s_x z before z is scaled).
    let mut x = [[0.0; LANES]; 3];
    let mut y = [[0.0; LANES]; 3];
    let mut z = [[0.0; LANES]; 3];
    for v in 0..3 {
        let p = &block.p[v];
        z[v] = map4(|i| p[kz][i] - r.o[2]);
        x[v] = map4(|i| (p[kx][i] - r.o[0]) + sx * z[v][i]);
        y[v] = map4(|i| (p[ky][i] - r.o[1]) + sy * z[v][i]);
    }
    let mut e = [
        map4(|i| difference_of_products(x[1][i], y[2][i], y[1][i], x[2][i])),
        map4(|i| difference_of_products(x[2][i], y[0][i], y[2][i], x[0][i])),
        map4(|i| difference_of_products(x[0][i], y[1][i], y[0][i], x[1][i])),
    ];
    // Only lanes holding a triangle of non-zero area: an unused lane's vertices are all zero,
    // so its edge functions are exactly zero, and redoing them cost a partly filled block
    // (most of a small scene's) a fifth of its test.
    let [e0, e1, e2] = e.map(Vec4::from_array);
    let zero = (e0.cmpeq(Vec4::ZERO) | e1.cmpeq(Vec4::ZERO) | e2.cmpeq(Vec4::ZERO)).bitmask() & block.mask;
    if zero != 0 {
        // Rare: an edge function is exactly zero; redo it in double precision.
        let f = |a: f32, b: f32, c: f32, d: f32| (f64::from(a) * f64::from(b) - f64::from(c) * f64::from(d)) as f32;
        for i in (0..LANES).filter(|&i| zero >> i & 1 != 0) {
            e[0][i] = f(x[1][i], y[2][i], y[1][i], x[2][i]);
            e[1][i] = f(x[2][i], y[0][i], y[2][i], x[0][i]);
            e[2][i] = f(x[0][i], y[1][i], y[0][i], x[1][i]);
        }
    }
    // Most rays miss every triangle of a block: stop before the distance when no lane is
    // inside its three edges.
    // (As lane masks: per-lane comparisons into a bit mask did not vectorise. Loaded again:
    // the redo above may have changed `e`.)
    let [e0, e1, e2] = e.map(Vec4::from_array);
    let negative = e0.cmplt(Vec4::ZERO) | e1.cmplt(Vec4::ZERO) | e2.cmplt(Vec4::ZERO);
    let positive = e0.cmpgt(Vec4::ZERO) | e1.cmpgt(Vec4::ZERO) | e2.cmpgt(Vec4::ZERO);
    let inside = !(negative & positive).bitmask() & block.mask;
    if inside == 0 {
        return Candidates {
            mask: 0,
            e,
            det: [0.0; LANES],
            t_scaled: [0.0; LANES],
        };
    }
    let det = map4(|i| e[0][i] + e[1][i] + e[2][i]);
    for zv in &mut z {
        *zv = map4(|i| zv[i] * sz);
    }
    let t_scaled = map4(|i| e[0][i] * z[0][i] + e[1][i] * z[1][i] + e[2][i] * z[2][i]);
    // The error bound on t (pbrt-v4 eq. 6.29-6.33), for every lane.
    let abs = |v: &[F4; 3], i: usize| max3(v[0][i].abs(), v[1][i].abs(), v[2][i].abs());
    let max_zt = map4(|i| abs(&z, i));
    let max_xt = map4(|i| abs(&x, i));
    let max_yt = map4(|i| abs(&y, i));
    let max_e = map4(|i| abs(&e, i));
    // The scalar test's last checks, in four lanes at once (the same operations in the
    // same order; a comparison with a NaN is false, `!=` true, as in scalar code).
    let [max_zt, max_xt, max_yt, max_e] = [max_zt, max_xt, max_yt, max_e].map(Vec4::from_array);
    let (det4, t4) = (Vec4::from_array(det), Vec4::from_array(t_scaled));
    let inv_det = Vec4::ONE / det4;
    let t = t4 * inv_det;
    let delta_z = gamma(3) * max_zt;
    let delta_x = gamma(5) * (max_xt + max_zt);
    let delta_y = gamma(5) * (max_yt + max_zt);
    let delta_e = 2.0 * (gamma(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
    let delta_t = 3.0 * (gamma(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * inv_det.abs();
    let m = t_max * det4;
    let out_of_range = det4.cmplt(Vec4::ZERO) & (t4.cmpge(Vec4::ZERO) | t4.cmplt(m))
        | det4.cmpgt(Vec4::ZERO) & (t4.cmple(Vec4::ZERO) | t4.cmpgt(m));
    let hit = det4.cmpne(Vec4::ZERO) & t.cmpeq(t) & (t.cmpgt(delta_t) | delta_t.cmpne(delta_t));
    let mask = hit.bitmask() & !out_of_range.bitmask();
    Candidates {
        mask: mask & inside,
        e,
        det,
        t_scaled,
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::*;
    use crate::shape::{Triangle, TriangleMesh};

    /// Lane by lane, the block test (with the closest-hit recheck) gives the scalar test's
    /// answer bit for bit: random triangles, zero-area ones, rays in a triangle's plane
    /// and through shared vertices, several `t_max`.
    #[test]
    fn lanes_match_the_scalar_triangle_test() {
        let mut seed = 7u32;
        let mut rnd = || {
            seed = seed.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
            (seed >> 8) as f32 / (1u32 << 24) as f32 * 4.0 - 2.0
        };
        let (mut hits, mut cases) = (0, 0);
        for k in 0..3000 {
            let mut tris = Vec::new();
            let n = 1 + k % LANES;
            for j in 0..n {
                let a = Vec3::new(rnd(), rnd(), rnd());
                let mut t = [a, a + Vec3::new(rnd(), rnd(), 0.0), a + Vec3::new(rnd(), 0.0, rnd())];
                match (k + j) % 7 {
                    0 => t[2] = t[1],                       // zero area
                    1 => t[2] = t[0] + 2.0 * (t[1] - t[0]), // collinear
                    2 => t[1].z = t[0].z,                   // an edge in a z plane
                    _ => {}
                }
                tris.push(t);
            }
            let ids: Vec<u32> = (0..n as u32).collect();
            let block = TriBlock::new(0, &ids, &tris);
            let mesh = Arc::new(TriangleMesh {
                positions: tris.iter().flatten().copied().collect(),
                indices: (0..3 * n as u32).collect(),
                ..Default::default()
            });
            let mut o = Vec3::new(rnd(), rnd(), rnd()) * 2.0;
            let mut d = Vec3::new(rnd(), rnd(), rnd());
            if k % 5 == 0 {
                // In the plane of the first triangle's edge, aimed at its first vertex.
                o.z = tris[0][0].z;
                d = tris[0][0] - o;
                d.z = 0.0;
            }
            if d == Vec3::ZERO {
                continue;
            }
            let ray = Ray::new(o, d);
            let rt = RayTriangles::new(&ray);
            for t_max in [f32::INFINITY, rnd().abs() * 2.0, 0.0] {
                let c = test(&block, &rt, t_max);
                for (i, t) in tris.iter().enumerate() {
                    let scalar = Triangle::new(mesh.clone(), i as u32).intersect(&ray, t_max);
                    let lane = (c.mask >> i & 1 != 0).then(|| c.hit(i, t_max)).flatten();
                    let as_bits = |h: Option<(f32, [f32; 3])>| h.map(|(t, b)| (t.to_bits(), b.map(f32::to_bits)));
                    assert_eq!(
                        as_bits(scalar.map(|h| (h.t, h.data))),
                        as_bits(lane.map(|h| (h.t, h.b))),
                        "case {k} lane {i}: ray {ray:?} t_max {t_max} triangle {t:?}"
                    );
                    hits += usize::from(scalar.is_some());
                    cases += 1;
                }
            }
        }
        assert!(
            hits > cases / 50,
            "only {hits} hits in {cases} cases: the test shows little"
        );
    }
}
