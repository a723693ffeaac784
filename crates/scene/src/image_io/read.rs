//! Reading images by extension, as linear RGB: EXR and PFM are linear floats; PNG, JPEG and
//! TGA are 8- or 16-bit values decoded from sRGB (pbrt-v4's default for such files; alpha is
//! dropped), or with another [`ColorEncoding`] through [`read_image_encoded`].

use std::path::Path;

use mcrender_core::color::{srgb_to_linear, Rgb};

use super::{read_exr, read_pfm, ImageError, ImageRgb};

/// Read `path` as a linear RGB image, by its extension: `.exr`, `.pfm`, `.png`, `.jpg` /
/// `.jpeg` or `.tga`.
///
/// # Errors
/// An unknown extension, or a file that cannot be read or decoded.
pub fn read_image(path: &Path) -> Result<ImageRgb, ImageError> {
    read_image_encoded(path, ColorEncoding::Srgb)
}

/// How the values of an 8- or 16-bit image map to linear values (pbrt-v4
/// `ColorEncoding`; texture parameter `"string encoding"`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ColorEncoding {
    /// The sRGB transfer curve.
    Srgb,
    /// Values are linear already.
    Linear,
    /// `linear = value^gamma`.
    Gamma(f32),
}

impl ColorEncoding {
    /// The linear value of an encoded value in [0, 1].
    #[must_use]
    pub fn to_linear(self, v: f32) -> f32 {
        match self {
            Self::Srgb => srgb_to_linear(v),
            Self::Linear => v,
            Self::Gamma(g) => v.max(0.0).powf(g),
        }
    }
}

/// Read `path` as [`read_image`] does, decoding 8- and 16-bit formats with `encoding`
/// (float formats are linear whatever `encoding` says, as in pbrt-v4).
///
/// # Errors
/// An unknown extension, or a file that cannot be read or decoded.
pub fn read_image_encoded(path: &Path, encoding: ColorEncoding) -> Result<ImageRgb, ImageError> {
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    match extension.as_str() {
        "exr" => read_exr(path),
        "pfm" => read_pfm(path),
        "png" | "jpg" | "jpeg" | "tga" => read_8bit(path, encoding),
        _ => Err(ImageError::InvalidImage {
            path: path.to_path_buf(),
            message: format!("unsupported image format \"{extension}\" (use .exr, .pfm, .png, .jpg, .jpeg or .tga)"),
        }),
    }
}

/// Decode an 8- or 16-bit image and undo its encoding.
fn read_8bit(path: &Path, encoding: ColorEncoding) -> Result<ImageRgb, ImageError> {
    let img = image::open(path).map_err(|e| match e {
        image::ImageError::IoError(source) => ImageError::Io {
            path: path.to_path_buf(),
            source,
        },
        other => ImageError::Codec {
            path: path.to_path_buf(),
            message: other.to_string(),
        },
    })?;
    let rgb = img.to_rgb32f();
    let (width, height) = rgb.dimensions();
    let pixels = rgb
        .pixels()
        .map(|p| {
            Rgb::new(
                encoding.to_linear(p[0]),
                encoding.to_linear(p[1]),
                encoding.to_linear(p[2]),
            )
        })
        .collect();
    Ok(ImageRgb { width, height, pixels })
}
