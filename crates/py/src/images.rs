//! `mcrender.read_image(path)` and `mcrender.write_image(path, array)`: EXR (linear 32-bit
//! float) and PNG (8-bit sRGB) through the project's image I/O; reading also takes PFM,
//! JPEG and TGA. Arrays are (H, W, 3) float32, linear RGB.

use std::path::PathBuf;

use mcrender_core::color::Rgb;
use mcrender_formats::image_io::ImageRgb;
use numpy::{PyArray3, PyReadonlyArray3, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::errors::image_error;
use crate::film::rgb_array;

/// Read an image as an (H, W, 3) float32 array of linear RGB.
#[pyfunction]
pub fn read_image<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let img = py
        .detach(|| mcrender_formats::read_image(&path))
        .map_err(|e| image_error(&e))?;
    rgb_array(py, img.width, img.height, &img.pixels)
}

/// The pixels of an (H, W, 3) float32 array, row-major.
pub fn array_pixels(array: &PyReadonlyArray3<'_, f32>, what: &str) -> PyResult<(u32, u32, Vec<Rgb>)> {
    let shape = array.shape();
    if shape[2] != 3 || shape[0] == 0 || shape[1] == 0 {
        return Err(PyValueError::new_err(format!(
            "{what}: expected an array of shape (H, W, 3), found {shape:?}"
        )));
    }
    let too_big = || PyValueError::new_err(format!("{what}: image of shape {shape:?} is too large"));
    let height = u32::try_from(shape[0]).map_err(|_| too_big())?;
    let width = u32::try_from(shape[1]).map_err(|_| too_big())?;
    let view = array.as_array();
    let pixels = view
        .outer_iter()
        .flat_map(|row| row.outer_iter().map(|p| Rgb::new(p[0], p[1], p[2])).collect::<Vec<_>>())
        .collect();
    Ok((width, height, pixels))
}

/// Write an (H, W, 3) float32 array: `.exr` as linear float, `.png` as 8-bit sRGB. The file
/// appears complete or not at all.
#[pyfunction]
pub fn write_image(py: Python<'_>, path: PathBuf, array: PyReadonlyArray3<'_, f32>) -> PyResult<()> {
    let (width, height, pixels) = array_pixels(&array, "write_image")?;
    let img = ImageRgb { width, height, pixels };
    py.detach(|| mcrender_formats::write_image(&path, &img))
        .map_err(|e| image_error(&e))
}
