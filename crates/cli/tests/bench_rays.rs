//! `mcrender bench-rays`: on a small random triangle soup, `--hits` agrees with brute force
//! (every triangle tested against every ray) for closest-hit and any-hit queries; malformed
//! ray files are refused with one line and exit code 2, writing no hits file.

mod common;

use std::path::Path;
use std::sync::Arc;

use common::{mcrender, stderr};
use mcrender_core::accel::Isa;
use mcrender_core::math::{Ray, Vec3};
use mcrender_core::shape::{Triangle, TriangleMesh};

/// A small deterministic generator (PCG-like LCG) so the test needs no RNG crate.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((self.0 >> 40) as f32) / (1u64 << 24) as f32
    }
    fn vec(&mut self, lo: f32, hi: f32) -> Vec3 {
        Vec3::new(self.next(), self.next(), self.next()) * (hi - lo) + Vec3::splat(lo)
    }
}

/// 200 random triangles (a few of them degenerate) as an ASCII PLY.
fn soup(rng: &mut Lcg) -> (Vec<Vec3>, String) {
    let mut positions = Vec::new();
    for k in 0..200 {
        let c = rng.vec(-4.0, 4.0);
        let a = c + rng.vec(-0.8, 0.8);
        let b = c + rng.vec(-0.8, 0.8);
        // Every 25th triangle has zero area (two equal corners).
        let d = if k % 25 == 0 { b } else { c + rng.vec(-0.8, 0.8) };
        positions.extend([a, b, d]);
    }
    let mut ply = format!(
        "ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\n\
         element face {}\nproperty list uchar int vertex_indices\nend_header\n",
        positions.len(),
        positions.len() / 3
    );
    for p in &positions {
        ply += &format!("{} {} {}\n", p.x, p.y, p.z);
    }
    for t in 0..positions.len() / 3 {
        ply += &format!("3 {} {} {}\n", 3 * t, 3 * t + 1, 3 * t + 2);
    }
    (positions, ply)
}

fn rays(rng: &mut Lcg, n: usize) -> Vec<[f32; 7]> {
    (0..n)
        .map(|k| {
            let o = rng.vec(-6.0, 6.0);
            // Unnormalised directions, some axis-aligned; finite and infinite t_max.
            let mut d = rng.vec(-1.0, 1.0) * (0.5 + 3.0 * rng.next());
            if k % 7 == 0 {
                d = Vec3::new(0.0, 0.0, d.z.signum());
            }
            let t_max = if k % 3 == 0 { 2.0 * rng.next() } else { f32::INFINITY };
            [o.x, o.y, o.z, d.x, d.y, d.z, t_max]
        })
        .collect()
}

fn write_rays(path: &Path, rays: &[[f32; 7]]) {
    let bytes: Vec<u8> = rays.iter().flatten().flat_map(|v| v.to_le_bytes()).collect();
    std::fs::write(path, bytes).unwrap();
}

fn read_hits(path: &Path) -> Vec<f32> {
    std::fs::read(path)
        .unwrap()
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect()
}

