//! `mcrender bench-rays MESH.ply RAYS.bin`: the BVH alone, fed a fixed list of rays, so any
//! other ray tracing kernel (`bench/rays.sh` runs Embree 4) can be given the same work.
//!
//! `RAYS.bin` is little-endian float32, 7 values per ray: origin xyz, direction xyz (any
//! non-zero length), `t_max` (may be +inf). The command loads the mesh, builds the BVH
//! (printing the build time and triangles per second), traces every ray `--repeat` times
//! and prints the best repeat as one line ending in `M rays/s`. `--hits OUT.bin` writes one
//! float32 per ray: the hit distance `t` in units of the direction's length (the hit point
//! is `o + t d`), +inf for a miss; for `--query any`, 0 for a blocked ray and +inf otherwise.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use mcrender_core::accel::{Isa, WideBvh, PACKET};
use mcrender_core::math::{Ray, Vec3};
use mcrender_core::shape::{Triangle, TriangleMesh};
use mcrender_formats::ply::read_ply;
use rayon::prelude::*;

use crate::stdout::say;

/// Bytes per ray in `RAYS.bin`.
const RAY_BYTES: usize = 7 * 4;
/// Rays per parallel work unit.
const CHUNK: usize = 1024;

/// Which query to run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Query {
    /// The nearest hit and its distance.
    Closest,
    /// Whether anything is hit within `t_max` (shadow rays).
    Any,
}

/// Options of `mcrender bench-rays`.
#[derive(Args, Debug)]
pub struct BenchRaysArgs {
    /// The mesh (PLY, triangles or quads).
    pub mesh: PathBuf,
    /// The rays: little-endian float32, 7 per ray (origin, direction, t_max).
    pub rays: PathBuf,
    /// Closest hit or any hit.
    #[arg(long, value_enum, default_value_t = Query::Closest)]
    pub query: Query,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
    /// Trace all rays this many times; the fastest pass is reported.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub repeat: u32,
    /// Write the hit distance of every ray (float32, little endian) to this file.
    #[arg(long, value_name = "OUT.bin")]
    pub hits: Option<PathBuf>,
    /// Trace consecutive rays of the file in packets of eight, together (the BVH's packet
    /// queries); by default each ray is traced alone.
    #[arg(long)]
    pub packets: bool,
    /// Instruction set of the wide BVH's queries (default: the best this CPU has).
    #[arg(long, value_enum)]
    pub isa: Option<IsaArg>,
}

/// `--isa` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum IsaArg {
    /// Baseline instructions, any CPU.
    Portable,
    /// AVX2 and FMA (x86-64).
    Avx2,
    /// AVX-512 F and VL, AVX2 and FMA (x86-64).
    Avx512,
}

impl From<IsaArg> for Isa {
    fn from(a: IsaArg) -> Self {
        match a {
            IsaArg::Portable => Isa::Portable,
            IsaArg::Avx2 => Isa::Avx2,
            IsaArg::Avx512 => Isa::Avx512,
        }
    }
}

/// Run the benchmark.
pub fn run(args: &BenchRaysArgs) -> Result<()> {
    let rays = read_rays(&args.rays)?;
    let ply = read_ply(&args.mesh).with_context(|| format!("{}: cannot read the PLY mesh", args.mesh.display()))?;
    let mesh = Arc::new(TriangleMesh {
        positions: ply.positions,
        indices: ply.indices,
        ..Default::default()
    });
    let triangles: Vec<Triangle> = (0..mesh.triangle_count() as u32)
        .map(|i| Triangle::new(mesh.clone(), i))
        .collect();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.map_or(0, |n| n as usize))
        .build()
        .context("cannot start the worker threads")?;
    let threads = pool.current_num_threads();

    let start = Instant::now();
    let mut bvh = pool.install(|| build(&triangles));
    let build_s = start.elapsed().as_secs_f64();
    if let Some(isa) = args.isa {
        bvh.set_isa(isa.into()).map_err(anyhow::Error::msg)?;
    }
    say!(
        "mesh {}: {} triangles; {}-wide BVH ({}, {} nodes, {} leaf blocks, traversal stack {}) built in {:.3} s on {threads} thread{} ({:.2} M triangles/s)",
        args.mesh.display(),
        triangles.len(),
        mcrender_core::accel::WIDTH,
        bvh.isa().name(),
        bvh.nodes().len(),
        bvh.triangle_blocks(),
        bvh.traversal_stack_size(),
        build_s,
        if threads == 1 { "" } else { "s" },
        triangles.len() as f64 / build_s / 1e6
    );

    let mut hits = vec![f32::INFINITY; rays.len()];
    let mut best = f64::INFINITY;
    for _ in 0..args.repeat {
        let start = Instant::now();
        pool.install(|| {
            hits.par_chunks_mut(CHUNK)
                .zip(rays.par_chunks(CHUNK))
                .for_each(|(out, rays)| {
                    if args.packets {
                        for (h, rays) in out.chunks_mut(PACKET).zip(rays.chunks(PACKET)) {
                            trace_packet(&bvh, &triangles, args.query, rays, h);
                        }
                    } else {
                        for (h, (ray, t_max)) in out.iter_mut().zip(rays) {
                            *h = trace(&bvh, &triangles, args.query, ray, *t_max);
                        }
                    }
                });
        });
        best = best.min(start.elapsed().as_secs_f64());
    }
    if let Some(path) = &args.hits {
        let bytes: Vec<u8> = hits.iter().flat_map(|t| t.to_le_bytes()).collect();
        std::fs::write(path, bytes).with_context(|| format!("{}: cannot write the hits", path.display()))?;
    }
    let hit_count = hits.iter().filter(|t| t.is_finite()).count();
    say!(
        "{} {} rays ({} hit), best of {} on {threads} thread{}: {:.4} s, {:.2} M rays/s",
        match args.query {
            Query::Closest => "closest-hit",
            Query::Any => "any-hit",
        },
        rays.len(),
        hit_count,
        args.repeat,
        if threads == 1 { "" } else { "s" },
        best,
        rays.len() as f64 / best / 1e6
    );
    Ok(())
}

