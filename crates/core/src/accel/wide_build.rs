//! The build of [`super::WideBvh`]: binned SAH (up to 12 buckets on each of the three
//! centroid axes, fewer in small nodes, [`buckets_for`]; large nodes bin a sample,
//! [`sample_stride`]; the cheapest split wins; costs in [`Costs`]) over 32-byte build
//! primitives,
//! partitioning the primitive array in place, so a leaf is a range of the final primitive
//! order. The 8-wide nodes are made directly as the binary splits are decided
//! ([`build_wide`]): the binary tree is never stored, nothing is allocated per node, and
//! large subtrees are built in parallel with rayon. The cost model depends on the tree's
//! size ([`Costs`]).
//!
//! Depth is bounded: below [`MEDIAN_DEPTH`] levels the builder stops looking at costs and
//! splits at the centroid median, so the traversal stack has a fixed size.

use rayon::prelude::*;

use glam::{Vec3A, Vec4};

use super::paged::Paged;
use super::wide::{WideNode, INNER, WIDTH};

use crate::math::Bounds3;

/// Primitives per leaf at most (one four-lane leaf block test).
pub(super) const MAX_LEAF: usize = 4;
/// SAH buckets per axis at most.
const BUCKETS: usize = 12;

/// SAH buckets per axis for a node of `n` primitives: fewer for small nodes, as in
/// Embree's binned builder (`4 + n / 20`, capped). Near the leaves, where most nodes are,
/// a bucket sweep's fixed cost outweighs the binning, and a few primitives gain little from
/// a fine grid: measured on `bench/rays.sh`'s 1M triangles, nodes of 8 to 63 primitives
/// took 38% of the single-thread build with 12 buckets each.
#[inline]
fn buckets_for(n: usize) -> usize {
    BUCKETS.min(4 + n / 20)
}
/// Subtrees with more primitives than this are built on two threads.
const PARALLEL_MIN: usize = 4096;
/// Depth from which splits are at the median, bounding the depth of the tree.
const MEDIAN_DEPTH: u32 = 64;
/// The deepest a binary node can be: median splits halve the count, so 32 more levels
/// reach single primitives for up to 2^32 of them.
pub(super) const MAX_DEPTH: usize = MEDIAN_DEPTH as usize + 33;

/// A primitive during the build, in 32 bytes: its box in two 4-lane vectors (for fast
/// unions), whose fourth lanes hold the primitive's index, 16 bits in each as a small
/// float (so the lane arithmetic of the build never meets a denormal or NaN there).
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C)]
pub(super) struct BuildPrim {
    lo: Vec4,
    hi: Vec4,
}

impl BuildPrim {
    /// The primitive `index` with box `b`.
    fn new(b: &Bounds3, index: u32) -> Self {
        Self {
            lo: b.min.extend((index & 0xffff) as f32),
            hi: b.max.extend((index >> 16) as f32),
        }
    }

    /// The primitive's index.
    #[inline]
    pub fn index(&self) -> u32 {
        self.lo.w as u32 | (self.hi.w as u32) << 16
    }

    /// Box minimum.
    #[inline]
    fn lo(&self) -> Vec3A {
        Vec3A::from_vec4(self.lo)
    }

    /// Box maximum.
    #[inline]
    fn hi(&self) -> Vec3A {
        Vec3A::from_vec4(self.hi)
    }

    /// Twice the centroid (the halving does not change any comparison or bucket).
    #[inline]
    fn centroid2(&self) -> Vec3A {
        self.lo() + self.hi()
    }
}

/// A box during the build.
#[derive(Clone, Copy, Debug)]
pub(super) struct Box3 {
    lo: Vec3A,
    hi: Vec3A,
}

impl Box3 {
    const EMPTY: Self = Self {
        lo: Vec3A::INFINITY,
        hi: Vec3A::NEG_INFINITY,
    };

    #[inline]
    fn union(self, lo: Vec3A, hi: Vec3A) -> Self {
        Self {
            lo: self.lo.min(lo),
            hi: self.hi.max(hi),
        }
    }

    #[inline]
    fn merge(self, b: Self) -> Self {
        self.union(b.lo, b.hi)
    }

