//! The light tracer's and BDPT's own sample loops, driven without the render session: each
//! camera (or light) sample is independent, so the spread of their totals gives the
//! standard error of the image mean without depending on how the film shows splats.

use mcrender_core::color::Rgb;
use mcrender_core::integrator::{BdptIntegrator, LightPathIntegrator, TraceStats};
use mcrender_core::math::{UVec2, Vec2};
use mcrender_core::sampling::Sampler;
use mcrender_core::scene::{BdptDesc, Scene, SceneDescription};

/// Mean and standard error per channel of `n` independent values with sums `sum` and
/// sums of squares `sum2`.
pub fn mean_and_se(sum: [f64; 3], sum2: [f64; 3], n: f64) -> ([f64; 3], [f64; 3]) {
    let mut mean = [0.0; 3];
    let mut se = [0.0; 3];
    for c in 0..3 {
        mean[c] = sum[c] / n;
        se[c] = ((sum2[c] / n - mean[c] * mean[c]).max(0.0) / (n - 1.0)).sqrt();
    }
    (mean, se)
}

/// Add `v` to the per-channel sums and sums of squares.
fn accumulate(sum: &mut [f64; 3], sum2: &mut [f64; 3], v: Rgb) {
    for c in 0..3 {
        sum[c] += f64::from(v[c]);
        sum2[c] += f64::from(v[c]) * f64::from(v[c]);
    }
}

/// Light tracing: the splat image (sums / spp), and the mean and standard error per
/// channel of the image mean (the mean of each light path's total splat). Every splat must
/// be finite and on the film.
pub fn light_trace(d: &SceneDescription) -> (Vec<Rgb>, [f64; 3], [f64; 3]) {
    let scene = Scene::build(d).expect("valid scene");
    let integrator = LightPathIntegrator {
        max_depth: d.integrator.max_depth,
        russian_roulette: d.integrator.russian_roulette,
    };
    let (w, h) = (scene.film.width, scene.film.height);
    let spp = scene.sampler.samples_per_pixel;
    let mut image = vec![Rgb::BLACK; (w * h) as usize];
    let mut sampler = Sampler::new(&scene.sampler);
    let mut stats = TraceStats::default();
    let (mut sum, mut sum2) = ([0.0f64; 3], [0.0f64; 3]);
    for y in 0..h {
        for x in 0..w {
            for s in 0..spp {
                sampler.start_pixel_sample(UVec2::new(x, y), s);
                let mut path = Rgb::BLACK;
                integrator.trace(&scene, &mut sampler, &mut stats, &mut |p: Vec2, l: Rgb| {
                    assert!(l.is_finite(), "non-finite splat {l:?}");
                    assert!(
                        p.x >= 0.0 && p.y >= 0.0 && p.x < w as f32 && p.y < h as f32,
                        "splat off the film at {p}"
                    );
                    image[(p.y as u32 * w + p.x as u32) as usize] += l / spp as f32;
                    path += l;
                });
                accumulate(&mut sum, &mut sum2, path);
            }
        }
    }
    let (mean, se) = mean_and_se(sum, sum2, f64::from(w * h * spp));
    (image, mean, se)
}

/// BDPT with `bdpt`'s strategies and weights: mean and standard error per channel of the
/// image mean, each camera sample counting its own radiance plus everything it splatted.
pub fn bdpt_mean(d: &SceneDescription, bdpt: BdptDesc) -> ([f64; 3], [f64; 3]) {
    let scene = Scene::build(d).expect("valid scene");
    let integrator = BdptIntegrator::new(&scene, &bdpt, d.integrator.max_depth);
    let mut sampler = Sampler::new(&scene.sampler);
    let mut stats = TraceStats::default();
    let mut splats = Vec::new();
    let (mut sum, mut sum2, mut n) = ([0.0f64; 3], [0.0f64; 3], 0.0f64);
    for y in 0..scene.film.height {
        for x in 0..scene.film.width {
            for s in 0..scene.sampler.samples_per_pixel {
                sampler.start_pixel_sample(UVec2::new(x, y), s);
                let fs = scene.filter.sample(sampler.get_pixel_2d());
                let p_film = Vec2::new(x as f32 + 0.5, y as f32 + 0.5) + fs.p;
                let ray = scene.camera.generate_ray(p_film, sampler.get_2d());
                splats.clear();
                let mut v = integrator.li(&scene, ray, &mut sampler, &mut stats, &mut splats);
                for sp in &splats {
                    assert!(sp.p_film.x >= 0.0 && sp.p_film.y >= 0.0);
                    v += sp.l;
                }
                assert!(v.is_finite(), "non-finite sample");
                accumulate(&mut sum, &mut sum2, v);
                n += 1.0;
            }
        }
    }
    mean_and_se(sum, sum2, n)
}
