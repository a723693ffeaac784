//! OpenEXR output and input with the `exr` crate: linear 32-bit float RGB, optionally
//! with extra named layers (channels `layer.R`, `layer.G`, `layer.B`).

use std::io::Cursor;
use std::path::Path;

use exr::meta::attribute::{AttributeValue, Text};
use exr::meta::MetaData;
use exr::prelude::{AnyChannel, AnyChannels, Encoding, FlatSamples, Image, Layer, LayerAttributes, WritableImage};
use mcrender_core::color::Rgb;

use super::atomic::{stage, Staged};
use super::{check_size, ImageError, ImageRgb};

/// Write an EXR of `width` x `height` with one RGB layer per entry of `layers`, atomically.
/// A layer named `""` is written as the plain `R`, `G`, `B` channels; a layer `"variance"`
/// as `variance.R`, `variance.G`, `variance.B`. Samples are 32-bit floats, ZIP-compressed.
///
/// # Errors
/// No layers, a layer whose pixel count does not match, duplicate layer names, or an I/O
/// or encoder failure (the target is then left untouched).
pub fn write_exr_layers(path: &Path, width: u32, height: u32, layers: &[(&str, &[Rgb])]) -> Result<(), ImageError> {
    write_exr_layers_with_metadata(path, width, height, layers, &[])
}

/// [`write_exr_layers`] with text attributes `(name, value)` in the layer's header (e.g.
/// the samples per pixel of a partial render), readable with [`read_exr_metadata`].
///
/// # Errors
/// As [`write_exr_layers`], and an attribute name or value that is not EXR text.
pub fn write_exr_layers_with_metadata(
    path: &Path,
    width: u32,
    height: u32,
    layers: &[(&str, &[Rgb])],
    metadata: &[(&str, &str)],
) -> Result<(), ImageError> {
    stage_exr_layers(path, width, height, layers, metadata)?.commit()
}

/// [`write_exr_layers_with_metadata`] without the final rename: the complete file, ready to
/// be put in place.
pub(super) fn stage_exr_layers(
    path: &Path,
    width: u32,
    height: u32,
    layers: &[(&str, &[Rgb])],
    metadata: &[(&str, &str)],
) -> Result<Staged, ImageError> {
    if layers.is_empty() {
        return Err(ImageError::InvalidImage {
            path: path.to_path_buf(),
            message: "no layers to write".into(),
        });
    }
    let mut channels = Vec::with_capacity(3 * layers.len());
    for (i, (name, pixels)) in layers.iter().enumerate() {
        check_size(path, width, height, pixels.len())?;
        if layers[..i].iter().any(|(other, _)| other == name) {
            return Err(ImageError::InvalidImage {
                path: path.to_path_buf(),
                message: format!("layer \"{name}\" appears twice"),
            });
        }
        let prefix = if name.is_empty() {
            String::new()
        } else {
            format!("{name}.")
        };
        for (c, channel) in ["R", "G", "B"].iter().enumerate() {
            let samples: Vec<f32> = pixels.iter().map(|p| p.to_array()[c]).collect();
            channels.push(AnyChannel::new(
                format!("{prefix}{channel}").as_str(),
                FlatSamples::F32(samples),
            ));
        }
    }
    let mut attributes = LayerAttributes::default();
    for (name, value) in metadata {
        let (Some(n), Some(v)) = (Text::new_or_none(name), Text::new_or_none(value)) else {
            return Err(ImageError::InvalidImage {
                path: path.to_path_buf(),
                message: format!("attribute \"{name}\" is not EXR text"),
            });
        };
        attributes.other.insert(n, AttributeValue::Text(v));
    }
    let layer = Layer::new(
        (width as usize, height as usize),
        attributes,
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(channels.into()),
    );
    let image = Image::from_layer(layer);
    stage(path, |out| {
        image.write().to_buffered(out).map_err(|e| ImageError::Codec {
            path: path.to_path_buf(),
            message: e.to_string(),
        })
    })
}

/// The text attributes of an EXR file's first layer header, sorted by name.
///
/// # Errors
/// When the file cannot be read or is not an EXR file.
pub fn read_exr_metadata(path: &Path) -> Result<Vec<(String, String)>, ImageError> {
    let meta = MetaData::read_from_file(path, false).map_err(|e| ImageError::Codec {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    let mut out: Vec<(String, String)> = meta
        .headers
        .first()
        .map(|h| {
            h.own_attributes
                .other
                .iter()
                .filter_map(|(k, v)| match v {
                    AttributeValue::Text(t) => Some((k.to_string(), t.to_string())),
                    _ => None,
                })
                .collect()
        })
        .unwrap_or_default();
    out.sort();
    Ok(out)
}

/// Read the first RGB layer of an EXR file (any sample type; alpha is ignored).
///
/// # Errors
/// When the file cannot be read or has no R, G, B channels.
pub fn read_exr(path: &Path) -> Result<ImageRgb, ImageError> {
    let bytes = std::fs::read(path).map_err(|source| ImageError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    decode_exr(path, &bytes)
}

/// The size of the first layer of EXR `bytes`, read from the header alone.
pub(super) fn exr_dimensions(path: &Path, bytes: &[u8]) -> Result<(u64, u64), ImageError> {
    let meta = exr::meta::MetaData::read_from_buffered(Cursor::new(bytes), false).map_err(|e| codec(path, &e))?;
    let header = meta.headers.first().ok_or_else(|| ImageError::Codec {
        path: path.to_path_buf(),
        message: "no layers".into(),
    })?;
    let size = header.layer_size;
    Ok((size.width() as u64, size.height() as u64))
}

/// Decode the first RGB layer of EXR `bytes`; `path` names the file in errors.
pub(super) fn decode_exr(path: &Path, bytes: &[u8]) -> Result<ImageRgb, ImageError> {
    use exr::prelude::{ReadChannels, ReadLayers};
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .rgba_channels(
            |size, _| (size.width(), vec![Rgb::BLACK; size.area()]),
            |(width, pixels): &mut (usize, Vec<Rgb>), pos, (r, g, b, _a): (f32, f32, f32, f32)| {
                pixels[pos.y() * *width + pos.x()] = Rgb::new(r, g, b);
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_buffered(Cursor::new(bytes))
        .map_err(|e| codec(path, &e))?;
    let size = image.layer_data.size;
    let (_, pixels) = image.layer_data.channel_data.pixels;
    let (width, height) = (u32::try_from(size.width()), u32::try_from(size.height()));
    match (width, height) {
        (Ok(width), Ok(height)) if width > 0 && height > 0 => Ok(ImageRgb { width, height, pixels }),
        _ => Err(ImageError::InvalidImage {
            path: path.to_path_buf(),
            message: format!("unusable size {}x{}", size.width(), size.height()),
        }),
    }
}

/// An `exr` decoding error as an [`ImageError`] (one line, the library's message).
fn codec(path: &Path, e: &exr::error::Error) -> ImageError {
    match e {
        exr::error::Error::Io(source) => ImageError::Io {
            path: path.to_path_buf(),
            source: std::io::Error::new(source.kind(), source.to_string()),
        },
        other => ImageError::Codec {
            path: path.to_path_buf(),
            message: other.to_string(),
        },
    }
}
