//! Measures closest-hit throughput of a grid of patches traced as bilinear patches against
//! the same grid as triangle pairs (planar), and of a curved grid as patches. Used to
//! decide that the pbrt loader keeps all-planar `bilinearmesh` shapes as triangle pairs.
//!
//! `cargo run --release -p mcrender-core --example bilinear_vs_triangles`

use mcrender_core::material::DiffuseMaterial;
use std::time::Instant;

use mcrender_core::color::Rgb;
use mcrender_core::math::{Ray, Vec2, Vec3};
use mcrender_core::sampling::Pcg32;
use mcrender_core::scene::*;

const N: u32 = 200;
const RAYS: u32 = 2_000_000;

fn scene(geometry: GeometryDesc) -> Scene {
    let d = SceneDescription {
        camera: CameraDesc::default(),
        film: FilmDesc { width: 4, height: 4 },
        filter: FilterDesc::Box {
            radius: Vec2::splat(0.5),
        },
        reconstruction: Reconstruction::default(),
        sampler: SamplerDesc::default(),
        integrator: IntegratorDesc::default(),
        materials: vec![MaterialDesc::Diffuse(DiffuseMaterial {
            reflectance: Rgb::WHITE.into(),
        })],
        shapes: vec![ShapeDesc {
            geometry,
            material: 0,
            area_light: None,
            flip_normals: false,
            alpha: None,
        }],
        lights: vec![],
        objects: vec![],
        instances: vec![],
    };
    Scene::build(&d).expect("valid scene")
}

/// `N x N` patches over `[-1, 1]^2`, heights from `h`.
fn grid(h: impl Fn(f32, f32) -> f32) -> (Vec<Vec3>, Vec<u32>) {
    let mut p = Vec::new();
    for j in 0..=N {
        for i in 0..=N {
            let (x, y) = (2.0 * i as f32 / N as f32 - 1.0, 2.0 * j as f32 / N as f32 - 1.0);
            p.push(Vec3::new(x, y, h(x, y)));
        }
    }
    let mut idx = Vec::new();
    for j in 0..N {
        for i in 0..N {
            let k = j * (N + 1) + i;
            idx.extend([k, k + 1, k + N + 1, k + N + 2]);
        }
    }
    (p, idx)
}

fn time(label: &str, s: &Scene) {
    let mut rng = Pcg32::new(1, 1);
    let start = Instant::now();
    let mut hits = 0u32;
    for _ in 0..RAYS {
        let o = Vec3::new(rng.next_f32() - 0.5, rng.next_f32() - 0.5, 3.0);
        let d = Vec3::new(rng.next_f32() - 0.5, rng.next_f32() - 0.5, -1.0);
        hits += u32::from(s.intersect(&Ray::new(o, d)).is_some());
    }
    let secs = start.elapsed().as_secs_f64();
    println!("{label:32} {:7.2} Mrays/s ({hits} hits)", f64::from(RAYS) / secs / 1e6);
}

fn main() {
    let (p, idx) = grid(|x, y| 0.1 * x + 0.05 * y);
    let tri_idx: Vec<u32> = idx
        .chunks_exact(4)
        .flat_map(|q| [q[0], q[1], q[3], q[0], q[3], q[2]])
        .collect();
    let planar_patches = scene(GeometryDesc::BilinearMesh(BilinearMeshDesc {
        positions: p.clone(),
        indices: idx,
        ..Default::default()
    }));
    let planar_tris = scene(GeometryDesc::TriangleMesh(TriangleMeshDesc {
        positions: p,
        indices: tri_idx,
        ..Default::default()
    }));
    let (p, idx) = grid(|x, y| 0.3 * (3.0 * x).sin() * (2.0 * y).cos());
    let curved = scene(GeometryDesc::BilinearMesh(BilinearMeshDesc {
        positions: p,
        indices: idx,
        ..Default::default()
    }));
    time("planar grid, triangle pairs", &planar_tris);
    time("planar grid, bilinear patches", &planar_patches);
    time("curved grid, bilinear patches", &curved);
}
