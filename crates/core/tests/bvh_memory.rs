//! The memory estimate of a BVH (used by `--max-memory` before anything is built) covers the
//! trees actually built, under both cost models, for scattered and for connected triangles,
//! without being wildly above them.

use std::sync::Arc;

use mcrender_core::accel::WideBvh;
use mcrender_core::math::Vec3;
use mcrender_core::sampling::Pcg32;
use mcrender_core::shape::{Triangle, TriangleMesh};

/// `n` small triangles scattered in a cube.
fn soup(n: usize) -> Vec<[Vec3; 3]> {
    let mut rng = Pcg32::new(1, 12345);
    let mut p = |s: f32| Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * s;
    (0..n)
        .map(|_| {
            let c = p(100.0);
            [c, c + p(1.0), c + p(1.0)]
        })
        .collect()
}

/// A `k` x `k` height field of `2 k^2` triangles sharing vertices.
fn grid(k: usize) -> Vec<[Vec3; 3]> {
    let mut rng = Pcg32::new(2, 777);
    let heights: Vec<f32> = (0..(k + 1) * (k + 1)).map(|_| rng.next_f32()).collect();
    let at = |i: usize, j: usize| Vec3::new(i as f32, heights[i * (k + 1) + j], j as f32);
    let mut tris = Vec::with_capacity(2 * k * k);
    for i in 0..k {
        for j in 0..k {
            tris.push([at(i, j), at(i + 1, j), at(i, j + 1)]);
            tris.push([at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    tris
}

/// The bytes of the tree over `tris` with its blocks attached, plus its build primitives
/// (freed after the build, but part of its peak).
fn built_bytes(tris: &[[Vec3; 3]]) -> u64 {
    let mesh = Arc::new(TriangleMesh {
        positions: tris.iter().flatten().copied().collect(),
        indices: (0..3 * tris.len() as u32).collect(),
        ..Default::default()
    });
    let triangles: Vec<Triangle> = (0..tris.len() as u32).map(|i| Triangle::new(mesh.clone(), i)).collect();
    let mut bvh = WideBvh::build_with(triangles.len(), |i| triangles[i].bounds());
    bvh.attach_triangles(|i| Some(triangles[i as usize].positions()));
    assert!(bvh.triangle_blocks() > 0, "no leaf blocks were made");
    bvh.memory_bytes() + WideBvh::BUILD_BYTES_PER_PRIMITIVE * tris.len() as u64
}

#[test]
fn memory_estimates_cover_built_trees() {
    let mut failures = Vec::new();
    for (name, tris) in [
        ("36-triangle soup", soup(36)),
        ("5000-triangle soup", soup(5000)),
        ("5000-triangle grid", grid(50)),
        ("100k-triangle soup", soup(100_000)),
        ("100k-triangle grid", grid(224)),
    ] {
        let n = tris.len() as u64;
        let (built, estimate) = (built_bytes(&tris), WideBvh::estimated_peak_bytes(n));
        eprintln!(
            "{name}: built {:.1} bytes a triangle, estimate {:.1}",
            built as f64 / n as f64,
            estimate as f64 / n as f64
        );
        if built > estimate || estimate > 3 * built {
            failures.push(format!("{name}: {built} bytes built, estimated {estimate}"));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
    assert_eq!(WideBvh::estimated_peak_bytes(0), 0);
    assert_eq!(WideBvh::estimated_peak_bytes(u64::MAX), u64::MAX);
}
