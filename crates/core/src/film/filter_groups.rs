//! One sample index's [`FilterGroup`]s under filter splatting: each pixel `c` of a window
//! sums `f(p_j - c)` and `f(p_j - c) L_j` over the camera samples `j` whose filter covers
//! it, then adds the group to its [`FilteredSums`] once.
//!
//! The samples are binned by the pixel they lie in and spread in a canonical order: bins
//! row by row, left to right, the samples of a bin sorted by value. So every pixel's group
//! is the same `f64` sum, in the same order, whatever order the samples came in, however
//! the image is split into tiles, bands or windows and however many threads run. The group
//! is then rounded to fixed point once (spreading the samples in the order they came had
//! to round every term, to stay independent of that order).

use rayon::prelude::*;

use super::accumulator::rows_per_band;
use super::{Filter, FilterGroup, FilteredSums, Footprint, Splat};
use crate::math::{ceil_to_i64, floor_to_i64};

/// Add the groups of `samples` (one sample index's camera samples) to the sums of the
/// pixels of `window` (`sums` row-major, `w x h`), in parallel over bands of rows of the
/// current rayon pool. Returns the number of samples reaching no pixel (or refused by
/// [`Splat::footprint`]) plus the number of groups refused.
pub(super) fn add_filter_groups(
    samples: &[Splat],
    filter: &Filter,
    (w, h): (u32, u32),
    window: Footprint,
    sums: &mut [FilteredSums],
) -> u64 {
    if w == 0 || h == 0 {
        return samples.len() as u64;
    }
    // (In parallel: this runs between waves, while the render threads wait.)
    let kept: Vec<(&Splat, Footprint)> = samples
        .par_iter()
        .filter_map(|s| Some((s, s.footprint(filter, w, h)?)))
        .collect();
    let dropped = (samples.len() - kept.len()) as u64;
    let bins = Bins::new(&kept, w, h);
    let reach = Reach::of(filter.radius().y);
    let (cols, rows) = (window.x0.min(w)..window.x1.min(w), window.y0..window.y1.min(h));
    let band_rows = rows_per_band(h);
    let refused: u64 = sums
        .par_chunks_mut(band_rows * w as usize)
        .enumerate()
        .map(|(b, band)| {
            let y0 = (b * band_rows) as u32;
            let band_y = y0.max(rows.start)..(y0 + (band.len() / w as usize) as u32).min(rows.end);
            if band_y.is_empty() || cols.is_empty() {
                return 0;
            }
            let groups = band_groups(&bins, filter, reach, (cols.clone(), band_y.clone()), h);
            let width = cols.len();
            let mut refused = 0;
            for (i, g) in groups.iter().enumerate().filter(|(_, g)| !g.is_zero()) {
                let (x, y) = (cols.start as usize + i % width, band_y.start - y0 + (i / width) as u32);
                if !band[y as usize * w as usize + x].add_group(g) {
                    refused += 1;
                }
            }
            refused
        })
        .sum();
    dropped + refused
}

/// The groups of the pixels `cols x rows` (row-major), spreading the bins of the rows that
/// may reach them in the canonical order.
fn band_groups(
    bins: &Bins<'_>,
    filter: &Filter,
    reach: Reach,
    (cols, rows): (std::ops::Range<u32>, std::ops::Range<u32>),
    h: u32,
) -> Vec<FilterGroup> {
    let width = cols.len();
    let mut groups = vec![FilterGroup::default(); width * rows.len()];
    // Pixel row y gathers from the bins of rows y - before ..= y + after.
    let sources = rows.start.saturating_sub(reach.before)..rows.end.saturating_add(reach.after).min(h);
    for sy in sources {
        for (s, fp) in bins.row(sy) {
            for y in fp.y0.max(rows.start)..fp.y1.min(rows.end) {
                let row = (y - rows.start) as usize * width;
                for x in fp.x0.max(cols.start)..fp.x1.min(cols.end) {
                    let wgt = s.weight(filter, 1.0, x, y);
                    if wgt != 0.0 {
                        groups[row + (x - cols.start) as usize].add(s.l, wgt);
                    }
                }
            }
        }
    }
    groups
}

/// The rows of bins whose samples may reach a pixel's row.
#[derive(Clone, Copy)]
struct Reach {
    /// How many rows above it (smaller `y`).
    before: u32,
    /// How many rows below it.
    after: u32,
}

