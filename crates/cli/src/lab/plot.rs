//! Log-log convergence plots: error against samples (per pixel, or points for the pi
//! estimator), one line with markers per series, a legend, and a dashed reference line of
//! slope -1, the 1/N law that the variance and MSE of every unbiased estimator follow.
//! Drawn with plotters into memory and written as an 8-bit sRGB PNG through
//! `write_image`, so the file appears complete or not at all. Text uses the embedded
//! DejaVu Sans: no system fonts are needed.

use std::path::Path;

use anyhow::{anyhow, bail, Context, Result};
use mcrender_core::color::{srgb_to_linear, Rgb};
use mcrender_scene::image_io::{write_image, ImageRgb};
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;

use super::font::{register_plot_font, PLOT_FONT_FAMILY};

/// Width and height of every plot, in pixels.
pub const PLOT_SIZE: (u32, u32) = (800, 600);

/// Series colours (Tableau 10): distinct, and readable on white.
const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// A named series of `(samples, error)` points.
pub type Series = (String, Vec<(f64, f64)>);

/// Write a log-log plot of error against samples per pixel to `path` (a `.png`,
/// [`PLOT_SIZE`]): one coloured line with markers per series, a legend, and a dashed line
/// of slope -1 labelled "1/N" through the first point of the first series.
///
/// # Errors
/// No series, a series without points, a value that is not finite and positive (a log
/// axis cannot show it), a path that does not end in `.png`, or a failed write.
pub fn convergence_plot(path: &Path, title: &str, y_label: &str, series: &[Series]) -> Result<()> {
    log_log_plot(path, title, "samples per pixel", y_label, series)
}

/// [`convergence_plot`] with a chosen x-axis label (e.g. "points N" for the pi estimator).
///
/// # Errors
/// As [`convergence_plot`].
pub fn log_log_plot(path: &Path, title: &str, x_label: &str, y_label: &str, series: &[Series]) -> Result<()> {
    validate(path, series)?;
    let (w, h) = PLOT_SIZE;
    let mut rgb8 = vec![255u8; w as usize * h as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb8, (w, h)).into_drawing_area();
        draw(&root, title, x_label, y_label, series).map_err(|e| anyhow!("cannot draw the plot: {e}"))?;
        root.present().map_err(|e| anyhow!("cannot draw the plot: {e}"))?;
    }
    let img = ImageRgb {
        width: w,
        height: h,
        pixels: rgb8
            .chunks_exact(3)
            .map(|c| Rgb::new(decode(c[0]), decode(c[1]), decode(c[2])))
            .collect(),
    };
    write_image(path, &img).with_context(|| format!("cannot write \"{}\"", path.display()))
}

/// An 8-bit sRGB value as linear light; `write_image` encodes it back to the same byte.
fn decode(v: u8) -> f32 {
    srgb_to_linear(f32::from(v) / 255.0)
}

/// Check that a plot can be written to `path` as far as its name goes: it ends in `.png`.
/// Commands call this before any long computation.
///
/// # Errors
/// Any other extension.
pub fn check_plot_path(path: &Path) -> Result<()> {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    if !ext.eq_ignore_ascii_case("png") {
        bail!("plot \"{}\": expected extension png, found \"{ext}\"", path.display());
    }
    Ok(())
}

fn validate(path: &Path, series: &[Series]) -> Result<()> {
    check_plot_path(path)?;
    if series.is_empty() {
        bail!("a convergence plot needs at least one series");
    }
    for (name, points) in series {
        if points.is_empty() {
            bail!("series \"{name}\" has no points");
        }
        if let Some((x, y)) = points
            .iter()
            .find(|(x, y)| !(x.is_finite() && y.is_finite() && *x > 0.0 && *y > 0.0))
        {
            bail!("series \"{name}\": point ({x}, {y}) is not positive and finite, so a log-log plot cannot show it");
        }
    }
    Ok(())
}

/// The reference line `y = y0 x0 / x` through the first point of the first series.
fn reference(series: &[Series]) -> impl Fn(f64) -> f64 {
    let (x0, y0) = series[0].1[0];
    move |x| y0 * x0 / x
}

/// The axis ranges: every point and the reference line at both ends, with a margin.
fn ranges(series: &[Series]) -> ((f64, f64), (f64, f64)) {
    let points = series.iter().flat_map(|(_, p)| p.iter().copied());
    let (mut x_lo, mut x_hi) = (f64::INFINITY, 0.0f64);
    for (x, _) in points.clone() {
        (x_lo, x_hi) = (x_lo.min(x), x_hi.max(x));
    }
    let r = reference(series);
    let (mut y_lo, mut y_hi) = (r(x_hi), r(x_lo));
    for (_, y) in points {
        (y_lo, y_hi) = (y_lo.min(y), y_hi.max(y));
    }
    ((x_lo / 1.4, x_hi * 1.4), (y_lo / 2.0, y_hi * 2.0))
}

