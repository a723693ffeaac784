//! Contact sheets: renders of one size laid out in a grid, each under a band that carries
//! its label (white text on dark grey), for `mcrender bounces` and `mcrender compare`.
//! The sheet is a linear [`ImageRgb`] like the renders, so it is written with
//! `write_image` (PNG gets the sRGB encoding there).

use anyhow::{bail, Result};
use mcrender_core::color::Rgb;
use mcrender_formats::image_io::ImageRgb;

use super::font::{draw_text, sans, text_width};

/// Pixels between cells and around the sheet.
pub const GAP: u32 = 4;
/// Label size in pixels per em when the labels fit; smaller labels are shrunk to fit the
/// cell width, down to [`MIN_LABEL_PX`], and clipped beyond that.
pub const LABEL_PX: f32 = 16.0;
/// The smallest label size.
pub const MIN_LABEL_PX: f32 = 9.0;
/// Pixels of band above and below the text.
const BAND_PAD: u32 = 3;
/// Pixels of band left and right of the text.
const SIDE_PAD: f32 = 4.0;
/// Colour of the gaps (linear).
pub const BACKGROUND: Rgb = Rgb::BLACK;
/// Colour of the label bands (linear; about 60/255 once sRGB-encoded).
pub const BAND: Rgb = Rgb::splat(0.045);
/// Colour of the label text (linear).
pub const TEXT: Rgb = Rgb::WHITE;

/// Lay `images` out left to right, top to bottom, `columns` per row (fewer when there are
/// fewer images), each under a band with its label centred in it. The sheet is
/// `GAP + cols (w + GAP)` wide and `GAP + rows (band + h + GAP)` high, where the band is
/// the label's line height plus a few pixels.
///
/// # Errors
/// No images, zero columns, an empty image, a pixel count that does not match its size,
/// or images of different sizes.
pub fn contact_sheet(images: &[(String, ImageRgb)], columns: usize) -> Result<ImageRgb> {
    let Some((_, first)) = images.first() else {
        bail!("a contact sheet needs at least one image");
    };
    if columns == 0 {
        bail!("a contact sheet needs at least one column");
    }
    let (w, h) = (first.width, first.height);
    for (label, img) in images {
        if img.width == 0 || img.height == 0 || img.pixels.len() != img.width as usize * img.height as usize {
            bail!(
                "image \"{label}\" is not a valid {}x{} image ({} pixels)",
                img.width,
                img.height,
                img.pixels.len()
            );
        }
        if (img.width, img.height) != (w, h) {
            bail!(
                "image \"{label}\" is {}x{} but \"{}\" is {w}x{h}: a contact sheet needs images of one size",
                img.width,
                img.height,
                images[0].0
            );
        }
    }

    let cols = columns.min(images.len()) as u32;
    let rows = images.len().div_ceil(cols as usize) as u32;
    let px = label_px(images.iter().map(|(l, _)| l.as_str()), w);
    let band = band_height(px);
    let mut sheet = ImageRgb {
        width: GAP + cols * (w + GAP),
        height: GAP + rows * (band + h + GAP),
        pixels: Vec::new(),
    };
    sheet.pixels = vec![BACKGROUND; sheet.width as usize * sheet.height as usize];

    for (i, (label, img)) in images.iter().enumerate() {
        let (c, r) = (i as u32 % cols, i as u32 / cols);
        let x0 = GAP + c * (w + GAP);
        let y0 = GAP + r * (band + h + GAP);
        fill(&mut sheet, x0, y0, w, band, BAND);
        draw_label(&mut sheet, label, px, (x0, y0, w, band));
        for y in 0..h {
            let src = &img.pixels[(y * w) as usize..((y + 1) * w) as usize];
            let start = ((y0 + band + y) * sheet.width + x0) as usize;
            sheet.pixels[start..start + w as usize].copy_from_slice(src);
        }
    }
    Ok(sheet)
}

