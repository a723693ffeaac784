//! `mcrender.load(path) -> Scene` and the `Scene` class: a loaded scene description whose
//! resolution, samples per pixel, integrator, direct-lighting technique, seed and maximum
//! depth can be changed before rendering, and its `render*` methods returning numpy arrays.

use std::path::PathBuf;

use mcrender_core::render::{RenderOptions, RenderOutput, Tile};
use mcrender_core::scene::{DirectStrategy, IntegratorKind, Reconstruction, Scene, SceneDescription};
use numpy::PyArray3;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::errors::{build_error, scene_error};
use crate::film::{rgb_array, Image, PyFilm};
use crate::run::{render_mlt, render_range, render_sppm, Progress, ProgressArg};

/// A scene loaded from a file, ready to render.
#[pyclass(name = "Scene", module = "mcrender")]
pub struct PyScene {
    /// The description the loader produced, with the properties' changes.
    pub desc: SceneDescription,
    /// The file it came from.
    path: PathBuf,
    /// The loader's warnings.
    warnings: Vec<String>,
}

/// Load a scene file (pbrt-v4, or Mitsuba 3 XML, by its extension) and the files it
/// includes or references.
#[pyfunction]
pub fn load(py: Python<'_>, path: PathBuf) -> PyResult<PyScene> {
    let loaded = py
        .detach(|| mcrender_formats::load(&path))
        .map_err(|e| scene_error(py, &e))?;
    Ok(PyScene {
        desc: loaded.description,
        path,
        warnings: loaded.warnings,
    })
}

fn positive(name: &str, v: u32) -> PyResult<u32> {
    if v == 0 {
        return Err(PyValueError::new_err(format!("{name}: expected at least 1, found 0")));
    }
    Ok(v)
}

/// Technique by name.
pub fn parse_technique(name: &str) -> PyResult<DirectStrategy> {
    DirectStrategy::ALL
        .into_iter()
        .find(|d| d.name() == name)
        .ok_or_else(|| {
            let names: Vec<_> = DirectStrategy::ALL.iter().map(|d| d.name()).collect();
            PyValueError::new_err(format!(
                "technique: expected one of {}, found \"{name}\"",
                names.join(", ")
            ))
        })
}

/// A window `(x0, y0, x1, y1)` of pixels `[x0, x1) x [y0, y1)` as a tile.
fn window_tile(window: (u32, u32, u32, u32)) -> Tile {
    let (x0, y0, x1, y1) = window;
    Tile { x0, y0, x1, y1 }
}

impl PyScene {
    /// Build the scene with the per-call overrides and render `start..end` (default
    /// `0..spp`) of the pixels of `window` (default: all).
    #[allow(clippy::too_many_arguments)]
    fn run(
        &self,
        py: Python<'_>,
        start: u32,
        end: Option<u32>,
        spp: Option<u32>,
        seed: Option<u64>,
        threads: Option<usize>,
        progress: &ProgressArg,
        window: Option<Tile>,
    ) -> PyResult<RenderOutput> {
        let mut desc = self.desc.clone();
        if let Some(spp) = spp {
            desc.sampler.samples_per_pixel = positive("spp", spp)?;
        }
        if let Some(seed) = seed {
            desc.sampler.seed = seed;
        }
        if threads == Some(0) {
            return Err(PyValueError::new_err("threads: expected at least 1, found 0"));
        }
        let whole = start == 0 && end.is_none() && window.is_none();
        if desc.integrator.kind == IntegratorKind::Sppm && !whole {
            return Err(PyValueError::new_err(
                "sppm renders in iterations of camera and photon passes over the whole image: sample ranges and windows are not available",
            ));
        }
        if desc.integrator.kind == IntegratorKind::Mlt {
            if !whole {
                return Err(PyValueError::new_err(
                    "mlt renders Markov chains over the whole image: sample ranges and windows are not available",
                ));
            }
            if spp.is_some() {
                return Err(PyValueError::new_err(
                    "spp: mlt counts mutations per pixel, not samples: set scene.mutations_per_pixel",
                ));
            }
        }
        let end = end.unwrap_or(desc.sampler.samples_per_pixel);
        if start >= end {
            return Err(PyValueError::new_err(format!(
                "sample range: expected start < end, found {start}..{end}"
            )));
        }
        let scene = py.detach(|| Scene::build(&desc)).map_err(|e| build_error(&e))?;
        if desc.integrator.kind == IntegratorKind::Sppm {
            return render_sppm(py, &scene, threads, progress);
        }
        if desc.integrator.kind == IntegratorKind::Mlt {
            return render_mlt(py, &scene, threads, progress);
        }
        let pixels = window.map_or(u64::from(desc.film.width) * u64::from(desc.film.height), |w| {
            w.pixel_count()
        });
        let mut progress = Progress::from_arg(py, progress, pixels * u64::from(end - start), "mcrender")?;
        let opts = RenderOptions {
            threads,
            ..Default::default()
        };
        render_range(py, &scene, &opts, start..end, window, &mut progress)
    }
}

