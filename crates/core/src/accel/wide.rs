//! An 8-wide BVH: each node holds the boxes of up to eight children in structure-of-arrays
//! form (`lo[axis][lane]`), so one ray is tested against the eight boxes with the same few
//! instructions per axis, which the compiler turns into SIMD (one 8-lane AVX2 instruction
//! per step in [`super::simd`]'s AVX2 build, two 4-lane ones with SSE on any x86-64, NEON
//! on aarch64) without `unsafe` or target-specific code: the lane loops below are plain
//! fixed-size array arithmetic, written so each step maps onto one vector instruction
//! (`a > b ? a : b` is `maxps`). Nodes are built by [`super::wide_build`] from binned-SAH
//! binary splits, repeatedly opening the child of largest surface area (as in Wald et al.
//! 2008, "Getting rid of packets", and Embree's BVH4 builder).
//!
//! Closest-hit traversal is ordered: the children a ray enters are pushed far to near with
//! their entry distance, and a popped entry farther than the closest hit so far is skipped.
//! Any-hit traversal stops at the first blocker and does not sort: it goes on with the first
//! entered child in lane order and pushes the others as they come, since its answer is the
//! same in any order (shadow rays on a 1M-triangle mesh ran 1.15x faster without the sort;
//! Embree's occlusion traversal does not sort either). The tree knows primitives by index and
//! bounds only; queries take a closure testing one primitive.

use bytemuck::Zeroable;
use rayon::prelude::*;

use super::paged::Paged;
use super::simd;
use super::tri_block::{self, RayTriangles, TriBlock, TriangleHit};
use super::wide_build::{self, MAX_DEPTH};
use crate::math::simd::slab::SlabRay;
use crate::math::simd::{Isa, Supported};
use crate::math::{gamma, Bounds3, Ray, Vec3};

/// Children per node.
pub const WIDTH: usize = 8;
/// `count` of an inner child.
pub(super) const INNER: u32 = u32::MAX;
/// Flag in a leaf's `count`: its triangles are precomputed, `child` is the block's index.
const BLOCK: u32 = 1 << 30;
/// Entries the traversal stack can ever need: each level pushes at most `WIDTH - 1` more.
pub(super) const MAX_STACK: usize = (WIDTH - 1) * MAX_DEPTH + WIDTH;

/// A query's traversal stack, on the call stack and big enough for any tree (8 KiB). Its
/// slots are left uninitialised until pushed, so a query pays only for what it uses: the
/// earlier stacks, zeroed per query, were sized by the tree to keep that cost down, and still
/// cost 1.5 KiB of `memset` per ray on a 1M-triangle mesh (4.6% of incoherent closest-hit
/// time on a 10k-triangle one, `perf report`).
pub(super) type TraversalStack<T> = arrayvec::ArrayVec<T, MAX_STACK>;

/// Trees of more bytes (nodes and triangle blocks) than about a core's L2 cache prefetch the
/// nodes and blocks the traversal pushes, so their cache misses overlap the work on nearer
/// children. `bench/rays.sh`'s 1M-triangle mesh, 1 thread, four alternating rounds:
/// incoherent closest hit 0.98 to 1.16 M rays/s on average, shadow rays 0.61 to 0.72. A small
/// tree stays in cache, where the hints are only instructions (1.3% more on the Cornell box).
const PREFETCH_FROM_BYTES: usize = 512 << 10;

/// A node: up to eight children's boxes and what each child is (plain data, so a large
/// tree's nodes can sit in a memory map, [`super::paged`]).
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C, align(64))]
pub struct WideNode {
    /// Box minima `planes[0][axis][lane]` and maxima `planes[1][axis][lane]`; minima `+inf`
    /// and maxima `-inf` in unused lanes, so no ray enters them. One array, so the traversal
    /// takes a ray's near and far planes by index (the ray's direction signs), with no
    /// select per axis and node.
    pub planes: [[[f32; WIDTH]; 3]; 2],
    /// An inner child's node index, or a leaf's first entry in the primitive order.
    pub child: [u32; WIDTH],
    /// A leaf's primitive count, `u32::MAX` for an inner child, 0 for an unused lane; a
    /// leaf with precomputed triangles has bit 30 set and `child` is its block's index.
    pub count: [u32; WIDTH],
}

impl WideNode {
    pub(super) const EMPTY: Self = Self {
        planes: [[[f32::INFINITY; WIDTH]; 3], [[f32::NEG_INFINITY; WIDTH]; 3]],
        child: [0; WIDTH],
        count: [0; WIDTH],
    };

    /// The box of lane `i`.
    #[must_use]
    pub fn lane_bounds(&self, i: usize) -> Bounds3 {
        Bounds3 {
            min: self.planes[0].map(|axis| axis[i]).into(),
            max: self.planes[1].map(|axis| axis[i]).into(),
        }
    }
}

/// What the traversal visits next: a node or a leaf, and the distance at which the ray
/// enters its box.
#[derive(Clone, Copy, Debug, Default)]
struct Entry {
    child: u32,
    count: u32,
    t_near: f32,
}

/// The per-ray constants of the box test: the origin, and the reciprocal direction scaled
/// once per ray by the test's rounding margins (see [`RayBoxes::hit_lanes`]):
/// `inv_near = (1 / d) (1 - 2 gamma(3))` for the near planes, `inv_far = (1 / d)
/// (1 + 2 gamma(3))` for the far ones.
pub(super) type RayBoxes = SlabRay;

/// The box test of a node as an instruction set runs it: [`PlainBoxes`] is
/// [`RayBoxes::hit_lanes`] as the compiler vectorises it, `simd::Avx2Boxes` and
/// `simd::Avx512Boxes` the same arithmetic written in intrinsics
/// ([`crate::math::simd::slab`]). All give the same bits.
pub(super) trait BoxTest: Copy {
    /// [`RayBoxes::hit_lanes`].
    fn hit_lanes(self, r: &RayBoxes, node: &WideNode, t_max: f32) -> ([f32; WIDTH], u32);
}