/// `img` scaled by `2^stops`: +1 doubles the radiance, -1 halves it. A simple tone
/// adjustment before 8-bit output, e.g. to make a dim render readable on a sheet.
#[must_use]
#[allow(dead_code)] // No command adjusts exposure yet; kept for sheets of dim renders.
pub fn exposure(img: &ImageRgb, stops: f32) -> ImageRgb {
    let k = stops.exp2();
    ImageRgb {
        width: img.width,
        height: img.height,
        pixels: img.pixels.iter().map(|p| p.map(|v| v * k)).collect(),
    }
}

/// The label size for cells `cell_width` wide: [`LABEL_PX`], or smaller so that the
/// widest label fits, but not below [`MIN_LABEL_PX`].
fn label_px<'a>(labels: impl Iterator<Item = &'a str>, cell_width: u32) -> f32 {
    let room = (cell_width as f32 - 2.0 * SIDE_PAD).max(1.0);
    let widest = labels.map(|l| text_width(l, LABEL_PX)).fold(0.0, f32::max);
    if widest <= room {
        LABEL_PX
    } else {
        (LABEL_PX * room / widest).max(MIN_LABEL_PX)
    }
}

/// Band height for labels of `px` pixels per em: the font's line height plus padding.
fn band_height(px: f32) -> u32 {
    use ab_glyph::{Font, PxScale, ScaleFont};
    let font = sans().as_scaled(PxScale::from(px));
    (font.ascent() - font.descent()).ceil() as u32 + 2 * BAND_PAD
}

fn fill(img: &mut ImageRgb, x0: u32, y0: u32, w: u32, h: u32, colour: Rgb) {
    for y in y0..y0 + h {
        let start = (y * img.width + x0) as usize;
        img.pixels[start..start + w as usize].fill(colour);
    }
}

