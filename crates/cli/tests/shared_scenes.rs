//! The shared scenes (`$MCRENDER_SCENES/{cornell-box,veach-mis,coffee}`) against their
//! Tungsten references, compared with [`ImageComparison`] after box-downsampling the
//! reference to our reduced resolution. They fail when the scenes cannot be found, unless
//! `MCRENDER_SKIP_SHARED_SCENES` is set.
//!
//! References were rendered with up to 64 bounces, hence max depth 65 here.

mod common;

use mcrender_core::material::CoatedDiffuseMaterial;
use std::path::PathBuf;

use mcrender_core::color::Rgb;
use mcrender_core::film::{block_means_of, downsample_box, ImageComparison, BLOCK_REL_EPSILON};
use mcrender_core::render::{render, RenderOptions, RenderOutput};
use mcrender_core::scene::{MaterialDesc, Scene, SceneDescription};
use mcrender_formats::image_io::{read_exr, ImageRgb};
use mcrender_formats::pbrt::load_file;

use common::shared_scenes::shared_scenes_dir;

const BLOCK: u32 = 8;

fn render_scene(path: &std::path::Path, w: u32, h: u32, spp: u32) -> RenderOutput {
    render_scene_at_depth(path, w, h, spp, Some(65))
}

/// Render at `w x h`, seed 7, with max depth `depth` (`None`: the file's).
fn render_scene_at_depth(path: &std::path::Path, w: u32, h: u32, spp: u32, depth: Option<u32>) -> RenderOutput {
    render_description(load_file(path).expect("scene loads").description, w, h, spp, depth)
}

/// Render a loaded description at `w x h`, seed 7, with max depth `depth` (`None`: the
/// file's); asserts that no sample was non-finite.
fn render_description(mut desc: SceneDescription, w: u32, h: u32, spp: u32, depth: Option<u32>) -> RenderOutput {
    desc.film.width = w;
    desc.film.height = h;
    desc.sampler.samples_per_pixel = spp;
    desc.sampler.seed = 7;
    if let Some(d) = depth {
        desc.integrator.max_depth = d;
    }
    let scene = Scene::build(&desc).expect("scene builds");
    let out = render(&scene, &RenderOptions::default(), &|_, _| {}).expect("render");
    assert_eq!(out.stats.nonfinite_samples, 0);
    assert!(out.film.mean_image().iter().all(|p| p.is_finite()));
    out
}

/// The reference box-downsampled to `w x h`.
fn reference(path: &std::path::Path, w: u32, h: u32) -> ImageRgb {
    let r = read_exr(path).expect("reference loads");
    assert_eq!(r.width % w, 0);
    let f = r.width / w;
    let (rw, rh, px) = downsample_box(&r.pixels, r.width, r.height, f).expect("downsample");
    assert_eq!((rw, rh), (w, h));
    ImageRgb {
        width: rw,
        height: rh,
        pixels: px,
    }
}

/// The block relative error expected from our render's noise alone, per channel: for each
/// block, the standard error of our block mean is sqrt(sum of the pixels' variance of the
/// mean) / 64, from the render's own per-pixel sample variance (the reference's noise is
/// ignored). An unbiased render's |block difference| then averages sqrt(2/pi) sigma, so the
/// expected block relative error is the mean over blocks of sqrt(2/pi) sigma / (|b| + eps).
fn expected_block_error(out: &RenderOutput, reference: &[Rgb], w: u32, h: u32) -> [f64; 3] {
    let (_, _, ref_blocks) = block_means_of(reference, w, h, BLOCK).unwrap();
    let mut expected = [0.0f64; 3];
    for (k, rb) in ref_blocks.iter().enumerate() {
        let (bx, by) = (k as u32 % w.div_ceil(BLOCK), k as u32 / w.div_ceil(BLOCK));
        let mut var = [0.0f64; 3];
        let mut n = 0u32;
        for y in by * BLOCK..((by + 1) * BLOCK).min(h) {
            for x in bx * BLOCK..((bx + 1) * BLOCK).min(w) {
                n += 1;
                let v = out.film.pixel(x, y).variance_of_mean();
                for (c, s) in var.iter_mut().enumerate() {
                    *s += f64::from(v[c]);
                }
            }
        }
        let n2 = f64::from(n).powi(2);
        for c in 0..3 {
            let sigma = (var[c] / n2).sqrt();
            expected[c] += (2.0 / std::f64::consts::PI).sqrt() * sigma / (rb[c].abs() + BLOCK_REL_EPSILON);
        }
    }
    expected.map(|e| e / ref_blocks.len() as f64)
}

