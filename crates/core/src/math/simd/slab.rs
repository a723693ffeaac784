//! The slab test of a ray against eight boxes (a BVH node's children) in AVX2 and in
//! AVX-512 intrinsics: the plain lane loop of `accel`'s `RayBoxes::hit_lanes`, step for step.
//! Each lane's operations and their order are the same, and `max` / `min` take the new
//! value only when it compares greater / less, keeping the running one on a NaN, as the
//! plain code's selects do (x86's `maxps a, b` is `a > b ? a : b`), so all three give the
//! same bits (tested in `accel`). The compiler had split the plain loop's far planes into
//! pieces of lanes with shuffles between them.

use super::{Avx2, Avx512};

/// Boxes per test.
pub const LANES: usize = 8;

/// Eight boxes: minima `planes[0][axis][lane]`, maxima `planes[1][axis][lane]`.
pub type Planes = [[[f32; LANES]; 3]; 2];

/// The per-ray constants of the test.
#[derive(Clone, Copy, Debug)]
pub struct SlabRay {
    /// The origin.
    pub o: [f32; 3],
    /// The reciprocal direction as the near planes use it (scaled for rounding margins).
    pub inv_near: [f32; 3],
    /// The reciprocal direction as the far planes use it.
    pub inv_far: [f32; 3],
    /// Whether each direction component is negative (its near plane is the maximum).
    pub neg: [bool; 3],
}

impl Avx2 {
    /// Entry distances into the eight boxes within `(0, t_max)` and the boxes entered as a
    /// mask (bit `i` for lane `i`).
    #[inline(always)]
    #[must_use]
    pub fn slab_test(self, r: &SlabRay, planes: &Planes, t_max: f32) -> ([f32; LANES], u32) {
        #[cfg(target_arch = "x86_64")]
        {
            // SAFETY: an `Avx2` exists only on a CPU with AVX2 and FMA, all that
            // `slab_test_avx2` requires.
            unsafe { x86::slab_test_avx2(r, planes, t_max) }
        }
        #[cfg(not(target_arch = "x86_64"))]
        unreachable!("no `Avx2` outside x86-64 ({r:?}, {planes:?}, {t_max})")
    }
}

impl Avx512 {
    /// [`Avx2::slab_test`], with the last comparison into a mask register.
    #[inline(always)]
    #[must_use]
    pub fn slab_test(self, r: &SlabRay, planes: &Planes, t_max: f32) -> ([f32; LANES], u32) {
        #[cfg(target_arch = "x86_64")]
        {
            // SAFETY: an `Avx512` exists only on a CPU with AVX-512 F and VL, AVX2 and FMA,
            // all that `slab_test_avx512` requires.
            unsafe { x86::slab_test_avx512(r, planes, t_max) }
        }
        #[cfg(not(target_arch = "x86_64"))]
        unreachable!("no `Avx512` outside x86-64 ({r:?}, {planes:?}, {t_max})")
    }
}

#[cfg(target_arch = "x86_64")]
mod x86 {
    use super::{Planes, SlabRay, LANES};
    use std::arch::x86_64::{
        __m256, _mm256_cmp_ps, _mm256_cmp_ps_mask, _mm256_loadu_ps, _mm256_max_ps, _mm256_min_ps, _mm256_movemask_ps,
        _mm256_mul_ps, _mm256_set1_ps, _mm256_setzero_ps, _mm256_storeu_ps, _mm256_sub_ps, _CMP_LE_OQ,
    };

    /// The running near and far distances after the three slabs.
    #[target_feature(enable = "avx2,fma")]
    #[inline]
    fn near_far(r: &SlabRay, planes: &Planes, t_max: f32) -> (__m256, __m256) {
        let mut near = _mm256_setzero_ps();
        let mut far = _mm256_set1_ps(t_max);
        for a in 0..3 {
            let near_plane = &planes[usize::from(r.neg[a])][a];
            let far_plane = &planes[usize::from(!r.neg[a])][a];
            let o = _mm256_set1_ps(r.o[a]);
            // SAFETY: each plane is an array of `LANES` = 8 floats, what an unaligned 256-bit
            // load reads.
            let (np, fp) = unsafe {
                (
                    _mm256_loadu_ps(near_plane.as_ptr()),
                    _mm256_loadu_ps(far_plane.as_ptr()),
                )
            };
            let tn = _mm256_mul_ps(_mm256_sub_ps(np, o), _mm256_set1_ps(r.inv_near[a]));
            let tf = _mm256_mul_ps(_mm256_sub_ps(fp, o), _mm256_set1_ps(r.inv_far[a]));
            near = _mm256_max_ps(tn, near);
            far = _mm256_min_ps(tf, far);
        }
        (near, far)
    }

    #[target_feature(enable = "avx2,fma")]
    #[inline]
    fn store(near: __m256) -> [f32; LANES] {
        let mut out = [0.0f32; LANES];
        // SAFETY: `out` holds 8 floats, what an unaligned 256-bit store writes.
        unsafe { _mm256_storeu_ps(out.as_mut_ptr(), near) };
        out
    }

    #[target_feature(enable = "avx2,fma")]
    #[inline]
    pub(super) fn slab_test_avx2(r: &SlabRay, planes: &Planes, t_max: f32) -> ([f32; LANES], u32) {
        let (near, far) = near_far(r, planes, t_max);
        let hit = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(near, far)) as u32;
        (store(near), hit)
    }

    #[target_feature(enable = "avx512f,avx512vl,avx2,fma")]
    #[inline]
    pub(super) fn slab_test_avx512(r: &SlabRay, planes: &Planes, t_max: f32) -> ([f32; LANES], u32) {
        let (near, far) = near_far(r, planes, t_max);
        let hit = u32::from(_mm256_cmp_ps_mask::<_CMP_LE_OQ>(near, far));
        (store(near), hit)
    }
}