#[pymethods]
impl PyScene {
    /// Render all samples per pixel; an (H, W, 3) float32 array of linear RGB.
    #[pyo3(signature = (spp=None, seed=None, threads=None, progress=ProgressArg::Flag(true)))]
    fn render<'py>(
        &self,
        py: Python<'py>,
        spp: Option<u32>,
        seed: Option<u64>,
        threads: Option<usize>,
        progress: ProgressArg,
    ) -> PyResult<Bound<'py, PyArray3<f32>>> {
        let out = self.run(py, 0, None, spp, seed, threads, &progress, None)?;
        let (w, h) = (out.film.width(), out.film.height());
        rgb_array(py, w, h, &out.film.mean_image())
    }

    /// Render; `(image, variance)`, the variance being each pixel's estimated variance of
    /// its estimate, both (H, W, 3) float32.
    #[pyo3(signature = (spp=None, seed=None, threads=None, progress=ProgressArg::Flag(true)))]
    fn render_with_variance<'py>(
        &self,
        py: Python<'py>,
        spp: Option<u32>,
        seed: Option<u64>,
        threads: Option<usize>,
        progress: ProgressArg,
    ) -> PyResult<(Image<'py>, Image<'py>)> {
        let out = self.run(py, 0, None, spp, seed, threads, &progress, None)?;
        let (w, h) = (out.film.width(), out.film.height());
        Ok((
            rgb_array(py, w, h, &out.film.mean_image())?,
            rgb_array(py, w, h, &out.film.variance_image())?,
        ))
    }

    /// Render only the sample indices `start..end` of every pixel; the estimate from those
    /// samples, (H, W, 3) float32.
    #[pyo3(signature = (start, end, seed=None, threads=None, progress=ProgressArg::Flag(true)))]
    fn render_samples<'py>(
        &self,
        py: Python<'py>,
        start: u32,
        end: u32,
        seed: Option<u64>,
        threads: Option<usize>,
        progress: ProgressArg,
    ) -> PyResult<Bound<'py, PyArray3<f32>>> {
        let out = self.run(py, start, Some(end), None, seed, threads, &progress, None)?;
        let (w, h) = (out.film.width(), out.film.height());
        rgb_array(py, w, h, &out.film.mean_image())
    }

    /// Render the sample indices `start..end` (default: all) of the pixels of `window`
    /// (`(x0, y0, x1, y1)`, pixels `[x0, x1) x [y0, y1)`; default: the whole image) and
    /// return the film. Films of the following sample ranges merge into it
    /// (`Film.merged`, up to rounding); films of disjoint windows with the same samples
    /// combine exactly (`Film.combined`).
    #[pyo3(signature = (start=0, end=None, seed=None, threads=None, progress=ProgressArg::Flag(false), window=None))]
    #[allow(clippy::too_many_arguments)]
    fn render_film(
        &self,
        py: Python<'_>,
        start: u32,
        end: Option<u32>,
        seed: Option<u64>,
        threads: Option<usize>,
        progress: ProgressArg,
        window: Option<(u32, u32, u32, u32)>,
    ) -> PyResult<PyFilm> {
        let out = self.run(py, start, end, None, seed, threads, &progress, window.map(window_tile))?;
        Ok(PyFilm { film: out.film })
    }

    /// The file the scene was loaded from.
    #[getter]
    fn path(&self) -> PathBuf {
        self.path.clone()
    }

    /// The loader's warnings (`file:line:col: warning: ...`).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }

    /// Image size `(width, height)` in pixels.
    #[getter]
    fn get_resolution(&self) -> (u32, u32) {
        (self.desc.film.width, self.desc.film.height)
    }

    #[setter]
    fn set_resolution(&mut self, value: (u32, u32)) -> PyResult<()> {
        self.desc.film.width = positive("resolution width", value.0)?;
        self.desc.film.height = positive("resolution height", value.1)?;
        Ok(())
    }

    /// Samples per pixel.
    #[getter]
    fn get_spp(&self) -> u32 {
        self.desc.sampler.samples_per_pixel
    }

    #[setter]
    fn set_spp(&mut self, value: u32) -> PyResult<()> {
        self.desc.sampler.samples_per_pixel = positive("spp", value)?;
        Ok(())
    }

    /// Random seed: the same seed and spp give the same image bit for bit.
    #[getter]
    fn get_seed(&self) -> u64 {
        self.desc.sampler.seed
    }

    #[setter]
    fn set_seed(&mut self, value: u64) {
        self.desc.sampler.seed = value;
    }

    /// Maximum path depth (0 emission only, 1 direct lighting, 2 one bounce, ...).
    #[getter]
    fn get_max_depth(&self) -> u32 {
        self.desc.integrator.max_depth
    }

    #[setter]
    fn set_max_depth(&mut self, value: u32) {
        self.desc.integrator.max_depth = value;
    }

    /// The integrator: "path", "direct", "bdpt", "lightpath", "sppm" or "mlt" (whose length
    /// is `mutations_per_pixel`, not `spp`).
    #[getter]
    fn get_integrator(&self) -> &'static str {
        match self.desc.integrator.kind {
            IntegratorKind::Path => "path",
            IntegratorKind::Direct => "direct",
            IntegratorKind::Bdpt => "bdpt",
            IntegratorKind::LightPath => "lightpath",
            IntegratorKind::Sppm => "sppm",
            IntegratorKind::Mlt => "mlt",
        }
    }

    #[setter]
    fn set_integrator(&mut self, value: &str) -> PyResult<()> {
        self.desc.integrator.kind = match value {
            "path" => IntegratorKind::Path,
            "direct" => IntegratorKind::Direct,
            "bdpt" => IntegratorKind::Bdpt,
            "lightpath" => IntegratorKind::LightPath,
            "sppm" => IntegratorKind::Sppm,
            "mlt" => IntegratorKind::Mlt,
            _ => {
                return Err(PyValueError::new_err(format!(
                    "integrator: expected \"path\", \"direct\", \"bdpt\", \"lightpath\", \"sppm\" or \"mlt\", found \"{value}\""
                )))
            }
        };
        Ok(())
    }

    /// How camera samples become pixels: "sample" (filter importance sampling, pbrt's) or
    /// "splat" (every sample counts for each pixel its filter covers, Mitsuba's; less noise
    /// per sample with wide filters; not with sppm or mlt).
    #[getter]
    fn get_reconstruction(&self) -> &'static str {
        match self.desc.reconstruction {
            Reconstruction::FilterSampling => "sample",
            Reconstruction::FilterSplatting => "splat",
        }
    }

    #[setter]
    fn set_reconstruction(&mut self, value: &str) -> PyResult<()> {
        self.desc.reconstruction = match value {
            "sample" => Reconstruction::FilterSampling,
            "splat" => Reconstruction::FilterSplatting,
            _ => {
                return Err(PyValueError::new_err(format!(
                    "reconstruction: expected \"sample\" or \"splat\", found \"{value}\""
                )))
            }
        };
        Ok(())
    }

    /// MLT's mutations per pixel over all chains (pbrt's `mutationsperpixel`; only the
    /// mlt integrator reads it).
    #[getter]
    fn get_mutations_per_pixel(&self) -> u32 {
        self.desc.integrator.mlt.mutations_per_pixel
    }

    #[setter]
    fn set_mutations_per_pixel(&mut self, value: u32) -> PyResult<()> {
        self.desc.integrator.mlt.mutations_per_pixel = positive("mutations_per_pixel", value)?;
        Ok(())
    }

    /// The direct-lighting technique: "uniform-hemisphere", "cosine-hemisphere",
    /// "light-area", "bsdf" or "mis".
    #[getter]
    fn get_direct(&self) -> &'static str {
        self.desc.integrator.direct.name()
    }

    #[setter]
    fn set_direct(&mut self, value: &str) -> PyResult<()> {
        self.desc.integrator.direct = parse_technique(value)?;
        Ok(())
    }

    fn __repr__(&self) -> String {
        format!(
            "Scene({:?}, resolution={}x{}, spp={}, integrator={:?}, max_depth={}, seed={})",
            self.path.display().to_string(),
            self.desc.film.width,
            self.desc.film.height,
            self.desc.sampler.samples_per_pixel,
            self.get_integrator(),
            self.desc.integrator.max_depth,
            self.desc.sampler.seed
        )
    }
}