fn print(name: &str, c: &ImageComparison) {
    eprintln!(
        "{name}: mean ours {:.5?} ref {:.5?} rel diff {:.5?}; block rel err mean {:.5?} max {:.3?}; rel MSE {:.4e}",
        c.mean_a,
        c.mean_b,
        c.mean_rel_diff(),
        c.block_rel_mean,
        c.block_rel_max,
        c.rel_mse
    );
}

/// Cornell box, 256x256, 256 spp, against Tungsten's 1024x1024 downsampled 4x.
///
/// Bound on the block error: the error expected from our noise ([`expected_block_error`])
/// plus a margin for the reference's own noise and filter differences.
///
/// Measured (seed 7): block rel err [0.0102, 0.0099, 0.0077] (R, G, B) against
/// [0.0072, 0.0063, 0.0038] expected from our noise alone: an excess of 0.003-0.004, which
/// is the reference's own noise and the different pixel filters at edges (Tungsten's filter
/// at 1024 then a 4x box, ours at 256), largest on blue where the values are smallest. We
/// assert measured < expected + 0.008 (the excess with a 2x margin): a 2% bias spread
/// over the image would add ~0.02 and fail. Per-channel means agree to 0.05% (bound 2%).
/// The block maximum (~0.9) is not bounded: it sits on the rim of the ceiling light, where
/// the pixel filters differ across an edge of enormous contrast (see `mcrender diff
/// --error-image`).
#[test]
fn cornell_box_matches_tungsten() {
    let Some(dir) = shared_scenes_dir("cornell_box_matches_tungsten") else {
        return;
    };
    let (w, h) = (256, 256);
    let out = render_scene(&dir.join("cornell-box/scene-v4.pbrt"), w, h, 256);
    let ours = out.film.mean_image();
    let r = reference(&dir.join("cornell-box/TungstenRender.exr"), w, h);
    let c = ImageComparison::new(&ours, &r.pixels, w, h, BLOCK).unwrap();
    print("cornell-box", &c);

    let expected = expected_block_error(&out, &r.pixels, w, h);
    eprintln!("cornell-box: block rel err expected from noise {expected:.5?}");

    for ch in 0..3 {
        assert!(
            c.mean_rel_diff()[ch].abs() < 0.02,
            "channel {ch} mean: {:?}",
            c.mean_rel_diff()
        );
        assert!(
            c.block_rel_mean[ch] < expected[ch] + 0.008,
            "channel {ch}: block rel err {:?} vs expected from noise {expected:?}",
            c.block_rel_mean
        );
    }
}

/// Veach MIS, 320x180, 256 spp, the file's max depth (3), against Mitsuba 3's render of the same
/// description (`scenes/references/veach-mis-mitsuba-320x180.exr`, 2048 spp, GGX; how it was
/// made is in the `.json` beside it). This is the full-image check of the glossy plates; the
/// Tungsten reference cannot serve (see the next test).
///
/// Measured (seed 7, 256 spp, the file's Sobol' sampler): means +0.11%/+0.03%/-0.00%; block
/// rel err [0.0145, 0.0115, 0.0106] against [0.0159, 0.0137, 0.0131] expected from our noise
/// (overstated: a Sobol' render's sample spread overstates its error). At 1024 spp with the
/// independent sampler, 15-row bands agree within 1% except the floor below the plates
/// (+2%), where glossy-to-diffuse paths from the smallest light are noisy in both renders.
/// Bounds: means within 1.5%, block error below the expected + 0.02 (a 3% bias fails).
#[test]
fn veach_mis_matches_mitsuba() {
    let Some(dir) = shared_scenes_dir("veach_mis_matches_mitsuba") else {
        return;
    };
    let (w, h) = (320, 180);
    let out = render_scene_at_depth(&dir.join("veach-mis/scene-v4.pbrt"), w, h, 256, None);
    let ours = out.film.mean_image();
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenes/references/veach-mis-mitsuba-320x180.exr");
    let r = reference(&path, w, h);
    let c = ImageComparison::new(&ours, &r.pixels, w, h, BLOCK).unwrap();
    print("veach-mis vs Mitsuba", &c);
    let expected = expected_block_error(&out, &r.pixels, w, h);
    eprintln!("veach-mis vs Mitsuba: block rel err expected from noise {expected:.5?}");
    for ch in 0..3 {
        assert!(
            c.mean_rel_diff()[ch].abs() < 0.015,
            "channel {ch}: {:?}",
            c.mean_rel_diff()
        );
        assert!(
            c.block_rel_mean[ch] < expected[ch] + 0.02,
            "channel {ch}: block rel err {:?} vs expected from noise {expected:?}",
            c.block_rel_mean
        );
    }
}

