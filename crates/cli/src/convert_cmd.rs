//! `mcrender convert IN OUT`: re-encode an image (EXR/PFM/PNG/... to PNG/EXR), optionally
//! box-downsampled and scaled, as pbrt's `imgtool convert` does. Used to make the README's
//! side-by-side pictures of our renders and the references.

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use clap::Args;
use mcrender_core::film::downsample_box;
use mcrender_formats::image_io::{read_image, write_image, ImageRgb};

/// Options of `mcrender convert`.
#[derive(Args, Debug)]
pub struct ConvertArgs {
    /// The image to read (EXR, PFM, PNG, JPEG, TGA).
    pub input: PathBuf,
    /// The image to write; the extension picks the format (.png: sRGB 8-bit, clamped;
    /// .exr: linear float).
    pub output: PathBuf,
    /// Box-downsample by this integer factor (must divide the width and height).
    #[arg(long, value_name = "N")]
    pub downsample: Option<u32>,
    /// Multiply every pixel by 2^STOPS before writing.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub exposure: f32,
}

/// Run the command.
pub fn run(args: &ConvertArgs) -> Result<()> {
    if !args.exposure.is_finite() {
        bail!("--exposure must be finite, got {}", args.exposure);
    }
    let mut img = read_image(&args.input).with_context(|| format!("cannot read \"{}\"", args.input.display()))?;
    if let Some(f) = args.downsample {
        let (width, height, pixels) = downsample_box(&img.pixels, img.width, img.height, f)
            .with_context(|| format!("--downsample {f} on \"{}\"", args.input.display()))?;
        img = ImageRgb { width, height, pixels };
    }
    let scale = args.exposure.exp2();
    if scale != 1.0 {
        for p in &mut img.pixels {
            *p *= scale;
        }
    }
    write_image(&args.output, &img).with_context(|| format!("cannot write \"{}\"", args.output.display()))?;
    Ok(())
}
