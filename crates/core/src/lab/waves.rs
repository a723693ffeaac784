//! Rendering a film in waves of doubling sample counts (1, 2, 4, ...), measuring it after
//! every wave: the data of a convergence plot. The waves continue one
//! [`RenderSession`]'s film, so the final film is the one a single pass gives.

use std::sync::atomic::AtomicBool;
use std::time::Duration;

use crate::film::Film;
use crate::render::{RenderError, RenderOptions, RenderSession, Watch};
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
/// the sample count) of one render session, calling `measure` on the film after each. The
/// final film is bit-identical to a render in one pass. Setting `cancel` stops the render
/// within a tile with [`RenderError::Cancelled`].
pub fn render_in_waves(
    desc: &SceneDescription,
    threads: Option<usize>,
    cancel: &AtomicBool,
    measure: impl Fn(&Film) -> f64,
) -> Result<Progression, LabError> {
    let scene = Scene::build(desc)?;
    let spp = desc.sampler.samples_per_pixel;
    let opts = RenderOptions {
        threads,
        ..Default::default()
    };
    let mut session = RenderSession::new(&scene, &opts)?;
    let mut points = Vec::new();
    let watch = Watch {
        progress: |_, _| {},
        cancel,
    };
    let stats = session.render_in_waves(0..spp, &watch, |film, _| {
        points.push((film.samples_per_pixel() as u32, measure(film)));
    })?;
    Ok(Progression {
        film: session.into_film(),
        time: stats.elapsed,
        rays: stats.trace.rays + stats.trace.shadow_rays,
        points,
    })
}

/// Check that a reference image, when given, has the film's pixel count (row-major).
///
/// # Errors
/// [`LabError::Argument`] naming both sizes.
pub fn check_reference(base: &SceneDescription, reference: Option<&[crate::color::Rgb]>) -> Result<(), LabError> {
    let pixels = u64::from(base.film.width) * u64::from(base.film.height);
    match reference {
        Some(r) if r.len() as u64 != pixels => Err(LabError::Argument(format!(
            "reference: expected {}x{} = {pixels} pixels, found {}",
            base.film.width,
            base.film.height,
            r.len()
        ))),
        _ => Ok(()),
    }
}
