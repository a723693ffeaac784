//! A BVH built by binned surface-area heuristic (12 buckets on the longest centroid axis,
//! as pbrt-v4 `BVHAggregate`), flattened depth-first into 32-byte nodes: the first child
//! directly follows its parent, the node stores the index of the second.
//!
//! The tree knows primitives only by index and bounds. Queries take a closure that tests
//! one primitive, so the same tree serves shapes, instances and the tests' brute-force
//! comparisons.

use crate::math::{Bounds3, Ray, Vec3};

/// Primitives per leaf above which a split is always tried.
const MAX_PRIMS_IN_LEAF: usize = 4;
/// Number of SAH buckets.
const BUCKETS: usize = 12;

/// A flattened node: bounds plus either a primitive range (leaf) or the second child.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct BvhNode {
    /// Bounds of everything below.
    pub bounds: Bounds3,
    /// Leaf: first entry in the primitive index array. Interior: index of the second child.
    pub offset: u32,
    /// Number of primitives (0 for interior nodes).
    pub prim_count: u16,
    /// Split axis of an interior node.
    pub axis: u8,
    _pad: u8,
}

/// The hierarchy and the primitive order its leaves refer to.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    nodes: Vec<BvhNode>,
    prim_indices: Vec<u32>,
}

struct BuildPrim {
    index: u32,
    bounds: Bounds3,
    centroid: Vec3,
}

impl Bvh {
    /// Build over primitives with the given bounds (index `i` is primitive `i`).
    #[must_use]
    pub fn build(bounds: &[Bounds3]) -> Self {
        let mut prims: Vec<BuildPrim> = bounds
            .iter()
            .enumerate()
            .map(|(i, b)| BuildPrim {
                index: i as u32,
                bounds: *b,
                centroid: b.centroid(),
            })
            .collect();
        let mut bvh = Self {
            nodes: Vec::with_capacity(2 * bounds.len()),
            prim_indices: Vec::with_capacity(bounds.len()),
        };
        if !prims.is_empty() {
            bvh.build_recursive(&mut prims);
        }
        bvh
    }

    /// Append the subtree over `prims` in depth-first order; returns its node index.
    fn build_recursive(&mut self, prims: &mut [BuildPrim]) -> usize {
        let node_index = self.nodes.len();
        let bounds = prims.iter().fold(Bounds3::EMPTY, |b, p| b.union(p.bounds));
        self.nodes.push(BvhNode {
            bounds,
            offset: 0,
            prim_count: 0,
            axis: 0,
            _pad: 0,
        });

        let centroid_bounds = prims.iter().fold(Bounds3::EMPTY, |b, p| b.union_point(p.centroid));
        let axis = centroid_bounds.max_extent_axis();
        let degenerate = centroid_bounds.max[axis] == centroid_bounds.min[axis];
        let split = if prims.len() == 1 || (degenerate && prims.len() <= MAX_PRIMS_IN_LEAF) {
            None
        } else if degenerate {
            // Coincident centroids cannot be separated by position: halve the list.
            Some(prims.len() / 2)
        } else if prims.len() <= 2 {
            // Too few to bin: split in the middle of the centroid order.
            prims.sort_by(|a, b| a.centroid[axis].total_cmp(&b.centroid[axis]));
            Some(1)
        } else {
            Self::sah_split(prims, bounds, centroid_bounds, axis)
        };

        match split {
            None => self.make_leaf(node_index, prims),
            Some(mid) => {
                let (left, right) = prims.split_at_mut(mid);
                self.build_recursive(left);
                let second = self.build_recursive(right);
                let node = &mut self.nodes[node_index];
                node.offset = second as u32;
                node.axis = axis as u8;
            }
        }
        node_index
    }

    fn make_leaf(&mut self, node_index: usize, prims: &[BuildPrim]) {
        let node = &mut self.nodes[node_index];
        node.offset = self.prim_indices.len() as u32;
        node.prim_count = prims.len() as u16;
        self.prim_indices.extend(prims.iter().map(|p| p.index));
    }

