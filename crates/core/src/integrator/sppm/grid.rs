//! The spatial hash grid over the visible points of one SPPM iteration (pbrt-v4
//! `SPPMIntegrator`'s grid): a uniform grid over the points' bounds with cells about the
//! size of the largest search radius, each point entered in every cell its search sphere
//! overlaps, cells hashed into a table with as many buckets as points. A photon looks up
//! the one cell holding its hit point and tests the points listed there.

use glam::IVec3;

use crate::math::{Bounds3, Vec3};

/// Points (with radii) bucketed by the grid cells their spheres overlap.
#[derive(Clone, Debug)]
pub struct PointGrid {
    bounds: Bounds3,
    /// Cells per axis.
    resolution: IVec3,
    /// Start of each bucket in `entries` (`buckets + 1` offsets).
    offsets: Vec<u32>,
    /// Point indices, bucket by bucket, each bucket in increasing point order.
    entries: Vec<u32>,
}

/// FNV-style hash of a cell, as pbrt's `hash(p) % size`.
fn cell_hash(c: IVec3, buckets: usize) -> usize {
    let h = (c.x as u32 as u64).wrapping_mul(73_856_093)
        ^ (c.y as u32 as u64).wrapping_mul(19_349_663)
        ^ (c.z as u32 as u64).wrapping_mul(83_492_791);
    (h % buckets as u64) as usize
}

impl PointGrid {
    /// Bucket the points `(index, position, radius)`; points with radius 0 are left out.
    #[must_use]
    pub fn new(points: &[(u32, Vec3, f32)]) -> Self {
        let mut bounds = Bounds3::EMPTY;
        let mut max_radius = 0.0f32;
        for &(_, p, r) in points {
            bounds = bounds.union_point(p - Vec3::splat(r)).union_point(p + Vec3::splat(r));
            max_radius = max_radius.max(r);
        }
        let buckets = points.len().max(1);
        if points.is_empty() || max_radius <= 0.0 {
            return Self {
                bounds,
                resolution: IVec3::ONE,
                offsets: vec![0; buckets + 1],
                entries: Vec::new(),
            };
        }
        // Cells about as wide as the largest search diameter (pbrt: maxDiag / (2 r)),
        // at most 2^20 per axis.
        let diag = bounds.diagonal();
        let base = diag.max_element() / (2.0 * max_radius);
        let resolution = (diag / diag.max_element() * base)
            .ceil()
            .max(Vec3::ONE)
            .min(Vec3::splat((1 << 20) as f32))
            .as_ivec3();
        let mut grid = Self {
            bounds,
            resolution,
            offsets: Vec::new(),
            entries: Vec::new(),
        };
        let mut pairs: Vec<(u32, u32)> = Vec::new();
        for &(index, p, r) in points {
            if r <= 0.0 {
                continue;
            }
            let lo = grid.cell(p - Vec3::splat(r));
            let hi = grid.cell(p + Vec3::splat(r));
            for z in lo.z..=hi.z {
                for y in lo.y..=hi.y {
                    for x in lo.x..=hi.x {
                        pairs.push((cell_hash(IVec3::new(x, y, z), buckets) as u32, index));
                    }
                }
            }
        }
        // Sorted by bucket then point; a point whose cells share a bucket is listed once
        // (a photon must not find it twice).
        pairs.sort_unstable();
        pairs.dedup();
        let mut counts = vec![0u32; buckets + 1];
        for &(b, _) in &pairs {
            counts[b as usize + 1] += 1;
        }
        for i in 1..counts.len() {
            counts[i] += counts[i - 1];
        }
        let entries = pairs.iter().map(|&(_, index)| index).collect();
        grid.offsets = counts;
        grid.entries = entries;
        grid
    }

    /// The cell holding `p` (clamped to the grid).
    fn cell(&self, p: Vec3) -> IVec3 {
        let t = (p - self.bounds.min) / self.bounds.diagonal().max(Vec3::splat(f32::MIN_POSITIVE));
        (t * self.resolution.as_vec3())
            .floor()
            .as_ivec3()
            .clamp(IVec3::ZERO, self.resolution - IVec3::ONE)
    }

    /// The points whose spheres may contain `p` (a superset: test the distance), or none
    /// when `p` is outside the grid.
    #[must_use]
    pub fn candidates(&self, p: Vec3) -> &[u32] {
        if self.entries.is_empty() || !self.bounds.contains(p) {
            return &[];
        }
        let b = cell_hash(self.cell(p), self.offsets.len() - 1);
        &self.entries[self.offsets[b] as usize..self.offsets[b + 1] as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Pcg32;

    /// Every point whose sphere contains a query is among the query's candidates
    /// (against brute force).
    #[test]
    fn candidates_include_every_point_in_range() {
        let mut rng = Pcg32::new(1, 2);
        let mut v = || Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
        let points: Vec<(u32, Vec3, f32)> = (0..500).map(|i| (i, v() * 4.0, 0.05 + 0.2 * v().x)).collect();
        let grid = PointGrid::new(&points);
        let mut total = 0;
        for _ in 0..5000 {
            let q = v() * 4.4 - Vec3::splat(0.2);
            let c = grid.candidates(q);
            let mut sorted = c.to_vec();
            sorted.dedup();
            assert_eq!(sorted.len(), c.len(), "a point is listed twice at {q}");
            for &(i, p, r) in &points {
                if (p - q).length_squared() <= r * r {
                    total += 1;
                    assert!(c.contains(&i), "point {i} missing at {q}");
                }
            }
        }
        assert!(total > 100);
    }
}
