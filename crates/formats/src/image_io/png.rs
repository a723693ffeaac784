//! PNG output: 8-bit sRGB, each channel clamped to [0, 1], encoded with
//! [`linear_to_srgb`] and rounded to the nearest integer.

use std::path::Path;

use image::codecs::png::PngEncoder;
use image::{ExtendedColorType, ImageEncoder};
use mcrender_core::color::{linear_to_srgb, Rgb};

use super::atomic::{stage, Staged};
use super::{ImageError, ImageRgb};

/// One linear channel as an 8-bit sRGB value (NaN becomes 0).
#[must_use]
pub fn encode_channel(v: f32) -> u8 {
    if v.is_nan() {
        return 0;
    }
    (linear_to_srgb(v) * 255.0).round().clamp(0.0, 255.0) as u8
}

/// Write `img` as an 8-bit sRGB PNG beside `path`, ready to be put in place.
pub(super) fn stage_png(path: &Path, img: &ImageRgb) -> Result<Staged, ImageError> {
    let bytes: Vec<u8> = img
        .pixels
        .iter()
        .flat_map(|p: &Rgb| [encode_channel(p.r), encode_channel(p.g), encode_channel(p.b)])
        .collect();
    stage(path, |out| {
        PngEncoder::new(out)
            .write_image(&bytes, img.width, img.height, ExtendedColorType::Rgb8)
            .map_err(|e| ImageError::Codec {
                path: path.to_path_buf(),
                message: e.to_string(),
            })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn channels_are_srgb_encoded_clamped_and_rounded() {
        assert_eq!(encode_channel(0.0), 0);
        assert_eq!(encode_channel(1.0), 255);
        assert_eq!(encode_channel(0.5), 188);
        assert_eq!(encode_channel(7.0), 255);
        assert_eq!(encode_channel(-1.0), 0);
        assert_eq!(encode_channel(f32::NAN), 0);
    }
}