    /// Choose a split by the SAH over bucketed centroids; partitions `prims` and returns
    /// the split position, or `None` when a leaf is cheaper.
    fn sah_split(prims: &mut [BuildPrim], bounds: Bounds3, centroid_bounds: Bounds3, axis: usize) -> Option<usize> {
        let bucket_of = |p: &BuildPrim| {
            let b = (BUCKETS as f32 * centroid_bounds.offset(p.centroid)[axis]) as usize;
            b.min(BUCKETS - 1)
        };
        let mut counts = [0usize; BUCKETS];
        let mut bucket_bounds = [Bounds3::EMPTY; BUCKETS];
        for p in prims.iter() {
            let b = bucket_of(p);
            counts[b] += 1;
            bucket_bounds[b] = bucket_bounds[b].union(p.bounds);
        }
        // Cost of splitting after bucket i: forward and backward prefix scans.
        let mut costs = [0.0f32; BUCKETS - 1];
        let (mut count_below, mut bounds_below) = (0, Bounds3::EMPTY);
        for i in 0..BUCKETS - 1 {
            count_below += counts[i];
            bounds_below = bounds_below.union(bucket_bounds[i]);
            costs[i] = count_below as f32 * bounds_below.surface_area();
        }
        let (mut count_above, mut bounds_above) = (0, Bounds3::EMPTY);
        for i in (1..BUCKETS).rev() {
            count_above += counts[i];
            bounds_above = bounds_above.union(bucket_bounds[i]);
            costs[i - 1] += count_above as f32 * bounds_above.surface_area();
        }
        let (best, min_cost) = costs
            .iter()
            .copied()
            .enumerate()
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .expect("BUCKETS > 1");
        // Relative costs: traversal 1/2, intersection 1 per primitive (pbrt-v4).
        let leaf_cost = prims.len() as f32;
        let split_cost = 0.5 + min_cost / bounds.surface_area();
        if prims.len() <= MAX_PRIMS_IN_LEAF && split_cost >= leaf_cost {
            return None;
        }
        let mid = partition(prims, |p| bucket_of(p) <= best);
        if mid == 0 || mid == prims.len() {
            // All centroids fell on one side (possible with huge primitives): split evenly.
            prims.sort_by(|a, b| a.centroid[axis].total_cmp(&b.centroid[axis]));
            return Some(prims.len() / 2);
        }
        Some(mid)
    }

    /// The flattened nodes (root first).
    #[must_use]
    pub fn nodes(&self) -> &[BvhNode] {
        &self.nodes
    }

    /// Primitive indices in leaf order.
    #[must_use]
    pub fn prim_indices(&self) -> &[u32] {
        &self.prim_indices
    }

    /// Bounds of everything (empty for an empty tree).
    #[must_use]
    pub fn bounds(&self) -> Bounds3 {
        self.nodes.first().map_or(Bounds3::EMPTY, |n| n.bounds)
    }

    /// Closest hit along `ray` in `(0, t_max)`. `test(prim, ray, t_max)` intersects one
    /// primitive and returns the hit distance with any payload; the tree shrinks `t_max`
    /// as hits are found and visits the nearer child first.
    pub fn closest_hit<H>(
        &self,
        ray: &Ray,
        mut t_max: f32,
        mut test: impl FnMut(u32, &Ray, f32) -> Option<(f32, H)>,
    ) -> Option<(u32, H)> {
        if self.nodes.is_empty() {
            return None;
        }
        let inv_d = glam::Vec3A::from(ray.d.recip());
        let origin = glam::Vec3A::from(ray.o);
        let dir_is_neg = [inv_d.x < 0.0, inv_d.y < 0.0, inv_d.z < 0.0];
        let mut best = None;
        let mut stack = [0u32; 64];
        let mut sp = 0;
        let mut current = 0usize;
        loop {
            let node = &self.nodes[current];
            if node.bounds.hit(origin, inv_d, t_max) {
                if node.prim_count > 0 {
                    let start = node.offset as usize;
                    for &prim in &self.prim_indices[start..start + node.prim_count as usize] {
                        if let Some((t, h)) = test(prim, ray, t_max) {
                            t_max = t;
                            best = Some((prim, h));
                        }
                    }
                } else {
                    // Visit the near child first, push the far one.
                    let (near, far) = if dir_is_neg[node.axis as usize] {
                        (node.offset as usize, current + 1)
                    } else {
                        (current + 1, node.offset as usize)
                    };
                    stack[sp] = far as u32;
                    sp += 1;
                    current = near;
                    continue;
                }
            }
            if sp == 0 {
                break;
            }
            sp -= 1;
            current = stack[sp] as usize;
        }
        best
    }

