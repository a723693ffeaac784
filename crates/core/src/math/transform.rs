//! Affine transforms with their inverse kept beside them, as pbrt does.

use glam::{Mat4, Vec3};

/// A 4x4 transform and its inverse.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    /// The matrix.
    pub m: Mat4,
    /// Its inverse.
    pub m_inv: Mat4,
}

impl Default for Transform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Transform {
    /// The identity.
    pub const IDENTITY: Self = Self {
        m: Mat4::IDENTITY,
        m_inv: Mat4::IDENTITY,
    };

    /// A transform from a matrix; `None` when the matrix is singular or not finite.
    #[must_use]
    pub fn new(m: Mat4) -> Option<Self> {
        let det = m.determinant();
        if !det.is_finite() || det == 0.0 || !m.is_finite() {
            return None;
        }
        Some(Self { m, m_inv: m.inverse() })
    }

    /// The inverse transform.
    #[must_use]
    pub fn inverse(&self) -> Self {
        Self {
            m: self.m_inv,
            m_inv: self.m,
        }
    }

    /// Composition: `self` applied after `t`.
    #[must_use]
    pub fn compose(&self, t: &Self) -> Self {
        Self {
            m: self.m * t.m,
            m_inv: t.m_inv * self.m_inv,
        }
    }

    /// Transform a point (with the projective divide).
    #[inline]
    #[must_use]
    pub fn point(&self, p: Vec3) -> Vec3 {
        self.m.project_point3(p)
    }

    /// Transform a point known to within `p_error` (absolute, per axis) by an affine
    /// transform; returns the point and the bound of its error, which adds the rounding of
    /// the transform itself (pbrt-v4 eqs. 6.28 and 6.30).
    #[must_use]
    pub fn point_with_error(&self, p: Vec3, p_error: Vec3) -> (Vec3, Vec3) {
        let m = &self.m;
        let lin = glam::Mat3::from_mat4(*m);
        let abs_lin = glam::Mat3::from_cols(lin.x_axis.abs(), lin.y_axis.abs(), lin.z_axis.abs());
        let error = (super::gamma(3) + 1.0) * (abs_lin * p_error)
            + super::gamma(3) * (abs_lin * p.abs() + m.w_axis.truncate().abs());
        (m.transform_point3(p), error)
    }

    /// Transform a direction.
    #[inline]
    #[must_use]
    pub fn vector(&self, v: Vec3) -> Vec3 {
        self.m.transform_vector3(v)
    }

    /// Transform a surface normal (by the inverse transpose).
    #[inline]
    #[must_use]
    pub fn normal(&self, n: Vec3) -> Vec3 {
        self.m_inv.transpose().transform_vector3(n)
    }

    /// True when the transform mirrors space (negative determinant of the linear part),
    /// which flips the orientation of triangles.
    #[must_use]
    pub fn swaps_handedness(&self) -> bool {
        glam::Mat3::from_mat4(self.m).determinant() < 0.0
    }
}