    /// Surface area; 0 for an empty box.
    #[inline]
    fn area(self) -> f32 {
        let d = (self.hi - self.lo).max(Vec3A::ZERO);
        2.0 * (d.x * d.y + d.y * d.z + d.z * d.x)
    }

    fn bounds(self) -> Bounds3 {
        Bounds3 {
            min: self.lo.into(),
            max: self.hi.into(),
        }
    }
}

/// The primitives `0..count` with bounds `bounds_of(i)`, in parallel. A large array goes in
/// a memory map advised to use huge pages ([`Paged`]): the build's first touch of 32 MB of
/// fresh 4 KiB pages for 1M primitives (a page fault each) was a tenth of its time on 2
/// threads (1M triangles, five alternating rounds: 0.34-0.42 s, mean 0.38, against 0.32-0.35,
/// mean 0.33).
pub(super) fn build_prims(count: usize, bounds_of: impl Fn(usize) -> Bounds3 + Sync) -> Paged<BuildPrim> {
    Paged::from_fn(count, |i| BuildPrim::new(&bounds_of(i), i as u32))
}

/// Bounds of the primitives and of their (doubled) centroids.
pub(super) fn bounds_of(prims: &[BuildPrim]) -> (Box3, Box3) {
    let fold = |(b, c): (Box3, Box3), p: &BuildPrim| (b.union(p.lo(), p.hi()), c.union(p.centroid2(), p.centroid2()));
    let empty = (Box3::EMPTY, Box3::EMPTY);
    if prims.len() > PARALLEL_MIN * 4 {
        prims
            .par_chunks(PARALLEL_MIN)
            .map(|chunk| chunk.iter().fold(empty, fold))
            .reduce(|| empty, |a, b| (a.0.merge(b.0), a.1.merge(b.1)))
    } else {
        prims.iter().fold(empty, fold)
    }
}

/// A node of the binary tree whose split is decided (and its primitives partitioned):
/// primitives `start..start + len` of the final order.
#[derive(Clone, Copy)]
struct Decided {
    start: usize,
    len: usize,
    /// Binary depth (0 for the root).
    depth: u32,
    /// Box of the primitives.
    bounds: Box3,
    /// `None` for a leaf; else the split position within the node and the bounds (boxes,
    /// doubled centroids) of both sides.
    split: Option<(usize, [(Box3, Box3); 2])>,
}

impl Decided {
    /// What the collapse compares: the surface area of an inner node, `-inf` for a leaf.
    fn collapse_area(&self) -> f32 {
        if self.split.is_some() {
            self.bounds.bounds().surface_area()
        } else {
            f32::NEG_INFINITY
        }
    }
}

/// Decide how the node over `prims`, which sit at `start..` in the final order, splits, and
/// partition them accordingly; `bounds` are those of the primitives and of their doubled
/// centroids ([`bounds_of`]), which the parent learnt while splitting, so no pass over the
/// primitives is spent on them.
fn decide(prims: &mut [BuildPrim], start: usize, depth: u32, costs: Costs, bounds: (Box3, Box3)) -> Decided {
    let (boxed, centroids) = bounds;
    let mut node = Decided {
        start,
        len: prims.len(),
        depth,
        bounds: boxed,
        split: None,
    };
    if prims.len() == 1 {
        return node;
    }
    let axis = (centroids.hi - centroids.lo).max_position();
    let (mid, sides) = if centroids.hi[axis] == centroids.lo[axis] {
        // Coincident centroids cannot be separated by position.
        if prims.len() <= MAX_LEAF {
            return node;
        }
        (prims.len() / 2, None)
    } else if depth >= MEDIAN_DEPTH || prims.len() <= 2 {
        (median_split(prims, axis), None)
    } else if costs == Costs::Blocks && prims.len() <= MAX_LEAF && (boxed.area() > 0.0 && boxed.area().is_finite()) {
        // What `sah_split` would find without binning: a split costs at least the
        // traversal, 1, a leaf of one block exactly 1, so the leaf wins (the area must be
        // finite and positive for the cost to be a number at least 1).
        return node;
    } else {
        match sah_split(prims, boxed, centroids, costs) {
            Split::Leaf => return node,
            Split::Median(mid) => (mid, None),
            Split::Sah(mid, sides) => (mid, Some(sides)),
        }
    };
    let sides = sides.unwrap_or_else(|| {
        let (left, right) = prims.split_at(mid);
        [bounds_of(left), bounds_of(right)]
    });
    node.split = Some((mid, sides));
    node
}