impl Reach {
    /// For a filter of radius `r`, counted as [`Splat::footprint`] does: a sample at `p`
    /// reaches pixel `c` when `p - r - 1/2 <= c <= p + r - 1/2`. With `p` in pixel `j`
    /// (`j <= p < j + 1`) that needs `c - j < r + 1/2` and `j - c <= r + 1/2`.
    fn of(r: f32) -> Self {
        let r = r + 0.5;
        let clamp = |v: i64| v.clamp(0, i64::from(u32::MAX)) as u32;
        Self {
            before: clamp(ceil_to_i64(r) - 1),
            after: clamp(floor_to_i64(r)),
        }
    }
}

/// Samples (with their footprints) binned by the pixel they lie in, clamped into the
/// image, in compressed rows: the samples of pixel `i` are `samples[start[i]..start[i + 1]]`,
/// sorted by value.
struct Bins<'a> {
    w: u32,
    start: Vec<u32>,
    samples: Vec<(&'a Splat, Footprint)>,
}

impl<'a> Bins<'a> {
    fn new(kept: &[(&'a Splat, Footprint)], w: u32, h: u32) -> Self {
        // Clamping is safe: a sample left of (or above) the image reaches no pixel that a
        // sample in the first column (row) could not, and likewise right of (below) it.
        let bin = |s: &Splat| {
            let cell = |v: f32, n: u32| floor_to_i64(v).clamp(0, i64::from(n) - 1) as usize;
            cell(s.p_film.y, h) * w as usize + cell(s.p_film.x, w)
        };
        let mut start = vec![0u32; (w * h) as usize + 1];
        for (s, _) in kept {
            start[bin(s) + 1] += 1;
        }
        for i in 1..start.len() {
            start[i] += start[i - 1];
        }
        let mut next = start.clone();
        // (Any entries to start with: every slot is overwritten.)
        let mut samples = kept.to_vec();
        for &(s, fp) in kept {
            let b = bin(s);
            samples[next[b] as usize] = (s, fp);
            next[b] += 1;
        }
        // A pixel holds one sample per index, except where p_film rounded onto the next
        // pixel's edge: order those by value, so that the input order does not matter.
        for b in start.windows(2).filter(|b| b[1] - b[0] > 1) {
            samples[b[0] as usize..b[1] as usize].sort_unstable_by_key(|(s, _)| value_key(s));
        }
        Self { w, start, samples }
    }

    /// The samples of image row `y`, left to right.
    fn row(&self, y: u32) -> &[(&'a Splat, Footprint)] {
        let i = (y * self.w) as usize;
        &self.samples[self.start[i] as usize..self.start[i + self.w as usize] as usize]
    }
}

/// A total order of samples by their bits (equal keys are equal samples).
fn value_key(s: &Splat) -> [u32; 5] {
    [
        s.p_film.x.to_bits(),
        s.p_film.y.to_bits(),
        s.l.r.to_bits(),
        s.l.g.to_bits(),
        s.l.b.to_bits(),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::Rgb;
    use crate::film::FilterDesc;
    use crate::math::Vec2;

    /// Samples of two indices' worth over a 7x5 image, some outside it and some on pixel
    /// edges, with radiance spread over magnitudes so that float order would show.
    fn samples() -> Vec<Splat> {
        (0..80u32)
            .map(|i| {
                let x = (i * 37 % 91) as f32 / 10.0 - 1.0;
                let y = (i * 53 % 67) as f32 / 10.0 - 0.7;
                let v = 1.7f32.powi((i * 13 % 29) as i32 - 14);
                Splat {
                    p_film: Vec2::new(x, y),
                    l: Rgb::new(v, 0.5 * v + 1.0, (i % 5) as f32),
                }
            })
            .collect()
    }

    fn whole(w: u32, h: u32) -> Footprint {
        Footprint {
            x0: 0,
            x1: w,
            y0: 0,
            y1: h,
        }
    }

    fn grouped(samples: &[Splat], filter: &Filter, window: Footprint) -> (Vec<FilteredSums>, u64) {
        let mut sums = vec![FilteredSums::ZERO; 35];
        let dropped = add_filter_groups(samples, filter, (7, 5), window, &mut sums);
        (sums, dropped)
    }

    fn filters() -> Vec<Filter> {
        [
            FilterDesc::Triangle { radius: Vec2::ONE },
            FilterDesc::Gaussian {
                radius: Vec2::splat(1.5),
                sigma: 0.5,
            },
            FilterDesc::Box {
                radius: Vec2::splat(0.5),
            },
            FilterDesc::Mitchell {
                radius: Vec2::splat(2.0),
                b: 1.0 / 3.0,
                c: 1.0 / 3.0,
            },
        ]
        .into_iter()
        .map(|d| Filter::new(&d))
        .collect()
    }

    #[test]
    fn groups_match_every_sample_weighed_for_every_pixel() {
        let all = samples();
        for filter in filters() {
            let (got, _) = grouped(&all, &filter, whole(7, 5));
            for (i, sums) in got.iter().enumerate() {
                let centre = Vec2::new((i % 7) as f32 + 0.5, (i / 7) as f32 + 0.5);
                let mut group = FilterGroup::default();
                let (mut sw, mut swl) = (0.0f64, 0.0f64);
                for s in &all {
                    let wgt = filter.evaluate(s.p_film - centre);
                    if wgt != 0.0 {
                        group.add(s.l, wgt);
                        sw += f64::from(wgt);
                        swl += f64::from(wgt) * f64::from(s.l.r);
                    }
                }
                // Same sums up to the order of the f64 additions.
                assert!((sums.weight_sum() - sw).abs() <= 1e-12 * sw.abs().max(1.0), "pixel {i}");
                let r = if sw == 0.0 { 0.0 } else { swl / sw };
                assert!((sums.mean_f64()[0] - r).abs() <= 1e-9 * r.abs().max(1e-6), "pixel {i}");
                assert_eq!(sums.is_zero(), group.is_zero(), "pixel {i}");
            }
        }
    }

    #[test]
    fn any_order_of_the_samples_gives_the_same_bits() {
        let mut all = samples();
        // Two samples in one pixel (a p_film rounded onto its edge), given in both orders.
        all.push(Splat {
            p_film: Vec2::new(3.0, 2.0),
            l: Rgb::splat(9.0),
        });
        all.push(Splat {
            p_film: Vec2::new(3.999_999_8, 2.5),
            l: Rgb::splat(1e-3),
        });
        for filter in filters() {
            let forward = grouped(&all, &filter, whole(7, 5));
            let mut reversed = all.clone();
            reversed.reverse();
            assert_eq!(grouped(&reversed, &filter, whole(7, 5)), forward);
            let mut rotated = all.clone();
            rotated.rotate_left(17);
            assert_eq!(grouped(&rotated, &filter, whole(7, 5)), forward);
        }
    }

    #[test]
    fn a_window_holds_the_whole_images_pixels_and_nothing_else() {
        let all = samples();
        let filter = &filters()[1];
        let (whole_sums, _) = grouped(&all, filter, whole(7, 5));
        let window = Footprint {
            x0: 2,
            x1: 5,
            y0: 1,
            y1: 3,
        };
        let (part, _) = grouped(&all, filter, window);
        for (i, (a, b)) in part.iter().zip(&whole_sums).enumerate() {
            let (x, y) = ((i % 7) as u32, (i / 7) as u32);
            if (2..5).contains(&x) && (1..3).contains(&y) {
                assert_eq!(a, b, "pixel ({x}, {y})");
            } else {
                assert!(a.is_zero(), "pixel ({x}, {y}) is outside the window");
            }
        }
    }

    #[test]
    fn samples_reaching_no_pixel_and_refused_groups_are_counted() {
        let filter = &filters()[0];
        let far = Splat {
            p_film: Vec2::new(-5.0, 2.0),
            l: Rgb::splat(1.0),
        };
        let nan = Splat {
            p_film: Vec2::new(f32::NAN, 2.0),
            l: Rgb::splat(1.0),
        };
        let near = Splat {
            p_film: Vec2::new(2.5, 2.5),
            l: Rgb::splat(1.0),
        };
        let (sums, dropped) = grouped(&[far, nan, near], filter, whole(7, 5));
        assert_eq!(dropped, 2);
        assert_eq!(sums[2 * 7 + 2].mean(), Rgb::splat(1.0));
        // A radiance whose square overflows the second moments refuses its pixels' groups
        // whole (the centre pixel only, at a weight of one).
        let huge = Splat {
            p_film: Vec2::new(2.5, 2.5),
            l: Rgb::new(1e15, 1.0, 1.0),
        };
        let (sums, refused) = grouped(&[huge], filter, whole(7, 5));
        assert_eq!(refused, 1);
        assert!(sums.iter().all(FilteredSums::is_zero));
        assert_eq!(add_filter_groups(&[near], filter, (0, 0), whole(0, 0), &mut []), 1);
    }
}