/// [`RayBoxes::hit_lanes`] itself.
#[derive(Clone, Copy, Debug)]
pub(super) struct PlainBoxes;

impl BoxTest for PlainBoxes {
    #[inline(always)]
    fn hit_lanes(self, r: &RayBoxes, node: &WideNode, t_max: f32) -> ([f32; WIDTH], u32) {
        r.hit_lanes(node, t_max)
    }
}

impl RayBoxes {
    #[inline(always)]
    pub(super) fn new(ray: &Ray) -> Self {
        let inv_d = ray.d.recip().to_array();
        Self {
            o: ray.o.to_array(),
            inv_near: inv_d.map(|v| v * (1.0 - 2.0 * gamma(3))),
            inv_far: inv_d.map(|v| v * (1.0 + 2.0 * gamma(3))),
            neg: inv_d.map(|v| v < 0.0),
        }
    }

    /// Slab test of the ray against the node's eight boxes within `(0, t_max)`: entry
    /// distances and the boxes entered as a mask (bit `i` for lane `i`). The far distances
    /// are scaled up by `1 + 2 gamma(3)` so rounding cannot make a ray miss a box it touches
    /// (pbrt-v4 `Bounds3::IntersectP`), and the near ones down by `1 - 2 gamma(3)` so a
    /// `t_max` just past a hit on a box face does not cull the box. The factors are folded
    /// into the reciprocal direction, once per ray: a distance is then
    /// `(plane - o) x (1/d) x factor` with four roundings (the difference, the reciprocal, the
    /// factor's product and the last product), each at most `2^-24` relative, which the
    /// margin of `2 gamma(3)`, about `6 x 2^-24`, still covers. A ray parallel to a slab
    /// with its origin on the slab's plane gives `0 x inf = NaN`, which the comparisons
    /// below ignore: that slab does not limit the ray (conservative, so flat boxes are not
    /// missed).
    #[inline(always)]
    pub(super) fn hit_lanes(&self, node: &WideNode, t_max: f32) -> ([f32; WIDTH], u32) {
        let mut near = [0.0f32; WIDTH];
        let mut far = [t_max; WIDTH];
        for a in 0..3 {
            // The maxima are nearer than the minima along a negative direction.
            let near_plane = &node.planes[usize::from(self.neg[a])][a];
            let far_plane = &node.planes[usize::from(!self.neg[a])][a];
            for i in 0..WIDTH {
                let tn = (near_plane[i] - self.o[a]) * self.inv_near[a];
                let tf = (far_plane[i] - self.o[a]) * self.inv_far[a];
                // Written so a NaN on the left keeps the running value.
                near[i] = if tn > near[i] { tn } else { near[i] };
                far[i] = if tf < far[i] { tf } else { far[i] };
            }
        }
        let mut hit = 0;
        for i in 0..WIDTH {
            hit |= u32::from(near[i] <= far[i]) << i;
        }
        (near, hit)
    }
}

/// The 8-wide hierarchy and the primitive order its leaves refer to.
#[derive(Clone, Debug, Default)]
pub struct WideBvh {
    nodes: Paged<WideNode>,
    prim_indices: Vec<u32>,
    /// The root: an inner node, or a leaf when there are at most [`wide_build::MAX_LEAF`]
    /// primitives.
    root: Option<(u32, u32)>,
    bounds: Bounds3,
    /// Traversal stack entries a query can need: one for the root, then at most
    /// `WIDTH - 1` more per inner level below it.
    stack_size: usize,
    /// Precomputed leaf triangles ([`Self::attach_triangles`]).
    blocks: Paged<TriBlock>,
    /// The instruction set of the `*_triangles` queries.
    isa: Supported,
    /// True when the tree is too large to stay in cache, so the traversal prefetches the
    /// children it pushes (see [`PREFETCH_FROM_BYTES`]).
    prefetch: bool,
}

impl WideBvh {
    /// Build over primitives with the given bounds (index `i` is primitive `i`), in
    /// parallel on the current rayon pool.
    #[must_use]
    pub fn build(bounds: &[Bounds3]) -> Self {
        Self::build_with(bounds.len(), |i| bounds[i])
    }

    /// [`Self::build`] over `count` primitives whose bounds `bounds_of(i)` gives, asked once
    /// each (in parallel), so no array of bounds need be made first.
    #[must_use]
    pub fn build_with(count: usize, bounds_of: impl Fn(usize) -> Bounds3 + Sync) -> Self {
        if count == 0 {
            return Self::default();
        }
        let mut prims = wide_build::build_prims(count, bounds_of);
        let (nodes, root, bounds, levels) = wide_build::build_wide(&mut prims, wide_build::Costs::for_count(count));
        let mut bvh = Self {
            nodes,
            prim_indices: prims.par_iter().map(wide_build::BuildPrim::index).collect(),
            root: Some(root),
            bounds,
            stack_size: (1 + (WIDTH - 1) * levels).min(MAX_STACK),
            blocks: Paged::default(),
            isa: Supported::best(),
            prefetch: false,
        };
        bvh.prefetch = bvh.is_larger_than_a_cache();
        bvh
    }

    /// True when the nodes and triangle blocks take [`PREFETCH_FROM_BYTES`] or more.
    fn is_larger_than_a_cache(&self) -> bool {
        std::mem::size_of_val(&self.nodes[..]) + std::mem::size_of_val(&self.blocks[..]) >= PREFETCH_FROM_BYTES
    }

