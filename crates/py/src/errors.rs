//! Python exceptions for mcrender's errors: `SceneError` (with `file`, `line`, `column`,
//! `kind` and `message` attributes) for a scene that cannot be loaded, `ValueError` for bad
//! arguments and scenes that cannot be rendered as configured, `OSError` for files.

use mcrender_core::lab::LabError;
use mcrender_core::render::RenderError;
use mcrender_core::scene::BuildError;
use mcrender_formats::{ImageError, SceneErrorKind};
use pyo3::exceptions::{PyException, PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;

pyo3::create_exception!(
    mcrender,
    SceneError,
    PyException,
    "A scene file could not be loaded. `str(e)` reads `file:line:col: message`; the \
     attributes `file`, `line` and `column` (None when the error names a whole file), \
     `kind` ('syntax', 'invalid', 'unsupported' or 'io') and `message` give the parts."
);

/// The Python `SceneError` for a loader error, its location as attributes.
pub fn scene_error(py: Python<'_>, e: &mcrender_formats::SceneError) -> PyErr {
    let err = SceneError::new_err(e.to_string());
    let value = err.value(py);
    let loc = &e.location;
    let (line, column) = if loc.line == 0 {
        (None, None)
    } else {
        (Some(loc.line), Some(loc.column))
    };
    let kind = match e.kind {
        SceneErrorKind::Syntax => "syntax",
        SceneErrorKind::Invalid => "invalid",
        SceneErrorKind::Unsupported => "unsupported",
        SceneErrorKind::Io => "io",
    };
    let attrs = [
        value.setattr("file", &*loc.file),
        value.setattr("line", line),
        value.setattr("column", column),
        value.setattr("kind", kind),
        value.setattr("message", &e.message),
    ];
    match attrs.into_iter().find_map(Result::err) {
        Some(setattr_failed) => setattr_failed,
        None => err,
    }
}

/// A scene description that cannot be built (an absurd resolution, a NaN parameter).
pub fn build_error(e: &BuildError) -> PyErr {
    PyValueError::new_err(format!("the scene cannot be rendered: {e}"))
}

/// A render that cannot run (an estimator that cannot see this scene's lights, no threads).
pub fn render_error(e: &RenderError) -> PyErr {
    match e {
        RenderError::Integrator(_)
        | RenderError::SampleRange { .. }
        | RenderError::FilmSize { .. }
        | RenderError::FilmReconstruction { .. }
        | RenderError::Window { .. } => PyValueError::new_err(e.to_string()),
        RenderError::ThreadPool { .. } | RenderError::Cancelled { .. } => PyRuntimeError::new_err(e.to_string()),
    }
}

/// A lab study that failed.
pub fn lab_error(e: &LabError) -> PyErr {
    match e {
        LabError::Build(b) => build_error(b),
        LabError::Render(r) => render_error(r),
        LabError::Argument(_) => PyValueError::new_err(e.to_string()),
    }
}

/// An image that cannot be read or written.
pub fn image_error(e: &ImageError) -> PyErr {
    match e {
        ImageError::Io { .. } => PyOSError::new_err(e.to_string()),
        _ => PyValueError::new_err(e.to_string()),
    }
}
