//! The estimator lab's studies: `compare` (variance, cost and efficiency of the
//! direct-lighting techniques, with a contact sheet and convergence plot), `bounces`
//! (one image per maximum depth) and `rr-study` (Russian roulette settings side by side).

pub mod bounces;
pub mod compare;
pub mod rr_study;

use std::path::Path;

use anyhow::{Context, Result};
use mcrender_core::color::Rgb;
use mcrender_core::film::Film;
pub use mcrender_core::lab::render_in_waves;
use mcrender_formats::image_io::{read_exr, write_image, ImageRgb};

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
