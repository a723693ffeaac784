//! The build of [`super::WideBvh`]: a binary tree by binned SAH (12 buckets on each of the
//! three centroid axes, the cheapest split wins; costs in [`Costs`]), built in
//! parallel with `rayon::join` on large subtrees and partitioning the primitive array in
//! place, so a leaf is a range of the final primitive order. The binary tree is then
//! collapsed into 4-wide nodes by [`super::wide`]. The cost model depends on the tree's size
//! ([`Costs`]).
//!
//! Depth is bounded: below [`MEDIAN_DEPTH`] levels the builder stops looking at costs and
//! splits at the centroid median, so the traversal stack has a fixed size.

use rayon::prelude::*;

use glam::Vec3A;

use crate::math::Bounds3;

/// Primitives per leaf at most (one 4-wide leaf test).
pub(super) const MAX_LEAF: usize = 4;
/// SAH buckets per axis.
const BUCKETS: usize = 12;
/// Subtrees with more primitives than this are built on two threads.
const PARALLEL_MIN: usize = 4096;
/// Depth from which splits are at the median, bounding the depth of the tree.
const MEDIAN_DEPTH: u32 = 64;
/// The deepest a binary node can be: median splits halve the count, so 32 more levels
/// reach single primitives for up to 2^32 of them.
pub(super) const MAX_DEPTH: usize = MEDIAN_DEPTH as usize + 33;

/// A primitive during the build: its box in 4-lane vectors (for fast unions) and index.
#[derive(Clone, Copy, Debug)]
pub(super) struct BuildPrim {
    pub lo: Vec3A,
    pub hi: Vec3A,
    pub index: u32,
}

impl BuildPrim {
    /// Twice the centroid (the halving does not change any comparison or bucket).
    #[inline]
    fn centroid2(&self) -> Vec3A {
        self.lo + self.hi
    }
}

