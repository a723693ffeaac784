//! The one typeface of the lab's pictures: DejaVu Sans, embedded (the `dejavu` crate ships
//! the TTF bytes), rasterised by `ab_glyph`. No system fonts are needed, so the pictures
//! look the same on every machine, CI included.

use std::sync::OnceLock;

use ab_glyph::{point, Font, FontRef, Glyph, PxScale, ScaleFont};

/// The family name under which [`register_plot_font`] registers the font with plotters.
pub const PLOT_FONT_FAMILY: &str = "sans-serif";

/// DejaVu Sans Regular.
pub fn sans() -> &'static FontRef<'static> {
    static FONT: OnceLock<FontRef<'static>> = OnceLock::new();
    FONT.get_or_init(|| FontRef::try_from_slice(dejavu::sans::regular()).expect("DejaVu Sans is a valid TTF"))
}

/// Register DejaVu Sans with plotters as [`PLOT_FONT_FAMILY`] (once per process).
pub fn register_plot_font() {
    static DONE: OnceLock<()> = OnceLock::new();
    DONE.get_or_init(|| {
        if plotters::style::register_font(
            PLOT_FONT_FAMILY,
            plotters::style::FontStyle::Normal,
            dejavu::sans::regular(),
        )
        .is_err()
        {
            unreachable!("DejaVu Sans is a valid TTF");
        }
    });
}

/// The advance width of `text` at `px` pixels per em, kerning included.
pub fn text_width(text: &str, px: f32) -> f32 {
    let font = sans().as_scaled(PxScale::from(px));
    let mut width = 0.0;
    let mut prev = None;
    for c in text.chars() {
        let id = font.glyph_id(c);
        if let Some(p) = prev {
            width += font.kern(p, id);
        }
        width += font.h_advance(id);
        prev = Some(id);
    }
    width
}

/// Rasterise `text` at `px` pixels per em with its top-left corner at `(x, y)`: calls
/// `plot(column, row, coverage)` for every covered pixel, coverage in (0, 1]. Columns and
/// rows may be negative or beyond any image; the caller clips.
pub fn draw_text(text: &str, px: f32, x: f32, y: f32, mut plot: impl FnMut(i64, i64, f32)) {
    let font = sans().as_scaled(PxScale::from(px));
    let baseline = y + font.ascent();
    let mut caret = x;
    let mut prev = None;
    for c in text.chars() {
        let id = font.glyph_id(c);
        if let Some(p) = prev {
            caret += font.kern(p, id);
        }
        let glyph: Glyph = id.with_scale_and_position(PxScale::from(px), point(caret, baseline));
        caret += font.h_advance(id);
        prev = Some(id);
        if let Some(outline) = sans().outline_glyph(glyph) {
            let bounds = outline.px_bounds();
            outline.draw(|gx, gy, coverage| {
                if coverage > 0.0 {
                    plot(
                        bounds.min.x as i64 + i64::from(gx),
                        bounds.min.y as i64 + i64::from(gy),
                        coverage.min(1.0),
                    );
                }
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_has_width_and_ink_inside_its_box() {
        let px = 20.0;
        let w = text_width("MIS 16 spp", px);
        assert!(w > 60.0 && w < 140.0, "{w}");
        assert_eq!(text_width("", px), 0.0);
        let mut ink = 0.0;
        let (mut min_x, mut max_x, mut min_y, mut max_y) = (i64::MAX, i64::MIN, i64::MAX, i64::MIN);
        draw_text("MIS 16 spp", px, 10.0, 5.0, |x, y, c| {
            ink += c;
            (min_x, max_x, min_y, max_y) = (min_x.min(x), max_x.max(x), min_y.min(y), max_y.max(y));
        });
        assert!(ink > 30.0, "{ink}");
        assert!(min_x >= 10 && (max_x as f32) <= 10.0 + w + 1.0, "{min_x}..{max_x}");
        assert!(min_y >= 5 && max_y <= 5 + px as i64 + 2, "{min_y}..{max_y}");
    }
}
