//! Metropolis light transport (`integrator::mlt`) against the closed forms of the analytic
//! scenes, its determinism, cancellation, its saved state (checkpoints), and its primary
//! sample space mutation.
//!
//! One MLT render's image mean is an estimate whose error comes from the bootstrap's
//! normalisation and the chains' correlated samples; renders with different seeds are
//! independent, so the spread of their image means gives the standard error of their
//! average.

#![allow(clippy::needless_range_loop)]

mod common;

use mcrender_core::material::DiffuseMaterial;
use std::sync::atomic::AtomicBool;

use common::*;
use mcrender_core::color::Rgb;
use mcrender_core::integrator::mlt::{self, render_with_threads, MltOutput, MltSettings, MltState};
use mcrender_core::math::{Mat4, Transform, Vec3, PI};
use mcrender_core::sampling::{chi2, MltSampler, SampleSource};
use mcrender_core::scene::{GeometryDesc, MaterialDesc, Scene, SceneDescription, ShapeDesc, TriangleMeshDesc};

/// Small settings: few bootstrap samples and mutations, so that a render takes milliseconds.
fn settings(scene: &Scene, seed: u64) -> MltSettings {
    MltSettings {
        bootstrap_samples: 2000,
        chains: 16,
        mutations_per_pixel: 64,
        seed,
        ..MltSettings::from_scene(scene)
    }
}

fn mlt(scene: &Scene, s: &MltSettings, threads: usize) -> MltOutput {
    let cancel = AtomicBool::new(false);
    render_with_threads(scene, s, Some(threads), &|_, _| {}, &cancel)
        .expect("thread pool")
        .0
}

/// Image mean per channel of one render.
fn image_mean(out: &MltOutput) -> [f64; 3] {
    let img = out.film.mean_image();
    let mut m = [0.0; 3];
    for p in &img {
        for c in 0..3 {
            m[c] += f64::from(p[c]);
        }
    }
    m.map(|v| v / img.len() as f64)
}

/// Average over `seeds` renders of the image mean, and its standard error.
fn mean_over_seeds(d: &SceneDescription, seeds: u64) -> ([f64; 3], [f64; 3]) {
    let scene = Scene::build(d).expect("valid scene");
    let means: Vec<[f64; 3]> = (0..seeds)
        .map(|seed| image_mean(&mlt(&scene, &settings(&scene, seed), 2)))
        .collect();
    let n = seeds as f64;
    let mut mean = [0.0; 3];
    let mut se = [0.0; 3];
    for c in 0..3 {
        mean[c] = means.iter().map(|m| m[c]).sum::<f64>() / n;
        let var = means.iter().map(|m| (m[c] - mean[c]).powi(2)).sum::<f64>() / (n - 1.0);
        se[c] = (var / n).sqrt();
    }
    (mean, se)
}

const SEEDS: u64 = 12;

fn closed_sphere(albedo: f32, le: f32) -> SceneDescription {
    emissive_sphere(2.0, Rgb::splat(albedo), Rgb::splat(le))
}

/// A sphere of albedo 1/2 lit by a point light of intensity pi at its centre: up to depth
/// D the radiance is 1 - 2^-D.
#[test]
fn sphere_lit_from_its_centre() {
    let mut d = point_lit_sphere(PI);
    d.integrator.max_depth = 6;
    let expected = 1.0 - 0.5f32.powi(6);
    assert_close(
        "sphere lit from its centre",
        mean_over_seeds(&d, SEEDS),
        Rgb::splat(expected),
    );
}

/// A closed sphere emitting Le with albedo a: up to depth D the radiance is
/// Le (1 - a^(D+1)) / (1 - a).
#[test]
fn closed_emissive_sphere() {
    let mut d = closed_sphere(0.5, 1.0);
    d.integrator.max_depth = 6;
    let expected = (1.0 - 0.5f32.powi(7)) / (1.0 - 0.5);
    assert_close(
        "closed emissive sphere",
        mean_over_seeds(&d, SEEDS),
        Rgb::splat(expected),
    );
}

