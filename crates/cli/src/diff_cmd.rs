//! `mcrender diff A B`: compare an image against a reference (B): MSE, relative MSE, mean
//! per channel of each, and the relative error of block means; optionally a false-colour
//! image of the per-pixel relative error.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use clap::Args;
use mcrender_core::color::Rgb;
use mcrender_core::film::{downsample_box, pixel_rel_error, ImageComparison, DEFAULT_BLOCK};
use mcrender_formats::image_io::{read_image, write_image, ImageRgb};

use crate::stdout::say;

/// Lower end of the error image's scale: relative error 10^LOG_MIN and below is pure blue.
const LOG_MIN: f64 = -3.0;
/// Upper end: relative error 10^LOG_MAX (100%) and above is pure red.
const LOG_MAX: f64 = 0.0;

/// Options of `mcrender diff`.
#[derive(Args, Debug)]
pub struct DiffArgs {
    /// The image to test (EXR, PFM, PNG, ...: whatever `render` can read).
    pub a: PathBuf,
    /// The reference image.
    pub b: PathBuf,
    /// Block side in pixels for the block-mean relative error (averages noise away, keeps
    /// bias).
    #[arg(long, default_value_t = DEFAULT_BLOCK)]
    pub block: u32,
    /// Box-downsample B by this integer factor before comparing (e.g. 4 to compare a 256x256
    /// render with a 1024x1024 reference); must divide B's width and height.
    #[arg(long, value_name = "N")]
    pub downsample_b: Option<u32>,
    /// Write a false-colour image (PNG or EXR) of the per-pixel relative error
    /// |a - b| / (|b| + 0.01), averaged over channels, on a log10 scale: blue = 0.1% or
    /// less, white = about 3%, red = 100% or more (blue -> white over 10^-3..10^-1.5,
    /// white -> red over 10^-1.5..10^0).
    #[arg(long, value_name = "ERR.png")]
    pub error_image: Option<PathBuf>,
    /// Print the metrics as JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

fn load(path: &Path) -> Result<ImageRgb> {
    read_image(path).with_context(|| format!("cannot read \"{}\"", path.display()))
}

/// Run the command.
pub fn run(args: &DiffArgs) -> Result<()> {
    let a = load(&args.a)?;
    let mut b = load(&args.b)?;
    if let Some(f) = args.downsample_b {
        let (w, h, px) = downsample_box(&b.pixels, b.width, b.height, f)
            .with_context(|| format!("--downsample-b {f} on \"{}\"", args.b.display()))?;
        b = ImageRgb {
            width: w,
            height: h,
            pixels: px,
        };
    }
    if (a.width, a.height) != (b.width, b.height) {
        bail!(
            "size mismatch: \"{}\" is {}x{}, \"{}\" is {}x{}{}",
            args.a.display(),
            a.width,
            a.height,
            args.b.display(),
            b.width,
            b.height,
            if args.downsample_b.is_some() {
                " after downsampling"
            } else {
                ""
            }
        );
    }
    if args.block == 0 {
        bail!("--block must be positive");
    }
    let cmp = ImageComparison::new(&a.pixels, &b.pixels, a.width, a.height, args.block)?;
    if args.json {
        say!("{}", serde_json::to_string_pretty(&to_json(&cmp))?);
    } else {
        crate::stdout::write(&table(args, &cmp))?;
    }
    if let Some(path) = &args.error_image {
        let err = pixel_rel_error(&a.pixels, &b.pixels);
        let img = ImageRgb {
            width: a.width,
            height: a.height,
            pixels: err.iter().map(|&e| false_colour(e)).collect(),
        };
        write_image(path, &img).with_context(|| format!("cannot write \"{}\"", path.display()))?;
    }
    Ok(())
}

/// The blue-white-red ramp over log10 of the relative error (see `--error-image`).
fn false_colour(e: f64) -> Rgb {
    let t = if e > 0.0 {
        ((e.log10() - LOG_MIN) / (LOG_MAX - LOG_MIN)).clamp(0.0, 1.0)
    } else {
        0.0
    } as f32;
    if t < 0.5 {
        let s = t * 2.0;
        Rgb::new(s, s, 1.0)
    } else {
        let s = (1.0 - t) * 2.0;
        Rgb::new(1.0, s, s)
    }
}

/// The comparison as the table `diff` prints.
fn table(args: &DiffArgs, c: &ImageComparison) -> String {
    let mut t = format!("A: {}\n", args.a.display());
    t += &format!(
        "B: {}{}\n",
        args.b.display(),
        args.downsample_b
            .map(|f| format!(" (box-downsampled {f}x)"))
            .unwrap_or_default()
    );
    t += &format!(
        "size {}x{}, {} blocks of {}x{}\n",
        c.width, c.height, c.blocks, c.block, c.block
    );
    t += &format!("MSE          {:.6e}\n", c.mse);
    t += &format!("relative MSE {:.6e}\n", c.rel_mse);
    t += &format!("{:<22}{:>12}{:>12}{:>12}\n", "", "R", "G", "B");
    for (name, v) in [
        ("mean A", c.mean_a),
        ("mean B", c.mean_b),
        ("mean (A-B)/B", c.mean_rel_diff()),
        ("block rel err mean", c.block_rel_mean),
        ("block rel err max", c.block_rel_max),
    ] {
        t += &format!("{name:<22}{:>12.6}{:>12.6}{:>12.6}\n", v[0], v[1], v[2]);
    }
    t
}

fn to_json(c: &ImageComparison) -> serde_json::Value {
    serde_json::json!({
        "width": c.width,
        "height": c.height,
        "block": c.block,
        "blocks": c.blocks,
        "mse": c.mse,
        "rel_mse": c.rel_mse,
        "mean_a": c.mean_a,
        "mean_b": c.mean_b,
        "mean_rel_diff": c.mean_rel_diff(),
        "block_rel_mean": c.block_rel_mean,
        "block_rel_max": c.block_rel_max,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ramp_ends() {
        assert_eq!(false_colour(0.0), Rgb::new(0.0, 0.0, 1.0));
        assert_eq!(false_colour(1e-4), Rgb::new(0.0, 0.0, 1.0));
        assert_eq!(false_colour(10.0), Rgb::new(1.0, 0.0, 0.0));
        let w = false_colour(10f64.powf(-1.5));
        assert!((w.g - 1.0).abs() < 1e-5 && (w.r - 1.0).abs() < 1e-5 && (w.b - 1.0).abs() < 1e-5);
    }
}