/// Veach MIS against Tungsten's reference: a documented model difference.
///
/// The reference does not show the file as written. Reproducing it with Mitsuba 3 from our
/// loaded description, every band of 30 rows agrees within 1% with Tungsten's image when
/// Mitsuba is given (1) direct lighting only (max depth 1), (2) a Beckmann instead of a GGX
/// distribution with the same alphas, and (3) the conductors' reflectance multiplied by
/// 0.3026 (`bench/mitsuba_scene.py --max-depth 2 --distribution beckmann --conductor-scale
/// 0.3026`; image means 0.674/0.611/0.593 against Tungsten's 0.673/0.611/0.592). With the
/// file's settings, Mitsuba and we agree (previous test) and are +62%/+46%/+40% brighter
/// than Tungsten, all of it on the plates.
///
/// What this test pins, rendering ourselves at max depth 1 (difference 1 removed):
/// - the back wall and the lights (pixel rows 0..56, above the plates) match Tungsten within
///   1% per channel: emission, sphere lights and diffuse transport agree;
/// - on the near-mirror plate (alpha 0.01), the reflection of the middle light is Tungsten's
///   times 1/0.3026 in all three channels alike (measured 0.3031 at 256 spp; wall and
///   lights -0.10%): the same Fresnel
///   colour, a grey factor of 0.30 (difference 3). Difference 2 (lobe tails: Beckmann's fall
///   off as exp(-tan^2/alpha^2), GGX's as a power) shows between the highlights of the glossy
///   plates, where Tungsten is black and GGX is not; it is not asserted here.
#[test]
fn veach_mis_tungsten_reference_differs_by_a_documented_factor() {
    let Some(dir) = shared_scenes_dir("veach_mis_tungsten_reference_differs_by_a_documented_factor") else {
        return;
    };
    let (w, h) = (320, 180);
    let out = render_scene_at_depth(&dir.join("veach-mis/scene-v4.pbrt"), w, h, 256, Some(1));
    let ours = out.film.mean_image();
    let r = reference(&dir.join("veach-mis/TungstenRender.exr"), w, h);
    let c = ImageComparison::new(&ours, &r.pixels, w, h, BLOCK).unwrap();
    print("veach-mis vs Tungsten (max depth 1)", &c);

    let region_mean = |img: &[Rgb], x0: u32, x1: u32, y0: u32, y1: u32| -> [f64; 3] {
        let mut s = [0.0f64; 3];
        for y in y0..y1 {
            for x in x0..x1 {
                let p = img[(y * w + x) as usize];
                for (ch, v) in s.iter_mut().enumerate() {
                    *v += f64::from(p[ch]);
                }
            }
        }
        s.map(|v| v / f64::from((x1 - x0) * (y1 - y0)))
    };
    let (wall_ours, wall_ref) = (region_mean(&ours, 0, w, 0, 56), region_mean(&r.pixels, 0, w, 0, 56));
    let wall: [f64; 3] = std::array::from_fn(|ch| wall_ours[ch] / wall_ref[ch] - 1.0);
    // The mirror image of the middle light on the top plate: pixels 154..164 x 75..82.
    let (m_ours, m_ref) = (
        region_mean(&ours, 154, 164, 75, 82),
        region_mean(&r.pixels, 154, 164, 75, 82),
    );
    let ratio: [f64; 3] = std::array::from_fn(|ch| m_ref[ch] / m_ours[ch]);
    eprintln!("veach-mis vs Tungsten: wall and lights rel diff {wall:.5?}; mirror-image ratio ref/ours {ratio:.4?}");
    for ch in 0..3 {
        assert!(wall[ch].abs() < 0.01, "wall and lights, channel {ch}: {wall:?}");
        assert!(
            (ratio[ch] - 0.3026).abs() < 0.01,
            "mirror image ratio, channel {ch}: {ratio:?}"
        );
    }
}