    /// Put `items`, the primitives `0..items.len()` the tree was built over, in the order its
    /// leaves list them, and renumber the tree to match (indices from `items.len()` on, e.g.
    /// a top level's instances, are left as they are). A leaf's primitives then sit side by
    /// side in memory and neighbouring leaves near each other, which is what incoherent rays
    /// need: measured with `mcrender bench-rays` on `bench/rays.sh`'s 1M-triangle mesh, one
    /// thread, incoherent rays went from 0.53 and 0.44 to 0.69 and 0.56 M rays/s in two
    /// alternating runs (about 1.27x); camera rays did not change.
    #[must_use]
    pub fn reorder_by_leaves<T>(&mut self, items: Vec<T>) -> Vec<T> {
        let n = items.len();
        let mut slots: Vec<Option<T>> = items.into_iter().map(Some).collect();
        let mut ordered = Vec::with_capacity(n);
        for index in &mut self.prim_indices {
            let old = *index as usize;
            if let Some(item) = slots.get_mut(old).and_then(Option::take) {
                *index = ordered.len() as u32;
                ordered.push(item);
            }
        }
        // Every primitive is in exactly one leaf (`check_invariants`), so nothing is left;
        // anything that were would be unreachable, and is kept only to keep the count.
        ordered.extend(slots.into_iter().flatten());
        ordered
    }

    /// The nodes (root first when the root is an inner node).
    #[must_use]
    pub fn nodes(&self) -> &[WideNode] {
        &self.nodes[..]
    }

    /// Primitive indices in leaf order.
    #[must_use]
    pub fn prim_indices(&self) -> &[u32] {
        &self.prim_indices
    }

    /// Bytes the tree holds: its nodes, leaf triangle blocks and primitive order.
    #[must_use]
    pub fn memory_bytes(&self) -> u64 {
        (std::mem::size_of_val(&self.nodes[..])
            + std::mem::size_of_val(&self.blocks[..])
            + std::mem::size_of_val(&self.prim_indices[..])) as u64
    }

    /// Bytes of one primitive's record during the build (freed when the tree is made, but part
    /// of the build's peak, [`Self::estimated_peak_bytes`]).
    pub const BUILD_BYTES_PER_PRIMITIVE: u64 = size_of::<wide_build::BuildPrim>() as u64;

    /// An estimate of the bytes a tree over `primitives` takes at the peak of its build, with
    /// triangle blocks attached, for memory limits checked before anything is built: the
    /// 32-byte build primitives and the 4-byte primitive order, plus nodes and blocks at
    /// allowances above what was measured, per primitive. Trees of 65,536 primitives or more
    /// (block costs, fuller leaves): 0.085 nodes and 0.29 blocks on `bench/rays.sh`'s 1M-triangle mesh,
    /// allowed 0.2 and 0.4, the nodes twice over for the copies of the parallel build.
    /// Smaller trees (pbrt's costs: leaves of one primitive, mostly): a block per primitive
    /// and 0.4 nodes.
    /// The `memory_estimates_cover_built_trees` test holds built trees to it.
    #[must_use]
    pub fn estimated_peak_bytes(primitives: u64) -> u64 {
        let (node, block) = (size_of::<WideNode>() as f64, size_of::<TriBlock>() as f64);
        let per_primitive = if primitives >= wide_build::BLOCK_COSTS_FROM as u64 {
            2.0 * 0.2 * node + 0.4 * block
        } else {
            2.0 * 0.4 * node + block
        };
        let fixed = (Self::BUILD_BYTES_PER_PRIMITIVE + size_of::<u32>() as u64) as f64;
        // Saturating: a float beyond u64::MAX converts to u64::MAX.
        ((fixed + per_primitive) * primitives as f64).ceil() as u64
    }

    /// Traversal stack entries a query on this tree can need (at most [`MAX_STACK`]).
    #[must_use]
    pub fn traversal_stack_size(&self) -> usize {
        self.stack_size
    }

    /// Bounds of everything (empty for an empty tree).
    #[must_use]
    pub fn bounds(&self) -> Bounds3 {
        self.bounds
    }

    /// The instruction set the `*_triangles` queries run with ([`Isa::best`] when built).
    #[must_use]
    pub fn isa(&self) -> Isa {
        self.isa.isa()
    }

    /// [`Self::isa`] with the proof that this CPU has it.
    pub(super) fn supported_isa(&self) -> Supported {
        self.isa
    }

    /// Run the queries with `isa` (to compare or test the kernels); refused, leaving the
    /// tree as it is, when this CPU does not support it.
    pub fn set_isa(&mut self, isa: Isa) -> Result<(), String> {
        self.isa = Supported::new(isa)
            .ok_or_else(|| format!("this CPU does not support the {} instruction set", isa.name()))?;
        Ok(())
    }

    /// Precompute the triangles of every leaf whose primitives are all triangles, so the
    /// `*_triangles` queries test them four at a time ([`super::tri_block`]).
    /// `triangle(prim)` gives primitive `prim`'s vertex positions, or `None` when it must be
    /// tested by the query's closure (another shape, an alpha cut-out, a surface shadow rays
    /// skip). Call after [`Self::reorder_by_leaves`], with the reordered primitives.
    pub fn attach_triangles(&mut self, triangle: impl Fn(u32) -> Option<[Vec3; 3]> + Sync) {
        // The leaves in order (root first, then the nodes' lanes, `WIDTH * node + lane`);
        // their blocks are made in parallel, each reading its triangles once, and numbered
        // in that order after the leaves that cannot have one are dropped, so no block's
        // index depends on the threads.
        const ROOT: u32 = u32::MAX;
        let is_plain_leaf = |count: u32| count != INNER && count & BLOCK == 0 && count != 0;
        let mut leaves: Vec<(u32, u32, u32)> = Vec::with_capacity(self.nodes.len() * WIDTH + 1);
        if let Some((child, count)) = self.root {
            if is_plain_leaf(count) {
                leaves.push((ROOT, child, count));
            }
        }
        for (n, node) in self.nodes.iter().enumerate() {
            for i in 0..WIDTH {
                if is_plain_leaf(node.count[i]) {
                    leaves.push(((WIDTH * n + i) as u32, node.child[i], node.count[i]));
                }
            }
        }
        let prim_indices = &self.prim_indices;
        // Each leaf's block in one pass over its triangles; a leaf with a primitive that is
        // not a plain triangle gets an empty block (count 0, which no real block has), and
        // those are dropped after, keeping the order.
        let block = |k: usize| {
            let (_, child, count) = leaves[k];
            let start = child as usize;
            let Some(prims) = prim_indices
                .get(start..start + count as usize)
                .filter(|p| p.len() <= tri_block::LANES)
            else {
                return TriBlock::zeroed();
            };
            let mut tris = [[Vec3::ZERO; 3]; tri_block::LANES];
            for (t, &p) in tris.iter_mut().zip(prims) {
                match triangle(p) {
                    Some(positions) => *t = positions,
                    None => return TriBlock::zeroed(),
                }
            }
            TriBlock::new(child, prims, &tris[..prims.len()])
        };
        let mut blocks = Paged::from_fn(leaves.len(), block);
        if blocks.iter().any(|b| b.count == 0) {
            let mut kept = 0;
            for k in 0..leaves.len() {
                if blocks[k].count != 0 {
                    blocks[kept] = blocks[k];
                    leaves[kept] = leaves[k];
                    kept += 1;
                }
            }
            blocks.truncate(kept);
            leaves.truncate(kept);
        }
        let first = self.blocks.len() as u32;
        for (k, &(at, _, _)) in leaves.iter().enumerate() {
            let (child, count) = if at == ROOT {
                self.root.as_mut().map(|(c, n)| (c, n)).expect("a leaf root")
            } else {
                let node = &mut self.nodes[at as usize / WIDTH];
                let i = at as usize % WIDTH;
                (&mut node.child[i], &mut node.count[i])
            };
            *child = first + k as u32;
            *count |= BLOCK;
        }
        // After any blocks of an earlier call.
        if first == 0 {
            self.blocks = blocks;
        } else {
            let earlier = std::mem::take(&mut self.blocks);
            self.blocks = Paged::from_fn(earlier.len() + blocks.len(), |k| {
                earlier.get(k).copied().unwrap_or_else(|| blocks[k - earlier.len()])
            });
        }
        self.prefetch = self.is_larger_than_a_cache();
    }

