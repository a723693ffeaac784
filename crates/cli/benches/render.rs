//! Criterion benchmarks: BVH construction and a small Cornell box render. Compare runs of
//! the same machine only; for peer comparisons use `bench/cbox.sh`.
#![allow(missing_docs)]

use std::path::PathBuf;

use criterion::{criterion_group, criterion_main, Criterion};
use mcrender_core::accel::WideBvh;
use mcrender_core::render::{render, RenderOptions};
use mcrender_core::scene::{Scene, SceneDescription};
use mcrender_formats::pbrt::load_file;

fn cornell() -> SceneDescription {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell-box/scene-v4.pbrt");
    load_file(&path).expect("scene loads").description
}

fn bench_render(c: &mut Criterion) {
    let mut desc = cornell();
    desc.film.width = 64;
    desc.film.height = 64;
    desc.sampler.samples_per_pixel = 16;
    let scene = Scene::build(&desc).unwrap();
    let opts = RenderOptions {
        threads: Some(1),
        ..Default::default()
    };
    c.bench_function("cornell 64x64 16spp 1 thread", |b| {
        b.iter(|| render(&scene, &opts, &|_, _| {}).unwrap())
    });
}

fn bench_bvh_build(c: &mut Criterion) {
    // A grid of small boxes' bounds, as a stand-in for a large mesh.
    let bounds: Vec<_> = (0..100_000)
        .map(|i| {
            let p = glam::Vec3::new((i % 47) as f32, ((i / 47) % 53) as f32, (i / (47 * 53)) as f32);
            mcrender_core::math::Bounds3 {
                min: p,
                max: p + glam::Vec3::splat(0.7),
            }
        })
        .collect();
    c.bench_function("bvh build 100k", |b| b.iter(|| WideBvh::build(&bounds)));
}

criterion_group!(benches, bench_render, bench_bvh_build);
criterion_main!(benches);
