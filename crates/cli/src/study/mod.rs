//! The estimator lab's studies: `compare` (variance, cost and efficiency of the
//! direct-lighting techniques, with a contact sheet and convergence plot), `bounces`
//! (one image per maximum depth) and `rr-study` (Russian roulette settings side by side).

pub mod bounces;
pub mod compare;
pub mod rr_study;

use std::path::Path;
use std::time::Duration;

use anyhow::{Context, Result};
use mcrender_core::color::Rgb;
use mcrender_core::film::Film;
use mcrender_core::render::{RenderOptions, RenderSession};
use mcrender_core::scene::{Scene, SceneDescription};
use mcrender_scene::image_io::{read_exr, write_image, ImageRgb};

/// A film grown in waves of doubling sample counts, with the time spent and a measurement
/// after every wave.
pub struct Progression {
    /// The accumulated film.
    pub film: Film,
    /// Render time summed over waves (scene building excluded).
    pub time: Duration,
    /// Rays traced (closest-hit and shadow).
    pub rays: u64,
    /// `(samples per pixel so far, measurement)` after each wave.
    pub points: Vec<(u32, f64)>,
}

/// Render `desc` up to its sample count in waves 1, 2, 4, ... (the last wave tops up to
/// the sample count) of one render session, calling `measure` on the film after each. The
/// final film is bit-identical to a render in one pass.
pub fn render_in_waves(
    desc: &SceneDescription,
    threads: Option<usize>,
    measure: impl Fn(&Film) -> f64,
) -> Result<Progression> {
    let scene = Scene::build(desc).context("the scene cannot be rendered")?;
    let spp = desc.sampler.samples_per_pixel;
    let opts = RenderOptions {
        threads,
        ..Default::default()
    };
    let mut session = RenderSession::new(&scene, &opts)?;
    let mut points = Vec::new();
    let stats = session.render_in_waves(0..spp, &(), |film, _| {
        points.push((film.samples_per_pixel() as u32, measure(film)));
    })?;
    let (time, rays) = (stats.elapsed, stats.trace.rays + stats.trace.shadow_rays);
    Ok(Progression {
        film: session.into_film(),
        time,
        rays,
        points,
    })
}

/// The film's estimate as an image.
pub fn film_image(film: &Film) -> ImageRgb {
    ImageRgb {
        width: film.width(),
        height: film.height(),
        pixels: film.mean_image(),
    }
}

/// Read a reference image and check it matches the render's size.
pub fn load_reference(path: &Path, width: u32, height: u32) -> Result<Vec<Rgb>> {
    let r = read_exr(path).with_context(|| format!("cannot read reference \"{}\"", path.display()))?;
    if (r.width, r.height) != (width, height) {
        anyhow::bail!(
            "reference \"{}\" is {}x{}, the render is {width}x{height} (use --resolution {}x{})",
            path.display(),
            r.width,
            r.height,
            r.width,
            r.height
        );
    }
    Ok(r.pixels)
}

/// Create `dir` and write `img` into it.
pub fn write_into(dir: &Path, name: &str, img: &ImageRgb) -> Result<std::path::PathBuf> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create \"{}\"", dir.display()))?;
    let path = dir.join(name);
    write_image(&path, img).with_context(|| format!("cannot write \"{}\"", path.display()))?;
    Ok(path)
}
