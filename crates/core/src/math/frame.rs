//! Orthonormal frames: the local shading space in which BSDFs are written (z = normal).

use glam::Vec3;

/// Three orthonormal axes; `z` is the normal of a shading frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// First tangent.
    pub x: Vec3,
    /// Second tangent.
    pub y: Vec3,
    /// Normal.
    pub z: Vec3,
}

impl Frame {
    /// A frame around the unit vector `n`, with tangents from Duff et al. 2017
    /// ("Building an orthonormal basis, revisited"), continuous except at `n.z = -0`.
    #[inline]
    #[must_use]
    pub fn from_z(n: Vec3) -> Self {
        let sign = 1.0f32.copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        let x = Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
        let y = Vec3::new(b, sign + n.y * n.y * a, -n.y);
        Self { x, y, z: n }
    }

    /// A frame with normal `n` whose first tangent is `t` made orthogonal to `n`
    /// (falls back to `from_z` when `t` is parallel to `n`).
    #[inline]
    #[must_use]
    pub fn from_zx(n: Vec3, t: Vec3) -> Self {
        let x = (t - n * n.dot(t)).try_normalize();
        match x {
            Some(x) => Self { x, y: n.cross(x), z: n },
            None => Self::from_z(n),
        }
    }

    /// World vector to local coordinates.
    #[inline]
    #[must_use]
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.x), v.dot(self.y), v.dot(self.z))
    }

    /// Local coordinates to world vector.
    #[inline]
    #[must_use]
    pub fn from_local(&self, v: Vec3) -> Vec3 {
        v.x * self.x + v.y * self.y + v.z * self.z
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_are_orthonormal_and_round_trip() {
        for n in [
            Vec3::Z,
            -Vec3::Z,
            Vec3::X,
            Vec3::new(0.3, -0.5, 0.8).normalize(),
            Vec3::new(1e-8, 0.0, -1.0).normalize(),
        ] {
            let f = Frame::from_z(n);
            assert!((f.x.length() - 1.0).abs() < 1e-5 && (f.y.length() - 1.0).abs() < 1e-5);
            assert!(f.x.dot(f.y).abs() < 1e-5 && f.x.dot(f.z).abs() < 1e-5 && f.y.dot(f.z).abs() < 1e-5);
            let v = Vec3::new(0.2, 0.7, -0.4);
            assert!((f.from_local(f.to_local(v)) - v).length() < 1e-5);
        }
    }
}
