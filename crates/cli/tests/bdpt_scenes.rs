//! Bidirectional path tracing on the shared scenes: agreement with the path tracer per
//! depth on the Cornell box, and Veach's bidirectional room against Tungsten's reference
//! with the efficiency gain BDPT exists for. They fail when the shared scenes cannot be
//! found, unless `MCRENDER_SKIP_SHARED_SCENES` is set (then a visible `SKIPPED` line).
//!
//! BDPT's light-tracing strategies splat onto other pixels, so a pixel's own sample spread
//! does not measure its noise. Every statistic here comes instead from `K` independent
//! renders (seeds 1..=K): the per-pixel variance of one render is the spread of the K
//! values, and the variance of their mean is that over K.

mod common;

use std::path::PathBuf;

use mcrender_core::color::Rgb;
use mcrender_core::film::{block_means_of, downsample_box, ImageComparison, BLOCK_REL_EPSILON};
use mcrender_core::render::{render, RenderOptions};
use mcrender_core::scene::{IntegratorKind, Scene, SceneDescription};
use mcrender_formats::image_io::read_exr;
use mcrender_formats::pbrt::load_file;

use common::shared_scenes::shared_scenes_dir;

const BLOCK: u32 = 8;

/// K independent renders: their mean image, the per-pixel variance of that mean, and the
/// rays (closest-hit plus shadow) one render traced on average.
struct Renders {
    mean: Vec<Rgb>,
    var_of_mean: Vec<[f64; 3]>,
    /// Per-pixel variance of a single render.
    var_one: Vec<[f64; 3]>,
    rays_per_render: f64,
}

fn renders(desc: &SceneDescription, k: u64) -> Renders {
    let n = (desc.film.width * desc.film.height) as usize;
    let (mut sum, mut sum2) = (vec![[0.0f64; 3]; n], vec![[0.0f64; 3]; n]);
    let mut rays = 0.0;
    for seed in 1..=k {
        let mut d = desc.clone();
        d.sampler.seed = seed;
        let scene = Scene::build(&d).expect("scene builds");
        let out = render(&scene, &RenderOptions::default(), &|_, _| {}).expect("render");
        assert_eq!(out.stats.nonfinite_samples, 0);
        rays += (out.stats.trace.rays + out.stats.trace.shadow_rays) as f64;
        for (i, p) in out.film.mean_image().iter().enumerate() {
            for c in 0..3 {
                let v = f64::from(p[c]);
                sum[i][c] += v;
                sum2[i][c] += v * v;
            }
        }
    }
    let kf = k as f64;
    let mut mean = Vec::with_capacity(n);
    let mut var_one = Vec::with_capacity(n);
    for i in 0..n {
        let m: [f64; 3] = std::array::from_fn(|c| sum[i][c] / kf);
        var_one.push(std::array::from_fn(|c| {
            ((sum2[i][c] - kf * m[c] * m[c]) / (kf - 1.0)).max(0.0)
        }));
        mean.push(Rgb::new(m[0] as f32, m[1] as f32, m[2] as f32));
    }
    let var_of_mean = var_one.iter().map(|v| v.map(|x| x / kf)).collect();
    Renders {
        mean,
        var_of_mean,
        var_one,
        rays_per_render: rays / kf,
    }
}

/// Block means and their standard errors (from the per-pixel variances of the mean).
fn blocks(r: &Renders, w: u32, h: u32) -> Vec<([f64; 3], [f64; 3])> {
    let mut out = Vec::new();
    for by in (0..h).step_by(BLOCK as usize) {
        for bx in (0..w).step_by(BLOCK as usize) {
            let (mut m, mut v, mut n) = ([0.0f64; 3], [0.0f64; 3], 0.0);
            for y in by..(by + BLOCK).min(h) {
                for x in bx..(bx + BLOCK).min(w) {
                    let i = (y * w + x) as usize;
                    for c in 0..3 {
                        m[c] += f64::from(r.mean[i][c]);
                        v[c] += r.var_of_mean[i][c];
                    }
                    n += 1.0;
                }
            }
            out.push((m.map(|x| x / n), v.map(|x| x.sqrt() / n)));
        }
    }
    out
}

fn with_integrator(
    mut d: SceneDescription,
    kind: IntegratorKind,
    w: u32,
    h: u32,
    spp: u32,
    depth: u32,
) -> SceneDescription {
    d.integrator.kind = kind;
    d.film.width = w;
    d.film.height = h;
    d.sampler.samples_per_pixel = spp;
    d.sampler.kind = mcrender_core::scene::SamplerKind::Independent;
    d.integrator.max_depth = depth;
    d
}

