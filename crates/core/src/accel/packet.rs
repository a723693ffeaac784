//! Packets of up to eight rays traced through a [`WideBvh`] together. A node's eight boxes
//! are tested against all of the packet's rays at once (one lane per ray, so AVX2 does a
//! step of the slab test for eight rays in one instruction), and a child is pushed once,
//! with the mask of the rays that enter it: the node loads, the stack and the loop are
//! shared by the rays. Leaves are tested ray by ray with the one-ray kernel
//! ([`tri_block::test`]), since the watertight test's axis permutation is the ray's own.
//!
//! A ray's box tests are the one-ray query's ([`super::wide`]'s `RayBoxes::hit_lanes`) step for
//! step: the same planes, roundings and NaN rules. So each ray enters every box it would
//! enter alone within its current closest distance, and finds the same closest distance
//! (the nearest hit is in a box the ray enters before reaching it). Only the order in which
//! leaves are tested can differ; of two primitives hit at exactly the same distance (an
//! edge shared by two triangles) the packet may report the other one. Any-hit answers are
//! the same.

use glam::Vec4;

use super::tri_block::{RayTriangles, TriangleHit};
use super::wide::{RayBoxes, TraversalStack, View, WideBvh, WideNode, INNER, WIDTH};
use crate::math::Ray;

/// Rays per packet.
pub const PACKET: usize = 8;

/// One value per ray of a packet.
type Lanes = [f32; PACKET];

/// Bit `r` of a ray mask, lane by lane (for selects that vectorise).
const LANE_BIT: [u32; PACKET] = [1, 2, 4, 8, 16, 32, 64, 128];

/// The per-ray constants of the box test, in lanes.
struct PacketBoxes {
    o: [Lanes; 3],
    /// The reciprocal directions scaled by the margins, as [`super::wide`]'s `RayBoxes`.
    inv_near: [Lanes; 3],
    inv_far: [Lanes; 3],
    /// All bits set in lane `r` of axis `a` when ray `r`'s direction is negative along `a`
    /// (its maxima are its near planes there).
    neg: [[u32; PACKET]; 3],
}

impl PacketBoxes {
    fn new(rays: &[Ray; PACKET]) -> Self {
        let mut p = Self {
            o: [[0.0; PACKET]; 3],
            inv_near: [[0.0; PACKET]; 3],
            inv_far: [[0.0; PACKET]; 3],
            neg: [[0; PACKET]; 3],
        };
        // Each ray's constants are the one-ray query's, so the two tests cannot drift apart.
        for (r, ray) in rays.iter().enumerate() {
            let one = RayBoxes::new(ray);
            for a in 0..3 {
                p.o[a][r] = one.o[a];
                p.inv_near[a][r] = one.inv_near[a];
                p.inv_far[a][r] = one.inv_far[a];
                p.neg[a][r] = if one.neg[a] { u32::MAX } else { 0 };
            }
        }
        p
    }

    /// Slab test of every ray against box `i` of `node` within `(0, limit[r])`: the mask of
    /// the rays that enter it and the nearest of their entry distances. A ray with limit
    /// `-inf` enters nothing. Each lane is `hit_lanes`'s computation for its ray.
    #[allow(clippy::needless_range_loop)] // lane loops read several arrays at the same index
    #[inline(always)]
    fn hit_child(&self, node: &WideNode, i: usize, limit: &Lanes) -> (u32, f32) {
        let mut near = [0.0f32; PACKET];
        let mut far = *limit;
        for a in 0..3 {
            let (lo, hi) = (node.planes[0][a][i].to_bits(), node.planes[1][a][i].to_bits());
            for r in 0..PACKET {
                let m = self.neg[a][r];
                let near_plane = f32::from_bits(hi & m | lo & !m);
                let far_plane = f32::from_bits(lo & m | hi & !m);
                let tn = (near_plane - self.o[a][r]) * self.inv_near[a][r];
                let tf = (far_plane - self.o[a][r]) * self.inv_far[a][r];
                // Written so a NaN on the left keeps the running value.
                near[r] = if tn > near[r] { tn } else { near[r] };
                far[r] = if tf < far[r] { tf } else { far[r] };
            }
        }
        let (n0, n1) = (Vec4::from_slice(&near[..4]), Vec4::from_slice(&near[4..]));
        let (f0, f1) = (Vec4::from_slice(&far[..4]), Vec4::from_slice(&far[4..]));
        let (in0, in1) = (n0.cmple(f0), n1.cmple(f1));
        let mask = in0.bitmask() | in1.bitmask() << 4;
        let nearest = Vec4::select(in0, n0, Vec4::INFINITY)
            .min(Vec4::select(in1, n1, Vec4::INFINITY))
            .min_element();
        (mask, nearest)
    }
}