/// Decide the two children of `node`, an inner node within `prims`, whose first primitive
/// sits at `base` in the final order.
fn children(prims: &mut [BuildPrim], base: usize, node: &Decided, costs: Costs) -> [Decided; 2] {
    let (mid, sides) = node.split.expect("an inner node");
    let at = node.start - base;
    let (left, right) = prims[at..at + node.len].split_at_mut(mid);
    let mut left = || decide(left, node.start, node.depth + 1, costs, sides[0]);
    let mut right = || decide(right, node.start + mid, node.depth + 1, costs, sides[1]);
    if node.len > PARALLEL_WIDE {
        // The splits above the parallel subtrees: both sides partitioned at once.
        rayon::join(left, right).into()
    } else {
        [left(), right()]
    }
}

/// The 8-wide tree over `prims` (primitives `0..` of the final order, reordered in place):
/// its nodes in depth-first order, the root's `(child, count)` entry (a leaf when there are
/// at most [`MAX_LEAF`] primitives), the bounds of everything and the deepest inner level
/// (1 for the root, 0 for a leaf root).
///
/// Each node is made as the binary tree is split: starting from the binary node's two
/// children, the inner child of largest surface area is opened until there are [`WIDTH`] (as in
/// Wald et al. 2008, "Getting rid of packets", and Embree's BVH4 and BVH8 builders). The binary tree
/// is never stored: a child is decided (split and partitioned) when it becomes a lane, and
/// an inner lane that stays closed starts its own wide node from that decision.
pub(super) fn build_wide(prims: &mut [BuildPrim], costs: Costs) -> (Paged<WideNode>, (u32, u32), Bounds3, usize) {
    let all = bounds_of(prims);
    let root = decide(prims, 0, 0, costs, all);
    let bounds = root.bounds.bounds();
    if root.split.is_none() {
        return (Paged::default(), (0, root.len as u32), bounds, 0);
    }
    // In a huge-page map for a large tree, first touched 2 MiB at a time and kept as the
    // tree's array with no copy (a `Vec` touched 4 KiB pages one fault at a time, then was
    // copied into a map).
    let mut nodes = Paged::with_capacity(prims.len() / 4 + 1);
    let mut pieces = Vec::new();
    let levels = wide_subtree(prims, root, 1, costs, &mut nodes, &mut pieces);
    place(&mut nodes, 0, pieces);
    (nodes, (0, INNER), bounds, levels)
}

/// The nodes of a subtree built on its own (in parallel with its siblings), its root first,
/// with the [`Holes`] of the subtrees below it that were built the same way.
struct Piece {
    nodes: Paged<WideNode>,
    holes: Holes,
}

/// Subtrees left out of a node list, each with the node (index in that list) and lane that
/// point at it, in the order they are to follow the list.
type Holes = Vec<(usize, usize, Piece)>;

/// Append the pieces of `holes`, whose node indices count from `at` in `out`, to `out`, each
/// followed at once by its own (depth first, so the order is that of one sequential build),
/// pointing their lanes at them and moving their inner children's indices to where they land.
/// Each node is copied once, from its piece to `out` (copying every parallel subtree into its
/// parent's list, level after level, wrote the nodes of a 1M-triangle tree about three times,
/// into fresh pages each time).
fn place(out: &mut Paged<WideNode>, at: usize, holes: Holes) {
    for (node, lane, piece) in holes {
        let offset = out.len();
        out[at + node].child[lane] = offset as u32;
        for &n in piece.nodes.iter() {
            let mut n = n;
            for k in 0..WIDTH {
                if n.count[k] == INNER {
                    n.child[k] += offset as u32;
                }
            }
            out.push(n);
        }
        place(out, offset, piece.holes);
    }
}

/// Subtrees of more primitives than this build their inner lanes in parallel.
const PARALLEL_WIDE: usize = 4 * PARALLEL_MIN;

