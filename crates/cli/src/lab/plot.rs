//! Log-log convergence plots: error against samples (per pixel, or points for the pi
//! estimator), one line with markers per series, a legend, and a dashed reference line of
//! slope -1, the 1/N law that the variance and MSE of every unbiased estimator follow.
//! Drawn with plotters into memory and written as an 8-bit sRGB PNG through
//! `write_image`, so the file appears complete or not at all. Text uses the embedded
//! DejaVu Sans: no system fonts are needed.

use std::path::Path;

use anyhow::{anyhow, bail, Context, Result};
use mcrender_core::color::{srgb_to_linear, Rgb};
use mcrender_formats::image_io::{write_image, ImageRgb};
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

/// Where the light grid lines of a log axis go: 1..9 times each power of ten.
const MINOR: [f64; 9] = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0];

/// A named series of `(samples, error)` points.
pub type Series = (String, Vec<(f64, f64)>);

/// Write a log-log plot of error against samples per pixel to `path` (a `.png`,
/// [`PLOT_SIZE`]): one coloured line with markers per series, a legend, and a dashed line
/// of slope -1 labelled "1/N" through the first point shown.
///
/// A point whose samples or error is not finite and positive (say the variance estimated
/// from a single sample, which is 0) has no place on a log axis: it is left out, and the
/// number of points left out is returned. A series left with no point is left out of the
/// legend too; colours stay tied to the series' positions.
///
/// # Errors
/// No series, a series without points, no point that can be shown at all, a path that
/// does not end in `.png`, or a failed write.
pub fn convergence_plot(path: &Path, title: &str, y_label: &str, series: &[Series]) -> Result<usize> {
    log_log_plot(path, title, "samples per pixel", y_label, series)
}

/// [`convergence_plot`] with a chosen x-axis label (e.g. "points N" for the pi estimator).
///
/// # Errors
/// As [`convergence_plot`].
pub fn log_log_plot(path: &Path, title: &str, x_label: &str, y_label: &str, series: &[Series]) -> Result<usize> {
    let (shown, left_out) = drawable(path, series)?;
    let (w, h) = PLOT_SIZE;
    let mut rgb8 = vec![255u8; w as usize * h as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb8, (w, h)).into_drawing_area();
        draw(&root, title, x_label, y_label, &shown).map_err(|e| anyhow!("cannot draw the plot: {e}"))?;
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
    write_image(path, &img).with_context(|| format!("cannot write \"{}\"", path.display()))?;
    Ok(left_out)
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

/// A series as drawn: its position in the input (which picks its colour and marker), its
/// name, and its points that a log-log plot can show.
struct Shown<'a> {
    index: usize,
    name: &'a str,
    points: Vec<(f64, f64)>,
}

/// The series with their drawable points (finite and positive), and how many points were
/// left out.
fn drawable<'a>(path: &Path, series: &'a [Series]) -> Result<(Vec<Shown<'a>>, usize)> {
    check_plot_path(path)?;
    if series.is_empty() {
        bail!("a convergence plot needs at least one series");
    }
    let mut shown = Vec::new();
    let mut left_out = 0;
    for (index, (name, points)) in series.iter().enumerate() {
        if points.is_empty() {
            bail!("series \"{name}\" has no points");
        }
        let good: Vec<(f64, f64)> = points
            .iter()
            .copied()
            .filter(|(x, y)| x.is_finite() && y.is_finite() && *x > 0.0 && *y > 0.0)
            .collect();
        left_out += points.len() - good.len();
        if !good.is_empty() {
            shown.push(Shown {
                index,
                name,
                points: good,
            });
        }
    }
    if shown.is_empty() {
        bail!("no point of any series is positive and finite, so a log-log plot cannot show one");
    }
    Ok((shown, left_out))
}

/// The reference line `y = y0 x0 / x` through the first point shown.
fn reference(series: &[Shown]) -> impl Fn(f64) -> f64 {
    let (x0, y0) = series[0].points[0];
    move |x| y0 * x0 / x
}

