//! Floating-point error bounds (pbrt-v4, section 6.8): `gamma(n)` bounds the relative error
//! of `n` successive roundings, and ray origins are pushed off surfaces by the bound of the
//! error in the hit point rather than by a fixed epsilon.

use glam::Vec3;

/// Fraction of a shadow ray's length left out at its far end, so the ray does not hit the
/// surface it is aimed at.
pub const SHADOW_EPSILON: f32 = 0.0001;

/// Bound on the relative error of `n` floating-point operations: `n u / (1 - n u)` with
/// `u` the unit roundoff (half the machine epsilon).
#[inline]
#[must_use]
pub fn gamma(n: i32) -> f32 {
    let nu = n as f32 * (f32::EPSILON * 0.5);
    nu / (1.0 - nu)
}

/// The smallest `f32` greater than `v` (identity for +inf and NaN).
#[inline]
#[must_use]
pub fn next_float_up(v: f32) -> f32 {
    if v.is_infinite() && v > 0.0 || v.is_nan() {
        return v;
    }
    let v = if v == -0.0 { 0.0 } else { v };
    let bits = v.to_bits();
    let bits = if v >= 0.0 { bits + 1 } else { bits - 1 };
    f32::from_bits(bits)
}

/// The largest `f32` smaller than `v` (identity for -inf and NaN).
#[inline]
#[must_use]
pub fn next_float_down(v: f32) -> f32 {
    if v.is_infinite() && v < 0.0 || v.is_nan() {
        return v;
    }
    let v = if v == 0.0 { -0.0 } else { v };
    let bits = v.to_bits();
    let bits = if v > 0.0 { bits - 1 } else { bits + 1 };
    f32::from_bits(bits)
}

/// Origin for a ray leaving a surface point `p` with absolute error bound `p_error` and
/// geometric normal `n` in direction `w`: `p` is moved along `n` (to the side `w` points
/// to) by the projection of the error box onto `n`, then rounded away from the surface so
/// the new origin is certainly on the correct side (pbrt-v4 `OffsetRayOrigin`).
#[must_use]
#[inline]
pub fn offset_ray_origin(p: Vec3, p_error: Vec3, n: Vec3, w: Vec3) -> Vec3 {
    let d = n.abs().dot(p_error);
    let mut offset = d * n;
    if w.dot(n) < 0.0 {
        offset = -offset;
    }
    // On arrays: indexing a vector by a loop variable went through memory.
    let mut po = (p + offset).to_array();
    for (po, o) in po.iter_mut().zip(offset.to_array()) {
        if o > 0.0 {
            *po = next_float_up(*po);
        } else if o < 0.0 {
            *po = next_float_down(*po);
        }
    }
    Vec3::from_array(po)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn next_float_steps_one_ulp() {
        assert!(next_float_up(1.0) > 1.0);
        assert_eq!(next_float_down(next_float_up(1.0)), 1.0);
        assert_eq!(next_float_up(0.0), f32::from_bits(1));
        assert_eq!(next_float_down(0.0), -f32::from_bits(1));
        assert!(next_float_up(-1.0) > -1.0);
    }

    #[test]
    fn offset_moves_to_the_side_of_w() {
        let p = Vec3::new(1.0, 2.0, 3.0);
        let err = Vec3::splat(1e-5);
        let n = Vec3::Z;
        assert!(offset_ray_origin(p, err, n, Vec3::Z).z > 3.0);
        assert!(offset_ray_origin(p, err, n, -Vec3::Z).z < 3.0);
    }
}
