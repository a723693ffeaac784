//! The Cornell box against an independent renderer: Bitterli's scene rendered by us at
//! 128x128 and by Mitsuba 3 at 256x256 with 12,800 spp (downsampled 2x2 here).
//!
//! Tolerances come from the measured noise: each pixel's difference is divided by its
//! standard error (our per-pixel variance of the mean, plus the reference's, estimated as
//! ours scaled by the ratio of sample counts). For an unbiased renderer these z-scores are
//! about standard normal, so we require their mean square to be near 1 and only a few tail
//! values, besides each channel's image mean within 1%.

use std::path::PathBuf;

use mcrender_core::color::Rgb;
use mcrender_core::render::{render, RenderOptions};
use mcrender_core::scene::Scene;
use mcrender_scene::image_io::read_exr;
use mcrender_scene::pbrt::load_file;

const RES: u32 = 128;
const SPP: u32 = 256;
/// Samples per pixel of the reference, per 2x2 block of its 256x256 pixels.
const REFERENCE_SPP: f64 = 12_800.0 * 4.0;

fn repo_file(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..").join(rel)
}

#[test]
fn cornell_box_matches_mitsuba_reference() {
    let loaded = load_file(&repo_file("scenes/cornell-box/scene-v4.pbrt")).expect("scene loads");
    let mut desc = loaded.description;
    desc.film.width = RES;
    desc.film.height = RES;
    desc.sampler.samples_per_pixel = SPP;
    desc.sampler.seed = 7;
    let scene = Scene::build(&desc).expect("scene builds");
    let out = render(&scene, &RenderOptions::default(), &|_, _| {}).expect("render");
    assert_eq!(out.stats.nonfinite_samples, 0);

    let reference = read_exr(&repo_file("scenes/cornell-box/reference-mitsuba-256.exr")).expect("reference loads");
    assert_eq!((reference.width, reference.height), (2 * RES, 2 * RES));
    let reference_at = |x: u32, y: u32| {
        let px = |dx, dy| reference.pixels[((2 * y + dy) * reference.width + 2 * x + dx) as usize];
        (px(0, 0) + px(1, 0) + px(0, 1) + px(1, 1)) * 0.25
    };

    let n = f64::from(RES * RES);
    let mut ours_sum = [0.0f64; 3];
    let mut ref_sum = [0.0f64; 3];
    let mut z2_sum = [0.0f64; 3];
    let mut tail = 0usize;
    let mut worst = (0.0f64, 0, 0, 0);
    for y in 0..RES {
        for x in 0..RES {
            let p = out.film.pixel(x, y);
            let (ours, var): (Rgb, Rgb) = (p.mean(), p.variance_of_mean());
            let r = reference_at(x, y);
            for c in 0..3 {
                ours_sum[c] += f64::from(ours[c]);
                ref_sum[c] += f64::from(r[c]);
                let var = f64::from(var[c]) * (1.0 + f64::from(SPP) / REFERENCE_SPP);
                if var == 0.0 {
                    continue;
                }
                let z = (f64::from(ours[c]) - f64::from(r[c])) / var.sqrt();
                z2_sum[c] += z * z;
                if z.abs() > 5.0 {
                    tail += 1;
                }
                if z.abs() > worst.0 {
                    worst = (z.abs(), x, y, c);
                }
            }
        }
    }
    for c in 0..3 {
        let (m_ours, m_ref) = (ours_sum[c] / n, ref_sum[c] / n);
        let rel = (m_ours - m_ref).abs() / m_ref;
        let msz = z2_sum[c] / n;
        eprintln!("channel {c}: mean ours {m_ours:.5} reference {m_ref:.5} (rel. diff {rel:.4}); mean z^2 {msz:.3}");
        assert!(
            rel < 0.01,
            "channel {c}: image mean {m_ours:.5} vs reference {m_ref:.5}, {:.2}% apart",
            rel * 100.0
        );
        assert!(
            msz < 1.5,
            "channel {c}: mean squared z-score {msz:.3}: differences exceed the noise"
        );
    }
    let tail_fraction = tail as f64 / (3.0 * n);
    eprintln!(
        "|z| > 5 in {tail} of {} pixel channels; worst |z| {:.2} at ({}, {}) channel {}",
        3.0 * n,
        worst.0,
        worst.1,
        worst.2,
        worst.3
    );
    assert!(
        tail_fraction < 0.002,
        "{tail} pixel channels differ by more than 5 standard errors"
    );
}