/// A box during the build.
#[derive(Clone, Copy, Debug)]
struct Box3 {
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

/// A node of the binary build tree.
#[derive(Debug)]
pub(super) enum BuildNode {
    /// Primitives `start..start + count` of the final order.
    Leaf { bounds: Bounds3, start: u32, count: u32 },
    /// Two subtrees.
    Inner {
        bounds: Bounds3,
        children: Box<[BuildNode; 2]>,
    },
}

impl BuildNode {
    pub fn bounds(&self) -> Bounds3 {
        match self {
            Self::Leaf { bounds, .. } | Self::Inner { bounds, .. } => *bounds,
        }
    }
}

/// The primitives of `bounds`, in parallel.
pub(super) fn build_prims(bounds: &[Bounds3]) -> Vec<BuildPrim> {
    bounds
        .par_iter()
        .enumerate()
        .map(|(i, b)| BuildPrim {
            lo: b.min.into(),
            hi: b.max.into(),
            index: i as u32,
        })
        .collect()
}

/// Bounds of the primitives and of their (doubled) centroids.
fn bounds_of(prims: &[BuildPrim]) -> (Box3, Box3) {
    let fold = |(b, c): (Box3, Box3), p: &BuildPrim| (b.union(p.lo, p.hi), c.union(p.centroid2(), p.centroid2()));
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

/// Build the subtree over `prims`, which sit at `start..` in the final order.
pub(super) fn build(prims: &mut [BuildPrim], start: usize, depth: u32, costs: Costs) -> BuildNode {
    let (boxed, centroids) = bounds_of(prims);
    let bounds = boxed.bounds();
    let leaf = |prims: &[BuildPrim]| BuildNode::Leaf {
        bounds,
        start: start as u32,
        count: prims.len() as u32,
    };
    if prims.len() == 1 {
        return leaf(prims);
    }
    let axis = (centroids.hi - centroids.lo).max_position();
    let mid = if centroids.hi[axis] == centroids.lo[axis] {
        // Coincident centroids cannot be separated by position.
        if prims.len() <= MAX_LEAF {
            return leaf(prims);
        }
        prims.len() / 2
    } else if depth >= MEDIAN_DEPTH || prims.len() <= 2 {
        median_split(prims, axis)
    } else {
        match sah_split(prims, boxed, centroids, costs) {
            Some(mid) => mid,
            None => return leaf(prims),
        }
    };
    let (left, right) = prims.split_at_mut(mid);
    let (a, b) = if left.len().min(right.len()) > PARALLEL_MIN {
        rayon::join(
            || build(left, start, depth + 1, costs),
            || build(right, start + mid, depth + 1, costs),
        )
    } else {
        (
            build(left, start, depth + 1, costs),
            build(right, start + mid, depth + 1, costs),
        )
    };
    BuildNode::Inner {
        bounds,
        children: Box::new([a, b]),
    }
}

/// Split at the median centroid along `axis`.
fn median_split(prims: &mut [BuildPrim], axis: usize) -> usize {
    let mid = prims.len() / 2;
    prims.select_nth_unstable_by(mid, |a, b| a.centroid2()[axis].total_cmp(&b.centroid2()[axis]));
    mid
}

/// The cheapest bucket boundary over the three axes by the SAH; partitions `prims` and
/// returns the split position, or `None` when a leaf (of at most [`MAX_LEAF`]) is cheaper.
fn sah_split(prims: &mut [BuildPrim], bounds: Box3, centroids: Box3, costs: Costs) -> Option<usize> {
    let extent = centroids.hi - centroids.lo;
    let scale = Vec3A::select(
        extent.cmpgt(Vec3A::ZERO),
        Vec3A::splat(BUCKETS as f32) / extent,
        Vec3A::ZERO,
    );
    let max_bucket = Vec3A::splat((BUCKETS - 1) as f32);
    let buckets_of = |p: &BuildPrim| ((p.centroid2() - centroids.lo) * scale).min(max_bucket).to_array();
    // One pass bins every primitive on all three axes.
    let mut counts = [[0usize; BUCKETS]; 3];
    let mut boxes = [[Box3::EMPTY; BUCKETS]; 3];
    for p in prims.iter() {
        let b = buckets_of(p);
        for axis in 0..3 {
            let k = b[axis] as usize;
            counts[axis][k] += 1;
            boxes[axis][k] = boxes[axis][k].union(p.lo, p.hi);
        }
    }
    let mut best = (f32::INFINITY, 0usize, 0usize);
    for axis in 0..3 {
        if extent[axis] <= 0.0 {
            continue;
        }
        let (counts, boxes) = (&counts[axis], &boxes[axis]);
        // Cost of splitting after bucket i: forward and backward prefix scans.
        let weight = |n: usize| costs.weight(n);
        let mut costs = [0.0f32; BUCKETS - 1];
        let (mut n, mut b) = (0, Box3::EMPTY);
        for i in 0..BUCKETS - 1 {
            n += counts[i];
            b = b.merge(boxes[i]);
            costs[i] = weight(n) * b.area();
        }
        let (mut n, mut b) = (0, Box3::EMPTY);
        for i in (1..BUCKETS).rev() {
            n += counts[i];
            b = b.merge(boxes[i]);
            costs[i - 1] += weight(n) * b.area();
        }
        for (i, &c) in costs.iter().enumerate() {
            if c < best.0 {
                best = (c, axis, i);
            }
        }
    }
    let (min_cost, axis, bucket) = best;
    let split_cost = costs.traversal() + min_cost / bounds.area();
    if prims.len() <= MAX_LEAF && split_cost >= costs.weight(prims.len()) {
        return None;
    }
    let mid = partition(prims, |p| buckets_of(p)[axis] as usize <= bucket);
    if mid == 0 || mid == prims.len() {
        // Everything on one side (possible with a tiny extent and rounding).
        return Some(median_split(prims, extent.max_position()));
    }
    Some(mid)
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

/// Reorder `v` so the elements satisfying `pred` come first; returns how many do.
fn partition<T>(v: &mut [T], pred: impl Fn(&T) -> bool) -> usize {
    let mut i = 0;
    for j in 0..v.len() {
        if pred(&v[j]) {
            v.swap(i, j);
            i += 1;
        }
    }
    i
}
