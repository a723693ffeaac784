//! The instruction set the BVH queries run with, chosen at run time, and the only module of
//! the workspace with `unsafe` code.
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
//! The module also holds the cache prefetch hint of the traversal ([`prefetch`]), an SSE
//! instruction every x86-64 CPU has.
//!
//! AVX-512 is not used: a node's eight boxes fill one 256-bit AVX2 register per plane (two
//! SSE registers in the portable build), and the leaf blocks are four lanes wide.

#![allow(unsafe_code)]

use super::packet::{any_hit_packet_impl, closest_hit_packet_impl, PACKET};
use super::tri_block::TriangleHit;
use super::wide::{any_hit_impl, closest_hit_impl, WideBvh};
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
    closest_hit_impl(bvh, ray, t_max, test, on_triangle)
}

/// Any hit with the tree's instruction set (see [`WideBvh::any_hit_triangles`]).
#[inline]
pub(super) fn any_hit(bvh: &WideBvh, ray: &Ray, t_max: f32, test: impl FnMut(u32, &Ray, f32) -> bool) -> bool {
    #[cfg(target_arch = "x86_64")]
    if bvh.isa() == Isa::Avx2 {
        // SAFETY: as in `closest_hit`: `Avx2` is set only on a CPU with AVX2 and FMA.
        return unsafe { any_hit_avx2(bvh, ray, t_max, test) };
    }
    any_hit_impl(bvh, ray, t_max, test)
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
    closest_hit_impl(bvh, ray, t_max, test, on_triangle)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn any_hit_avx2(bvh: &WideBvh, ray: &Ray, t_max: f32, test: impl FnMut(u32, &Ray, f32) -> bool) -> bool {
    any_hit_impl(bvh, ray, t_max, test)
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

#[cfg(test)]
mod tests {
    use super::*;

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