/// Append the nodes of the subtree of `node`, an inner node over exactly `prims` at wide
/// `level`, to `out`, its root first, except for subtrees built in parallel, which go in
/// `holes` (to be [`place`]d after `out` is complete); returns the deepest inner level below.
fn wide_subtree(
    prims: &mut [BuildPrim],
    node: Decided,
    level: usize,
    costs: Costs,
    out: &mut Paged<WideNode>,
    holes: &mut Holes,
) -> usize {
    let base = node.start;
    // Open the inner lane of largest surface area until there are `WIDTH` (kept in a fixed
    // array with their areas).
    let [a, b] = children(prims, base, &node, costs);
    let mut lanes: [(Decided, f32); WIDTH] = [(a, 0.0); WIDTH];
    lanes[0] = (a, a.collapse_area());
    lanes[1] = (b, b.collapse_area());
    let mut len = 2;
    while len < WIDTH {
        // The last of the largest (as `Iterator::max_by` picks): scan backwards.
        let mut widest = None;
        for i in (0..len).rev() {
            if lanes[i].0.split.is_some() && widest.is_none_or(|w: usize| lanes[i].1.total_cmp(&lanes[w].1).is_gt()) {
                widest = Some(i);
            }
        }
        let Some(i) = widest else { break };
        let [a, b] = children(prims, base, &lanes[i].0, costs);
        // As `Vec::swap_remove` then two pushes.
        lanes[i] = lanes[len - 1];
        lanes[len - 1] = (a, a.collapse_area());
        lanes[len] = (b, b.collapse_area());
        len += 1;
    }
    let index = out.len();
    let mut wide = WideNode::EMPTY;
    for (i, (lane, _)) in lanes[..len].iter().enumerate() {
        let b = lane.bounds.bounds();
        for a in 0..3 {
            wide.planes[0][a][i] = b.min[a];
            wide.planes[1][a][i] = b.max[a];
        }
        wide.child[i] = lane.start as u32;
        wide.count[i] = if lane.split.is_some() { INNER } else { lane.len as u32 };
    }
    out.push(wide);
    // The inner lanes' primitives, each a disjoint part of `prims`.
    let mut by_start: [usize; WIDTH] = std::array::from_fn(|i| i);
    by_start[..len].sort_unstable_by_key(|&i| lanes[i].0.start);
    let mut parts: [Option<&mut [BuildPrim]>; WIDTH] = Default::default();
    let mut rest = prims;
    for &i in &by_start[..len] {
        let (part, tail) = rest.split_at_mut(lanes[i].0.len);
        parts[i] = Some(part);
        rest = tail;
    }
    let inner = |i: usize| lanes[i].0.split.is_some();
    let mut deepest = level;
    if node.len > PARALLEL_WIDE {
        // Each inner lane's subtree into its own piece, in parallel, placed in lane order
        // right after this node once the whole tree is built.
        let jobs: Vec<(usize, &mut [BuildPrim])> = parts
            .into_iter()
            .enumerate()
            .filter(|&(i, _)| i < len && inner(i))
            .map(|(i, p)| (i, p.expect("a part per lane")))
            .collect();
        let built: Vec<(usize, Piece, usize)> = jobs
            .into_par_iter()
            .map(|(i, part)| {
                // A part above `PARALLEL_WIDE` makes one node here and leaves the rest to
                // pieces of its own.
                let capacity = if part.len() > PARALLEL_WIDE {
                    1
                } else {
                    part.len() / 4 + 1
                };
                let mut piece = Piece {
                    nodes: Paged::with_capacity(capacity),
                    holes: Vec::new(),
                };
                let deepest = wide_subtree(part, lanes[i].0, level + 1, costs, &mut piece.nodes, &mut piece.holes);
                (i, piece, deepest)
            })
            .collect();
        // A parallel node's parent is one too (it has more primitives), so the node is the
        // first and only of its list, and its pieces follow it directly.
        debug_assert_eq!((index, out.len()), (0, 1), "a parallel node heads its list");
        for (i, piece, d) in built {
            holes.push((index, i, piece));
            deepest = deepest.max(d);
        }
    } else {
        for (i, part) in parts.into_iter().enumerate().take(len) {
            if inner(i) {
                out[index].child[i] = out.len() as u32;
                let d = wide_subtree(part.expect("a part per lane"), lanes[i].0, level + 1, costs, out, holes);
                deepest = deepest.max(d);
            }
        }
    }
    deepest
}