/// The axis ranges: every point and the reference line at both ends, with a margin.
fn ranges(series: &[Shown]) -> ((f64, f64), (f64, f64)) {
    let points = series.iter().flat_map(|s| s.points.iter().copied());
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

/// A tick value: plain for 0.01 <= |v| < 10^4, else like `1e6`, `1.64e4` or `2e-5`
/// (three significant digits at most).
fn tick(v: f64) -> String {
    let trim = |s: &str| {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s.to_string()
        }
    };
    let a = v.abs();
    if a == 0.0 {
        "0".into()
    } else if (0.01..1e4).contains(&a) {
        trim(&format!("{v:.3}"))
    } else {
        let s = format!("{v:.2e}");
        match s.split_once('e') {
            Some((mantissa, exp)) => format!("{}e{exp}", trim(mantissa)),
            None => s,
        }
    }
}

/// `m 10^k` for every `m` in `mantissas` and integer `k`, within `[lo, hi]` (with a
/// little tolerance for rounding), ascending.
fn log_grid(lo: f64, hi: f64, mantissas: &[f64]) -> Vec<f64> {
    let (k0, k1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    (k0..=k1)
        .flat_map(|k| mantissas.iter().map(move |m| m * 10f64.powi(k)))
        .filter(|&v| v >= lo * (1.0 - 1e-9) && v <= hi * (1.0 + 1e-9))
        .collect()
}

/// Labelled ticks of a log axis over `[lo, hi]`: the decades when there are at least
/// three, else 1-2-5 steps, else every 1..9 step.
fn log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    for mantissas in [
        &[1.0][..],
        &[1.0, 2.0, 5.0],
        &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0],
    ] {
        let ticks = log_grid(lo, hi, mantissas);
        if ticks.len() >= 3 {
            return ticks;
        }
    }
    log_grid(lo, hi, &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0])
}

/// Labelled ticks of the x axis: the sample counts of the data themselves when there are
/// few (a convergence study's 1, 2, 4, 8, ... spp), else [`log_ticks`].
fn x_ticks(series: &[Shown], lo: f64, hi: f64) -> Vec<f64> {
    let mut xs: Vec<f64> = series.iter().flat_map(|s| s.points.iter().map(|p| p.0)).collect();
    xs.sort_by(f64::total_cmp);
    xs.dedup();
    if xs.len() <= 12 {
        xs
    } else {
        log_ticks(lo, hi)
    }
}

type DrawResult<T> =
    std::result::Result<T, DrawingAreaErrorKind<<BitMapBackend<'static> as DrawingBackend>::ErrorType>>;