    /// Leaves whose triangles are precomputed by [`Self::attach_triangles`].
    #[must_use]
    pub fn triangle_blocks(&self) -> usize {
        self.blocks.len()
    }

    /// Closest hit along `ray` in `(0, t_max)`. `test(prim, ray, t_max)` intersects one
    /// primitive and returns the hit distance with any payload; `t_max` shrinks as hits are
    /// found. A ray with a non-finite origin or direction hits nothing. Leaves with
    /// precomputed triangles are tested through `test` too, one primitive at a time (see
    /// [`Self::closest_hit_triangles`] for the fast path).
    pub fn closest_hit<H>(
        &self,
        ray: &Ray,
        t_max: f32,
        test: impl FnMut(u32, &Ray, f32) -> Option<(f32, H)>,
    ) -> Option<(u32, H)> {
        traverse_closest::<H, false>(self, ray, t_max, test, PlainBoxes, |_, _| {
            unreachable!("leaf blocks are tested through `test` in this query")
        })
    }

    /// [`Self::closest_hit`] with the leaves of [`Self::attach_triangles`] tested four
    /// triangles at a time, with the tree's instruction set: `on_triangle(prim, hit)` makes
    /// the payload of such a hit. The answers are those of `closest_hit` with `test` calling
    /// [`crate::shape::Triangle::intersect`] on those primitives, bit for bit.
    pub fn closest_hit_triangles<H>(
        &self,
        ray: &Ray,
        t_max: f32,
        test: impl FnMut(u32, &Ray, f32) -> Option<(f32, H)>,
        on_triangle: impl FnMut(u32, TriangleHit) -> H,
    ) -> Option<(u32, H)> {
        simd::closest_hit(self, ray, t_max, test, on_triangle)
    }

    /// True when any primitive blocks `ray` within `(0, t_max)`: `test` says whether one
    /// primitive does. Children are visited near to far and the query stops at the first
    /// blocker. A ray with a non-finite origin or direction is blocked by nothing. Leaves
    /// with precomputed triangles are tested through `test`, one primitive at a time.
    pub fn any_hit(&self, ray: &Ray, t_max: f32, test: impl FnMut(u32, &Ray, f32) -> bool) -> bool {
        traverse_any::<false>(self, ray, t_max, test, PlainBoxes)
    }

    /// [`Self::any_hit`] with the leaves of [`Self::attach_triangles`] tested four
    /// triangles at a time, with the tree's instruction set.
    pub fn any_hit_triangles(&self, ray: &Ray, t_max: f32, test: impl FnMut(u32, &Ray, f32) -> bool) -> bool {
        simd::any_hit(self, ray, t_max, test)
    }

