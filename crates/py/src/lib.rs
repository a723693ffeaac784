//! The `mcrender._mcrender` extension module: mcrender from Python with numpy arrays.
//! The Python package `mcrender` (python/mcrender/__init__.py) re-exports it.
//!
//! * [`scene`]: `mcrender.load(path) -> Scene`, its settable properties and `render*`;
//! * [`run`]: a render off the GIL, with progress and Ctrl-C cancellation;
//! * [`film`]: `Film`, a render's per-pixel sums (mergeable, picklable for Ray);
//! * [`images`]: `read_image`, `write_image`;
//! * [`lab`]: the estimator lab, `compare` and `pi`;
//! * [`errors`]: `SceneError` and the mapping of Rust errors to Python exceptions.

mod errors;
mod film;
mod images;
mod lab;
mod run;
mod scene;

use pyo3::prelude::*;

/// The native module.
#[pymodule]
fn _mcrender(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("SceneError", m.py().get_type::<errors::SceneError>())?;
    m.add_class::<scene::PyScene>()?;
    m.add_class::<film::PyFilm>()?;
    m.add_function(wrap_pyfunction!(scene::load, m)?)?;
    m.add_function(wrap_pyfunction!(images::read_image, m)?)?;
    m.add_function(wrap_pyfunction!(images::write_image, m)?)?;
    m.add_function(wrap_pyfunction!(lab::compare, m)?)?;
    m.add_function(wrap_pyfunction!(lab::pi, m)?)?;
    Ok(())
}