/// Coffee maker (`coateddiffuse` plastics and floor, a silver conductor, glass) against
/// Tungsten: a documented model difference in the plastics, then a match once it is removed.
///
/// The file's plastics are pbrt-v4 `coateddiffuse` with the defaults: an absorbing slab of
/// thickness 0.01 under the coat and random walks cut at 10 scattering events. Tungsten's
/// plastic (the reference) is a coat over a Lambertian base with the internal reflections
/// summed in closed form, without absorption. Both defaults darken: the orange plastic's
/// base reflects 1.0 in red, so its light bounces many times under the coat, and the cut
/// walks and the slab's absorption lose the most there.
///
/// Measured at 100x125, 256 spp (seed 7), against Tungsten's 800x1000 downsampled 8x:
/// - as written: means -9.0%/-2.1%/-2.7% (R/G/B), block rel err 0.078/0.049/0.047;
/// - with the coat made like Tungsten's (thickness 1e-5, walks up to 100 events): means
///   +1.5%/+1.6%/+0.9%, block rel err 0.029/0.026/0.026 (the rest is noise: the
///   near-specular floor and plastics, roughness 0.001, make fireflies in both renders).
///
/// Asserted: as written, red is 5-14% darker and green and blue within 5% (the size of the
/// difference); with the Tungsten-like coat, every channel mean within 2% (the issue's
/// bound) and the block error below 0.06, which the render as written fails in red (0.078).
#[test]
fn coffee_matches_tungsten_once_the_coat_is_lossless() {
    let Some(dir) = shared_scenes_dir("coffee_matches_tungsten_once_the_coat_is_lossless") else {
        return;
    };
    let path = dir.join("coffee/scene-v4.pbrt");
    let (w, h, spp) = (100, 125, 256);
    let r = reference(&dir.join("coffee/TungstenRender.exr"), w, h);
    let loaded = load_file(&path).expect("coffee loads");
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);

    let as_written = render_description(loaded.description.clone(), w, h, spp, Some(65));
    let c = ImageComparison::new(&as_written.film.mean_image(), &r.pixels, w, h, BLOCK).unwrap();
    print("coffee as written", &c);
    let d = c.mean_rel_diff();
    assert!((-0.14..-0.05).contains(&d[0]), "red: {d:?}");
    assert!(d[1].abs() < 0.05 && d[2].abs() < 0.05, "green, blue: {d:?}");

    let mut desc = loaded.description;
    let mut coats = 0;
    for m in &mut desc.materials {
        if let MaterialDesc::CoatedDiffuse(CoatedDiffuseMaterial {
            thickness, max_depth, ..
        }) = m
        {
            *thickness = 1e-5.into();
            *max_depth = 100;
            coats += 1;
        }
    }
    assert_eq!(coats, 3, "the file has three coateddiffuse materials");
    let lossless = render_description(desc, w, h, spp, Some(65));
    let c = ImageComparison::new(&lossless.film.mean_image(), &r.pixels, w, h, BLOCK).unwrap();
    print("coffee with a lossless coat", &c);
    for ch in 0..3 {
        assert!(
            c.mean_rel_diff()[ch].abs() < 0.02,
            "channel {ch}: {:?}",
            c.mean_rel_diff()
        );
        assert!(c.block_rel_mean[ch] < 0.06, "channel {ch}: {:?}", c.block_rel_mean);
    }
}
