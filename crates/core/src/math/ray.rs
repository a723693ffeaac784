//! Rays: an origin and a direction (not necessarily unit length).

use glam::Vec3;

/// A ray `o + t d`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Origin.
    pub o: Vec3,
    /// Direction; unit length for camera and scattered rays, `to - from` for shadow rays.
    pub d: Vec3,
}

impl Ray {
    /// A ray from `o` in direction `d`.
    #[inline]
    #[must_use]
    pub fn new(o: Vec3, d: Vec3) -> Self {
        Self { o, d }
    }

    /// Whether the origin and direction are finite (two four-lane tests, a compare and a
    /// mask each, rather than six scalar ones: the BVH queries ask it of every ray).
    #[inline(always)]
    #[must_use]
    pub fn is_finite(&self) -> bool {
        glam::Vec3A::from(self.o).is_finite() && glam::Vec3A::from(self.d).is_finite()
    }

    /// The point at parameter `t`.
    #[inline]
    #[must_use]
    pub fn at(&self, t: f32) -> Vec3 {
        self.o + t * self.d
    }
}