/// The same sphere with pbrt's default Gaussian filter (radius 1.5) on the 4x4 film, where
/// 12 of the 16 pixels are at the border: every pixel's filtered integral is the constant
/// radiance, so the image mean must be too. This needs camera subpaths started over the
/// film's sample bounds with their contribution scaled to the pixel bounds' density (off
/// by the area ratio 36/16 for the camera-side strategies otherwise) and the importance
/// of the light-tracing strategies reaching the margin (the border pixels darken
/// otherwise).
#[test]
fn closed_emissive_sphere_with_a_wide_filter() {
    let mut d = closed_sphere(0.5, 1.0);
    d.filter = mcrender_core::scene::FilterDesc::default();
    d.integrator.max_depth = 3;
    let expected = (1.0 - 0.5f32.powi(4)) / (1.0 - 0.5);
    assert_close(
        "closed emissive sphere, Gaussian filter",
        mean_over_seeds(&d, SEEDS),
        Rgb::splat(expected),
    );
}

#[test]
fn uniform_sky() {
    let (d, expected) = receiver_under_sky(1.5, 0.8);
    assert_close("uniform sky", mean_over_seeds(&d, SEEDS), expected);
}

#[test]
fn sphere_and_square_lights() {
    let (d, expected) = receiver_under_sphere_light(0.5, 1.2, 2.0, 0.9);
    assert_close("sphere light", mean_over_seeds(&d, SEEDS), expected);

    let (d, expected) = receiver_under_square_light(0.8, 1.0, 3.0, 0.7);
    assert_close("square light", mean_over_seeds(&d, SEEDS), expected);
}

/// Two receivers side by side, `x < 0` of albedo 0.9 and `x > 0` of albedo 0.3, under a
/// square light, seen from straight above so that each fills half of the image.
fn two_receivers() -> SceneDescription {
    let mut d = empty_scene();
    let (s, h, l) = (0.8f32, 1.0f32, 3.0f32);
    for (albedo, x0) in [(0.9f32, -0.1f32), (0.3, 0.0)] {
        d.materials.push(MaterialDesc::Diffuse(DiffuseMaterial {
            reflectance: Rgb::splat(albedo).into(),
        }));
        d.shapes.push(ShapeDesc {
            geometry: GeometryDesc::TriangleMesh(TriangleMeshDesc {
                positions: vec![
                    Vec3::new(x0, 0.0, -0.1),
                    Vec3::new(x0 + 0.1, 0.0, -0.1),
                    Vec3::new(x0 + 0.1, 0.0, 0.1),
                    Vec3::new(x0, 0.0, 0.1),
                ],
                indices: vec![0, 2, 1, 0, 3, 2],
                normals: None,
                uvs: None,
                tangents: None,
            }),
            material: (d.materials.len() - 1) as u32,
            area_light: None,
            flip_normals: false,
            alpha: None,
        });
    }
    add_square_light(&mut d, s, h, Rgb::splat(l));
    let camera_from_world = Mat4::look_at_lh(Vec3::new(0.0, 0.3, 0.0), Vec3::ZERO, Vec3::Z);
    d.camera.world_from_camera = Transform::new(camera_from_world).unwrap().inverse();
    d.camera.fov_degrees = 30.0;
    d.film = mcrender_core::scene::FilmDesc { width: 8, height: 8 };
    d.integrator.max_depth = 2;
    d
}

