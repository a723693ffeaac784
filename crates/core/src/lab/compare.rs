//! The efficiency report behind `mcrender compare` (and the Python `mcrender.compare`):
//! each direct-lighting technique renders the same scene with the same samples per pixel;
//! a row gives its mean radiance, average per-pixel variance (from the samples' own second
//! moments), relative MSE against a reference when one is given, render time, efficiency
//! `1 / (variance x time)` and efficiency relative to the best technique.

use std::sync::atomic::AtomicBool;

use crate::color::Rgb;
use crate::film::FilmStatistics;
use crate::scene::{DirectStrategy, SceneDescription};

use super::waves::{check_reference, render_in_waves, LabError, Progression};

/// One technique's figures.
#[derive(Clone, Debug)]
pub struct CompareRow {
    /// The direct-lighting technique.
    pub technique: DirectStrategy,
    /// Samples per pixel.
    pub spp: u32,
    /// Mean radiance, average per-pixel variance and relative MSE of the final film.
    pub stats: FilmStatistics,
    /// Render time in seconds (scene building excluded).
    pub seconds: f64,
    /// Rays traced (closest-hit and shadow).
    pub rays: u64,
    /// `1 / (variance x time)`; infinite for a noiseless estimate.
    pub efficiency: f64,
    /// Efficiency over the best finite efficiency of the report.
    pub relative_efficiency: f64,
    /// The film and its convergence points (relative MSE against the reference when one is
    /// given, else the mean per-pixel variance, after each wave of 1, 2, 4, ... spp).
    pub progression: Progression,
}

/// Efficiency `1 / (variance x time)`; infinite for a noiseless estimate.
#[must_use]
pub fn efficiency(variance: f64, seconds: f64) -> f64 {
    1.0 / (variance * seconds)
}

/// Render `base` once per technique (its other settings unchanged) and measure each.
/// `reference`, when given, must have the film's pixel count (row-major). `on_start` is
/// called before each technique renders (for progress messages). Setting `cancel` stops
/// the comparison within a tile with [`crate::render::RenderError::Cancelled`].
pub fn compare_techniques(
    base: &SceneDescription,
    techniques: &[DirectStrategy],
    reference: Option<&[Rgb]>,
    threads: Option<usize>,
    cancel: &AtomicBool,
    mut on_start: impl FnMut(DirectStrategy),
) -> Result<Vec<CompareRow>, LabError> {
    if techniques.is_empty() {
        return Err(LabError::Argument("techniques: expected at least one technique".into()));
    }
    check_reference(base, reference)?;
    let spp = base.sampler.samples_per_pixel;
    let mut rows = Vec::with_capacity(techniques.len());
    for &technique in techniques {
        on_start(technique);
        let mut desc = base.clone();
        desc.integrator.direct = technique;
        let measure = |f: &_| {
            let s = FilmStatistics::measure(f, reference);
            s.rel_mse.unwrap_or(s.mean_variance)
        };
        let progression = render_in_waves(&desc, threads, cancel, measure)?;
        let stats = FilmStatistics::measure(&progression.film, reference);
        let seconds = progression.time.as_secs_f64();
        rows.push(CompareRow {
            technique,
            spp,
            stats,
            seconds,
            rays: progression.rays,
            efficiency: efficiency(stats.mean_variance, seconds),
            relative_efficiency: 0.0,
            progression,
        });
    }
    let best = rows
        .iter()
        .map(|r| r.efficiency)
        .filter(|e| e.is_finite())
        .fold(0.0, f64::max);
    for r in &mut rows {
        r.relative_efficiency = r.efficiency / best;
    }
    Ok(rows)
}
