//! `mcrender.Film`: the per-pixel sums of a render of some sample range or window of the
//! image (weights, weighted radiance and its square, sample counts in `f64`; splat sums in
//! exact fixed point). Films of disjoint windows rendered with the same samples combine
//! exactly (`combined`) into the film of the whole image, bit for bit: this is how
//! `mcrender.distributed` assembles the bands rendered on Ray workers. Films of consecutive
//! sample ranges merge (`merged`) into the film of their union up to the rounding of the f64
//! additions' grouping. Films pickle to a compact byte string. A film of filter splatting
//! also holds each pixel's filtered sums (fixed point), which combine and merge exactly.

use mcrender_core::color::Rgb;
use mcrender_core::film::{Film, FilteredSums, PixelStats, SplatSum, FILTERED_SUMS_LEN};
use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyArray3};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyTuple};

/// Bytes of the header (width, height as little-endian u32, samples per pixel as u64) and
/// of one pixel (seven f64 sums, a u64 count, three i128 fixed-point splat sums); a film of
/// filter splatting then has, per pixel, its filtered sums (i128 each).
const HEADER: usize = 16;
const PIXEL: usize = 64 + 48;
const FILTERED: usize = 16 * FILTERED_SUMS_LEN;

/// The accumulated samples of a render: `image()` is the estimate, `variance()` the
/// estimated variance of each pixel's estimate.
#[pyclass(name = "Film", module = "mcrender", frozen)]
pub struct PyFilm {
    /// The sums.
    pub film: Film,
}

/// An (H, W, 3) float32 numpy array.
pub type Image<'py> = Bound<'py, PyArray3<f32>>;

/// An (H, W, 3) float32 array of `pixels` (row-major).
pub fn rgb_array<'py>(py: Python<'py>, width: u32, height: u32, pixels: &[Rgb]) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let data: Vec<f32> = pixels.iter().flat_map(|p| [p[0], p[1], p[2]]).collect();
    let array = Array3::from_shape_vec((height as usize, width as usize, 3), data)
        .map_err(|e| PyValueError::new_err(format!("image of {width}x{height} pixels: {e}")))?;
    Ok(array.into_pyarray(py))
}

impl PyFilm {
    fn encode(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(HEADER + PIXEL * self.film.pixels().len());
        out.extend_from_slice(&self.film.width().to_le_bytes());
        out.extend_from_slice(&self.film.height().to_le_bytes());
        out.extend_from_slice(&self.film.samples_per_pixel().to_le_bytes());
        for (p, splat) in self.film.pixels().iter().zip(self.film.splat_sums()) {
            out.extend_from_slice(&p.sum_w.to_le_bytes());
            for v in p.sum_wl.iter().chain(&p.sum_wl2) {
                out.extend_from_slice(&v.to_le_bytes());
            }
            out.extend_from_slice(&p.count.to_le_bytes());
            for v in splat.to_fixed() {
                out.extend_from_slice(&v.to_le_bytes());
            }
        }
        for f in self.film.filtered_sums().unwrap_or_default() {
            for v in f.to_fixed() {
                out.extend_from_slice(&v.to_le_bytes());
            }
        }
        out
    }

    fn decode(bytes: &[u8]) -> PyResult<Film> {
        let bad = || PyValueError::new_err("Film.from_bytes: not a film's bytes (see Film.to_bytes)");
        let word = |i: usize| -> [u8; 8] { bytes[i..i + 8].try_into().unwrap_or_default() };
        if bytes.len() < HEADER {
            return Err(bad());
        }
        let width = u32::from_le_bytes(bytes[0..4].try_into().map_err(|_| bad())?);
        let height = u32::from_le_bytes(bytes[4..8].try_into().map_err(|_| bad())?);
        let spp = u64::from_le_bytes(word(8));
        let n = width as usize * height as usize;
        let with_filtered = bytes.len() == HEADER + (PIXEL + FILTERED) * n && n > 0;
        if bytes.len() != HEADER + PIXEL * n && !with_filtered {
            return Err(bad());
        }
        let int = |b: usize| i128::from_le_bytes(bytes[b..b + 16].try_into().unwrap_or_default());
        let (mut pixels, mut splats) = (Vec::with_capacity(n), Vec::with_capacity(n));
        for i in 0..n {
            let at = HEADER + PIXEL * i;
            let f = |k: usize| f64::from_le_bytes(word(at + 8 * k));
            pixels.push(PixelStats {
                sum_w: f(0),
                sum_wl: [f(1), f(2), f(3)],
                sum_wl2: [f(4), f(5), f(6)],
                count: u64::from_le_bytes(word(at + 56)),
            });
            let fixed = |k: usize| int(at + 64 + 16 * k);
            splats.push(SplatSum::from_fixed([fixed(0), fixed(1), fixed(2)]));
        }
        let film = Film::from_parts(width, height, pixels, splats, spp).ok_or_else(bad)?;
        if !with_filtered {
            return Ok(film);
        }
        let filtered = (0..n)
            .map(|i| {
                let at = HEADER + PIXEL * n + FILTERED * i;
                FilteredSums::from_fixed(std::array::from_fn(|k| int(at + 16 * k)))
            })
            .collect();
        film.with_filtered_sums(filtered).ok_or_else(bad)
    }
}

