//! Reading the images a Mitsuba scene names (bitmap textures, envmaps) with their memory
//! counted against the load's [`LoadLimits`](crate::limits::LoadLimits) *before* decoding,
//! from the image's header, with the same per-image estimates as the pbrt-v4 loader
//! (`crate::limits`). The total is reported as [`LoadedScene::image_bytes`](
//! crate::pbrt::LoadedScene::image_bytes) for the command line's memory check.

use crate::error::{io_error_text, quoted, Location, SceneError};
use crate::image_io::{decode_image, image_dimensions, ColorEncoding, ImageError, ImageFormat, ImageRgb};
use crate::limits::{count_image_bytes, env_image_bytes, image_texture_bytes};

use super::builder::Builder;

/// What an image is read for, which decides the memory it needs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageUse {
    /// A bitmap texture (MIP-mapped).
    Texture,
    /// An environment map (image plus sampling distribution).
    Environment,
}

impl Builder {
    /// Read the image `file` (as written in the scene, resolved against its directory and
    /// search paths; `what` in errors, e.g. "image") for `purpose`, refusing it from its
    /// header alone when decoding it would pass the memory limit.
    pub fn read_image_counted(
        &mut self,
        file: &str,
        what: &str,
        encoding: ColorEncoding,
        purpose: ImageUse,
        loc: &Location,
    ) -> Result<ImageRgb, SceneError> {
        let path = &self.resolve(file);
        let error = |err: ImageError| {
            let why = match &err {
                ImageError::Io { source, .. } => io_error_text(source),
                other => other.to_string(),
            };
            SceneError::io(loc, format!("cannot read {what} {}: {why}", quoted(file)))
        };
        let format = ImageFormat::from_path(path).map_err(error)?;
        let bytes = self.reader.files().read(path).map_err(|source| {
            error(ImageError::Io {
                path: path.to_path_buf(),
                source,
            })
        })?;
        let (w, h) = image_dimensions(path, format, &bytes).map_err(error)?;
        let need = match purpose {
            ImageUse::Texture => image_texture_bytes(w, h),
            ImageUse::Environment => env_image_bytes(w, h),
        };
        count_image_bytes(
            &mut self.image_bytes,
            need,
            &format!("{what} {} ({w}x{h})", quoted(file)),
            &self.limits,
        )
        .map_err(|m| SceneError::invalid(loc, m))?;
        decode_image(path, format, &bytes, encoding).map_err(error)
    }
}
