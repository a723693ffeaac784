//! Reading images by extension, as linear RGB: EXR and PFM are linear floats; PNG, JPEG and
//! TGA are 8- or 16-bit values decoded from sRGB (pbrt-v4's default for such files; alpha is
//! dropped).

use std::path::Path;

use mcrender_core::color::{srgb_to_linear, Rgb};

use super::{read_exr, read_pfm, ImageError, ImageRgb};

/// Read `path` as a linear RGB image, by its extension: `.exr`, `.pfm`, `.png`, `.jpg` /
/// `.jpeg` or `.tga`.
///
/// # Errors
/// An unknown extension, or a file that cannot be read or decoded.
pub fn read_image(path: &Path) -> Result<ImageRgb, ImageError> {
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    match extension.as_str() {
        "exr" => read_exr(path),
        "pfm" => read_pfm(path),
        "png" | "jpg" | "jpeg" | "tga" => read_srgb(path),
        _ => Err(ImageError::InvalidImage {
            path: path.to_path_buf(),
            message: format!("unsupported image format \"{extension}\" (use .exr, .pfm, .png, .jpg, .jpeg or .tga)"),
        }),
    }
}

/// Decode an 8- or 16-bit image and undo the sRGB curve.
fn read_srgb(path: &Path) -> Result<ImageRgb, ImageError> {
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
        .map(|p| Rgb::new(srgb_to_linear(p[0]), srgb_to_linear(p[1]), srgb_to_linear(p[2])))
        .collect();
    Ok(ImageRgb { width, height, pixels })
}