/// Per depth (max depth 1, 2, 3), BDPT and the path tracer estimate the same image of the
/// Cornell box at 16x16 with pbrt's default Gaussian filter: on every 8x8 block and channel, the difference of the block means
/// is within 4.5 combined standard errors (12 z-scores per depth; an unbiased pair exceeds
/// 4.5 with probability about 1e-4), and the image means within 4.
#[test]
fn cornell_box_agrees_with_the_path_tracer_per_depth() {
    let Some(dir) = shared_scenes_dir("cornell_box_agrees_with_the_path_tracer_per_depth") else {
        return;
    };
    let mut desc = load_file(&dir.join("cornell-box/scene-v4.pbrt"))
        .expect("loads")
        .description;
    // pbrt's default Gaussian (radius 1.5): BDPT's splats are spread by the same filter
    // the camera samples, so its strategies estimate the same filtered image.
    desc.filter = mcrender_core::scene::FilterDesc::default();
    let (w, h) = (16, 16);
    for depth in 1..=3 {
        let b = renders(&with_integrator(desc.clone(), IntegratorKind::Bdpt, w, h, 64, depth), 4);
        let p = renders(
            &with_integrator(desc.clone(), IntegratorKind::Path, w, h, 256, depth),
            4,
        );
        let (bb, pb) = (blocks(&b, w, h), blocks(&p, w, h));
        let mut worst = 0.0f64;
        for ((bm, bs), (pm, ps)) in bb.iter().zip(&pb) {
            for c in 0..3 {
                let z = (bm[c] - pm[c]) / (bs[c] * bs[c] + ps[c] * ps[c]).sqrt().max(1e-12);
                worst = worst.max(z.abs());
            }
        }
        let img = |r: &Renders| -> ([f64; 3], [f64; 3]) {
            let n = r.mean.len() as f64;
            let m = std::array::from_fn(|c| r.mean.iter().map(|p| f64::from(p[c])).sum::<f64>() / n);
            let s = std::array::from_fn(|c| r.var_of_mean.iter().map(|v| v[c]).sum::<f64>().sqrt() / n);
            (m, s)
        };
        let ((bm, bs), (pm, ps)) = (img(&b), img(&p));
        eprintln!("depth {depth}: bdpt {bm:.5?} path {pm:.5?}; worst block |z| {worst:.2}");
        assert!(
            worst < 4.5,
            "depth {depth}: a block differs by {worst:.2} standard errors"
        );
        for c in 0..3 {
            let z = (bm[c] - pm[c]) / (bs[c] * bs[c] + ps[c] * ps[c]).sqrt();
            assert!(
                z.abs() < 4.0,
                "depth {depth}, channel {c}: image means differ by z = {z:.2}"
            );
        }
    }
}

/// The repository's copy of a scene (always present: these tests never skip).
fn repo_file(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..").join(rel)
}

/// Per pixel and channel, `z = (a - b) / sqrt(se_a^2 + se_b^2)`: the mean of `z^2` and the
/// largest `|z|` with its pixel.
fn pixel_z(a: &Renders, b: &Renders, w: u32) -> (f64, (f64, u32, u32)) {
    let (mut sum, mut n, mut worst) = (0.0, 0.0, (0.0f64, 0, 0));
    for i in 0..a.mean.len() {
        for c in 0..3 {
            let var = a.var_of_mean[i][c] + b.var_of_mean[i][c];
            let d = f64::from(a.mean[i][c]) - f64::from(b.mean[i][c]);
            if var == 0.0 {
                assert_eq!(
                    d, 0.0,
                    "pixel {i} channel {c}: no noise on either side, yet they differ"
                );
                continue;
            }
            let z = d / var.sqrt();
            sum += z * z;
            n += 1.0;
            if z.abs() > worst.0 {
                worst = (z.abs(), i as u32 % w, i as u32 / w);
            }
        }
    }
    (sum / n, worst)
}