/// What the packet traversal visits next, and which rays.
#[derive(Clone, Copy, Debug)]
struct PacketEntry {
    child: u32,
    count: u32,
    /// The rays that entered the box.
    mask: u32,
    /// The nearest of their entry distances.
    t_near: f32,
}

/// What the packet traversal does at a leaf, for one of its rays.
trait PacketLeaf {
    /// Test the leaf entry `(child, count)` for ray `r`, possibly shrinking its `t_max`;
    /// true when the ray is done.
    fn visit(&mut self, view: &View<'_>, r: usize, ray: &Ray, child: u32, count: u32, t_max: &mut f32) -> bool;
}

/// Visit, for every ray of `active`, the leaves it enters within its `t_max` (which `leaf`
/// shrinks), children of a node nearest entry first; a ray `leaf` says is done is left out
/// from then on.
#[inline(always)]
fn traverse(bvh: &WideBvh, rays: &[Ray; PACKET], t_max: &mut Lanes, active: u32, leaf: &mut impl PacketLeaf) {
    let (view, root, prefetch) = bvh.query_parts();
    let Some((root, root_count)) = root else {
        return;
    };
    let mut alive = active & 0xff;
    for (r, ray) in rays.iter().enumerate() {
        if !ray.is_finite() {
            alive &= !LANE_BIT[r];
        }
    }
    if alive == 0 {
        return;
    }
    let boxes = PacketBoxes::new(rays);
    let mut stack = TraversalStack::<PacketEntry>::new();
    stack.push(PacketEntry {
        child: root,
        count: root_count,
        mask: alive,
        t_near: 0.0,
    });
    while let Some(e) = stack.pop() {
        // The rays still searching whose closest hit so far is not before the box.
        let (t0, t1) = (Vec4::from_slice(&t_max[..4]), Vec4::from_slice(&t_max[4..]));
        let reach = Vec4::splat(e.t_near);
        let within = t0.cmpge(reach).bitmask() | t1.cmpge(reach).bitmask() << 4;
        let m = e.mask & alive & within;
        if m == 0 {
            continue;
        }
        if e.count != INNER {
            let mut bits = m;
            while bits != 0 {
                let r = bits.trailing_zeros() as usize;
                bits &= bits - 1;
                if leaf.visit(&view, r, &rays[r], e.child, e.count, &mut t_max[r]) {
                    alive &= !LANE_BIT[r];
                }
            }
            if alive == 0 {
                return;
            }
            continue;
        }
        let node = &view.nodes[e.child as usize];
        let limit: Lanes = std::array::from_fn(|r| {
            if m & LANE_BIT[r] != 0 {
                t_max[r]
            } else {
                f32::NEG_INFINITY
            }
        });
        // Push the entered children far to near (insertion into the stack top); unused
        // lanes come last.
        let base = stack.len();
        for i in 0..WIDTH {
            if node.count[i] == 0 {
                break;
            }
            let (mask, t_near) = boxes.hit_child(node, i, &limit);
            if mask == 0 {
                continue;
            }
            let entry = PacketEntry {
                child: node.child[i],
                count: node.count[i],
                mask,
                t_near,
            };
            if prefetch {
                view.prefetch_child(entry.child, entry.count);
            }
            stack.push(entry);
            let mut j = stack.len() - 1;
            while j > base && stack[j - 1].t_near < entry.t_near {
                stack[j] = stack[j - 1];
                j -= 1;
            }
            stack[j] = entry;
        }
    }
}

/// The closest-hit leaf test of a packet.
struct Closest<H, T, F> {
    rt: [RayTriangles; PACKET],
    test: T,
    on_triangle: F,
    best: [Option<(u32, H)>; PACKET],
}

impl<H, T, F> PacketLeaf for Closest<H, T, F>
where
    T: FnMut(usize, u32, &Ray, f32) -> Option<(f32, H)>,
    F: FnMut(usize, u32, TriangleHit) -> H,
{
    #[inline(always)]
    fn visit(&mut self, view: &View<'_>, r: usize, ray: &Ray, child: u32, count: u32, t_max: &mut f32) -> bool {
        let found = view.closest_in_leaf(
            true,
            &self.rt[r],
            ray,
            (child, count),
            t_max,
            &mut |prim, ray, t| (self.test)(r, prim, ray, t),
            &mut |prim, h| (self.on_triangle)(r, prim, h),
        );
        if found.is_some() {
            self.best[r] = found;
        }
        false
    }
}

/// The any-hit leaf test of a packet; it records the rays it finds blocked.
struct Any<T> {
    rt: [RayTriangles; PACKET],
    test: T,
    blocked: u32,
}

impl<T: FnMut(usize, u32, &Ray, f32) -> bool> PacketLeaf for Any<T> {
    #[inline(always)]
    fn visit(&mut self, view: &View<'_>, r: usize, ray: &Ray, child: u32, count: u32, t_max: &mut f32) -> bool {
        let hit = view.any_in_leaf(true, &self.rt[r], ray, (child, count), *t_max, &mut |prim, ray, t| {
            (self.test)(r, prim, ray, t)
        });
        if hit {
            self.blocked |= LANE_BIT[r];
        }
        hit
    }
}

/// [`WideBvh::closest_hit_triangles_packet`] in the caller's instruction set.
#[inline(always)]
pub(super) fn closest_hit_packet_impl<H>(
    bvh: &WideBvh,
    rays: &[Ray; PACKET],
    mut t_max: Lanes,
    active: u32,
    test: impl FnMut(usize, u32, &Ray, f32) -> Option<(f32, H)>,
    on_triangle: impl FnMut(usize, u32, TriangleHit) -> H,
) -> [Option<(u32, H)>; PACKET] {
    let mut leaf = Closest {
        rt: std::array::from_fn(|r| RayTriangles::new(&rays[r])),
        test,
        on_triangle,
        best: std::array::from_fn(|_| None),
    };
    traverse(bvh, rays, &mut t_max, active, &mut leaf);
    leaf.best
}

/// [`WideBvh::any_hit_triangles_packet`] in the caller's instruction set.
#[inline(always)]
pub(super) fn any_hit_packet_impl(
    bvh: &WideBvh,
    rays: &[Ray; PACKET],
    mut t_max: Lanes,
    active: u32,
    test: impl FnMut(usize, u32, &Ray, f32) -> bool,
) -> u32 {
    let mut leaf = Any {
        rt: std::array::from_fn(|r| RayTriangles::new(&rays[r])),
        test,
        blocked: 0,
    };
    traverse(bvh, rays, &mut t_max, active, &mut leaf);
    leaf.blocked
}

impl WideBvh {
    /// [`Self::closest_hit_triangles`] for the rays of `active` (bit `r` for `rays[r]`) among
    /// up to eight, traced together, each within `(0, t_max[r])`; the other entries of the
    /// answer are `None`. `test(r, prim, ray, t_max)` and `on_triangle(r, prim, hit)` are
    /// told which ray they serve. Each ray's closest distance is the one-ray query's, bit for
    /// bit; of primitives hit at the same distance, either may be the one reported.
    pub fn closest_hit_triangles_packet<H>(
        &self,
        rays: &[Ray; PACKET],
        t_max: [f32; PACKET],
        active: u32,
        test: impl FnMut(usize, u32, &Ray, f32) -> Option<(f32, H)>,
        on_triangle: impl FnMut(usize, u32, TriangleHit) -> H,
    ) -> [Option<(u32, H)>; PACKET] {
        super::simd::closest_hit_packet(self, rays, t_max, active, test, on_triangle)
    }

    /// [`Self::any_hit_triangles`] for the rays of `active` among up to eight, traced
    /// together: the mask of those blocked within `(0, t_max[r])`.
    pub fn any_hit_triangles_packet(
        &self,
        rays: &[Ray; PACKET],
        t_max: [f32; PACKET],
        active: u32,
        test: impl FnMut(usize, u32, &Ray, f32) -> bool,
    ) -> u32 {
        super::simd::any_hit_packet(self, rays, t_max, active, test)
    }
}
