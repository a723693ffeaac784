//! Rendering a film in waves of doubling sample counts (1, 2, 4, ...), measuring it after
//! every wave: the data of a convergence plot. The waves are disjoint sample ranges merged
//! with [`Film::merge`].

use std::time::Duration;

use crate::film::Film;
use crate::render::{render_samples, RenderError, RenderOptions};
use crate::scene::{BuildError, Scene, SceneDescription};

/// Why a study could not run.
#[derive(Debug, thiserror::Error)]
pub enum LabError {
    /// The scene description cannot be built.
    #[error("the scene cannot be rendered: {0}")]
    Build(#[from] BuildError),
    /// The render failed.
    #[error(transparent)]
    Render(#[from] RenderError),
    /// A bad argument (no techniques, a reference of the wrong size, ...).
    #[error("{0}")]
    Argument(String),
}

/// A film grown in waves of doubling sample counts, with the time spent and a measurement
/// after every wave.
#[derive(Clone, Debug)]
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
/// the sample count), calling `measure` on the film after each.
pub fn render_in_waves(
    desc: &SceneDescription,
    threads: Option<usize>,
    measure: impl Fn(&Film) -> f64,
) -> Result<Progression, LabError> {
    let scene = Scene::build(desc)?;
    let spp = desc.sampler.samples_per_pixel;
    let opts = RenderOptions {
        threads,
        ..Default::default()
    };
    let mut film = Film::new(desc.film.width, desc.film.height);
    let (mut time, mut rays, mut points) = (Duration::ZERO, 0, Vec::new());
    let mut done = 0;
    while done < spp {
        let next = (done * 2).clamp(1, spp);
        let out = render_samples(&scene, &opts, done..next, &|_, _| {})?;
        film.merge(&out.film);
        time += out.stats.elapsed;
        rays += out.stats.trace.rays + out.stats.trace.shadow_rays;
        done = next;
        points.push((done, measure(&film)));
    }
    Ok(Progression {
        film,
        time,
        rays,
        points,
    })
}