/// The image mean of a grey scene is `b` whatever the chains do (every splat carries
/// luminance weight one), so the tests above check the bootstrap; this one checks where the
/// chains put their splats: each half of [`two_receivers`]'s image (their radiances differ
/// threefold), averaged over seeds, must match the path tracer's within 4 standard errors
/// (both measured).
#[test]
fn chains_distribute_the_image_like_the_path_tracer() {
    let mut d = two_receivers();
    let scene = Scene::build(&d).expect("valid scene");
    // Left and right halves of the image.
    let halves = |img: &[Rgb]| -> [f64; 2] {
        let mut m = [0.0; 2];
        for (i, p) in img.iter().enumerate() {
            m[usize::from(i % 8 >= 4)] += f64::from(p.luminance()) / 32.0;
        }
        m
    };
    let runs: Vec<[f64; 2]> = (0..SEEDS)
        .map(|seed| halves(&mlt(&scene, &settings(&scene, 100 + seed), 2).film.mean_image()))
        .collect();
    d.sampler.samples_per_pixel = 1024;
    let reference = render_desc(&d);
    let ref_halves = halves(&reference.film.mean_image());
    let mut ref_var = [0.0; 2];
    for (i, p) in reference.film.pixels().iter().enumerate() {
        ref_var[usize::from(i % 8 >= 4)] += f64::from(p.variance_of_mean().luminance()) / (32.0 * 32.0);
    }
    let ratio = ref_halves[0].max(ref_halves[1]) / ref_halves[0].min(ref_halves[1]);
    assert!(ratio > 2.5, "the halves should differ threefold: {ref_halves:?}");
    let n = SEEDS as f64;
    for k in 0..2 {
        let mean = runs.iter().map(|r| r[k]).sum::<f64>() / n;
        let var = runs.iter().map(|r| (r[k] - mean).powi(2)).sum::<f64>() / (n - 1.0) / n;
        let se = (var + ref_var[k]).sqrt();
        eprintln!("half {k}: mlt {mean:.5}, path {:.5}, se {se:.2e}", ref_halves[k]);
        assert!(
            (mean - ref_halves[k]).abs() <= 4.0 * se,
            "half {k}: mlt {mean:.5} vs path tracer {:.5} (standard error {se:.2e})",
            ref_halves[k]
        );
    }
}

#[test]
fn one_and_two_threads_give_identical_bytes() {
    let (mut d, _) = receiver_under_square_light(0.8, 1.0, 3.0, 0.7);
    d.camera.fov_degrees = 30.0;
    d.film = mcrender_core::scene::FilmDesc { width: 24, height: 20 };
    d.integrator.max_depth = 3;
    let scene = Scene::build(&d).unwrap();
    let st = settings(&scene, 9);
    let bits = |out: &MltOutput| {
        out.film
            .mean_image()
            .iter()
            .flat_map(|p| p.to_array().map(f32::to_bits))
            .collect::<Vec<_>>()
    };
    let (a, b) = (mlt(&scene, &st, 1), mlt(&scene, &st, 2));
    assert!(a.film.mean_image().iter().any(|p| !p.is_black()));
    assert!(
        a.accepted > 0 && a.accepted < a.mutations,
        "accepted {} of {}",
        a.accepted,
        a.mutations
    );
    assert_eq!(bits(&a), bits(&b));
    assert_eq!(a.film.samples_per_pixel(), u64::from(st.mutations_per_pixel));
}

/// The scene of [`one_and_two_threads_give_identical_bytes`]: a receiver under a square
/// light, at 24x20 pixels and depth 3.
fn lit_receiver() -> Scene {
    let mut d = empty_scene();
    add_receiver(&mut d, 0.7);
    add_square_light(&mut d, 0.8, 1.0, Rgb::splat(3.0));
    aim_at_receiver(&mut d);
    d.camera.fov_degrees = 30.0;
    d.film = mcrender_core::scene::FilmDesc { width: 24, height: 20 };
    d.integrator.max_depth = 3;
    Scene::build(&d).unwrap()
}

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap()
}

/// A checkpoint's round trip: the state as bytes and back.
fn saved(state: &MltState, st: &MltSettings) -> MltState {
    let bytes = state.to_bytes();
    let back = MltState::from_bytes(&bytes, 24, 20, st).unwrap();
    assert_eq!(back.to_bytes(), bytes, "the state round-trips exactly");
    back
}