    /// True when any primitive blocks `ray` within `(0, t_max)`: `test` says whether one
    /// primitive does. Stops at the first blocker.
    pub fn any_hit(&self, ray: &Ray, t_max: f32, mut test: impl FnMut(u32, &Ray, f32) -> bool) -> bool {
        if self.nodes.is_empty() {
            return false;
        }
        let inv_d = glam::Vec3A::from(ray.d.recip());
        let origin = glam::Vec3A::from(ray.o);
        let mut stack = [0u32; 64];
        let mut sp = 0;
        let mut current = 0usize;
        loop {
            let node = &self.nodes[current];
            if node.bounds.hit(origin, inv_d, t_max) {
                if node.prim_count > 0 {
                    let start = node.offset as usize;
                    for &prim in &self.prim_indices[start..start + node.prim_count as usize] {
                        if test(prim, ray, t_max) {
                            return true;
                        }
                    }
                } else {
                    stack[sp] = node.offset;
                    sp += 1;
                    current += 1;
                    continue;
                }
            }
            if sp == 0 {
                return false;
            }
            sp -= 1;
            current = stack[sp] as usize;
        }
    }

    /// Check the tree's invariants against the primitive bounds it was built from: every
    /// node's bounds are exactly the union of what is below it, and every primitive sits in
    /// exactly one leaf. Returns a description of the first violation.
    pub fn check_invariants(&self, prim_bounds: &[Bounds3]) -> Result<(), String> {
        let mut seen = vec![0u32; prim_bounds.len()];
        if self.nodes.is_empty() {
            return if prim_bounds.is_empty() {
                Ok(())
            } else {
                Err("empty tree over primitives".into())
            };
        }
        self.check_node(0, prim_bounds, &mut seen)?;
        match seen.iter().position(|&c| c != 1) {
            Some(i) => Err(format!("primitive {i} is in {} leaves", seen[i])),
            None => Ok(()),
        }
    }

    fn check_node(&self, index: usize, prim_bounds: &[Bounds3], seen: &mut [u32]) -> Result<Bounds3, String> {
        let node = self
            .nodes
            .get(index)
            .ok_or_else(|| format!("node {index} out of range"))?;
        let below = if node.prim_count > 0 {
            let start = node.offset as usize;
            let mut b = Bounds3::EMPTY;
            for &p in &self.prim_indices[start..start + node.prim_count as usize] {
                seen[p as usize] += 1;
                b = b.union(prim_bounds[p as usize]);
            }
            b
        } else {
            if node.offset as usize <= index + 1 {
                return Err(format!("interior node {index} has second child {}", node.offset));
            }
            let a = self.check_node(index + 1, prim_bounds, seen)?;
            let b = self.check_node(node.offset as usize, prim_bounds, seen)?;
            a.union(b)
        };
        if below != node.bounds {
            return Err(format!(
                "node {index} bounds {:?} are not the union {:?} of its contents",
                node.bounds, below
            ));
        }
        Ok(below)
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;

    #[test]
    fn nodes_are_32_bytes() {
        assert_eq!(std::mem::size_of::<BvhNode>(), 32);
    }

    #[test]
    fn empty_and_single() {
        let bvh = Bvh::build(&[]);
        assert!(bvh
            .closest_hit(&Ray::new(Vec3::ZERO, Vec3::Z), f32::INFINITY, |_, _, _| {
                Some((1.0, ()))
            })
            .is_none());
        let b = [Bounds3 {
            min: Vec3::splat(-1.0),
            max: Vec3::splat(1.0),
        }];
        let bvh = Bvh::build(&b);
        bvh.check_invariants(&b).unwrap();
        assert_eq!(bvh.nodes().len(), 1);
    }

    #[test]
    fn identical_boxes_make_a_valid_tree() {
        let b = vec![
            Bounds3 {
                min: Vec3::ZERO,
                max: Vec3::ONE
            };
            100
        ];
        let bvh = Bvh::build(&b);
        bvh.check_invariants(&b).unwrap();
    }
}