#[pymethods]
impl PyFilm {
    /// Width in pixels.
    #[getter]
    fn width(&self) -> u32 {
        self.film.width()
    }

    /// Height in pixels.
    #[getter]
    fn height(&self) -> u32 {
        self.film.height()
    }

    /// Samples per pixel rendered into the film.
    #[getter]
    fn samples(&self) -> u64 {
        self.film.samples_per_pixel()
    }

    /// A new film with `other`'s samples added to this one's. Merge films in sample order
    /// (0..a, then a..b, ...).
    fn merged(&self, other: &PyFilm) -> PyResult<PyFilm> {
        if (self.film.width(), self.film.height()) != (other.film.width(), other.film.height()) {
            return Err(PyValueError::new_err(format!(
                "Film.merged: films of different sizes ({}x{} and {}x{})",
                self.film.width(),
                self.film.height(),
                other.film.width(),
                other.film.height()
            )));
        }
        if self.film.filtered_sums().is_some() != other.film.filtered_sums().is_some() {
            return Err(PyValueError::new_err(
                "Film.merged: films of different reconstructions (filter sampling and splatting)",
            ));
        }
        let mut film = self.film.clone();
        film.merge(&other.film);
        Ok(PyFilm { film })
    }

    /// A new film combining this one with `other`, a film of another window of the same
    /// image rendered with the same samples (``Scene.render_film(window=...)``): each pixel
    /// from the film that rendered it, splats added exactly. Combined in any order, the
    /// films of windows covering the image give the bits of a film rendered whole.
    fn combined(&self, other: &PyFilm) -> PyResult<PyFilm> {
        let mut film = self.film.clone();
        film.combine_disjoint(&other.film)
            .map_err(|e| PyValueError::new_err(format!("Film.combined: {e}")))?;
        Ok(PyFilm { film })
    }

    /// The estimate: an (H, W, 3) float32 array of linear RGB.
    fn image<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray3<f32>>> {
        rgb_array(py, self.film.width(), self.film.height(), &self.film.mean_image())
    }

    /// The estimated variance of each pixel's estimate, (H, W, 3) float32.
    fn variance<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray3<f32>>> {
        rgb_array(py, self.film.width(), self.film.height(), &self.film.variance_image())
    }

    /// The sums as bytes (little-endian; what pickling uses).
    fn to_bytes<'py>(&self, py: Python<'py>) -> Bound<'py, PyBytes> {
        PyBytes::new(py, &self.encode())
    }

    /// A film from [`to_bytes`](Self::to_bytes)' output.
    #[staticmethod]
    fn from_bytes(data: &[u8]) -> PyResult<PyFilm> {
        Ok(PyFilm {
            film: Self::decode(data)?,
        })
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        let py = slf.py();
        let ctor = py.get_type::<PyFilm>().getattr("from_bytes")?;
        let bytes = slf.get().to_bytes(py);
        PyTuple::new(py, [ctor.into_any(), PyTuple::new(py, [bytes])?.into_any()])
    }

    fn __eq__(&self, other: &PyFilm) -> bool {
        self.film == other.film
    }

    fn __repr__(&self) -> String {
        format!(
            "Film({}x{}, {} samples per pixel)",
            self.film.width(),
            self.film.height(),
            self.samples()
        )
    }
}