/// Light tracing (`t = 1` alone) and the path tracer estimate the same filtered pixel
/// integrals under wide filters: the Cornell box at 16x16, 128 spp, max depth 3 (edges of
/// the light, the boxes and the walls, and the image border, where the filter reaches past
/// the film) with pbrt's default Gaussian (radius 1.5), the file's triangle filter
/// (radius 1) and pbrt's Mitchell filter (radius 2, B = C = 1/3, negative lobes: signed
/// camera weights and signed splats), 16 seeds each.
///
/// Every pixel and channel gives a z-score from the two renders' measured variances (each
/// the spread of 16 seeds, so `z` follows about a Student t with 15 degrees of freedom:
/// `E[z^2]` = 15/13 = 1.15, with a standard deviation of the mean over 768 correlated
/// scores of about 0.12). We assert mean `z^2` < 1.8 and no `|z|` above 7.
///
/// Measured: mean `z^2` 0.88 (Gaussian), 0.90 (triangle), 0.86 (Mitchell), worst `|z|` 3.1,
/// 3.6 and 2.9. Splats that dropped the Mitchell filter's negative lobes fail with 5.3.
/// With splats on one pixel of weight one (the code before filtered splats) the Gaussian
/// case fails with mean `z^2` 10.1, worst `|z|` 18 (59 at the file's framing and 256 spp);
/// with filtered splats but the camera importance cut at the pixel bounds, 5.7 and 15 at
/// the border (the top row, under the light, 0.2 to 0.5 of the path tracer's value).
#[test]
fn light_tracing_agrees_with_the_path_tracer_per_pixel_under_wide_filters() {
    use mcrender_core::math::Vec2;
    use mcrender_core::scene::FilterDesc;
    let mut desc = load_file(&repo_file("scenes/cornell-box/scene-v4.pbrt"))
        .expect("loads")
        .description;
    // Zoomed in from the file's 19.5 degrees, so that the image border cuts through the
    // lit walls (with the file's framing the film ends where the box does and the margin
    // the filter reaches beyond the border is black).
    desc.camera.fov_degrees = 15.0;
    let (w, h) = (16, 16);
    let filters = [
        (
            "gaussian",
            FilterDesc::Gaussian {
                radius: Vec2::splat(1.5),
                sigma: 0.5,
            },
        ),
        ("triangle", desc.filter),
        (
            "mitchell",
            FilterDesc::Mitchell {
                radius: Vec2::splat(2.0),
                b: 1.0 / 3.0,
                c: 1.0 / 3.0,
            },
        ),
    ];
    for (name, filter) in filters {
        desc.filter = filter;
        let l = renders(
            &with_integrator(desc.clone(), IntegratorKind::LightPath, w, h, 128, 3),
            16,
        );
        let p = renders(&with_integrator(desc.clone(), IntegratorKind::Path, w, h, 128, 3), 16);
        let (z2, (worst, x, y)) = pixel_z(&l, &p, w);
        eprintln!("{name}: mean z^2 {z2:.3}, worst |z| {worst:.2} at ({x}, {y})");
        assert!(
            z2 < 1.8,
            "{name}: light tracing and path tracing differ: mean z^2 {z2:.3}"
        );
        assert!(
            worst < 7.0,
            "{name}: pixel ({x}, {y}) differs by {worst:.2} standard errors"
        );
    }
}

/// The reference box-downsampled to `w x h`.
fn reference(path: &std::path::Path, w: u32, h: u32) -> Vec<Rgb> {
    let r = read_exr(path).expect("reference loads");
    let f = r.width / w;
    let (rw, rh, px) = downsample_box(&r.pixels, r.width, r.height, f).expect("downsample");
    assert_eq!((rw, rh), (w, h));
    px
}

/// Mean over pixels of the relative variance of one render, `var / (ref^2 + eps^2)`, per
/// channel averaged: the relative MSE a single render has from noise alone.
fn rel_variance(r: &Renders, reference: &[Rgb]) -> f64 {
    let mut s = 0.0;
    for (v, p) in r.var_one.iter().zip(reference) {
        for c in 0..3 {
            let d = f64::from(p[c]).abs() + BLOCK_REL_EPSILON;
            s += v[c] / (d * d);
        }
    }
    s / (3 * reference.len()) as f64
}