/// Split at the median centroid along `axis`.
fn median_split(prims: &mut [BuildPrim], axis: usize) -> usize {
    let mid = prims.len() / 2;
    prims.select_nth_unstable_by(mid, |a, b| a.centroid2()[axis].total_cmp(&b.centroid2()[axis]));
    mid
}

/// What [`sah_split`] decided.
enum Split {
    /// A leaf is cheaper.
    Leaf,
    /// Split at this position, after a fallback to the median (bounds unknown).
    Median(usize),
    /// Split at this position; the bounds of both sides (boxes, doubled centroids).
    Sah(usize, [(Box3, Box3); 2]),
}

/// Per-axis SAH bins: primitive counts and box unions.
#[derive(Clone, Copy)]
struct Bins {
    counts: [[u32; BUCKETS]; 3],
    boxes: [[Box3; BUCKETS]; 3],
}

impl Bins {
    const EMPTY: Self = Self {
        counts: [[0; BUCKETS]; 3],
        boxes: [[Box3::EMPTY; BUCKETS]; 3],
    };

    /// Add `o`'s counts and unite its boxes, both exact, so the order of merging does not
    /// matter.
    fn merge(&mut self, o: &Self) {
        for axis in 0..3 {
            for k in 0..BUCKETS {
                self.counts[axis][k] += o.counts[axis][k];
                self.boxes[axis][k] = self.boxes[axis][k].merge(o.boxes[axis][k]);
            }
        }
    }

    /// Add one primitive whose buckets on the three axes are `b`.
    #[inline]
    fn add(&mut self, b: [u32; 3], p: &BuildPrim) {
        for (axis, &k) in b.iter().enumerate() {
            let k = k as usize;
            self.counts[axis][k] += 1;
            self.boxes[axis][k] = self.boxes[axis][k].union(p.lo(), p.hi());
        }
    }
}

/// Primitives from which [`bin`] fills two sets of bins.
const TWO_BIN_SETS_FROM: usize = 256;

/// Nodes of this many primitives or more choose their split from a sample
/// ([`sample_stride`]), and find the sides' boxes while partitioning instead of from the bins.
/// On `bench/rays.sh`'s 1M triangles the tree's SAH cost (node and leaf-block tests per
/// ray, relative to the root's area) went from 20.090 to 20.086, and the build from 1.97 to
/// 1.69 G instructions (callgrind, one thread): the top levels' binning, a pass over every
/// primitive per level, costs next to nothing. Nodes from [`HALVED_FROM`] bin every other
/// primitive: SAH cost 20.109, build 1.61 G instructions.
const SAMPLED_FROM: usize = 1 << 12;
/// Nodes of this many primitives or more, and fewer than [`SAMPLED_FROM`], bin every other
/// one (at least 128, a dozen per bucket).
const HALVED_FROM: usize = 256;
/// A sampled node bins `SAMPLES` to `2 * SAMPLES` primitives, or a quarter of its own when
/// it has fewer than `8 * SAMPLES` (at least `SAMPLES / 4`, a few dozen per bucket).
const SAMPLES: usize = 1 << 12;

/// Bin every `sample_stride(n)`-th primitive of a node of `n`: all of them in small nodes,
/// every other from [`HALVED_FROM`], every fourth from [`SAMPLED_FROM`], and in large nodes
/// a stride (a power of two) that leaves `SAMPLES` to `2 * SAMPLES` of them.
#[inline]
fn sample_stride(n: usize) -> usize {
    if n < HALVED_FROM {
        1
    } else if n < SAMPLED_FROM {
        2
    } else {
        // `n / SAMPLES >= 1`, as `SAMPLED_FROM` is `SAMPLES`.
        (1 << (n / SAMPLES).ilog2()).max(4)
    }
}