    /// Visit the leaves `ray` enters, nearest entry first, with `leaf` (which may shrink
    /// `t_max`); true when it stopped the traversal.
    #[inline(always)]
    fn traverse<L: Leaf>(&self, ray: &Ray, mut t_max: f32, leaf: &mut L, boxes: impl BoxTest) -> bool {
        let Some((root, root_count)) = self.root else {
            return false;
        };
        if !ray.is_finite() {
            return false;
        }
        let view = View {
            nodes: &self.nodes,
            blocks: &self.blocks,
            prim_indices: &self.prim_indices,
        };
        let r = RayBoxes::new(ray);
        let mut stack = TraversalStack::<Entry>::new();
        // `cur` is what is visited next; the stack holds the rest, nearest entry on top.
        let mut cur = Entry {
            child: root,
            count: root_count,
            t_near: 0.0,
        };
        loop {
            if cur.count != INNER {
                if leaf.visit(&view, ray, cur.child, cur.count, &mut t_max) {
                    return true;
                }
            } else {
                let node = &view.nodes[cur.child as usize];
                let (near, mut lanes) = boxes.hit_lanes(&r, node, t_max);
                let entry = |i: usize| Entry {
                    child: node.child[i],
                    count: node.count[i],
                    t_near: near[i],
                };
                // The entered lanes in lane order. One or two go straight on without the
                // stack's sorting (most nodes of an incoherent ray, whose mispredicted
                // branches cost more than the box test); from three on they are pushed far
                // to near. Either way they are visited in the same order: nearest first, and
                // of equal entry distances the later lane first.
                if lanes != 0 {
                    let first = entry(lanes.trailing_zeros() as usize);
                    lanes &= lanes - 1;
                    if self.prefetch {
                        view.prefetch(first);
                    }
                    if lanes == 0 {
                        cur = first;
                        continue;
                    }
                    if !L::ORDERED {
                        // Any order will do: go on with the first, push the others.
                        while lanes != 0 {
                            let e = entry(lanes.trailing_zeros() as usize);
                            lanes &= lanes - 1;
                            if self.prefetch {
                                view.prefetch(e);
                            }
                            stack.push(e);
                        }
                        cur = first;
                        continue;
                    }
                    let second = entry(lanes.trailing_zeros() as usize);
                    lanes &= lanes - 1;
                    if self.prefetch {
                        view.prefetch(second);
                    }
                    let (nearer, farther) = if second.t_near <= first.t_near {
                        (second, first)
                    } else {
                        (first, second)
                    };
                    if lanes == 0 {
                        stack.push(farther);
                        cur = nearer;
                        continue;
                    }
                    let base = stack.len();
                    stack.push(farther);
                    stack.push(nearer);
                    while lanes != 0 {
                        let e = entry(lanes.trailing_zeros() as usize);
                        lanes &= lanes - 1;
                        if self.prefetch {
                            view.prefetch(e);
                        }
                        // Insertion below the nearer entries already on top.
                        stack.push(e);
                        let mut j = stack.len() - 1;
                        while j > base && stack[j - 1].t_near < e.t_near {
                            stack[j] = stack[j - 1];
                            j -= 1;
                        }
                        stack[j] = e;
                    }
                }
            }
            // The nearest pending entry the ray can still reach.
            loop {
                let Some(next) = stack.pop() else {
                    return false;
                };
                cur = next;
                if cur.t_near <= t_max {
                    break;
                }
            }
        }
    }

    /// What a query reads: the arrays, the root entry and whether to prefetch (for the
    /// packet queries of [`super::packet`]).
    #[inline(always)]
    pub(super) fn query_parts(&self) -> (View<'_>, Option<(u32, u32)>, bool) {
        let view = View {
            nodes: &self.nodes,
            blocks: &self.blocks,
            prim_indices: &self.prim_indices,
        };
        (view, self.root, self.prefetch)
    }

    /// Check the tree's invariants against the primitive bounds it was built from: every
    /// lane's box is exactly the union of what is below it, unused lanes are empty and come
    /// last, leaves hold 1 to 4 primitives, and every primitive sits in exactly one leaf.
    /// Returns a description of the first violation.
    pub fn check_invariants(&self, prim_bounds: &[Bounds3]) -> Result<(), String> {
        let mut seen = vec![0u32; prim_bounds.len()];
        match self.root {
            None if prim_bounds.is_empty() => return Ok(()),
            None => return Err("empty tree over primitives".into()),
            Some((child, count)) => {
                let b = self.check_entry(child, count, prim_bounds, &mut seen, 0)?;
                if b != self.bounds {
                    return Err(format!("root bounds {:?} are not {:?}", self.bounds, b));
                }
            }
        }
        match seen.iter().position(|&c| c != 1) {
            Some(i) => Err(format!("primitive {i} is in {} leaves", seen[i])),
            None => Ok(()),
        }
    }

    fn check_entry(
        &self,
        child: u32,
        count: u32,
        prim_bounds: &[Bounds3],
        seen: &mut [u32],
        depth: usize,
    ) -> Result<Bounds3, String> {
        if depth > MAX_DEPTH {
            return Err(format!("deeper than {MAX_DEPTH} levels"));
        }
        if count != INNER {
            let (start, count) = if count & BLOCK != 0 {
                let b = self
                    .blocks
                    .get(child as usize)
                    .ok_or_else(|| format!("leaf block {child} out of range"))?;
                if count & !BLOCK != b.count {
                    return Err(format!(
                        "leaf block {child} has {} primitives, its lane says {}",
                        b.count,
                        count & !BLOCK
                    ));
                }
                (b.start as usize, b.count)
            } else {
                (child as usize, count)
            };
            if count == 0 || count as usize > wide_build::MAX_LEAF {
                return Err(format!("leaf at {start} with {count} primitives"));
            }
            let mut b = Bounds3::EMPTY;
            for &p in &self.prim_indices[start..start + count as usize] {
                seen[p as usize] += 1;
                b = b.union(prim_bounds[p as usize]);
            }
            return Ok(b);
        }
        let node = self
            .nodes
            .get(child as usize)
            .ok_or_else(|| format!("node {child} out of range"))?;
        let mut all = Bounds3::EMPTY;
        let mut used = 0;
        for i in 0..WIDTH {
            if node.count[i] == 0 {
                if node.lane_bounds(i) != WideNode::EMPTY.lane_bounds(i) {
                    return Err(format!("node {child} lane {i} is unused but has a box"));
                }
                continue;
            }
            if used != i {
                return Err(format!("node {child} has a used lane {i} after an unused one"));
            }
            used += 1;
            let below = self.check_entry(node.child[i], node.count[i], prim_bounds, seen, depth + 1)?;
            if below != node.lane_bounds(i) {
                return Err(format!(
                    "node {child} lane {i} box {:?} is not the union {:?} of its contents",
                    node.lane_bounds(i),
                    below
                ));
            }
            all = all.union(below);
        }
        if used < 2 {
            return Err(format!("node {child} has {used} children"));
        }
        Ok(all)
    }
}

/// What the traversal does at a leaf: a trait rather than a closure so that its code is
/// always inlined, and so compiled in the instruction set of the query ([`simd`]).
trait Leaf {
    /// Whether the traversal visits entered children nearest first (a closest hit needs it
    /// to cull; an any-hit query's answer is the same in any order).
    const ORDERED: bool;
    /// Test the leaf entry `(child, count)`, possibly shrinking `t_max`; true to stop.
    fn visit(&mut self, view: &View<'_>, ray: &Ray, child: u32, count: u32, t_max: &mut f32) -> bool;
}

/// The arrays of a tree a query reads, borrowed once per query: a memory-mapped array's
/// slice is checked as it is made ([`Paged`]'s `Deref`), which indexing the tree's fields
/// directly did at every node and block (a branch on the kind of storage, a length check).
pub(super) struct View<'a> {
    pub(super) nodes: &'a [WideNode],
    pub(super) blocks: &'a [TriBlock],
    pub(super) prim_indices: &'a [u32],
}