#[test]
fn hits_agree_with_brute_force() {
    let dir = tempfile::tempdir().unwrap();
    let mut rng = Lcg(7);
    let (positions, ply) = soup(&mut rng);
    std::fs::write(dir.path().join("mesh.ply"), ply).unwrap();
    let rays = rays(&mut rng, 3001);
    write_rays(&dir.path().join("rays.bin"), &rays);

    // Brute force over triangles built from the same (decimal-printed, re-read) positions.
    let mesh = Arc::new(TriangleMesh {
        positions: positions
            .iter()
            .map(|p| {
                let r = |v: f32| format!("{v}").parse::<f32>().unwrap();
                Vec3::new(r(p.x), r(p.y), r(p.z))
            })
            .collect(),
        indices: (0..positions.len() as u32).collect(),
        ..Default::default()
    });
    let tris: Vec<Triangle> = (0..positions.len() as u32 / 3)
        .map(|i| Triangle::new(mesh.clone(), i))
        .collect();
    let brute: Vec<f32> = rays
        .iter()
        .map(|r| {
            let ray = Ray::new(Vec3::new(r[0], r[1], r[2]), Vec3::new(r[3], r[4], r[5]));
            tris.iter()
                .filter_map(|t| t.intersect(&ray, r[6]).map(|h| h.t))
                .fold(f32::INFINITY, f32::min)
        })
        .collect();
    let hit_count = brute.iter().filter(|t| t.is_finite()).count();
    assert!(
        hit_count > 150 && hit_count < 2850,
        "the test rays should hit and miss: {hit_count}"
    );

    // The tree in each instruction set (the best, and the portable kernels forced).
    // Also in packets of eight consecutive rays (the last one partial: 3001 rays).
    let mut configs = vec![
        vec![],
        vec!["--isa", "portable"],
        vec!["--packets"],
        vec!["--packets", "--isa", "portable"],
    ];
    for isa in [Isa::Avx2, Isa::Avx512] {
        if isa.is_supported() {
            configs.push(vec!["--isa", isa.name()]);
            configs.push(vec!["--packets", "--isa", isa.name()]);
        } else {
            eprintln!("NOT TESTED: --isa {} (this CPU does not have it)", isa.name());
        }
    }
    for config in &configs {
        let accel = config.join(" ");
        for threads in ["1", "2"] {
            let o = mcrender(
                &[
                    "bench-rays",
                    "mesh.ply",
                    "rays.bin",
                    "--threads",
                    threads,
                    "--repeat",
                    "2",
                    "--hits",
                    "closest.bin",
                ]
                .into_iter()
                .chain(config.iter().copied())
                .collect::<Vec<_>>(),
                dir.path(),
            );
            assert!(o.status.success(), "{}", stderr(&o));
            let out = String::from_utf8_lossy(&o.stdout);
            assert!(out.contains("M triangles/s"), "{out}");
            assert!(out.trim_end().ends_with("M rays/s"), "{out}");
            assert_eq!(
                read_hits(&dir.path().join("closest.bin")),
                brute,
                "{accel} closest hits, {threads} threads"
            );

            let o = mcrender(
                &[
                    "bench-rays",
                    "mesh.ply",
                    "rays.bin",
                    "--query",
                    "any",
                    "--threads",
                    threads,
                    "--hits",
                    "any.bin",
                ]
                .into_iter()
                .chain(config.iter().copied())
                .collect::<Vec<_>>(),
                dir.path(),
            );
            assert!(o.status.success(), "{}", stderr(&o));
            let any = read_hits(&dir.path().join("any.bin"));
            let expected: Vec<f32> = brute
                .iter()
                .map(|t| if t.is_finite() { 0.0 } else { f32::INFINITY })
                .collect();
            assert_eq!(any, expected, "{accel} any hits, {threads} threads");
        }
    }
}

#[test]
fn malformed_inputs_are_refused_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let mut rng = Lcg(3);
    let (_, ply) = soup(&mut rng);
    std::fs::write(dir.path().join("mesh.ply"), ply).unwrap();
    let good = rays(&mut rng, 4);
    let mut nan = good.clone();
    nan[2][4] = f32::NAN;
    let mut zero = good.clone();
    zero[1][3..6].copy_from_slice(&[0.0; 3]);
    let mut negative = good.clone();
    negative[3][6] = -1.0;
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        ("short.bin", vec![0; 27], "27 bytes"),
        (
            "nan.bin",
            nan.iter().flatten().flat_map(|v| v.to_le_bytes()).collect(),
            "ray 2",
        ),
        (
            "zero.bin",
            zero.iter().flatten().flat_map(|v| v.to_le_bytes()).collect(),
            "ray 1",
        ),
        (
            "neg.bin",
            negative.iter().flatten().flat_map(|v| v.to_le_bytes()).collect(),
            "ray 3",
        ),
    ];
    for (name, bytes, expect) in cases {
        std::fs::write(dir.path().join(name), bytes).unwrap();
        let o = mcrender(&["bench-rays", "mesh.ply", name, "--hits", "out.bin"], dir.path());
        assert_eq!(o.status.code(), Some(2), "{name}: {}", stderr(&o));
        let msg = stderr(&o);
        assert_eq!(msg.trim_end().lines().count(), 1, "{name}: {msg}");
        assert!(msg.contains(name) && msg.contains(expect), "{name}: {msg}");
        assert!(!dir.path().join("out.bin").exists(), "{name}: a hits file was written");
    }
    // A broken mesh.
    std::fs::write(dir.path().join("bad.ply"), "ply\nformat ascii 1.0\nelement vertex x\n").unwrap();
    write_rays(&dir.path().join("ok.bin"), &good);
    let o = mcrender(&["bench-rays", "bad.ply", "ok.bin"], dir.path());
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert_eq!(stderr(&o).trim_end().lines().count(), 1, "{}", stderr(&o));
    assert!(stderr(&o).contains("bad.ply"), "{}", stderr(&o));
    let o = mcrender(&["bench-rays", "missing.ply", "ok.bin"], dir.path());
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}