/// A tick value: plain for 0.01 <= |v| < 10^4, else like `1e6` or `2e-5`.
fn tick(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        "0".into()
    } else if !(0.01..1e4).contains(&a) {
        format!("{v:.0e}")
    } else {
        let s = format!("{v:.3}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

type DrawResult<T> =
    std::result::Result<T, DrawingAreaErrorKind<<BitMapBackend<'static> as DrawingBackend>::ErrorType>>;

fn draw(
    root: &DrawingArea<BitMapBackend<'_>, Shift>,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
) -> DrawResult<()> {
    register_plot_font();
    root.fill(&WHITE)?;
    let ((x_lo, x_hi), (y_lo, y_hi)) = ranges(series);
    let mut chart = ChartBuilder::on(root)
        .caption(title, (PLOT_FONT_FAMILY, 24))
        .margin(20)
        .x_label_area_size(56)
        .y_label_area_size(84)
        .build_cartesian_2d((x_lo..x_hi).log_scale(), (y_lo..y_hi).log_scale())?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .label_style((PLOT_FONT_FAMILY, 15))
        .axis_desc_style((PLOT_FONT_FAMILY, 17))
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(&|v| tick(*v))
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(210, 210, 210))
        .draw()?;

    // The 1/N law, dashed, through the first point of the first series.
    let r = reference(series);
    let grey = RGBColor(90, 90, 90);
    let ends = [(x_lo, r(x_lo)), (x_hi, r(x_hi))];
    chart
        .draw_series(DashedLineSeries::new(ends, 10, 6, grey.stroke_width(2)))?
        .label("1/N")
        .legend(move |(x, y)| DashedPathElement::new([(x, y), (x + 24, y)], 6, 4, grey.stroke_width(2)));

    for (i, (name, points)) in series.iter().enumerate() {
        let colour = PALETTE[i % PALETTE.len()];
        let line = colour.stroke_width(2);
        chart
            .draw_series(LineSeries::new(points.iter().copied(), line))?
            .label(name.as_str())
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 24, y)], line));
        // Markers differ by shape too, for readers who cannot tell the colours apart.
        let fill = colour.filled();
        match (i / PALETTE.len() + i) % 3 {
            0 => chart.draw_series(points.iter().map(|&p| Circle::new(p, 4, fill)))?,
            1 => chart.draw_series(points.iter().map(|&p| TriangleMarker::new(p, 6, fill)))?,
            _ => chart.draw_series(points.iter().map(|&p| Cross::new(p, 5, colour.stroke_width(2))))?,
        };
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .label_font((PLOT_FONT_FAMILY, 15))
        .background_style(WHITE.mix(0.9))
        .border_style(RGBColor(160, 160, 160))
        .draw()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use mcrender_core::color::linear_to_srgb;

    fn sample_series() -> Vec<Series> {
        let spp = [1.0, 4.0, 16.0, 64.0, 256.0];
        vec![
            ("uniform-hemisphere".into(), spp.iter().map(|&n| (n, 0.8 / n)).collect()),
            ("cosine-hemisphere".into(), spp.iter().map(|&n| (n, 0.3 / n)).collect()),
            ("mis".into(), spp.iter().map(|&n| (n, 0.02 / n.powf(0.95))).collect()),
        ]
    }

    fn decode_png(path: &Path) -> image::RgbImage {
        image::ImageReader::open(path)
            .unwrap()
            .with_guessed_format()
            .unwrap()
            .decode()
            .expect("a valid PNG")
            .to_rgb8()
    }

    #[test]
    fn every_byte_survives_the_trip_through_linear_light() {
        for b in 0..=255u8 {
            let back = (linear_to_srgb(decode(b)) * 255.0).round() as u8;
            assert_eq!(back, b);
        }
    }

    #[test]
    fn plot_is_a_png_of_the_plot_size_with_every_series_colour() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("convergence.png");
        convergence_plot(
            &path,
            "Direct lighting: MSE against spp",
            "relative MSE",
            &sample_series(),
        )
        .unwrap();
        let img = decode_png(&path);
        assert_eq!(img.dimensions(), PLOT_SIZE);
        for (i, c) in PALETTE.iter().take(3).enumerate() {
            let n = img.pixels().filter(|p| p.0 == [c.0, c.1, c.2]).count();
            assert!(n > 200, "series {i}: {n} pixels of its colour");
        }
        let dark = img.pixels().filter(|p| p.0.iter().all(|&v| v < 80)).count();
        assert!(dark > 2000, "too little text: {dark} dark pixels");
        // No temporary file is left behind.
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[test]
    fn reference_line_has_slope_minus_one_through_the_first_point() {
        let s = sample_series();
        let r = reference(&s);
        assert!((r(1.0) - 0.8).abs() < 1e-12 && (r(256.0) - 0.8 / 256.0).abs() < 1e-12);
        let ((x_lo, x_hi), (y_lo, y_hi)) = ranges(&s);
        assert!(x_lo < 1.0 && x_hi > 256.0);
        assert!(y_lo < 0.02 / 256f64.powf(0.95) && y_hi > 0.8);
    }

    #[test]
    fn ticks_read_as_numbers() {
        assert_eq!(tick(1.0), "1");
        assert_eq!(tick(0.5), "0.5");
        assert_eq!(tick(100.0), "100");
        assert_eq!(tick(1e6), "1e6");
        assert_eq!(tick(2e-5), "2e-5");
    }

    #[test]
    fn bad_series_are_errors_and_write_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("p.png");
        let err = |series: &[Series]| convergence_plot(&path, "t", "e", series).unwrap_err().to_string();
        assert!(err(&[]).contains("at least one series"));
        assert!(err(&[("empty".into(), vec![])]).contains("\"empty\" has no points"));
        assert!(err(&[("zero".into(), vec![(1.0, 0.5), (4.0, 0.0)])]).contains("not positive"));
        assert!(err(&[("nan".into(), vec![(f64::NAN, 0.5)])]).contains("not positive"));
        let bad_ext = convergence_plot(&dir.path().join("p.exr"), "t", "e", &sample_series()).unwrap_err();
        assert!(bad_ext.to_string().contains("png"), "{bad_ext}");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }
}