/// Bin every `stride`-th primitive of `prims` (from the first) on all three axes into
/// `bins`. Large nodes fill two sets of bins with alternate primitives, so that neighbours
/// falling in the same bucket (the common case) do not wait on each other's
/// read-modify-write of the same bin.
#[inline]
fn bin(bins: &mut Bins, prims: &[BuildPrim], stride: usize, buckets_of: impl Fn(&BuildPrim) -> [u32; 3]) {
    if prims.len() < TWO_BIN_SETS_FROM * stride {
        for p in prims.iter().step_by(stride) {
            bins.add(buckets_of(p), p);
        }
        return;
    }
    let mut odd = Bins::EMPTY;
    let mut pairs = prims.chunks_exact(2 * stride);
    for pair in &mut pairs {
        bins.add(buckets_of(&pair[0]), &pair[0]);
        odd.add(buckets_of(&pair[stride]), &pair[stride]);
    }
    for p in pairs.remainder().iter().step_by(stride) {
        bins.add(buckets_of(p), p);
    }
    bins.merge(&odd);
}

/// The cheapest bucket boundary over the three axes by the SAH; partitions `prims` and
/// returns the split position with the bounds of both sides, or [`Split::Leaf`] when a leaf
/// (of at most [`MAX_LEAF`]) is cheaper.
fn sah_split(prims: &mut [BuildPrim], bounds: Box3, centroids: Box3, costs: Costs) -> Split {
    let extent = centroids.hi - centroids.lo;
    let buckets = buckets_for(prims.len());
    let scale = Vec3A::select(
        extent.cmpgt(Vec3A::ZERO),
        Vec3A::splat(buckets as f32) / extent,
        Vec3A::ZERO,
    );
    let max_bucket = Vec3A::splat((buckets - 1) as f32);
    let buckets_of = |p: &BuildPrim| {
        // In 0..=buckets - 1 (a NaN became the maximum), where rounding down is truncating:
        // one vector conversion (`as` on each lane saturates lane by lane, and was a fifth of
        // the binning's time; adding 2^23 and correcting where that rounded up took twelve
        // instructions).
        crate::math::simd::truncate_lanes(((p.centroid2() - centroids.lo) * scale).min(max_bucket))
    };
    // One pass bins every primitive, or a sample of a large node's, on all three axes. (Large
    // nodes were binned in parallel before sampling; a sample is at most `2 * SAMPLES`.)
    let stride = sample_stride(prims.len());
    let mut bins = Bins::EMPTY;
    bin(&mut bins, prims, stride, buckets_of);
    let mut best = (f32::INFINITY, 0usize, 0usize);
    for axis in 0..3 {
        if extent[axis] <= 0.0 {
            continue;
        }
        let (counts, boxes) = (&bins.counts[axis], &bins.boxes[axis]);
        // Cost of splitting after bucket i: forward and backward prefix scans (a sample's
        // counts stand for `stride` primitives each).
        let weight = |n: usize| costs.weight(n * stride);
        // An empty bucket changes neither the count nor the box (merging an empty box is
        // exact), so its side's cost is the previous one: only occupied buckets cost an area,
        // which is most of the saving in the many small nodes near the leaves.
        let mut costs = [0.0f32; BUCKETS - 1];
        let (mut n, mut b, mut side) = (0, Box3::EMPTY, 0.0f32);
        for i in 0..buckets - 1 {
            if counts[i] != 0 {
                n += counts[i] as usize;
                b = b.merge(boxes[i]);
                side = weight(n) * b.area();
            }
            costs[i] = side;
        }
        let (mut n, mut b, mut side) = (0, Box3::EMPTY, 0.0f32);
        for i in (1..buckets).rev() {
            if counts[i] != 0 {
                n += counts[i] as usize;
                b = b.merge(boxes[i]);
                side = weight(n) * b.area();
            }
            costs[i - 1] += side;
        }
        for (i, &c) in costs[..buckets - 1].iter().enumerate() {
            if c < best.0 {
                best = (c, axis, i);
            }
        }
    }
    let (min_cost, axis, bucket) = best;
    let split_cost = costs.traversal() + min_cost / bounds.area();
    if prims.len() <= MAX_LEAF && split_cost >= costs.weight(prims.len()) {
        return Split::Leaf;
    }
    // `bucket <= buckets - 2`, so a primitive's bucket is at most `bucket` exactly when its
    // scaled centroid (non-negative) is below `bucket + 1`: no conversion needed. A NaN
    // (bucket buckets - 1) compares false, as it should.
    // The comparison is made on all three lanes and the axis's bit read from the mask, which
    // keeps the vector in a register (indexing a lane by a run-time axis goes via memory).
    let limit = Vec3A::splat((bucket + 1) as f32);
    let goes_left = |p: &BuildPrim| ((p.centroid2() - centroids.lo) * scale).cmplt(limit).bitmask() >> axis & 1 != 0;
    // When the bins saw only a sample, the sides' boxes come from the partition's pass.
    let sampled = stride > 1;
    let (mid, sides) = if sampled {
        partition::<true>(prims, goes_left)
    } else {
        partition::<false>(prims, goes_left)
    };
    if mid == 0 || mid == prims.len() {
        // Everything on one side (possible with a tiny extent and rounding).
        return Split::Median(median_split(prims, extent.max_position()));
    }
    if sampled {
        return Split::Sah(mid, sides);
    }
    // The sides' boxes are the unions of their bins (min and max are exact).
    let boxes = &bins.boxes[axis];
    let left = boxes[..=bucket].iter().fold(Box3::EMPTY, |a, &b| a.merge(b));
    let right = boxes[bucket + 1..].iter().fold(Box3::EMPTY, |a, &b| a.merge(b));
    Split::Sah(mid, [(left, sides[0].1), (right, sides[1].1)])
}

