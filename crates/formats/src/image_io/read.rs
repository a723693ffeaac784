//! Reading images by extension, as linear RGB: EXR and PFM are linear floats; PNG, JPEG and
//! TGA are 8- or 16-bit values decoded from sRGB (pbrt-v4's default for such files; alpha is
//! dropped), or with another [`ColorEncoding`] through [`read_image_encoded`].

use std::io::Cursor;
use std::path::Path;

use mcrender_core::color::{srgb_to_linear, Rgb};

use super::{ImageError, ImageRgb};

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
    let format = ImageFormat::from_path(path)?;
    let bytes = std::fs::read(path).map_err(|source| ImageError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    decode_image(path, format, &bytes, encoding)
}

/// The image file formats read, chosen by extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageFormat {
    /// OpenEXR (linear floats).
    Exr,
    /// Portable float map (linear floats).
    Pfm,
    /// PNG (8 or 16 bits).
    Png,
    /// JPEG.
    Jpeg,
    /// Truevision TGA.
    Tga,
}

impl ImageFormat {
    /// The format of `path` by its extension.
    ///
    /// # Errors
    /// An extension that names none of the formats.
    pub fn from_path(path: &Path) -> Result<Self, ImageError> {
        let extension = path
            .extension()
            .and_then(|e| e.to_str())
            .unwrap_or("")
            .to_ascii_lowercase();
        match extension.as_str() {
            "exr" => Ok(Self::Exr),
            "pfm" => Ok(Self::Pfm),
            "png" => Ok(Self::Png),
            "jpg" | "jpeg" => Ok(Self::Jpeg),
            "tga" => Ok(Self::Tga),
            _ => Err(ImageError::InvalidImage {
                path: path.to_path_buf(),
                message: format!(
                    "unsupported image format {} (use .exr, .pfm, .png, .jpg, .jpeg or .tga)",
                    crate::error::quoted(&extension)
                ),
            }),
        }
    }

    fn codec(self) -> Option<image::ImageFormat> {
        match self {
            Self::Exr | Self::Pfm => None,
            Self::Png => Some(image::ImageFormat::Png),
            Self::Jpeg => Some(image::ImageFormat::Jpeg),
            Self::Tga => Some(image::ImageFormat::Tga),
        }
    }
}

/// The width and height of the image in `bytes`, from its header alone (nothing is
/// decoded, so this is cheap even for a huge image). `path` names the file in errors.
///
/// # Errors
/// When the header cannot be read.
pub fn image_dimensions(path: &Path, format: ImageFormat, bytes: &[u8]) -> Result<(u64, u64), ImageError> {
    match format.codec() {
        None if format == ImageFormat::Exr => super::exr::exr_dimensions(path, bytes),
        None => super::pfm::pfm_dimensions(path, bytes),
        Some(f) => {
            let reader = image::ImageReader::with_format(Cursor::new(bytes), f);
            let (w, h) = reader.into_dimensions().map_err(|e| codec_error(path, e))?;
            Ok((u64::from(w), u64::from(h)))
        }
    }
}

/// Decode the image file `bytes` of `format` as linear RGB, 8- and 16-bit formats with
/// `encoding`. `path` names the file in errors.
///
/// # Errors
/// When the bytes are not a valid image of that format.
pub fn decode_image(
    path: &Path,
    format: ImageFormat,
    bytes: &[u8],
    encoding: ColorEncoding,
) -> Result<ImageRgb, ImageError> {
    match format.codec() {
        None if format == ImageFormat::Exr => super::exr::decode_exr(path, bytes),
        None => super::pfm::decode_pfm_file(path, bytes),
        Some(f) => decode_8bit(path, f, bytes, encoding),
    }
}

fn codec_error(path: &Path, e: image::ImageError) -> ImageError {
    match e {
        image::ImageError::IoError(source) => ImageError::Io {
            path: path.to_path_buf(),
            source,
        },
        other => ImageError::Codec {
            path: path.to_path_buf(),
            message: other.to_string(),
        },
    }
}

/// Decode an 8- or 16-bit image and undo its encoding.
fn decode_8bit(
    path: &Path,
    format: image::ImageFormat,
    bytes: &[u8],
    encoding: ColorEncoding,
) -> Result<ImageRgb, ImageError> {
    let img = image::ImageReader::with_format(Cursor::new(bytes), format)
        .decode()
        .map_err(|e| codec_error(path, e))?;
    let (width, height) = (img.width(), img.height());
    if width == 0 || height == 0 {
        return Err(ImageError::InvalidImage {
            path: path.to_path_buf(),
            message: format!("empty image ({width}x{height})"),
        });
    }
    let color = img.color();
    let pixels = if color.bytes_per_pixel() == color.channel_count() {
        // 8 bits a channel: 256 possible values, converted once each.
        let table: Vec<f32> = (0..=255u8).map(|v| encoding.to_linear(f32::from(v) / 255.0)).collect();
        let rgb = img.to_rgb8();
        drop(img);
        rgb.pixels()
            .map(|p| Rgb::new(table[p[0] as usize], table[p[1] as usize], table[p[2] as usize]))
            .collect()
    } else {
        let rgb = img.to_rgb32f();
        drop(img);
        rgb.pixels()
            .map(|p| {
                Rgb::new(
                    encoding.to_linear(p[0]),
                    encoding.to_linear(p[1]),
                    encoding.to_linear(p[2]),
                )
            })
            .collect()
    };
    Ok(ImageRgb { width, height, pixels })
}
