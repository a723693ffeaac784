//! The instruction set the BVH queries run with, chosen at run time, and one of the two
//! modules of the workspace with `unsafe` code (the other is `math::sse2`, one SSE2 step of
//! the ray-origin offset, which sits below this layer).
//!
//! The traversal and leaf kernels ([`super::wide`], [`super::tri_block`]) are written once
//! as fixed-size lane arithmetic and compiled twice: for any x86-64 (SSE2) or other CPU,
//! and inside functions marked `#[target_feature(enable = "avx2,fma")]`, where the compiler
//! vectorises them with 256-bit AVX2 and fused multiply-adds (the triangle test's
//! difference of products otherwise calls the C library's `fmaf`). The binary stays
//! portable: the AVX2 code runs only after the CPU said it has the features. Both builds
//! give the same bits (a fused multiply-add is exactly rounded whichever unit does it, and
//! Rust never contracts a separate multiply and add), which the tests check.
//!
//! One step is written out in AVX2 intrinsics instead: a node's box test
//! ([`Avx2Boxes`]), where the compiler had split the far planes' arithmetic into pieces of
//! lanes with shuffles between them (after the change, incoherent rays on a 1k-triangle
//! mesh, whose tree sits in cache, ran 1.2x faster). It computes the plain code's bits,
//! which a test checks.
//!
//! The module also holds the cache prefetch hint of the traversal ([`prefetch`]), an SSE
//! instruction every x86-64 CPU has, and the build's conversion of bucket positions to
//! integers ([`truncate_lanes`], SSE2).
//!
//! AVX-512 is not used: a node's eight boxes fill one 256-bit AVX2 register per plane (two
//! SSE registers in the portable build), and the leaf blocks are four lanes wide.

#![allow(unsafe_code)]

use super::packet::{any_hit_packet_impl, closest_hit_packet_impl, PACKET};
use super::tri_block::TriangleHit;
use super::wide::{any_hit_impl, closest_hit_impl, BoxTest, PlainBoxes, RayBoxes, WideBvh, WideNode, WIDTH};
use crate::math::Ray;

/// An instruction set the queries can run with.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Isa {
    /// Any CPU: baseline instructions (SSE2 on x86-64).
    #[default]
    Portable,
    /// x86-64 with AVX2 and FMA.
    Avx2,
}

impl Isa {
    /// Every instruction set, supported here or not.
    pub const ALL: [Self; 2] = [Self::Portable, Self::Avx2];

    /// True when this CPU runs `self`.
    #[must_use]
    pub fn is_supported(self) -> bool {
        match self {
            Self::Portable => true,
            #[cfg(target_arch = "x86_64")]
            Self::Avx2 => std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma"),
            #[cfg(not(target_arch = "x86_64"))]
            Self::Avx2 => false,
        }
    }

    /// The fastest one this CPU runs.
    #[must_use]
    pub fn best() -> Self {
        if Self::Avx2.is_supported() {
            Self::Avx2
        } else {
            Self::Portable
        }
    }

    /// Lower-case name (`portable`, `avx2`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Portable => "portable",
            Self::Avx2 => "avx2",
        }
    }
}

/// Closest hit with the tree's instruction set (see [`WideBvh::closest_hit_triangles`]).
#[inline]
pub(super) fn closest_hit<H>(
    bvh: &WideBvh,
    ray: &Ray,
    t_max: f32,
    test: impl FnMut(u32, &Ray, f32) -> Option<(f32, H)>,
    on_triangle: impl FnMut(u32, TriangleHit) -> H,
) -> Option<(u32, H)> {
    #[cfg(target_arch = "x86_64")]
    if bvh.isa() == Isa::Avx2 {
        // SAFETY: a tree's instruction set is `Avx2` only when `Isa::Avx2.is_supported()`
        // said this CPU has AVX2 and FMA (`WideBvh::set_isa` refuses it otherwise), which is
        // all `closest_hit_avx2` requires.
        return unsafe { closest_hit_avx2(bvh, ray, t_max, test, on_triangle) };
    }
    closest_hit_impl(bvh, ray, t_max, test, on_triangle, PlainBoxes)
}