/// Build over `triangles`, left in the mesh's order: the leaf blocks hold every leaf's
/// vertices and primitive indices, so tracing never reads the triangles, and putting them in
/// leaf order (as a scene does for its shading lookups, [`WideBvh::reorder_by_leaves`]) is no
/// part of the tree. Embree, the peer, leaves the caller's arrays as they are too.
fn build(triangles: &[Triangle]) -> WideBvh {
    let mut bvh = WideBvh::build_with(triangles.len(), |i| triangles[i].bounds());
    bvh.attach_triangles(|i| Some(triangles[i as usize].positions()));
    bvh
}

/// Hit distance of one ray (closest) or 0 / +inf (any).
fn trace(bvh: &WideBvh, triangles: &[Triangle], query: Query, ray: &Ray, t_max: f32) -> f32 {
    match query {
        Query::Closest => bvh
            .closest_hit_triangles(
                ray,
                t_max,
                |i, r, t| triangles[i as usize].intersect(r, t).map(|h| (h.t, h.t)),
                |_, h| h.t,
            )
            .map_or(f32::INFINITY, |(_, t)| t),
        Query::Any => {
            if bvh.any_hit_triangles(ray, t_max, |i, r, t| triangles[i as usize].intersect(r, t).is_some()) {
                0.0
            } else {
                f32::INFINITY
            }
        }
    }
}

/// Hit distances of up to [`PACKET`] rays traced together, into `out` (as [`trace`]).
fn trace_packet(bvh: &WideBvh, triangles: &[Triangle], query: Query, rays: &[(Ray, f32)], out: &mut [f32]) {
    let placeholder = Ray::new(Vec3::ZERO, Vec3::Z);
    let packet: [Ray; PACKET] = std::array::from_fn(|r| rays.get(r).map_or(placeholder, |(ray, _)| *ray));
    let t_max: [f32; PACKET] = std::array::from_fn(|r| rays.get(r).map_or(0.0, |(_, t)| *t));
    let active = (1u32 << rays.len()) - 1;
    match query {
        Query::Closest => {
            let hits = bvh.closest_hit_triangles_packet(
                &packet,
                t_max,
                active,
                |_, i, r, t| triangles[i as usize].intersect(r, t).map(|h| (h.t, h.t)),
                |_, _, h| h.t,
            );
            for (o, h) in out.iter_mut().zip(hits) {
                *o = h.map_or(f32::INFINITY, |(_, t)| t);
            }
        }
        Query::Any => {
            let blocked = bvh.any_hit_triangles_packet(&packet, t_max, active, |_, i, r, t| {
                triangles[i as usize].intersect(r, t).is_some()
            });
            for (r, o) in out.iter_mut().enumerate() {
                *o = if blocked >> r & 1 != 0 { 0.0 } else { f32::INFINITY };
            }
        }
    }
}

/// Read and check `RAYS.bin`.
fn read_rays(path: &Path) -> Result<Vec<(Ray, f32)>> {
    let bytes = std::fs::read(path).with_context(|| format!("{}: cannot read the rays", path.display()))?;
    if bytes.len() % RAY_BYTES != 0 {
        bail!(
            "{}: expected a whole number of rays of {RAY_BYTES} bytes (7 little-endian float32: origin, direction, t_max), found {} bytes",
            path.display(),
            bytes.len()
        );
    }
    let mut rays = Vec::with_capacity(bytes.len() / RAY_BYTES);
    for (k, chunk) in bytes.chunks_exact(RAY_BYTES).enumerate() {
        let v: Vec<f32> = chunk
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect();
        let (o, d, t_max) = (Vec3::new(v[0], v[1], v[2]), Vec3::new(v[3], v[4], v[5]), v[6]);
        let at = || format!("{}: ray {k} (byte {})", path.display(), k * RAY_BYTES);
        if !o.is_finite() || !d.is_finite() {
            bail!("{}: expected a finite origin and direction, found {o} and {d}", at());
        }
        if d == Vec3::ZERO {
            bail!("{}: expected a non-zero direction", at());
        }
        if t_max.is_nan() || t_max < 0.0 {
            bail!("{}: expected t_max >= 0 (or +inf), found {t_max}", at());
        }
        rays.push((Ray::new(o, d), t_max));
    }
    Ok(rays)
}
