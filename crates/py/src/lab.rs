//! The estimator lab from Python: `mcrender.compare(scene, techniques, spp, reference)`
//! (the figures of `mcrender compare --json`, computed by the same
//! `mcrender_core::lab::compare_techniques`, or with `integrators=[...]` by
//! `compare_integrators`) and `mcrender.pi(samples, seed, trials)` (those
//! of `mcrender pi --json`).

use std::f64::consts::PI;
use std::path::PathBuf;

use mcrender_core::color::Rgb;
use mcrender_core::lab::{
    compare_integrators, compare_techniques, estimate_pi, integrator_name, parse_integrator, pi_trials, Budget,
    ReferenceSource, EXACT_VARIANCE_TIMES_N,
};
use mcrender_core::scene::IntegratorKind;
use numpy::PyReadonlyArray3;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::errors::{image_error, lab_error};
use crate::film::rgb_array;
use crate::images::array_pixels;
use crate::run::{run_cancellable, Progress};
use crate::scene::{parse_technique, PyScene};

/// A reference image: a path to an EXR file or an (H, W, 3) float32 array.
#[derive(FromPyObject)]
pub enum Reference<'py> {
    /// An EXR file.
    Path(PathBuf),
    /// An array.
    Array(PyReadonlyArray3<'py, f32>),
}

/// The lecture's techniques, in order.
const ALL_TECHNIQUES: [&str; 5] = ["uniform-hemisphere", "cosine-hemisphere", "light-area", "bsdf", "mis"];

/// Compare direct-lighting techniques on `scene`: one dict per technique with the keys of
/// `mcrender compare --json` (technique, spp, mean_radiance, mean_luminance, variance,
/// rel_mse, time_s, rays, efficiency, relative_efficiency), plus `image` (the render, an
/// (H, W, 3) array) and `convergence` (a list of (spp, error) after waves 1, 2, 4, ...).
///
/// With `integrators=[...]` (names as `mcrender compare --integrators`), compares
/// integrators instead, at `spp` each or, with `time_budget` (seconds), at equal time: the
/// dicts have the keys of `--integrators --json`'s rows (integrator, samples, sample_unit,
/// ..., `variance` None for sppm and lightpath, `reference`: "given" or the long render
/// used) and `convergence` as (seconds, rel. MSE).
#[pyfunction]
#[pyo3(signature = (scene, techniques=None, spp=None, reference=None, threads=None, integrators=None, time_budget=None))]
#[allow(clippy::too_many_arguments)]
pub fn compare<'py>(
    py: Python<'py>,
    scene: &PyScene,
    techniques: Option<Vec<String>>,
    spp: Option<u32>,
    reference: Option<Reference<'py>>,
    threads: Option<usize>,
    integrators: Option<Vec<String>>,
    time_budget: Option<f64>,
) -> PyResult<Bound<'py, PyList>> {
    if integrators.is_some() && techniques.is_some() {
        return Err(PyValueError::new_err(
            "techniques and integrators: give one or the other",
        ));
    }
    if time_budget.is_some() && integrators.is_none() {
        return Err(PyValueError::new_err("time_budget: only with integrators"));
    }
    let names = techniques.unwrap_or_else(|| ALL_TECHNIQUES.iter().map(|s| s.to_string()).collect());
    let techniques = names.iter().map(|n| parse_technique(n)).collect::<PyResult<Vec<_>>>()?;
    let mut desc = scene.desc.clone();
    if let Some(spp) = spp {
        if spp == 0 {
            return Err(PyValueError::new_err("spp: expected at least 1, found 0"));
        }
        desc.sampler.samples_per_pixel = spp;
    }
    if threads == Some(0) {
        return Err(PyValueError::new_err("threads: expected at least 1, found 0"));
    }
    let (w, h) = (desc.film.width, desc.film.height);
    let reference: Option<Vec<Rgb>> = match reference {
        None => None,
        Some(Reference::Path(p)) => {
            let img = py
                .detach(|| mcrender_formats::read_exr(&p))
                .map_err(|e| image_error(&e))?;
            if (img.width, img.height) != (w, h) {
                return Err(PyValueError::new_err(format!(
                    "reference \"{}\" is {}x{}, the render is {w}x{h}",
                    p.display(),
                    img.width,
                    img.height
                )));
            }
            Some(img.pixels)
        }
        Some(Reference::Array(a)) => {
            let (aw, ah, pixels) = array_pixels(&a, "reference")?;
            if (aw, ah) != (w, h) {
                return Err(PyValueError::new_err(format!(
                    "reference: the array is {aw}x{ah} (shape ({ah}, {aw}, 3)), the render is {w}x{h}"
                )));
            }
            Some(pixels)
        }
    };
    if let Some(names) = integrators {
        let kinds = names
            .iter()
            .map(|n| parse_integrator(n).map_err(PyValueError::new_err))
            .collect::<PyResult<Vec<IntegratorKind>>>()?;
        let budget = match time_budget {
            Some(s) if !(s.is_finite() && s > 0.0) => {
                return Err(PyValueError::new_err(format!(
                    "time_budget: expected a positive number of seconds, found {s}"
                )))
            }
            Some(s) => Budget::Time(std::time::Duration::from_secs_f64(s)),
            None => Budget::Samples(desc.sampler.samples_per_pixel),
        };
        let report = run_cancellable(
            py,
            0,
            &mut Progress::Off,
            |_, cancel| compare_integrators(&desc, &kinds, reference.as_deref(), threads, budget, cancel, |_, _| {}),
            lab_error,
        )?;
        let source = match report.reference {
            ReferenceSource::Given => "given".to_string(),
            ReferenceSource::LongRender(k) => format!("long render of {}", integrator_name(k)),
        };
        let out = PyList::empty(py);
        for r in &report.rows {
            let d = PyDict::new(py);
            d.set_item("integrator", integrator_name(r.kind))?;
            d.set_item("samples", r.samples)?;
            d.set_item("sample_unit", r.sample_unit)?;
            d.set_item("mean_radiance", r.stats.mean.to_array())?;
            d.set_item("mean_luminance", r.stats.mean.luminance())?;
            let no_variance = matches!(r.kind, IntegratorKind::Sppm | IntegratorKind::LightPath);
            d.set_item("variance", (!no_variance).then_some(r.stats.mean_variance))?;
            d.set_item("rel_mse", r.stats.rel_mse)?;
            d.set_item("time_s", r.seconds)?;
            d.set_item("rays", r.rays)?;
            d.set_item("efficiency", r.efficiency)?;
            d.set_item("relative_efficiency", r.relative_efficiency)?;
            d.set_item("reference", &source)?;
            d.set_item("image", rgb_array(py, w, h, &r.film.mean_image())?)?;
            d.set_item("convergence", r.points.clone())?;
            out.append(d)?;
        }
        return Ok(out);
    }
    let rows = run_cancellable(
        py,
        0,
        &mut Progress::Off,
        |_, cancel| compare_techniques(&desc, &techniques, reference.as_deref(), threads, cancel, |_| {}),
        lab_error,
    )?;
    let out = PyList::empty(py);
    for r in &rows {
        let d = PyDict::new(py);
        d.set_item("technique", r.technique.name())?;
        d.set_item("spp", r.spp)?;
        d.set_item("mean_radiance", r.stats.mean.to_array())?;
        d.set_item("mean_luminance", r.stats.mean.luminance())?;
        d.set_item("variance", r.stats.mean_variance)?;
        d.set_item("rel_mse", r.stats.rel_mse)?;
        d.set_item("time_s", r.seconds)?;
        d.set_item("rays", r.rays)?;
        d.set_item("efficiency", r.efficiency)?;
        d.set_item("relative_efficiency", r.relative_efficiency)?;
        d.set_item("image", rgb_array(py, w, h, &r.progression.film.mean_image())?)?;
        d.set_item("convergence", r.progression.points.clone())?;
        out.append(d)?;
    }
    Ok(out)
}