/// Any hit with the tree's instruction set (see [`WideBvh::any_hit_triangles`]).
#[inline]
pub(super) fn any_hit(bvh: &WideBvh, ray: &Ray, t_max: f32, test: impl FnMut(u32, &Ray, f32) -> bool) -> bool {
    #[cfg(target_arch = "x86_64")]
    if bvh.isa() == Isa::Avx2 {
        // SAFETY: as in `closest_hit`: `Avx2` is set only on a CPU with AVX2 and FMA.
        return unsafe { any_hit_avx2(bvh, ray, t_max, test) };
    }
    any_hit_impl(bvh, ray, t_max, test, PlainBoxes)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn closest_hit_avx2<H>(
    bvh: &WideBvh,
    ray: &Ray,
    t_max: f32,
    test: impl FnMut(u32, &Ray, f32) -> Option<(f32, H)>,
    on_triangle: impl FnMut(u32, TriangleHit) -> H,
) -> Option<(u32, H)> {
    closest_hit_impl(bvh, ray, t_max, test, on_triangle, Avx2Boxes(()))
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn any_hit_avx2(bvh: &WideBvh, ray: &Ray, t_max: f32, test: impl FnMut(u32, &Ray, f32) -> bool) -> bool {
    any_hit_impl(bvh, ray, t_max, test, Avx2Boxes(()))
}

/// The AVX2 box test ([`BoxTest`]). Made only inside the `*_avx2` functions (and the tests,
/// after checking the CPU), which run only
/// on a CPU with AVX2 and FMA, so holding one proves the CPU has them.
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy, Debug)]
struct Avx2Boxes(());

#[cfg(target_arch = "x86_64")]
impl BoxTest for Avx2Boxes {
    #[inline(always)]
    fn hit_lanes(self, r: &RayBoxes, node: &WideNode, t_max: f32) -> ([f32; WIDTH], u32) {
        // SAFETY: an `Avx2Boxes` exists only on a CPU with AVX2 and FMA (see the type), all
        // that `hit_lanes_avx2` requires.
        unsafe { hit_lanes_avx2(r, node, t_max) }
    }
}

/// [`RayBoxes::hit_lanes`] in AVX2, step for step: each lane's operations and their
/// order are the same, and `max`/`min` take the new value only when it compares greater
/// / less, keeping the running one on a NaN, as the plain code's selects do (x86's
/// `maxps a, b` is `a > b ? a : b`).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline]
fn hit_lanes_avx2(r: &RayBoxes, node: &WideNode, t_max: f32) -> ([f32; WIDTH], u32) {
    const { assert!(WIDTH == 8, "one 256-bit register per plane") };
    use std::arch::x86_64::{
        _mm256_cmp_ps, _mm256_loadu_ps, _mm256_max_ps, _mm256_min_ps, _mm256_movemask_ps, _mm256_mul_ps,
        _mm256_set1_ps, _mm256_setzero_ps, _mm256_storeu_ps, _mm256_sub_ps, _CMP_LE_OQ,
    };
    let mut near = _mm256_setzero_ps();
    let mut far = _mm256_set1_ps(t_max);
    for a in 0..3 {
        let near_plane = &node.planes[usize::from(r.neg[a])][a];
        let far_plane = &node.planes[usize::from(!r.neg[a])][a];
        let o = _mm256_set1_ps(r.o[a]);
        // SAFETY: each plane is an array of `WIDTH` = 8 floats, what an unaligned 256-bit
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
    let hit = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(near, far)) as u32;
    let mut out = [0.0f32; WIDTH];
    // SAFETY: `out` holds 8 floats, what an unaligned 256-bit store writes.
    unsafe { _mm256_storeu_ps(out.as_mut_ptr(), near) };
    (out, hit)
}