/// Draw `label` centred in the band `(x, y, w, h)` (left-aligned when it is too wide),
/// blending [`TEXT`] over the band by coverage and clipping to the band.
fn draw_label(img: &mut ImageRgb, label: &str, px: f32, (x, y, w, h): (u32, u32, u32, u32)) {
    let tw = text_width(label, px);
    let left = x as f32 + ((w as f32 - tw) / 2.0).max(SIDE_PAD);
    let top = (y + BAND_PAD) as f32;
    let (x_end, y_end) = (i64::from(x + w), i64::from(y + h));
    let width = img.width;
    draw_text(label, px, left, top, |gx, gy, coverage| {
        if gx >= i64::from(x) && gx < x_end && gy >= i64::from(y) && gy < y_end {
            let p = &mut img.pixels[gy as usize * width as usize + gx as usize];
            *p = Rgb::new(
                p.r + (TEXT.r - p.r) * coverage,
                p.g + (TEXT.g - p.g) * coverage,
                p.b + (TEXT.b - p.b) * coverage,
            );
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat(w: u32, h: u32, v: f32) -> ImageRgb {
        ImageRgb {
            width: w,
            height: h,
            pixels: vec![Rgb::splat(v); (w * h) as usize],
        }
    }

    fn labelled(labels: &[&str], w: u32, h: u32) -> Vec<(String, ImageRgb)> {
        labels
            .iter()
            .enumerate()
            .map(|(i, l)| (l.to_string(), flat(w, h, 0.2 + 0.1 * i as f32)))
            .collect()
    }

    #[test]
    fn sheet_has_the_grid_size_and_each_image_in_its_cell() {
        let images = labelled(&["depth 1", "depth 2", "depth 4", "depth 8", "depth 16"], 96, 48);
        let sheet = contact_sheet(&images, 3).unwrap();
        let band = band_height(LABEL_PX);
        assert!((18..=28).contains(&band), "{band}");
        assert_eq!(sheet.width, GAP + 3 * (96 + GAP));
        assert_eq!(sheet.height, GAP + 2 * (band + 48 + GAP));
        assert_eq!(sheet.pixels.len(), (sheet.width * sheet.height) as usize);
        for (i, (_, img)) in images.iter().enumerate() {
            let (c, r) = (i as u32 % 3, i as u32 / 3);
            let (x0, y0) = (GAP + c * (96 + GAP), GAP + r * (band + 48 + GAP) + band);
            assert_eq!(sheet.get(x0, y0), img.pixels[0]);
            assert_eq!(sheet.get(x0 + 95, y0 + 47), img.pixels[0]);
            assert_eq!(sheet.get(x0 - 1, y0), BACKGROUND, "gap left of image {i}");
        }
        // The sixth cell is empty.
        assert_eq!(
            sheet.get(GAP + 2 * (96 + GAP) + 10, sheet.height - GAP - 10),
            BACKGROUND
        );
        // Fewer images than columns: one row, no empty columns.
        let one = contact_sheet(&images[..2], 8).unwrap();
        assert_eq!((one.width, one.height), (GAP + 2 * (96 + GAP), GAP + band + 48 + GAP));
    }

    #[test]
    fn label_band_carries_white_text_on_dark_grey() {
        let images = labelled(&["uniform-hemisphere", "mis"], 160, 32);
        let sheet = contact_sheet(&images, 2).unwrap();
        let band = band_height(LABEL_PX);
        for cell in 0..2u32 {
            let x0 = GAP + cell * (160 + GAP);
            let mut text = 0;
            let mut white = 0;
            for y in GAP..GAP + band {
                for x in x0..x0 + 160 {
                    let p = sheet.get(x, y);
                    assert!(p.r >= BAND.r - 1e-6 && p.r <= 1.0 && p.r == p.g && p.g == p.b, "{p:?}");
                    text += usize::from(p != BAND);
                    white += usize::from(p.r > 0.9);
                }
            }
            assert!(
                text > 40 && white > 10,
                "cell {cell}: {text} text pixels, {white} white"
            );
            // Corners of the band are bare.
            assert_eq!(sheet.get(x0, GAP), BAND);
            assert_eq!(sheet.get(x0 + 159, GAP + band - 1), BAND);
        }
        // Different labels, different ink.
        let ink = |cell: u32| -> Vec<Rgb> {
            let x0 = GAP + cell * (160 + GAP);
            (GAP..GAP + band)
                .flat_map(|y| (x0..x0 + 160).map(move |x| (x, y)))
                .map(|(x, y)| sheet.get(x, y))
                .collect()
        };
        assert_ne!(ink(0), ink(1));
    }

    #[test]
    fn long_labels_shrink_to_fit_narrow_cells_and_never_spill() {
        let images = labelled(&["a rather long label for a small image", "x"], 40, 20);
        let sheet = contact_sheet(&images, 2).unwrap();
        let px = label_px(images.iter().map(|(l, _)| l.as_str()), 40);
        assert_eq!(px, MIN_LABEL_PX);
        let band = band_height(px);
        assert_eq!(sheet.height, GAP + band + 20 + GAP);
        // The gap between the two cells stays background: the label was clipped.
        for y in 0..sheet.height {
            assert_eq!(sheet.get(GAP + 40, y), BACKGROUND, "row {y}");
        }
        assert!(label_px(["short"].into_iter(), 200) == LABEL_PX);
        let mid = label_px(["0123456789abcdef"].into_iter(), 120);
        assert!(mid < LABEL_PX && mid > MIN_LABEL_PX, "{mid}");
    }

    #[test]
    fn bad_input_is_an_error() {
        assert!(contact_sheet(&[], 2)
            .unwrap_err()
            .to_string()
            .contains("at least one image"));
        let images = labelled(&["a", "b"], 8, 8);
        assert!(contact_sheet(&images, 0).unwrap_err().to_string().contains("column"));
        let mut mixed = images.clone();
        mixed[1].1 = flat(8, 9, 0.5);
        let e = contact_sheet(&mixed, 2).unwrap_err().to_string();
        assert!(e.contains("8x9") && e.contains("one size"), "{e}");
        let mut broken = images;
        broken[0].1.pixels.pop();
        assert!(contact_sheet(&broken, 2).is_err());
    }

    #[test]
    fn exposure_scales_by_powers_of_two() {
        let img = flat(2, 2, 0.25);
        assert_eq!(exposure(&img, 1.0).pixels[3], Rgb::splat(0.5));
        assert_eq!(exposure(&img, -2.0).pixels[0], Rgb::splat(0.0625));
        assert_eq!(exposure(&img, 0.0), img);
    }
}