impl View<'_> {
    /// The primitive range `(start, count)` of a leaf entry.
    #[inline(always)]
    pub(super) fn leaf_range(&self, child: u32, count: u32) -> (usize, usize) {
        if count & BLOCK != 0 {
            let b = &self.blocks[child as usize];
            (b.start as usize, b.count as usize)
        } else {
            (child as usize, count as usize)
        }
    }

    /// Closest-hit test of one ray against the leaf entry `(child, count)`: `t_max` shrinks
    /// to every nearer hit, and the last of them (the nearest) is returned with its payload.
    /// With `blocks`, a leaf block takes the four-lane triangle test and `on_triangle` makes
    /// the payload; other leaves (and all of them without `blocks`) call `test` per primitive.
    #[allow(clippy::too_many_arguments)] // the per-ray state of both traversals
    #[inline(always)]
    pub(super) fn closest_in_leaf<H>(
        &self,
        blocks: bool,
        rt: &RayTriangles,
        ray: &Ray,
        (child, count): (u32, u32),
        t_max: &mut f32,
        test: &mut impl FnMut(u32, &Ray, f32) -> Option<(f32, H)>,
        on_triangle: &mut impl FnMut(u32, TriangleHit) -> H,
    ) -> Option<(u32, H)> {
        let mut found = None;
        if blocks && count & BLOCK != 0 {
            let block = &self.blocks[child as usize];
            let c = tri_block::test(block, rt, *t_max);
            let mut mask = c.mask;
            while mask != 0 {
                let i = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                if let Some(h) = c.hit(i, *t_max) {
                    let prim = block.prims[i];
                    *t_max = h.t;
                    found = Some((prim, on_triangle(prim, h)));
                }
            }
            return found;
        }
        let (start, n) = self.leaf_range(child, count);
        for &prim in &self.prim_indices[start..start + n] {
            if let Some((t, h)) = test(prim, ray, *t_max) {
                *t_max = t;
                found = Some((prim, h));
            }
        }
        found
    }

    /// Any-hit test of one ray against the leaf entry `(child, count)` within `(0, t_max)`
    /// (leaf blocks four lanes at a time when `blocks`, as [`Self::closest_in_leaf`]).
    #[inline(always)]
    pub(super) fn any_in_leaf(
        &self,
        blocks: bool,
        rt: &RayTriangles,
        ray: &Ray,
        (child, count): (u32, u32),
        t_max: f32,
        test: &mut impl FnMut(u32, &Ray, f32) -> bool,
    ) -> bool {
        if blocks && count & BLOCK != 0 {
            return tri_block::test(&self.blocks[child as usize], rt, t_max).mask != 0;
        }
        let (start, n) = self.leaf_range(child, count);
        self.prim_indices[start..start + n]
            .iter()
            .any(|&prim| test(prim, ray, t_max))
    }

    /// Start loading what `entry` refers to: the node, or the leaf's triangle block.
    #[inline(always)]
    fn prefetch(&self, entry: Entry) {
        self.prefetch_child(entry.child, entry.count);
    }

    /// Start loading the node or leaf block of the lane entry `(child, count)`.
    #[inline(always)]
    pub(super) fn prefetch_child(&self, child: u32, count: u32) {
        if count == INNER {
            if let Some(node) = self.nodes.get(child as usize) {
                crate::math::simd::prefetch(node);
            }
        } else if count & BLOCK != 0 {
            if let Some(block) = self.blocks.get(child as usize) {
                crate::math::simd::prefetch(block);
            }
        }
    }
}

/// The closest-hit leaf test; with `BLOCKS`, leaf blocks take the four-lane triangle test.
struct Closest<H, T, F, const BLOCKS: bool> {
    rt: RayTriangles,
    test: T,
    on_triangle: F,
    best: Option<(u32, H)>,
}

impl<H, T, F, const BLOCKS: bool> Leaf for Closest<H, T, F, BLOCKS>
where
    T: FnMut(u32, &Ray, f32) -> Option<(f32, H)>,
    F: FnMut(u32, TriangleHit) -> H,
{
    const ORDERED: bool = true;
    #[inline(always)]
    fn visit(&mut self, view: &View<'_>, ray: &Ray, child: u32, count: u32, t_max: &mut f32) -> bool {
        let found = view.closest_in_leaf(
            BLOCKS,
            &self.rt,
            ray,
            (child, count),
            t_max,
            &mut self.test,
            &mut self.on_triangle,
        );
        if found.is_some() {
            self.best = found;
        }
        false
    }
}

/// The any-hit leaf test; with `BLOCKS`, leaf blocks take the four-lane triangle test.
struct Any<T, const BLOCKS: bool> {
    rt: RayTriangles,
    test: T,
}

impl<T: FnMut(u32, &Ray, f32) -> bool, const BLOCKS: bool> Leaf for Any<T, BLOCKS> {
    const ORDERED: bool = false;
    #[inline(always)]
    fn visit(&mut self, view: &View<'_>, ray: &Ray, child: u32, count: u32, t_max: &mut f32) -> bool {
        view.any_in_leaf(BLOCKS, &self.rt, ray, (child, count), *t_max, &mut self.test)
    }
}

/// The closest-hit query.
#[inline(always)]
fn traverse_closest<H, const BLOCKS: bool>(
    bvh: &WideBvh,
    ray: &Ray,
    t_max: f32,
    test: impl FnMut(u32, &Ray, f32) -> Option<(f32, H)>,
    boxes: impl BoxTest,
    on_triangle: impl FnMut(u32, TriangleHit) -> H,
) -> Option<(u32, H)> {
    let mut leaf = Closest::<H, _, _, BLOCKS> {
        rt: RayTriangles::new(ray),
        test,
        on_triangle,
        best: None,
    };
    bvh.traverse(ray, t_max, &mut leaf, boxes);
    leaf.best
}