/// Closest hits of a packet with the tree's instruction set (see
/// [`WideBvh::closest_hit_triangles_packet`]).
#[inline]
pub(super) fn closest_hit_packet<H>(
    bvh: &WideBvh,
    rays: &[Ray; PACKET],
    t_max: [f32; PACKET],
    active: u32,
    test: impl FnMut(usize, u32, &Ray, f32) -> Option<(f32, H)>,
    on_triangle: impl FnMut(usize, u32, TriangleHit) -> H,
) -> [Option<(u32, H)>; PACKET] {
    #[cfg(target_arch = "x86_64")]
    if bvh.isa() == Isa::Avx2 {
        // SAFETY: as in `closest_hit`: `Avx2` is set only on a CPU with AVX2 and FMA.
        return unsafe { closest_hit_packet_avx2(bvh, rays, t_max, active, test, on_triangle) };
    }
    closest_hit_packet_impl(bvh, rays, t_max, active, test, on_triangle)
}

/// Any hits of a packet with the tree's instruction set (see
/// [`WideBvh::any_hit_triangles_packet`]).
#[inline]
pub(super) fn any_hit_packet(
    bvh: &WideBvh,
    rays: &[Ray; PACKET],
    t_max: [f32; PACKET],
    active: u32,
    test: impl FnMut(usize, u32, &Ray, f32) -> bool,
) -> u32 {
    #[cfg(target_arch = "x86_64")]
    if bvh.isa() == Isa::Avx2 {
        // SAFETY: as in `closest_hit`: `Avx2` is set only on a CPU with AVX2 and FMA.
        return unsafe { any_hit_packet_avx2(bvh, rays, t_max, active, test) };
    }
    any_hit_packet_impl(bvh, rays, t_max, active, test)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn closest_hit_packet_avx2<H>(
    bvh: &WideBvh,
    rays: &[Ray; PACKET],
    t_max: [f32; PACKET],
    active: u32,
    test: impl FnMut(usize, u32, &Ray, f32) -> Option<(f32, H)>,
    on_triangle: impl FnMut(usize, u32, TriangleHit) -> H,
) -> [Option<(u32, H)>; PACKET] {
    closest_hit_packet_impl(bvh, rays, t_max, active, test, on_triangle)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn any_hit_packet_avx2(
    bvh: &WideBvh,
    rays: &[Ray; PACKET],
    t_max: [f32; PACKET],
    active: u32,
    test: impl FnMut(usize, u32, &Ray, f32) -> bool,
) -> u32 {
    any_hit_packet_impl(bvh, rays, t_max, active, test)
}

/// Ask the CPU to start loading the cache lines of `value` (a hint: no effect on results).
#[inline(always)]
pub(super) fn prefetch<T>(value: &T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        let start = std::ptr::from_ref(value).cast::<i8>();
        for line in (0..std::mem::size_of::<T>()).step_by(64) {
            // SAFETY: `prefetch` is SSE, which every x86-64 CPU has; it reads nothing and
            // cannot fault, and `start + line` stays inside `value`.
            unsafe { _mm_prefetch::<_MM_HINT_T0>(start.add(line)) };
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = value;
}

/// The first three lanes of `v`, each in `0..2^31`, truncated to integers: one SSE2
/// conversion on x86-64 (`cvttps2dq`), where a lane-by-lane `as` saturates each lane with
/// compares and branches (the BVH build's binning converts three lanes per primitive per
/// level).
#[inline(always)]
pub(super) fn truncate_lanes(v: glam::Vec3A) -> [u32; 3] {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{__m128, __m128i, _mm_cvttps_epi32};
        let v: __m128 = v.into();
        // SAFETY: `cvttps2dq` is SSE2, which every x86-64 CPU has; it only converts lanes.
        // The transmute reinterprets 16 bytes of integers as four `u32`, which any bits are.
        let lanes: [u32; 4] = unsafe { std::mem::transmute::<__m128i, [u32; 4]>(_mm_cvttps_epi32(v)) };
        [lanes[0], lanes[1], lanes[2]]
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        [v.x as u32, v.y as u32, v.z as u32]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The SSE2 truncation gives `as u32`'s integers on every float in `0..=2^22` near the
    /// integers below 64, on a dense sample of the BVH build's bucket range `0..=12` and a
    /// sparse one above, so the conversion behind the `unsafe` block is the one the build's
    /// binning assumes.
    #[test]
    fn truncate_lanes_matches_as() {
        let mut checked = 0;
        let mut x = 0.0f32;
        while x <= 4_194_304.0 {
            let v = glam::Vec3A::new(x, x * 0.37, f32::from_bits(x.to_bits().saturating_sub(1)));
            assert_eq!(truncate_lanes(v), [v.x as u32, v.y as u32, v.z as u32], "{v:?}");
            let step = if x >= 0.5 && (x - x.round()).abs() < 1e-3 && x < 64.0 {
                1
            } else if x <= 12.0 {
                4096
            } else {
                65_536
            };
            x = f32::from_bits(x.to_bits() + step);
            checked += 1;
        }
        assert!(checked > 10_000, "{checked}");
        assert_eq!(
            truncate_lanes(glam::Vec3A::new(0.0, 11.0, 4_194_304.0)),
            [0, 11, 4_194_304]
        );
    }

    /// Runs the prefetch loop over no cache line, part of one and several, so every path of
    /// its `unsafe` block runs in the tests (the hint itself cannot fail: an out-of-bounds
    /// pointer would show under Miri), and the value is left as it was.
    #[test]
    fn prefetch_any_size() {
        prefetch(&());
        prefetch(&7u8);
        let big = [3u64; 100];
        prefetch(&big);
        assert_eq!(big, [3u64; 100]);
    }

    /// The AVX2 box test gives the plain one's entry distances and mask, bit for bit: random
    /// boxes, some lanes empty, directions with zero components (rays parallel to a slab,
    /// some with the origin on its plane: `0 x inf = NaN`), finite and infinite `t_max`.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn avx2_box_test_matches_the_plain_one() {
        use crate::math::Vec3;
        if !Isa::Avx2.is_supported() {
            eprintln!("NOT TESTED: this CPU has no AVX2 and FMA; the AVX2 box test did not run");
            return;
        }
        let mut seed = 7u32;
        let mut rnd = || {
            seed = seed.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
            (seed >> 8) as f32 / (1u32 << 24) as f32 * 4.0 - 2.0
        };
        let mut entered = 0;
        for k in 0..4000 {
            let mut node = WideNode::EMPTY;
            // Leave the last lanes empty in some nodes, as the build does.
            let used = 1 + k % WIDTH;
            for i in 0..used {
                for a in 0..3 {
                    let (u, v) = (rnd(), rnd());
                    node.planes[0][a][i] = u.min(v);
                    node.planes[1][a][i] = u.max(v);
                }
            }
            let mut d = Vec3::new(rnd(), rnd(), rnd());
            let mut o = Vec3::new(rnd(), rnd(), rnd()) * 2.0;
            if k % 3 == 0 {
                d.y = 0.0;
            }
            if k % 5 == 0 {
                // The origin on a box's lower y plane, the direction parallel to it.
                d.y = 0.0;
                o.y = node.planes[0][1][0];
            }
            let ray = Ray::new(o, d);
            let t_max = if k % 2 == 0 { f32::INFINITY } else { rnd().abs() };
            let r = RayBoxes::new(&ray);
            let (plain_near, plain_hit) = PlainBoxes.hit_lanes(&r, &node, t_max);
            let (near, hit) = Avx2Boxes(()).hit_lanes(&r, &node, t_max);
            assert_eq!(hit, plain_hit, "node {k}");
            assert_eq!(near.map(f32::to_bits), plain_near.map(f32::to_bits), "node {k}");
            entered += hit.count_ones();
        }
        // Both outcomes were tested, many times.
        assert!(entered > 200 && entered < 4000, "{entered} lanes entered");
    }

    #[test]
    fn portable_runs_everywhere_and_best_is_supported() {
        assert!(Isa::Portable.is_supported());
        assert!(Isa::best().is_supported());
        #[cfg(target_arch = "x86_64")]
        if !Isa::Avx2.is_supported() {
            eprintln!("NOT TESTED: this CPU has no AVX2 and FMA; only the portable kernels ran");
        }
    }
}
