//! Portable float maps (`.pfm`): a text header `PF` (RGB) or `Pf` (grey), the size, and a
//! scale whose sign gives the byte order (negative: little endian), then 32-bit floats row
//! by row from the *bottom* of the image.

use std::path::Path;

use mcrender_core::color::Rgb;

use super::{ImageError, ImageRgb};

/// Read a PFM file; grey images become RGB with equal channels. The header's scale
/// magnitude is ignored, as pbrt does.
///
/// # Errors
/// When the file cannot be read, or the header or the data size is malformed.
pub fn read_pfm(path: &Path) -> Result<ImageRgb, ImageError> {
    let bytes = std::fs::read(path).map_err(|source| ImageError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    decode_pfm_file(path, &bytes)
}

/// Decode PFM `bytes`; `path` names the file in errors.
pub(super) fn decode_pfm_file(path: &Path, bytes: &[u8]) -> Result<ImageRgb, ImageError> {
    decode_pfm(bytes).map_err(|message| invalid(path, &message))
}

/// The size in a PFM header.
pub(super) fn pfm_dimensions(path: &Path, bytes: &[u8]) -> Result<(u64, u64), ImageError> {
    let h = header(bytes).map_err(|message| invalid(path, &message))?;
    Ok((u64::from(h.width), u64::from(h.height)))
}

fn invalid(path: &Path, message: &str) -> ImageError {
    ImageError::Codec {
        path: path.to_path_buf(),
        message: format!("not a valid PFM file: {message}"),
    }
}

/// The fields of a PFM header and where the data starts.
struct Header {
    channels: u64,
    width: u32,
    height: u32,
    scale: f32,
    data_start: usize,
}

/// Parse the header: three whitespace-separated fields after the magic, then one
/// whitespace byte.
fn header(bytes: &[u8]) -> Result<Header, String> {
    let mut pos = 0;
    let mut next_token = || -> Result<String, String> {
        while pos < bytes.len() && bytes[pos].is_ascii_whitespace() {
            pos += 1;
        }
        let start = pos;
        while pos < bytes.len() && !bytes[pos].is_ascii_whitespace() {
            pos += 1;
        }
        if start == pos {
            return Err("truncated header".into());
        }
        let token = String::from_utf8_lossy(&bytes[start..pos]).into_owned();
        pos += 1; // the single whitespace byte that ends the field
        Ok(token)
    };
    let channels = match next_token()?.as_str() {
        "PF" => 3,
        "Pf" => 1,
        other => return Err(format!("bad magic {} (expected PF or Pf)", crate::error::quoted(other))),
    };
    let width: u32 = next_token()?.parse().map_err(|_| "bad width".to_string())?;
    let height: u32 = next_token()?.parse().map_err(|_| "bad height".to_string())?;
    let scale: f32 = next_token()?.parse().map_err(|_| "bad scale".to_string())?;
    if width == 0 || height == 0 || !scale.is_finite() || scale == 0.0 {
        return Err(format!("bad size {width}x{height} or scale {scale}"));
    }
    Ok(Header {
        channels,
        width,
        height,
        scale,
        data_start: pos,
    })
}

/// Decode PFM bytes.
fn decode_pfm(bytes: &[u8]) -> Result<ImageRgb, String> {
    let Header {
        channels,
        width,
        height,
        scale,
        data_start: pos,
    } = header(bytes)?;
    let count = (u64::from(width) * u64::from(height)).saturating_mul(channels);
    let data = bytes.get(pos.min(bytes.len())..).unwrap_or_default();
    if (data.len() as u64) / 4 < count {
        return Err(format!(
            "{} bytes of data for a {width}x{height} image of {channels} channel(s)",
            data.len()
        ));
    }
    let little = scale < 0.0;
    let values: Vec<f32> = data
        .chunks_exact(4)
        .take(count as usize)
        .map(|c| {
            let b = [c[0], c[1], c[2], c[3]];
            if little {
                f32::from_le_bytes(b)
            } else {
                f32::from_be_bytes(b)
            }
        })
        .collect();
    let (w, h, ch) = (width as usize, height as usize, channels as usize);
    let mut pixels = Vec::with_capacity(w * h);
    // Rows are stored bottom to top.
    for y in (0..h).rev() {
        for x in 0..w {
            let i = (y * w + x) * ch;
            pixels.push(if ch == 3 {
                Rgb::new(values[i], values[i + 1], values[i + 2])
            } else {
                Rgb::splat(values[i])
            });
        }
    }
    Ok(ImageRgb { width, height, pixels })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pfm(magic: &str, w: u32, h: u32, scale: &str, values: &[f32], little: bool) -> Vec<u8> {
        let mut b = format!("{magic}\n{w} {h}\n{scale}\n").into_bytes();
        for v in values {
            b.extend(if little { v.to_le_bytes() } else { v.to_be_bytes() });
        }
        b
    }

    #[test]
    fn reads_rgb_and_grey_in_both_byte_orders_bottom_row_first() {
        let v = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
        let img = decode_pfm(&pfm("PF", 1, 2, "-1.0", &v, true)).unwrap();
        assert_eq!(img.pixels, vec![Rgb::new(4.0, 5.0, 6.0), Rgb::new(1.0, 2.0, 3.0)]);
        let img = decode_pfm(&pfm("PF", 2, 1, "1.0", &v, false)).unwrap();
        assert_eq!(img.pixels, vec![Rgb::new(1.0, 2.0, 3.0), Rgb::new(4.0, 5.0, 6.0)]);
        let img = decode_pfm(&pfm("Pf", 3, 1, "-2", &v[..3], true)).unwrap();
        assert_eq!(img.pixels, vec![Rgb::splat(1.0), Rgb::splat(2.0), Rgb::splat(3.0)]);
    }

    #[test]
    fn malformed_files_are_errors() {
        assert!(decode_pfm(b"P6\n1 1\n255\n").unwrap_err().contains("bad magic"));
        assert!(decode_pfm(b"PF\n1").unwrap_err().contains("truncated"));
        assert!(decode_pfm(b"PF\n1 1\n-1\n\0\0").unwrap_err().contains("bytes of data"));
        assert!(decode_pfm(b"PF\n0 1\n-1\n").unwrap_err().contains("bad size"));
        assert!(decode_pfm(b"PF\nx 1\n-1\n").unwrap_err().contains("bad width"));
    }
}
