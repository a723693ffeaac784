//! Axis-aligned bounding boxes.

use glam::Vec3;

/// An axis-aligned box; the empty box has `min > max`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds3 {
    /// Lower corner.
    pub min: Vec3,
    /// Upper corner.
    pub max: Vec3,
}

impl Default for Bounds3 {
    fn default() -> Self {
        Self::EMPTY
    }
}

impl Bounds3 {
    /// The empty box, neutral for `union`.
    pub const EMPTY: Self = Self {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    /// The box holding exactly one point.
    #[inline]
    #[must_use]
    pub fn from_point(p: Vec3) -> Self {
        Self { min: p, max: p }
    }

    /// Smallest box holding `self` and `p`.
    #[inline]
    #[must_use]
    pub fn union_point(self, p: Vec3) -> Self {
        Self {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    /// Smallest box holding both boxes.
    #[inline]
    #[must_use]
    pub fn union(self, b: Self) -> Self {
        Self {
            min: self.min.min(b.min),
            max: self.max.max(b.max),
        }
    }

    /// True for the empty box.
    #[inline]
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x || self.min.y > self.max.y || self.min.z > self.max.z
    }

    /// Edge lengths.
    #[inline]
    #[must_use]
    pub fn diagonal(&self) -> Vec3 {
        self.max - self.min
    }

    /// Centre point.
    #[inline]
    #[must_use]
    pub fn centroid(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    /// Surface area (zero for the empty box).
    #[inline]
    #[must_use]
    pub fn surface_area(&self) -> f32 {
        if self.is_empty() {
            return 0.0;
        }
        let d = self.diagonal();
        2.0 * (d.x * d.y + d.y * d.z + d.z * d.x)
    }

    /// Index of the longest axis.
    #[inline]
    #[must_use]
    pub fn max_extent_axis(&self) -> usize {
        let d = self.diagonal();
        if d.x > d.y && d.x > d.z {
            0
        } else if d.y > d.z {
            1
        } else {
            2
        }
    }

    /// Position of `p` relative to the box: 0 at `min`, 1 at `max`, per axis.
    #[inline]
    #[must_use]
    pub fn offset(&self, p: Vec3) -> Vec3 {
        let mut o = p - self.min;
        let d = self.diagonal();
        for i in 0..3 {
            if d[i] > 0.0 {
                o[i] /= d[i];
            }
        }
        o
    }

    /// True when `p` lies inside or on the box.
    #[inline]
    #[must_use]
    pub fn contains(&self, p: Vec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }

    /// True when `b` lies inside or on the box.
    #[inline]
    #[must_use]
    pub fn contains_box(&self, b: &Self) -> bool {
        self.contains(b.min) && self.contains(b.max)
    }

    /// Slab test of a ray against the box within `(0, t_max)`, given the precomputed
    /// reciprocal direction. The far distance is scaled by `1 + 2 gamma(3)` so rounding
    /// cannot make a ray miss a box it touches (pbrt-v4 `Bounds3::IntersectP`); the near
    /// one by `1 - 2 gamma(3)`, so a `t_max` within rounding of a hit on a face keeps it.
    #[inline]
    #[must_use]
    pub fn hit(&self, o: glam::Vec3A, inv_d: glam::Vec3A, t_max: f32) -> bool {
        // SIMD lanes via Vec3A: four-wide arithmetic on the three slabs at once. The
        // margins scale the reciprocal direction, once (the wide BVH's box test does the same,
        // `RayBoxes::hit_lanes`): entries shrink by `1 - 2 gamma(3)`, so a `t_max` just past
        // a hit on a face keeps the box, and exits grow by `1 + 2 gamma(3)`.
        let inv_near = inv_d * (1.0 - 2.0 * super::gamma(3));
        let inv_far = inv_d * (1.0 + 2.0 * super::gamma(3));
        let (min, max) = (glam::Vec3A::from(self.min) - o, glam::Vec3A::from(self.max) - o);
        let (t0_near, t1_near) = (min * inv_near, max * inv_near);
        let (t0_far, t1_far) = (min * inv_far, max * inv_far);
        // 0 x inf = NaN for a ray parallel to a slab whose origin lies on the slab's
        // plane: that slab does not limit the ray (conservative, so flat boxes are not missed).
        let nan = t0_near.is_nan_mask() | t1_near.is_nan_mask();
        let t_near = glam::Vec3A::select(nan, glam::Vec3A::NEG_INFINITY, t0_near.min(t1_near));
        let t_far = glam::Vec3A::select(nan, glam::Vec3A::INFINITY, t0_far.max(t1_far));
        let t_enter = t_near.max_element().max(0.0);
        let t_exit = t_far.min_element().min(t_max);
        t_enter <= t_exit
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3A;

    /// A ray parallel to a slab with its origin exactly on the slab's plane gives 0 x inf =
    /// NaN in the slab test; it must count as inside (conservative), as for a flat box.
    #[test]
    fn rays_in_a_slab_plane_hit_flat_boxes() {
        let flat = Bounds3 {
            min: Vec3::new(1.0, 0.0, 0.0),
            max: Vec3::new(1.0, 1.0, 1.0),
        };
        let o = Vec3::new(1.0, -1.0, 0.5);
        let d = Vec3::new(0.0, 1.0, 0.0);
        assert!(flat.hit(Vec3A::from(o), Vec3A::from(d.recip()), f32::INFINITY));
        let boxed = Bounds3 {
            min: Vec3::new(1.0, 0.0, 0.0),
            max: Vec3::new(2.0, 1.0, 1.0),
        };
        assert!(boxed.hit(Vec3A::from(o), Vec3A::from(d.recip()), f32::INFINITY));
        let miss = Bounds3 {
            min: Vec3::new(1.5, 0.0, 0.0),
            max: Vec3::new(2.0, 1.0, 1.0),
        };
        assert!(!miss.hit(Vec3A::from(o), Vec3A::from(d.recip()), f32::INFINITY));
    }

    /// Rays that touch a box only at a corner, an edge point or a face point, on a grid of
    /// eighths where every difference is exact (so the ray passes exactly through the
    /// point, at `t = 1`), enter the box: with no limit, with the limit exactly at the touch
    /// and just past it. The rounding margins folded into the reciprocal direction must
    /// cover the slab test's roundings for these grazing rays.
    #[test]
    fn grazing_rays_enter_the_box_at_the_point_they_touch() {
        let mut seed = 7u32;
        let mut grid = |range: i32| {
            seed = seed.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
            ((seed >> 8) as i32 % (2 * range + 1) - range) as f32 / 8.0
        };
        for _ in 0..20_000 {
            let a = Vec3::new(grid(40), grid(40), grid(40));
            let b = Vec3::new(grid(40), grid(40), grid(40));
            let bx = Bounds3 {
                min: a.min(b),
                max: a.max(b),
            };
            // A point of the surface: each coordinate a box plane, or (for an edge or a
            // face point) inside the box's range on up to two axes.
            let mut p = Vec3::ZERO;
            let inside_axes = (grid(8).abs() * 8.0) as usize % 3;
            for axis in 0..3 {
                let (lo, hi) = (bx.min[axis], bx.max[axis]);
                p[axis] = if axis < inside_axes {
                    (lo + hi) * 0.5
                } else if grid(1) > 0.0 {
                    hi
                } else {
                    lo
                };
            }
            // An origin outside, away from the box along each axis the point is on a plane of.
            let mut o = p;
            for axis in inside_axes..3 {
                let away = 1.0 + grid(40).abs();
                o[axis] = if p[axis] == bx.max[axis] {
                    p[axis] + away
                } else {
                    p[axis] - away
                };
            }
            let d = p - o;
            let inv_d = Vec3A::from(d.recip());
            for t_max in [f32::INFINITY, 1.0, 1.0 + 1e-6] {
                assert!(
                    bx.hit(Vec3A::from(o), inv_d, t_max),
                    "box {bx:?} ray from {o:?} to {p:?}, t_max {t_max}"
                );
            }
        }
    }
}