/// The any-hit query.
#[inline(always)]
fn traverse_any<const BLOCKS: bool>(
    bvh: &WideBvh,
    ray: &Ray,
    t_max: f32,
    test: impl FnMut(u32, &Ray, f32) -> bool,
    boxes: impl BoxTest,
) -> bool {
    let mut leaf = Any::<_, BLOCKS> {
        rt: RayTriangles::new(ray),
        test,
    };
    bvh.traverse(ray, t_max, &mut leaf, boxes)
}

/// [`WideBvh::closest_hit_triangles`] in the caller's instruction set (see [`simd`]).
#[inline(always)]
pub(super) fn closest_hit_impl<H>(
    bvh: &WideBvh,
    ray: &Ray,
    t_max: f32,
    test: impl FnMut(u32, &Ray, f32) -> Option<(f32, H)>,
    on_triangle: impl FnMut(u32, TriangleHit) -> H,
    boxes: impl BoxTest,
) -> Option<(u32, H)> {
    traverse_closest::<H, true>(bvh, ray, t_max, test, boxes, on_triangle)
}

/// [`WideBvh::any_hit_triangles`] in the caller's instruction set (see [`simd`]).
#[inline(always)]
pub(super) fn any_hit_impl(
    bvh: &WideBvh,
    ray: &Ray,
    t_max: f32,
    test: impl FnMut(u32, &Ray, f32) -> bool,
    boxes: impl BoxTest,
) -> bool {
    traverse_any::<true>(bvh, ray, t_max, test, boxes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;

    fn unit_box(c: Vec3) -> Bounds3 {
        Bounds3 {
            min: c - Vec3::splat(0.5),
            max: c + Vec3::splat(0.5),
        }
    }

    #[test]
    fn nodes_are_four_cache_lines() {
        assert_eq!(std::mem::size_of::<WideNode>(), 256);
    }

    #[test]
    fn empty_single_and_small() {
        let bvh = WideBvh::build(&[]);
        assert!(bvh.check_invariants(&[]).is_ok());
        let ray = Ray::new(Vec3::ZERO, Vec3::Z);
        assert!(bvh
            .closest_hit(&ray, f32::INFINITY, |_, _, _| Some((1.0, ())))
            .is_none());
        assert!(!bvh.any_hit(&ray, f32::INFINITY, |_, _, _| true));
        for n in 1..=9 {
            let b: Vec<Bounds3> = (0..n).map(|i| unit_box(Vec3::new(3.0 * i as f32, 0.0, 0.0))).collect();
            let bvh = WideBvh::build(&b);
            bvh.check_invariants(&b).unwrap();
            // The root is tested without a box, so every primitive is reachable.
            let mut visited = vec![false; n];
            let ray = Ray::new(Vec3::new(-5.0, 0.0, 0.0), Vec3::X);
            bvh.closest_hit(&ray, f32::INFINITY, |i, _, _| {
                visited[i as usize] = true;
                None::<(f32, ())>
            });
            assert!(visited.iter().all(|&v| v), "{n} boxes: {visited:?}");
        }
    }

    /// A tree large enough for the block cost model is valid, and its leaves fill up.
    #[test]
    fn large_trees_use_block_costs_and_stay_valid() {
        let n = wide_build::BLOCK_COSTS_FROM + 100;
        let b: Vec<Bounds3> = (0..n)
            .map(|i| {
                let c = Vec3::new((i % 97) as f32, (i / 97 % 89) as f32, (i / (97 * 89)) as f32);
                Bounds3 {
                    min: c,
                    max: c + Vec3::splat(0.3),
                }
            })
            .collect();
        let bvh = WideBvh::build(&b);
        bvh.check_invariants(&b).unwrap();
        let leaves = bvh
            .nodes()
            .iter()
            .flat_map(|n| n.count)
            .filter(|&c| c != 0 && c != INNER)
            .count();
        assert!(
            leaves < n / 3,
            "{leaves} leaves for {n} primitives: leaves did not fill up"
        );
    }

    /// A tree of 300,000 scattered boxes, large enough for parallel subtrees inside parallel
    /// subtrees (placed as pieces after the build) and for sampled binning at every stride up
    /// to 64, is valid, and built alike on one thread and two, node for node.
    #[test]
    fn large_parallel_builds_are_valid_and_the_same_on_any_thread_count() {
        let mut state = 0x2545_f491u32;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            state as f32 / u32::MAX as f32
        };
        let b: Vec<Bounds3> = (0..300_000)
            .map(|i| {
                // Clustered: a tenth of the boxes in a small corner, the rest spread out.
                let scale = if i % 10 == 0 { 1.0 } else { 100.0 };
                let c = Vec3::new(next(), next(), next()) * scale;
                Bounds3 {
                    min: c,
                    max: c + Vec3::new(next(), next(), next()) * 0.5,
                }
            })
            .collect();
        let on = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| WideBvh::build(&b))
        };
        let (one, two) = (on(1), on(2));
        two.check_invariants(&b).unwrap();
        let bits = |t: &WideBvh| {
            t.nodes()
                .iter()
                .map(|n| (n.planes.map(|p| p.map(|a| a.map(f32::to_bits))), n.child, n.count))
                .collect::<Vec<_>>()
        };
        assert_eq!(bits(&one), bits(&two));
        assert_eq!(one.prim_indices(), two.prim_indices());
    }

    /// A tree larger than a cache prefetches, a small one does not, and prefetching changes
    /// no answer.
    #[test]
    fn large_trees_prefetch_and_find_the_same_hits() {
        let small = WideBvh::build(&[unit_box(Vec3::ZERO), unit_box(Vec3::X * 3.0)]);
        assert!(!small.prefetch);
        let b: Vec<Bounds3> = (0..40_000)
            .map(|i| unit_box(Vec3::new((i % 200) as f32, (i / 200) as f32, (i % 7) as f32)))
            .collect();
        let bvh = WideBvh::build(&b);
        assert!(bvh.prefetch, "{} nodes", bvh.nodes().len());
        let mut plain = bvh.clone();
        plain.prefetch = false;
        let hits = |tree: &WideBvh, ray: &Ray| {
            // A box that is hit counts at the distance of its centre along the ray.
            let closest = tree.closest_hit(ray, f32::INFINITY, |i, r, t_max| {
                let bx = b[i as usize];
                let t = ((bx.min + bx.max) * 0.5 - r.o).dot(r.d) / r.d.length_squared();
                (bx.hit(r.o.into(), r.d.recip().into(), t_max) && t > 0.0 && t < t_max).then_some((t, ()))
            });
            let any = tree.any_hit(ray, 50.0, |i, r, t| {
                b[i as usize].hit(r.o.into(), r.d.recip().into(), t)
            });
            (closest.map(|(i, ())| i), any)
        };
        let mut hit_some = 0;
        for k in 0..500 {
            let f = k as f32;
            let ray = Ray::new(
                Vec3::new(-5.0, f * 0.37 % 200.0, 3.0),
                Vec3::new(1.0, 0.3 * (f * 0.13).sin(), 0.1 * (f * 0.7).cos()),
            );
            let found = hits(&bvh, &ray);
            assert_eq!(found, hits(&plain, &ray), "ray {ray:?}");
            hit_some += usize::from(found.0.is_some());
        }
        assert!(hit_some > 250, "only {hit_some} of 500 rays hit a box");
    }

    #[test]
    fn identical_boxes_make_a_valid_tree() {
        let b = vec![unit_box(Vec3::ONE); 1000];
        WideBvh::build(&b).check_invariants(&b).unwrap();
    }

    /// A chain of ever larger nested boxes drives the SAH to peel one primitive per level;
    /// the depth bound must hold (the traversal stack is fixed).
    #[test]
    fn nested_boxes_stay_within_the_depth_bound() {
        let b: Vec<Bounds3> = (0..5000)
            .map(|i| {
                let s = 1.1f32.powi(i % 200);
                Bounds3 {
                    min: Vec3::splat(-s),
                    max: Vec3::new(s, s, s + i as f32 * 1e-3),
                }
            })
            .collect();
        let bvh = WideBvh::build(&b);
        bvh.check_invariants(&b).unwrap();
        let mut n = 0;
        bvh.closest_hit(&Ray::new(Vec3::ZERO, Vec3::X), f32::INFINITY, |_, _, _| {
            n += 1;
            None::<(f32, ())>
        });
        assert_eq!(n, b.len(), "every box contains the origin");
    }

    /// Rays along a face of flat boxes, parallel to it, with the origin in the plane.
    #[test]
    fn rays_in_a_box_plane_enter_flat_boxes() {
        let b: Vec<Bounds3> = (0..16)
            .map(|i| Bounds3 {
                min: Vec3::new(i as f32, 0.0, 0.0),
                max: Vec3::new(i as f32 + 0.5, 1.0, 0.0),
            })
            .collect();
        let bvh = WideBvh::build(&b);
        let ray = Ray::new(Vec3::new(-1.0, 0.5, 0.0), Vec3::X);
        let mut found = Vec::new();
        bvh.closest_hit(&ray, f32::INFINITY, |i, _, _| {
            found.push(i);
            None::<(f32, ())>
        });
        found.sort_unstable();
        assert_eq!(found, (0..16).collect::<Vec<_>>());
    }

    #[test]
    fn non_finite_rays_hit_nothing() {
        let b: Vec<Bounds3> = (0..40).map(|i| unit_box(Vec3::new(i as f32, 0.0, 0.0))).collect();
        let bvh = WideBvh::build(&b);
        for d in [Vec3::new(f32::NAN, 0.0, 1.0), Vec3::new(f32::INFINITY, 0.0, 0.0)] {
            let ray = Ray::new(Vec3::ZERO, d);
            assert!(bvh
                .closest_hit(&ray, f32::INFINITY, |_, _, _| Some((1.0, ())))
                .is_none());
            assert!(!bvh.any_hit(&ray, f32::INFINITY, |_, _, _| true));
        }
    }

    /// The box test agrees lane by lane with the scalar `Bounds3::hit`.
    #[test]
    fn lane_box_test_matches_the_scalar_one() {
        let mut seed = 1u32;
        let mut rnd = || {
            seed = seed.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
            (seed >> 8) as f32 / (1u32 << 24) as f32 * 4.0 - 2.0
        };
        for _ in 0..2000 {
            let mut node = WideNode::EMPTY;
            let mut boxes = Vec::new();
            for i in 0..WIDTH {
                let a = Vec3::new(rnd(), rnd(), rnd());
                let b = Vec3::new(rnd(), rnd(), rnd());
                let bx = Bounds3 {
                    min: a.min(b),
                    max: a.max(b),
                };
                for ax in 0..3 {
                    node.planes[0][ax][i] = bx.min[ax];
                    node.planes[1][ax][i] = bx.max[ax];
                }
                boxes.push(bx);
            }
            let mut d = Vec3::new(rnd(), rnd(), rnd());
            if rnd() > 1.0 {
                d.y = 0.0;
            }
            let ray = Ray::new(Vec3::new(rnd(), rnd(), rnd()) * 2.0, d);
            let t_max = if rnd() > 0.0 { f32::INFINITY } else { rnd().abs() };
            let (_, hit) = RayBoxes::new(&ray).hit_lanes(&node, t_max);
            for (i, b) in boxes.iter().enumerate() {
                let scalar = b.hit(ray.o.into(), ray.d.recip().into(), t_max);
                assert_eq!(
                    hit >> i & 1 != 0,
                    scalar,
                    "lane {i}: box {:?} ray {ray:?} t_max {t_max}",
                    b
                );
            }
        }
    }
}