/// Estimate pi from random points in the unit square, for each number of points in
/// `samples`; with `trials` (at least 2) also the mean, variance and variance x N over
/// that many independent trials. The dict of `mcrender pi --json`.
#[pyfunction]
#[pyo3(signature = (samples=None, seed=1, trials=None))]
pub fn pi<'py>(
    py: Python<'py>,
    samples: Option<Vec<u64>>,
    seed: u64,
    trials: Option<u64>,
) -> PyResult<Bound<'py, PyDict>> {
    let samples = samples.unwrap_or_else(|| vec![1, 10, 100, 1_000, 10_000, 100_000, 1_000_000]);
    if samples.contains(&0) {
        return Err(PyValueError::new_err(
            "samples: the number of points must be at least 1",
        ));
    }
    if trials.is_some_and(|k| k < 2) {
        return Err(PyValueError::new_err(
            "trials: at least 2 trials are needed to measure a variance",
        ));
    }
    let computed: Vec<_> = py.detach(|| {
        samples
            .iter()
            .map(|&n| (n, estimate_pi(n, seed, 0), trials.map(|k| pi_trials(n, seed, k))))
            .collect()
    });
    let rows = PyList::empty(py);
    for (n, estimate, stats) in computed {
        let d = PyDict::new(py);
        d.set_item("samples", n)?;
        d.set_item("estimate", estimate)?;
        d.set_item("abs_error", (estimate - PI).abs())?;
        if let Some(s) = stats {
            d.set_item("mean", s.mean)?;
            d.set_item("variance", s.variance)?;
            d.set_item("variance_times_n", s.variance_times_n)?;
        }
        rows.append(d)?;
    }
    let out = PyDict::new(py);
    out.set_item("seed", seed)?;
    out.set_item("trials", trials)?;
    out.set_item("exact_variance_times_n", EXACT_VARIANCE_TIMES_N)?;
    out.set_item("rows", rows)?;
    Ok(out)
}