/// Primitives from which [`Costs::Blocks`] is used.
pub(super) const BLOCK_COSTS_FROM: usize = 1 << 16;

/// The SAH's cost model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Costs {
    /// pbrt-v4's: traversal 1/2, intersection 1 per primitive. Leaves stay small with tight
    /// boxes, which pays where the tree fits in cache: a Cornell box rendered 5-10% faster
    /// than with `Blocks` in alternating runs.
    Primitives,
    /// Embree's for 4-triangle leaves: traversal 1, intersection 1 per block of up to four
    /// primitives (tested four at a time), so leaves fill up and there are fewer nodes,
    /// which pays on large meshes: camera rays on `bench/rays.sh`'s 1M triangles ran 1.3-1.4x
    /// faster than with `Primitives`.
    Blocks,
}

impl Costs {
    /// The model for a tree over `n` primitives.
    pub(super) fn for_count(n: usize) -> Self {
        if n >= BLOCK_COSTS_FROM {
            Self::Blocks
        } else {
            Self::Primitives
        }
    }

    fn traversal(self) -> f32 {
        match self {
            Self::Primitives => 0.5,
            Self::Blocks => 1.0,
        }
    }

    /// The intersection cost of `n` primitives in a leaf.
    #[inline]
    fn weight(self, n: usize) -> f32 {
        match self {
            Self::Primitives => n as f32,
            Self::Blocks => n.div_ceil(MAX_LEAF) as f32,
        }
    }
}