/// A render cut into steps of odd sizes, saved and read back between them, stopped by its
/// cancel flag in the middle of a step, and continued on alternating thread counts, ends
/// with the film of a render never stopped, bit for bit (splat sums and sample count).
#[test]
fn a_render_stopped_saved_and_continued_is_bit_identical() {
    let scene = lit_receiver();
    let st = MltSettings {
        chains: 13, // more chains than run at once, and shares of unequal sizes
        mutations_per_pixel: 1000,
        ..settings(&scene, 4)
    };
    let whole = mlt(&scene, &st, 2);
    let never = AtomicBool::new(false);
    let mut state = saved(&MltState::new(24, 20), &st);
    // A bootstrap cancelled before it starts leaves the state as it was.
    let stop = AtomicBool::new(true);
    mlt::bootstrap(&scene, &st, &mut state, &stop);
    assert!(!state.is_bootstrapped());
    pool(1).install(|| mlt::bootstrap(&scene, &st, &mut state, &never));
    assert_eq!(state.b(), whole.b);
    let mut state = saved(&state, &st);
    // Stopped by the flag from another thread while a chain runs (at a point that varies
    // from run to run).
    let stop = AtomicBool::new(false);
    std::thread::scope(|sc| {
        sc.spawn(|| {
            std::thread::sleep(std::time::Duration::from_millis(20));
            stop.store(true, std::sync::atomic::Ordering::Relaxed);
        });
        pool(2).install(|| mlt::advance(&scene, &st, &mut state, u64::MAX, &|_, _| {}, &stop));
    });
    assert!(
        !state.is_finished(),
        "stopped before the end ({} mutations)",
        state.mutations()
    );
    let mut state = saved(&state, &st);
    for (i, budget) in [1u64, 37, 500, 4097, 3].into_iter().cycle().enumerate() {
        if state.is_finished() {
            break;
        }
        pool(1 + i % 2).install(|| mlt::advance(&scene, &st, &mut state, budget, &|_, _| {}, &never));
        state = saved(&state, &st);
    }
    assert_eq!(state.mutations(), whole.mutations);
    assert_eq!(state.accepted(), whole.accepted);
    assert_eq!(state.film(&st), whole.film);
}

/// A saved state is refused when cut short, extended, or read for another film size or
/// another number of chains.
#[test]
fn a_saved_state_of_another_render_is_refused() {
    let scene = lit_receiver();
    let st = settings(&scene, 2);
    let mut state = MltState::new(24, 20);
    mlt::bootstrap(&scene, &st, &mut state, &AtomicBool::new(false));
    mlt::advance(&scene, &st, &mut state, 3000, &|_, _| {}, &AtomicBool::new(false));
    let bytes = state.to_bytes();
    assert!(MltState::from_bytes(&bytes, 24, 20, &st).is_ok());
    for cut in [0, 8, 40, bytes.len() / 2, bytes.len() - 1] {
        assert!(
            MltState::from_bytes(&bytes[..cut], 24, 20, &st).is_err(),
            "cut at {cut}"
        );
    }
    let mut longer = bytes.clone();
    longer.push(0);
    assert!(MltState::from_bytes(&longer, 24, 20, &st).is_err());
    let err = MltState::from_bytes(&bytes, 20, 24, &st).unwrap_err();
    assert!(err.contains("24x20"), "{err}");
    let other = MltSettings { chains: 15, ..st };
    assert!(MltState::from_bytes(&bytes, 24, 20, &other)
        .unwrap_err()
        .contains("chains"));
}

#[test]
fn cancellation_returns_promptly() {
    let mut d = closed_sphere(0.5, 1.0);
    d.film = mcrender_core::scene::FilmDesc { width: 64, height: 64 };
    let scene = Scene::build(&d).unwrap();
    let st = MltSettings {
        mutations_per_pixel: 100_000,
        ..settings(&scene, 0)
    };
    let cancel = AtomicBool::new(false);
    let start = std::time::Instant::now();
    let out = std::thread::scope(|sc| {
        let h = sc.spawn(|| {
            render_with_threads(&scene, &st, Some(2), &|_, _| {}, &cancel)
                .unwrap()
                .0
        });
        std::thread::sleep(std::time::Duration::from_millis(300));
        cancel.store(true, std::sync::atomic::Ordering::Relaxed);
        h.join().unwrap()
    });
    let elapsed = start.elapsed();
    assert!(out.cancelled);
    assert!(out.mutations < 64 * 64 * 100_000);
    assert!(elapsed.as_secs_f64() < 5.0, "took {elapsed:?} to stop");
}

