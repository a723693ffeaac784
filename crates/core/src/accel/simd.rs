//! Which build of the BVH kernels a query runs: the traversal and leaf kernels
//! ([`super::wide`], [`super::tri_block`], [`super::packet`]) are written once as
//! fixed-size lane arithmetic and compiled three times, as plain code (SSE2 on any x86-64,
//! NEON on aarch64), inside [`Avx2::run`] (256-bit AVX2 and fused multiply-adds, where the
//! triangle test's difference of products would otherwise call the C library's `fmaf`) and
//! inside [`Avx512::run`] (the same width, with AVX-512's mask registers). The tree holds
//! the instruction set it was given with the proof that this CPU has it
//! ([`crate::math::simd::Supported`]), so this module needs no `unsafe`: all of it is in
//! [`crate::math::simd`]. Every build gives the same bits, which the tests check.
//!
//! A node's box test is written out in intrinsics for AVX2 and AVX-512
//! ([`crate::math::simd::slab`]), where the compiler had split the far planes' arithmetic
//! into pieces of lanes with shuffles between them (after the change, incoherent rays on a
//! 1k-triangle mesh, whose tree sits in cache, ran 1.2x faster). Eight boxes fill one
//! 256-bit register per plane in both, as in Embree's AVX-512 kernels for 8-wide trees.

use super::packet::{any_hit_packet_impl, closest_hit_packet_impl, PACKET};
use super::tri_block::TriangleHit;
use super::wide::{any_hit_impl, closest_hit_impl, BoxTest, PlainBoxes, RayBoxes, WideBvh, WideNode, WIDTH};
use crate::math::simd::{Avx2, Avx512, Supported};
use crate::math::Ray;

/// Closest hit with the tree's instruction set (see [`WideBvh::closest_hit_triangles`]).
#[inline]
pub(super) fn closest_hit<H>(
    bvh: &WideBvh,
    ray: &Ray,
    t_max: f32,
    test: impl FnMut(u32, &Ray, f32) -> Option<(f32, H)>,
    on_triangle: impl FnMut(u32, TriangleHit) -> H,
) -> Option<(u32, H)> {
    match bvh.supported_isa() {
        Supported::Avx512(cpu) => cpu.run(|| closest_hit_impl(bvh, ray, t_max, test, on_triangle, Avx512Boxes(cpu))),
        Supported::Avx2(cpu) => cpu.run(|| closest_hit_impl(bvh, ray, t_max, test, on_triangle, Avx2Boxes(cpu))),
        Supported::Portable => closest_hit_impl(bvh, ray, t_max, test, on_triangle, PlainBoxes),
    }
}

/// Any hit with the tree's instruction set (see [`WideBvh::any_hit_triangles`]).
#[inline]
pub(super) fn any_hit(bvh: &WideBvh, ray: &Ray, t_max: f32, test: impl FnMut(u32, &Ray, f32) -> bool) -> bool {
    match bvh.supported_isa() {
        Supported::Avx512(cpu) => cpu.run(|| any_hit_impl(bvh, ray, t_max, test, Avx512Boxes(cpu))),
        Supported::Avx2(cpu) => cpu.run(|| any_hit_impl(bvh, ray, t_max, test, Avx2Boxes(cpu))),
        Supported::Portable => any_hit_impl(bvh, ray, t_max, test, PlainBoxes),
    }
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
    // One closure per arm: a closure with one call site is inlined into its `run`, and so
    // compiled with its instruction set.
    match bvh.supported_isa() {
        Supported::Avx512(cpu) => cpu.run(|| closest_hit_packet_impl(bvh, rays, t_max, active, test, on_triangle)),
        Supported::Avx2(cpu) => cpu.run(|| closest_hit_packet_impl(bvh, rays, t_max, active, test, on_triangle)),
        Supported::Portable => closest_hit_packet_impl(bvh, rays, t_max, active, test, on_triangle),
    }
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
    match bvh.supported_isa() {
        Supported::Avx512(cpu) => cpu.run(|| any_hit_packet_impl(bvh, rays, t_max, active, test)),
        Supported::Avx2(cpu) => cpu.run(|| any_hit_packet_impl(bvh, rays, t_max, active, test)),
        Supported::Portable => any_hit_packet_impl(bvh, rays, t_max, active, test),
    }
}

/// The AVX2 box test ([`BoxTest`]).
#[derive(Clone, Copy, Debug)]
struct Avx2Boxes(Avx2);

impl BoxTest for Avx2Boxes {
    #[inline(always)]
    fn hit_lanes(self, r: &RayBoxes, node: &WideNode, t_max: f32) -> ([f32; WIDTH], u32) {
        const { assert!(WIDTH == crate::math::simd::slab::LANES, "a node is one slab test") };
        self.0.slab_test(r, &node.planes, t_max)
    }
}

/// The AVX-512 box test ([`BoxTest`]).
#[derive(Clone, Copy, Debug)]
struct Avx512Boxes(Avx512);

impl BoxTest for Avx512Boxes {
    #[inline(always)]
    fn hit_lanes(self, r: &RayBoxes, node: &WideNode, t_max: f32) -> ([f32; WIDTH], u32) {
        self.0.slab_test(r, &node.planes, t_max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The AVX2 and AVX-512 box tests give the plain one's entry distances and mask, bit for
    /// bit: random
    /// boxes, some lanes empty, directions with zero components (rays parallel to a slab,
    /// some with the origin on its plane: `0 x inf = NaN`), finite and infinite `t_max`.
    #[test]
    fn avx2_box_test_matches_the_plain_one() {
        use crate::math::Vec3;
        let Some(avx2) = Avx2::detect() else {
            eprintln!("NOT TESTED: this CPU has no AVX2 and FMA; the AVX2 and AVX-512 box tests did not run");
            return;
        };
        let avx512 = Avx512::detect();
        if avx512.is_none() {
            eprintln!("NOT TESTED: this CPU has no AVX-512 F and VL; the AVX-512 box test did not run");
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
            let (near, hit) = Avx2Boxes(avx2).hit_lanes(&r, &node, t_max);
            assert_eq!(hit, plain_hit, "node {k}");
            assert_eq!(near.map(f32::to_bits), plain_near.map(f32::to_bits), "node {k}");
            if let Some(cpu) = avx512 {
                let (near, hit) = Avx512Boxes(cpu).hit_lanes(&r, &node, t_max);
                assert_eq!(hit, plain_hit, "AVX-512, node {k}");
                assert_eq!(
                    near.map(f32::to_bits),
                    plain_near.map(f32::to_bits),
                    "AVX-512, node {k}"
                );
            }
            entered += hit.count_ones();
        }
        // Both outcomes were tested, many times.
        assert!(entered > 200 && entered < 4000, "{entered} lanes entered");
    }
}
