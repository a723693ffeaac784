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
#[inline(always)]
pub fn offset_ray_origin(p: Vec3, p_error: Vec3, n: Vec3, w: Vec3) -> Vec3 {
    let d = n.abs().dot(p_error);
    let mut offset = d * n;
    if w.dot(n) < 0.0 {
        offset = -offset;
    }
    let po = p + offset;
    // (The fourth lane steps nowhere: its offset is zero.)
    let [x, y, z, _] = step_away_lanes([po.x, po.y, po.z, 0.0], [offset.x, offset.y, offset.z, 0.0]);
    Vec3::new(x, y, z)
}

/// `step_away` (the tests' reference) in four lanes at once: [`next_float_up`] of `v` where
/// `o > 0`, [`next_float_down`] where `o < 0`, else `v`. On x86-64 in SSE2 intrinsics
/// (`super::simd::sse2`), elsewhere [`step_away_lanes_portable`]; the same bits (tested).
#[inline(always)]
fn step_away_lanes(v: [f32; 4], o: [f32; 4]) -> [f32; 4] {
    #[cfg(target_arch = "x86_64")]
    {
        super::simd::sse2::step_away_lanes(v, o)
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        step_away_lanes_portable(v, o)
    }
}

/// [`step_away_lanes`] with lane-wise integer operations only (shifts, masks, compares and
/// selects), for any CPU. `key` is `step_away`'s, as `(|bits| ^ s) - s` with `s` the sign
/// mask, so `|key|` is `|bits|`. (On x86-64 the compiler made two vector lanes and a scalar
/// one of it: about 100 instructions per origin, against about 35 in SSE2.)
#[cfg_attr(target_arch = "x86_64", allow(dead_code))]
#[inline(always)]
fn step_away_lanes_portable(v: [f32; 4], o: [f32; 4]) -> [f32; 4] {
    const INF_KEY: i32 = 0x7f80_0000;
    let mut out = [0.0f32; 4];
    for i in 0..4 {
        let bits = v[i].to_bits() as i32;
        let sign = bits >> 31;
        let magnitude = bits & i32::MAX;
        let key = (magnitude ^ sign).wrapping_sub(sign);
        let step = -i32::from(o[i] < 0.0) + i32::from(o[i] > 0.0);
        let stepped = key.wrapping_add(step);
        let stepped_sign = stepped >> 31;
        let stepped_magnitude = (stepped ^ stepped_sign).wrapping_sub(stepped_sign);
        // A step onto zero keeps the sign it came from.
        let moved = if stepped == 0 {
            bits & i32::MIN
        } else {
            stepped_magnitude | (stepped_sign & i32::MIN)
        };
        // No step, a NaN, or a step past an infinity (`stepped_magnitude` read unsigned).
        let keep = step == 0 || magnitude > INF_KEY || (stepped_magnitude as u32) > INF_KEY as u32;
        out[i] = f32::from_bits(if keep { bits } else { moved } as u32);
    }
    out
}

/// [`next_float_up`] of `v` when `o > 0`, [`next_float_down`] when `o < 0`, else `v`,
/// without branches (the sign of an offset component is as good as random from one ray to
/// the next, and the branches were most of [`offset_ray_origin`]'s time). Floats ordered
/// as integers: `k = bits` for a positive sign, `-(bits & 0x7fff_ffff)` for a negative one
/// (both zeros are 0), so a step is `k +- 1`; no step (`o` zero or NaN), a step past an
/// infinity, or one from a NaN keeps `v`, as the two functions do.
/// This is the one-lane reference that [`step_away_lanes`] is tested against.
#[cfg(test)]
fn step_away(v: f32, o: f32) -> f32 {
    const INF_KEY: u32 = 0x7f80_0000;
    let bits = v.to_bits() as i32;
    let key = if bits >= 0 { bits } else { i32::MIN - bits };
    let stepped = key + i32::from(o > 0.0) - i32::from(o < 0.0);
    // A step onto zero keeps the sign it came from (as the bit arithmetic of the two).
    let out = if stepped > 0 {
        stepped
    } else if stepped == 0 {
        bits & i32::MIN
    } else {
        i32::MIN - stepped
    };
    let keep = stepped == key || key.unsigned_abs() > INF_KEY || stepped.unsigned_abs() > INF_KEY;
    if keep {
        v
    } else {
        f32::from_bits(out as u32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The branch-free step equals `next_float_up` / `next_float_down` bit for bit, on
    /// zeros, infinities, NaN, denormals, the largest floats and a sweep of ordinary ones.
    #[test]
    fn step_away_matches_next_float() {
        let mut values = vec![
            0.0,
            -0.0,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            -f32::NAN,
            f32::from_bits(1),
            -f32::from_bits(1),
            f32::MIN_POSITIVE,
            -f32::MIN_POSITIVE,
            f32::MAX,
            f32::MIN,
        ];
        let mut bits = 0u32;
        for _ in 0..100_000 {
            bits = bits.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
            values.push(f32::from_bits(bits));
        }
        for v in values {
            for (o, want) in [
                (1.0, next_float_up(v)),
                (-1.0, next_float_down(v)),
                (0.0, v),
                (-0.0, v),
                (f32::NAN, v),
            ] {
                assert_eq!(
                    step_away(v, o).to_bits(),
                    want.to_bits(),
                    "v = {v:e} ({:#x}), o = {o}",
                    v.to_bits()
                );
                let lanes = step_away_lanes([v, 1.0, v, -2.0], [o, 0.0, -o, 1.0]);
                assert_eq!(
                    lanes.map(f32::to_bits),
                    step_away_lanes_portable([v, 1.0, v, -2.0], [o, 0.0, -o, 1.0]).map(f32::to_bits)
                );
                assert_eq!(lanes[0].to_bits(), want.to_bits(), "lanes: v = {v:e}, o = {o}");
                assert_eq!(
                    lanes[2].to_bits(),
                    step_away(v, -o).to_bits(),
                    "lanes: v = {v:e}, o = {o}"
                );
                assert_eq!([lanes[1], lanes[3]], [1.0, next_float_up(-2.0)]);
            }
        }
    }

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