/// The small step of the primary sample space mutation: from a value x, a normal step of
/// deviation sigma wrapped into [0, 1). The density of the new value at y is the wrapped
/// normal, sum_k N(y - x + k; sigma); a chi-square test compares the histogram of many
/// steps with it. A large sigma (0.3) makes the wrapping matter.
#[test]
fn small_step_follows_the_wrapped_normal() {
    let (x0, sigma) = (0.9f64, 0.3f64);
    let bins = 40;
    let n = 200_000u64;
    let mut counts = vec![0u64; bins];
    for i in 0..n {
        // A fresh chain whose first value is x: one step from iteration 0 to 1.
        let mut s = MltSampler::new(i, 17, sigma as f32, 0.0, 1);
        s.start_stream(0);
        let x = f64::from(s.get_1d());
        s.start_iteration();
        assert!(!s.is_large_step());
        s.start_stream(0);
        let y = f64::from(s.get_1d());
        assert!((0.0..1.0).contains(&y));
        // Shift so that every step starts from x0 (the step is translation invariant).
        let shifted = (y - x + x0).rem_euclid(1.0);
        counts[((shifted * bins as f64) as usize).min(bins - 1)] += 1;
    }
    let cdf = |z: f64| 0.5 * (1.0 + erf(z / (sigma * std::f64::consts::SQRT_2)));
    let expected: Vec<f64> = (0..bins)
        .map(|b| {
            let (lo, hi) = (b as f64 / bins as f64, (b + 1) as f64 / bins as f64);
            (-6..=6)
                .map(|k| cdf(hi - x0 + f64::from(k)) - cdf(lo - x0 + f64::from(k)))
                .sum::<f64>()
                * n as f64
        })
        .collect();
    let (stat, dof) = chi2_stat(&counts, &expected);
    let p = chi2::chi_square_p_value(stat, dof as u32);
    eprintln!("chi2 {stat:.1} with {dof} dof, p = {p:.3}");
    assert!(
        p > 1e-4,
        "small step histogram does not match the wrapped normal: p = {p:.2e}"
    );
}

fn chi2_stat(counts: &[u64], expected: &[f64]) -> (f64, usize) {
    let stat = counts
        .iter()
        .zip(expected)
        .map(|(&o, &e)| (o as f64 - e).powi(2) / e)
        .sum();
    (stat, counts.len() - 1)
}

/// The error function (Abramowitz and Stegun 7.1.26 is too coarse; this is the series /
/// continued fraction pair of Numerical Recipes' erfc, accurate to ~1e-7).
fn erf(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let r = t
        * (-z * z - 1.265_512_23
            + t * (1.000_023_68
                + t * (0.374_091_96
                    + t * (0.096_784_18
                        + t * (-0.186_288_06
                            + t * (0.278_868_07
                                + t * (-1.135_203_98
                                    + t * (1.488_515_87 + t * (-0.822_152_23 + t * 0.170_872_77)))))))))
            .exp();
    if x >= 0.0 {
        1.0 - r
    } else {
        r - 1.0
    }
}

/// A dimension left untouched for `k` accepted small-step iterations receives the `k`
/// steps at once: its change (taken on the circle) has mean 0 and standard deviation
/// `sigma sqrt(k)`; both moments within 4 standard errors.
#[test]
fn a_dimension_skipped_for_k_iterations_moves_sigma_sqrt_k() {
    let (sigma, k, n) = (0.01f64, 9u32, 20_000u64);
    let mut d = Vec::with_capacity(n as usize);
    for i in 0..n {
        let mut s = MltSampler::new(i, 23, sigma as f32, 0.0, 2);
        s.start_stream(0);
        let x = f64::from(s.get_1d());
        for _ in 0..k - 1 {
            s.start_iteration();
            s.start_stream(1);
            s.get_1d();
            s.accept();
        }
        s.start_iteration();
        s.start_stream(0);
        let y = f64::from(s.get_1d());
        let mut delta = y - x;
        delta -= delta.round();
        d.push(delta);
    }
    let nf = n as f64;
    let mean = d.iter().sum::<f64>() / nf;
    let var = d.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (nf - 1.0);
    let expected_var = sigma * sigma * f64::from(k);
    // For a normal variable the sample variance has standard error var sqrt(2 / (n - 1)).
    let se_var = expected_var * (2.0 / (nf - 1.0)).sqrt();
    eprintln!("mean {mean:.2e}, variance {var:.4e} vs {expected_var:.4e} (se {se_var:.1e})");
    assert!(mean.abs() <= 4.0 * (expected_var / nf).sqrt(), "mean {mean}");
    assert!(
        (var - expected_var).abs() <= 4.0 * se_var,
        "variance {var} vs {expected_var}"
    );
}