/// Veach's bidirectional room (`veach-bidir`: the main light shines from inside a lamp
/// shade onto the ceiling) at 64x64 and the file's max depth 7, against Tungsten's
/// 1024x1024 reference downsampled 16x.
///
/// - Means within 2.5% per channel; block relative error (8x8 blocks) below what our
///   measured noise predicts plus a margin for the reference's own difference.
/// - Efficiency, `1 / (relative variance x cost)`, with the cost counted in rays traced
///   (closest-hit and shadow) rather than seconds, so the test does not depend on the
///   machine's load; rays are what both integrators spend nearly all their time on. The
///   relative variance is measured from 4 seeds against the reference's values (noise
///   only: the depth-7 cut biases both integrators alike, so the reference's extra bounces
///   must not count against either). BDPT must be at least 4x as efficient.
///
/// Measured (4 seeds of 16 spp for BDPT, of 64 spp for the path tracer; shared machine,
/// which the ray counts do not see): means +1.37%/+0.91%/+0.53% (R/G/B) against the
/// reference, the size and sign the issue measured with our path tracer at depth 7
/// (+1.9/+1.3/+0.7% at 2048 spp), so the difference is not BDPT's. Block rel err
/// 0.041/0.035/0.030 against 0.010 expected from our noise; rescaled to the reference's
/// means, 0.032/0.029/0.027: an excess of about 0.02 spread over many blocks, nearly all
/// brighter than the reference (the same sign as the means), not at a few edges. We
/// assert block error < expected + 0.04 (a 5% bias fails the means first). Relative
/// variance x rays: BDPT 4.46e-2 x 1.72e6, path 3.16 x 9.34e5, an efficiency ratio of 38.
#[test]
fn veach_bidir_matches_tungsten_and_beats_the_path_tracer() {
    let Some(dir) = shared_scenes_dir("veach_bidir_matches_tungsten_and_beats_the_path_tracer") else {
        return;
    };
    let loaded = load_file(&dir.join("veach-bidir/scene-v4.pbrt")).expect("loads");
    assert_eq!(loaded.description.integrator.kind, IntegratorKind::Bdpt);
    assert_eq!(loaded.description.integrator.max_depth, 7);
    let (w, h) = (64, 64);
    let r = reference(&dir.join("veach-bidir/TungstenRender.exr"), w, h);
    let b = renders(
        &with_integrator(loaded.description.clone(), IntegratorKind::Bdpt, w, h, 16, 7),
        4,
    );
    let p = renders(
        &with_integrator(loaded.description.clone(), IntegratorKind::Path, w, h, 64, 7),
        4,
    );

    let c = ImageComparison::new(&b.mean, &r, w, h, BLOCK).unwrap();
    let (_, _, ref_blocks) = block_means_of(&r, w, h, BLOCK).unwrap();
    let ours = blocks(&b, w, h);
    let expected: [f64; 3] = std::array::from_fn(|ch| {
        ours.iter()
            .zip(&ref_blocks)
            .map(|((_, s), rb)| (2.0 / std::f64::consts::PI).sqrt() * s[ch] / (rb[ch].abs() + BLOCK_REL_EPSILON))
            .sum::<f64>()
            / ref_blocks.len() as f64
    });
    let (eb, ep) = (
        1.0 / (rel_variance(&b, &r) * b.rays_per_render),
        1.0 / (rel_variance(&p, &r) * p.rays_per_render),
    );
    eprintln!(
        "veach-bidir bdpt: means {:.5?} ref {:.5?} rel diff {:.4?}; block rel err {:.4?}, expected from noise {expected:.4?}",
        c.mean_a,
        c.mean_b,
        c.mean_rel_diff(),
        c.block_rel_mean
    );
    eprintln!(
        "veach-bidir: rel variance bdpt {:.4e} ({:.3e} rays), path {:.4e} ({:.3e} rays); efficiency ratio {:.2}",
        rel_variance(&b, &r),
        b.rays_per_render,
        rel_variance(&p, &r),
        p.rays_per_render,
        eb / ep
    );
    let cp = ImageComparison::new(&p.mean, &r, w, h, BLOCK).unwrap();
    eprintln!(
        "veach-bidir path: rel diff {:.4?}, block rel err {:.4?}",
        cp.mean_rel_diff(),
        cp.block_rel_mean
    );
    // The same after removing the global difference of the means (the depth cut).
    let scale: [f32; 3] = std::array::from_fn(|ch| (c.mean_b[ch] / c.mean_a[ch]) as f32);
    let rescaled: Vec<Rgb> = b
        .mean
        .iter()
        .map(|p| Rgb::new(p.r * scale[0], p.g * scale[1], p.b * scale[2]))
        .collect();
    let cr = ImageComparison::new(&rescaled, &r, w, h, BLOCK).unwrap();
    eprintln!(
        "veach-bidir bdpt rescaled to the reference's means: block rel err {:.4?}",
        cr.block_rel_mean
    );
    for ch in 0..3 {
        assert!(
            c.mean_rel_diff()[ch].abs() < 0.025,
            "channel {ch}: {:?}",
            c.mean_rel_diff()
        );
        assert!(
            c.block_rel_mean[ch] < expected[ch] + 0.04,
            "channel {ch}: block rel err {:?} vs expected from noise {expected:?}",
            c.block_rel_mean
        );
    }
    assert!(
        eb >= 4.0 * ep,
        "BDPT is only {:.2}x as efficient as the path tracer",
        eb / ep
    );
}