/// Reorder `prims` so those satisfying `pred` come first (those keep their order; the
/// others are permuted as a swap-based partition leaves them); returns how many do and the
/// bounds of both sides (boxes, doubled centroids). The boxes are found only when `BOXES`
/// (else they are left empty). (Tried and not faster in alternating runs: a branch-free
/// version writing both slots with lane selects, one swapping every element
/// unconditionally, and splitting the root's partition over two threads.)
fn partition<const BOXES: bool>(
    prims: &mut [BuildPrim],
    pred: impl Fn(&BuildPrim) -> bool,
) -> (usize, [(Box3, Box3); 2]) {
    let mut sides = [(Box3::EMPTY, Box3::EMPTY); 2];
    let mut i = 0;
    for j in 0..prims.len() {
        let p = prims[j];
        let c = p.centroid2();
        let add = |side: &mut (Box3, Box3)| {
            side.1 = side.1.union(c, c);
            if BOXES {
                side.0 = side.0.union(p.lo(), p.hi());
            }
        };
        if pred(&p) {
            add(&mut sides[0]);
            // A swap with `p` kept in registers (`slice::swap` went through the stack).
            prims[j] = prims[i];
            prims[i] = p;
            i += 1;
        } else {
            add(&mut sides[1]);
        }
    }
    (i, sides)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Uniform floats in `[0, 1]` from a xorshift generator started at `seed`.
    fn uniform(seed: u32) -> impl FnMut() -> f32 {
        let mut state = seed;
        move || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            state as f32 / u32::MAX as f32
        }
    }

    /// Small nodes bin every primitive, middling ones every other, sampled ones at least
    /// `SAMPLES / 4` and at most `2 * SAMPLES` of them.
    #[test]
    fn sample_strides_leave_enough_primitives() {
        assert_eq!(sample_stride(1), 1);
        assert_eq!(sample_stride(HALVED_FROM - 1), 1);
        assert_eq!(sample_stride(HALVED_FROM), 2);
        assert_eq!(sample_stride(SAMPLED_FROM - 1), 2);
        for n in (SAMPLED_FROM..1 << 24).step_by(997) {
            let (stride, samples) = (sample_stride(n), n / sample_stride(n));
            assert!(stride.is_power_of_two() && stride >= 4, "{n}: {stride}");
            assert!((SAMPLES / 4..2 * SAMPLES).contains(&samples), "{n}: {samples}");
        }
    }

    /// The index survives the trip through the boxes' fourth lanes.
    #[test]
    fn build_prims_keep_their_index() {
        let b = Bounds3 {
            min: crate::math::Vec3::splat(-1.0),
            max: crate::math::Vec3::splat(2.0),
        };
        for i in [0, 1, 0xffff, 0x1_0000, 0x1234_5678, u32::MAX] {
            let p = BuildPrim::new(&b, i);
            assert_eq!(p.index(), i);
            assert_eq!((p.lo(), p.hi()), (Vec3A::splat(-1.0), Vec3A::splat(2.0)));
        }
    }

    /// With block costs, up to four primitives in a box of positive area always make a
    /// leaf by the SAH, which `decide` then takes without binning.
    #[test]
    fn block_cost_small_nodes_are_leaves_by_the_sah() {
        let mut next = uniform(987);
        for trial in 0..2000 {
            let n = 3 + trial % 2;
            let bounds: Vec<Bounds3> = (0..n)
                .map(|_| {
                    let c = crate::math::Vec3::new(next(), next(), next()) * 10.0;
                    let e = crate::math::Vec3::new(next(), next(), next()) * (0.01 + next());
                    Bounds3 { min: c - e, max: c + e }
                })
                .collect();
            let mut prims = build_prims(bounds.len(), |i| bounds[i]);
            let (boxed, centroids) = bounds_of(&prims);
            assert!(matches!(
                sah_split(&mut prims, boxed, centroids, Costs::Blocks),
                Split::Leaf
            ));
            assert!(decide(&mut prims, 0, 0, Costs::Blocks, (boxed, centroids))
                .split
                .is_none());
        }
    }

    /// The bounds a split hands down equal those computed from the primitives afresh, and the
    /// tree is the same as one built computing them afresh.
    #[test]
    fn split_bounds_match_a_fresh_pass() {
        // 200 boxes are binned all, 500 every other, 5000 every fourth, 40,000 every eighth.
        for n in [200, 500, 5000, 40_000] {
            split_bounds_match_a_fresh_pass_for(n);
        }
    }

    fn split_bounds_match_a_fresh_pass_for(n: usize) {
        let mut next = uniform(12345);
        let bounds: Vec<Bounds3> = (0..n)
            .map(|_| {
                let c = crate::math::Vec3::new(next(), next(), next()) * 10.0;
                let e = crate::math::Vec3::new(next(), next(), next()) * 0.3;
                Bounds3 { min: c - e, max: c + e }
            })
            .collect();
        let mut prims = build_prims(bounds.len(), |i| bounds[i]);
        let (boxed, centroids) = bounds_of(&prims);
        let Split::Sah(mid, sides) = sah_split(&mut prims, boxed, centroids, Costs::Primitives) else {
            panic!("{n} spread boxes must split by the SAH");
        };
        for (side, prims) in sides.iter().zip([&prims[..mid], &prims[mid..]]) {
            let fresh = bounds_of(prims);
            assert_eq!((side.0.lo, side.0.hi), (fresh.0.lo, fresh.0.hi));
            assert_eq!((side.1.lo, side.1.hi), (fresh.1.lo, fresh.1.hi));
        }
    }
}
