//! Image files: [`write_image`] picks PNG (8-bit sRGB) or EXR (linear 32-bit float) by the
//! file extension; [`write_exr_layers`] writes extra named layers; [`read_image`] reads
//! EXR, PFM, PNG, JPEG or TGA as linear RGB ([`read_exr`], [`read_pfm`] for the float
//! formats). Every write is atomic: the image goes to a temporary file in the target
//! directory that is renamed over the target only when complete.

mod atomic;
mod exr;
mod pfm;
mod png;
mod read;

use std::path::{Path, PathBuf};

use mcrender_core::color::Rgb;

pub use self::exr::{read_exr, read_exr_metadata, write_exr_layers, write_exr_layers_with_metadata};
pub use self::pfm::read_pfm;
pub use self::read::{decode_image, image_dimensions, read_image, read_image_encoded, ColorEncoding, ImageFormat};

/// A linear RGB image, row-major, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct ImageRgb {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` pixels, row by row from the top.
    pub pixels: Vec<Rgb>,
}

impl ImageRgb {
    /// A black image.
    #[must_use]
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            pixels: vec![Rgb::BLACK; width as usize * height as usize],
        }
    }

    /// The pixel at column `x`, row `y` (0 = top).
    ///
    /// # Panics
    /// When `(x, y)` is outside the image.
    #[must_use]
    pub fn get(&self, x: u32, y: u32) -> Rgb {
        self.pixels[y as usize * self.width as usize + x as usize]
    }
}

/// Why an image could not be written or read.
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    /// The extension is neither `.png` nor `.exr`.
    #[error("{}: unsupported image format \"{extension}\" (use .png or .exr)", path.display())]
    UnsupportedFormat {
        /// The file.
        path: PathBuf,
        /// Its extension ("" when it has none).
        extension: String,
    },
    /// The pixel count does not match the size, or the size is zero.
    #[error("{}: {message}", path.display())]
    InvalidImage {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// Opening, writing, renaming or reading failed.
    #[error("{}: {}", path.display(), crate::error::io_error_text(source))]
    Io {
        /// The file.
        path: PathBuf,
        /// The error.
        #[source]
        source: std::io::Error,
    },
    /// The PNG or EXR encoder or decoder failed.
    #[error("{}: {message}", path.display())]
    Codec {
        /// The file.
        path: PathBuf,
        /// The codec's message.
        message: String,
    },
}

/// Write `img` to `path`: `.png` as 8-bit sRGB (clamped, rounded), `.exr` as linear 32-bit
/// float RGB. The file appears complete or not at all.
///
/// # Errors
/// An unknown extension, a pixel count that does not match the size, or an I/O or
/// encoder failure (the target is then left untouched).
pub fn write_image(path: &Path, img: &ImageRgb) -> Result<(), ImageError> {
    stage_image(path, img)?.commit()
}

/// Write several images all or none: each is encoded completely beside its target first,
/// and only when every one succeeded are they put in place (so a failing variance image
/// does not leave the main image behind).
///
/// # Errors
/// As [`write_image`], for the first image that fails; no target is then touched.
pub fn write_images(images: &[(&Path, &ImageRgb)]) -> Result<(), ImageError> {
    let staged = images
        .iter()
        .map(|(path, img)| stage_image(path, img))
        .collect::<Result<Vec<_>, _>>()?;
    staged.into_iter().try_for_each(atomic::Staged::commit)
}

/// Encode `img` for `path` into a temporary file beside it.
fn stage_image(path: &Path, img: &ImageRgb) -> Result<atomic::Staged, ImageError> {
    check_size(path, img.width, img.height, img.pixels.len())?;
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    match extension.as_str() {
        "png" => png::stage_png(path, img),
        "exr" => self::exr::stage_exr_layers(path, img.width, img.height, &[("", &img.pixels)], &[]),
        _ => Err(ImageError::UnsupportedFormat {
            path: path.to_path_buf(),
            extension,
        }),
    }
}

/// Check that an image of `width` x `height` has `len` pixels and is not empty.
fn check_size(path: &Path, width: u32, height: u32, len: usize) -> Result<(), ImageError> {
    if width == 0 || height == 0 {
        return Err(ImageError::InvalidImage {
            path: path.to_path_buf(),
            message: format!("empty image ({width}x{height})"),
        });
    }
    if width as usize * height as usize != len {
        return Err(ImageError::InvalidImage {
            path: path.to_path_buf(),
            message: format!("{len} pixels do not make a {width}x{height} image"),
        });
    }
    Ok(())
}
