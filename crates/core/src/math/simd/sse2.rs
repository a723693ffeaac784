//! One step of the ray-origin offset written in SSE2 intrinsics (x86-64 only).
//!
//! `float::offset_ray_origin` rounds the three coordinates of a moved origin one float
//! away from the surface. Left to the compiler, its lane-wise integer code came out as two
//! vector lanes and one scalar lane (the fourth lane is unused), and a shadow ray's two
//! offsets took about 276 instructions; here all lanes go through one SSE2 sequence.

/// `math::float`'s `step_away_lanes_portable`, the same integer steps lane for lane in
/// SSE2: `next_float_up(v)` where `o > 0`, `next_float_down(v)` where `o < 0`, else `v`.
/// Tested bit for bit against the portable lanes and the one-lane reference on zeros,
/// infinities, NaN, denormals and the largest floats (`float::tests`).
#[inline(always)]
pub(in crate::math) fn step_away_lanes(v: [f32; 4], o: [f32; 4]) -> [f32; 4] {
    // SAFETY: the function only needs SSE2, which every x86-64 CPU has (it is part of the
    // architecture's baseline, enabled in every x86-64 build); it reads and writes no memory.
    unsafe { step_away_lanes_sse2(v, o) }
}

#[inline]
#[target_feature(enable = "sse2")]
fn step_away_lanes_sse2(v: [f32; 4], o: [f32; 4]) -> [f32; 4] {
    use std::arch::x86_64::{
        _mm_add_epi32, _mm_and_si128, _mm_andnot_si128, _mm_castps_si128, _mm_castsi128_ps, _mm_cmpeq_epi32,
        _mm_cmpgt_epi32, _mm_cmpgt_ps, _mm_cmplt_epi32, _mm_cmplt_ps, _mm_or_si128, _mm_set1_epi32, _mm_setzero_ps,
        _mm_setzero_si128, _mm_srai_epi32, _mm_sub_epi32, _mm_xor_si128,
    };
    const INF_KEY: i32 = 0x7f80_0000;
    let (v, o) = (glam::Vec4::from_array(v).into(), glam::Vec4::from_array(o).into());
    let zero = _mm_setzero_si128();
    let sign_bit = _mm_set1_epi32(i32::MIN);
    let inf_key = _mm_set1_epi32(INF_KEY);
    let bits = _mm_castps_si128(v);
    // Floats ordered as integers: key = (|bits| ^ s) - s with s the sign mask.
    let sign = _mm_srai_epi32::<31>(bits);
    let magnitude = _mm_andnot_si128(sign_bit, bits);
    let key = _mm_sub_epi32(_mm_xor_si128(magnitude, sign), sign);
    // Compare masks are -1 where true, so [o < 0] - [o > 0] is +1 up, -1 down, 0 neither.
    let step = _mm_sub_epi32(
        _mm_castps_si128(_mm_cmplt_ps(o, _mm_setzero_ps())),
        _mm_castps_si128(_mm_cmpgt_ps(o, _mm_setzero_ps())),
    );
    let stepped = _mm_add_epi32(key, step);
    let stepped_sign = _mm_srai_epi32::<31>(stepped);
    let stepped_magnitude = _mm_sub_epi32(_mm_xor_si128(stepped, stepped_sign), stepped_sign);
    // A step onto zero keeps the sign it came from.
    let onto_zero = _mm_cmpeq_epi32(stepped, zero);
    let moved = _mm_or_si128(
        _mm_and_si128(onto_zero, _mm_and_si128(bits, sign_bit)),
        _mm_andnot_si128(
            onto_zero,
            _mm_or_si128(stepped_magnitude, _mm_and_si128(stepped_sign, sign_bit)),
        ),
    );
    // No step, a NaN, or a step past an infinity: `stepped_magnitude` read unsigned is above
    // INF_KEY when it is so signed, or negative (|i32::MIN|).
    let keep = _mm_or_si128(
        _mm_or_si128(_mm_cmpeq_epi32(step, zero), _mm_cmpgt_epi32(magnitude, inf_key)),
        _mm_or_si128(
            _mm_cmpgt_epi32(stepped_magnitude, inf_key),
            _mm_cmplt_epi32(stepped_magnitude, zero),
        ),
    );
    let out = _mm_or_si128(_mm_and_si128(keep, bits), _mm_andnot_si128(keep, moved));
    glam::Vec4::from(_mm_castsi128_ps(out)).to_array()
}