fn draw(
    root: &DrawingArea<BitMapBackend<'_>, Shift>,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Shown],
) -> DrawResult<()> {
    register_plot_font();
    root.fill(&WHITE)?;
    let ((x_lo, x_hi), (y_lo, y_hi)) = ranges(series);
    let mut chart = ChartBuilder::on(root)
        .caption(title, (PLOT_FONT_FAMILY, 24))
        .margin(20)
        .x_label_area_size(56)
        .y_label_area_size(84)
        .build_cartesian_2d(
            (x_lo..x_hi)
                .log_scale()
                .with_key_points(x_ticks(series, x_lo, x_hi))
                .with_light_points(log_grid(x_lo, x_hi, &MINOR)),
            (y_lo..y_hi)
                .log_scale()
                .with_key_points(log_ticks(y_lo, y_hi))
                .with_light_points(log_grid(y_lo, y_hi, &MINOR)),
        )?;
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

    for &Shown {
        index: i,
        name,
        ref points,
    } in series
    {
        let colour = PALETTE[i % PALETTE.len()];
        let line = colour.stroke_width(2);
        chart
            .draw_series(LineSeries::new(points.iter().copied(), line))?
            .label(name)
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
        let left_out = convergence_plot(
            &path,
            "Direct lighting: MSE against spp",
            "relative MSE",
            &sample_series(),
        )
        .unwrap();
        assert_eq!(left_out, 0);
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
        let series = sample_series();
        let (s, left_out) = drawable(Path::new("p.png"), &series).unwrap();
        assert_eq!(left_out, 0);
        let r = reference(&s);
        assert!((r(1.0) - 0.8).abs() < 1e-12 && (r(256.0) - 0.8 / 256.0).abs() < 1e-12);
        let ((x_lo, x_hi), (y_lo, y_hi)) = ranges(&s);
        assert!(x_lo < 1.0 && x_hi > 256.0);
        assert!(y_lo < 0.02 / 256f64.powf(0.95) && y_hi > 0.8);
    }

    /// A variance estimated from one sample is 0: compare's first wave gives such points.
    #[test]
    fn points_a_log_axis_cannot_show_are_left_out_and_counted() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("p.png");
        let series: Vec<Series> = vec![
            ("all zero".into(), vec![(1.0, 0.0), (2.0, 0.0)]),
            (
                "first zero".into(),
                vec![(1.0, 0.0), (2.0, 0.5), (4.0, 0.25), (8.0, f64::INFINITY)],
            ),
        ];
        assert_eq!(convergence_plot(&path, "t", "e", &series).unwrap(), 4);
        assert_eq!(decode_png(&path).dimensions(), PLOT_SIZE);
        let (shown, _) = drawable(&path, &series).unwrap();
        assert_eq!(shown.len(), 1);
        assert_eq!((shown[0].index, shown[0].name), (1, "first zero"));
        assert_eq!(shown[0].points, vec![(2.0, 0.5), (4.0, 0.25)]);
        // The reference goes through the first point shown.
        assert!((reference(&shown)(4.0) - 0.25).abs() < 1e-12);
    }

    #[test]
    fn ticks_read_as_numbers() {
        assert_eq!(tick(1.0), "1");
        assert_eq!(tick(0.5), "0.5");
        assert_eq!(tick(100.0), "100");
        assert_eq!(tick(1e6), "1e6");
        assert_eq!(tick(2e-5), "2e-5");
        assert_eq!(tick(16384.0), "1.64e4");
        assert_eq!(tick(0.015), "0.015");
    }

    #[test]
    fn log_axes_get_enough_labelled_ticks() {
        assert_eq!(log_ticks(0.5, 2e6), vec![1.0, 10.0, 100.0, 1e3, 1e4, 1e5, 1e6]);
        let few = log_ticks(1.4, 22.0);
        assert_eq!(few, vec![2.0, 5.0, 10.0, 20.0]);
        assert_eq!(log_ticks(1.1, 1.9).len(), 0, "no tick value lies in (1.1, 1.9)");
        assert_eq!(log_ticks(2.5, 4.5), vec![3.0, 4.0]);
        let series = sample_series();
        let (shown, _) = drawable(Path::new("p.png"), &series).unwrap();
        assert_eq!(x_ticks(&shown, 0.7, 360.0), vec![1.0, 4.0, 16.0, 64.0, 256.0]);
        let many: Vec<Series> = vec![("s".into(), (0..20).map(|k| (2f64.powi(k), 1.0)).collect())];
        let (shown, _) = drawable(Path::new("p.png"), &many).unwrap();
        assert_eq!(x_ticks(&shown, 0.7, 7e5), log_ticks(0.7, 7e5));
    }

    #[test]
    fn bad_series_are_errors_and_write_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("p.png");
        let err = |series: &[Series]| convergence_plot(&path, "t", "e", series).unwrap_err().to_string();
        assert!(err(&[]).contains("at least one series"));
        assert!(err(&[("empty".into(), vec![])]).contains("\"empty\" has no points"));
        let nothing = [
            ("zero".into(), vec![(1.0, 0.0)]),
            ("nan".into(), vec![(f64::NAN, 0.5), (2.0, -1.0)]),
        ];
        assert!(err(&nothing).contains("no point of any series is positive"));
        let bad_ext = convergence_plot(&dir.path().join("p.exr"), "t", "e", &sample_series()).unwrap_err();
        assert!(bad_ext.to_string().contains("png"), "{bad_ext}");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }
}
