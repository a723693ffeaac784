//! Per-pixel accumulation of weighted radiance samples, with the second moments needed to
//! report the variance of each pixel's estimate.
//!
//! Each sample is `(w, L)` with `w` the filter weight (about 1, see [`super::Filter`]). The
//! pixel value is the weighted mean `sum(w L) / sum(w)`. Its variance is estimated from the
//! samples' own spread: with `n` samples, `Var[mean] ~= s^2 / n` where `s^2` is the unbiased
//! sample variance of the `w L / mean(w)` values.
//!
//! Beside the samples, each pixel has a splat sum ([`super::Splat`]: every splat adds its
//! value times the pixel filter's normalised weight to each pixel the filter covers, kept
//! exactly and in any order by [`SplatSum`]); the displayed value is
//! `mean + splat_sum / spp` with `spp` the samples per pixel of the whole film. The
//! variance covers the pixel's own samples only.
//!
//! Under filter splatting ([`super::Reconstruction::FilterSplatting`]) the film also holds
//! each pixel's [`FilteredSums`], which then replace the accumulators as the pixel's mean
//! and variance.

use rayon::prelude::*;

use super::filter_groups::add_filter_groups;
use super::{Filter, FilteredSums, Footprint, Splat, SplatSum};
use crate::color::Rgb;

/// Running sums for one pixel, in `f64` so long renders do not lose precision.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PixelStats {
    /// Sum of weights.
    pub sum_w: f64,
    /// Sum of `w L` per channel.
    pub sum_wl: [f64; 3],
    /// Sum of `(w L)^2` per channel.
    pub sum_wl2: [f64; 3],
    /// Number of samples.
    pub count: u64,
}

impl PixelStats {
    /// Add one sample of radiance `l` with filter weight `w`.
    #[inline]
    pub fn add(&mut self, l: Rgb, w: f32) {
        let w = f64::from(w);
        self.sum_w += w;
        for c in 0..3 {
            let v = w * f64::from(l[c]);
            self.sum_wl[c] += v;
            self.sum_wl2[c] += v * v;
        }
        self.count += 1;
    }

    /// Merge another accumulator (used to resume or combine renders of the same pixel).
    pub fn merge(&mut self, o: &Self) {
        self.sum_w += o.sum_w;
        for c in 0..3 {
            self.sum_wl[c] += o.sum_wl[c];
            self.sum_wl2[c] += o.sum_wl2[c];
        }
        self.count += o.count;
    }

    /// The pixel's estimate: weighted mean radiance.
    #[must_use]
    pub fn mean(&self) -> Rgb {
        let [r, g, b] = self.mean_f64();
        Rgb::new(r as f32, g as f32, b as f32)
    }

    /// [`Self::mean`] in `f64` (zero without weight).
    #[must_use]
    pub fn mean_f64(&self) -> [f64; 3] {
        if self.sum_w == 0.0 {
            return [0.0; 3];
        }
        self.sum_wl.map(|v| v / self.sum_w)
    }

    /// Estimated variance of [`Self::mean`] per channel (0 with fewer than two samples).
    #[must_use]
    pub fn variance_of_mean(&self) -> Rgb {
        if self.count < 2 || self.sum_w == 0.0 {
            return Rgb::BLACK;
        }
        let n = self.count as f64;
        // Normalise by the mean weight so that sum(w L)/sum(w) = mean of x_i = w_i L_i / wbar.
        let wbar = self.sum_w / n;
        let v = |c: usize| {
            let mean_x = self.sum_wl[c] / n / wbar;
            let mean_x2 = self.sum_wl2[c] / n / (wbar * wbar);
            let sample_var = (mean_x2 - mean_x * mean_x).max(0.0) * n / (n - 1.0);
            (sample_var / n) as f32
        };
        Rgb::new(v(0), v(1), v(2))
    }
}

/// An image of pixel accumulators, row-major with row 0 at the top, with a splat sum per
/// pixel and the number of samples per pixel rendered into it.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    width: u32,
    height: u32,
    pixels: Vec<PixelStats>,
    /// Sum of the splats landing in each pixel (fixed point: the order they land in does
    /// not matter).
    splats: Vec<SplatSum>,
    /// Under filter splatting, each pixel's sums of filter-weighted samples (fixed point).
    filtered: Option<Vec<FilteredSums>>,
    /// Samples per pixel rendered (sample indices, counting dropped non-finite samples).
    samples_per_pixel: u64,
}

impl Film {
    /// An empty film.
    #[must_use]
    pub fn new(width: u32, height: u32) -> Self {
        let n = width as usize * height as usize;
        Self {
            width,
            height,
            pixels: vec![PixelStats::default(); n],
            splats: vec![SplatSum::ZERO; n],
            filtered: None,
            samples_per_pixel: 0,
        }
    }

    /// An empty film for filter splatting: camera samples go to [`Self::add_filtered`].
    #[must_use]
    pub fn for_filter_splatting(width: u32, height: u32) -> Self {
        let mut f = Self::new(width, height);
        f.filtered = Some(vec![FilteredSums::ZERO; f.pixels.len()]);
        f
    }

    /// The film with `filtered` as its filter-splatting sums (as a checkpoint stores them);
    /// `None` when the length does not match the size.
    #[must_use]
    pub fn with_filtered_sums(mut self, filtered: Vec<FilteredSums>) -> Option<Self> {
        (filtered.len() == self.pixels.len()).then(|| {
            self.filtered = Some(filtered);
            self
        })
    }

    /// The filter-splatting sums, row-major (`None` for a film of filter sampling).
    #[must_use]
    pub fn filtered_sums(&self) -> Option<&[FilteredSums]> {
        self.filtered.as_deref()
    }

    /// A film from its parts (as a checkpoint stores them); `None` when the lengths do not
    /// match the size.
    #[must_use]
    pub fn from_parts(
        width: u32,
        height: u32,
        pixels: Vec<PixelStats>,
        splats: Vec<SplatSum>,
        samples_per_pixel: u64,
    ) -> Option<Self> {
        let n = (width as usize).checked_mul(height as usize)?;
        (pixels.len() == n && splats.len() == n).then_some(Self {
            width,
            height,
            pixels,
            splats,
            filtered: None,
            samples_per_pixel,
        })
    }

    /// Width in pixels.
    #[must_use]
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    #[must_use]
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The accumulator of pixel `(x, y)`.
    #[must_use]
    pub fn pixel(&self, x: u32, y: u32) -> &PixelStats {
        &self.pixels[(y * self.width + x) as usize]
    }

    /// Mutable accumulator of pixel `(x, y)`.
    pub fn pixel_mut(&mut self, x: u32, y: u32) -> &mut PixelStats {
        &mut self.pixels[(y * self.width + x) as usize]
    }

    /// All accumulators, row-major.
    #[must_use]
    pub fn pixels(&self) -> &[PixelStats] {
        &self.pixels
    }

    /// All splat sums, row-major.
    #[must_use]
    pub fn splat_sums(&self) -> &[SplatSum] {
        &self.splats
    }

    /// Samples per pixel rendered into this film (the `spp` splats are divided by).
    #[must_use]
    pub fn samples_per_pixel(&self) -> u64 {
        self.samples_per_pixel
    }

    /// Record that `n` more samples per pixel were rendered into the film.
    pub fn add_samples_per_pixel(&mut self, n: u64) {
        self.samples_per_pixel += n;
    }

    /// Add a splat to every pixel `filter` covers, with weight `f(offset) / integral of f`
    /// (see [`Splat`]). A splat that reaches no pixel, or whose value is not finite or huge
    /// ([`SplatSum::accepts`]), is dropped (returns `false`). The order splats are added
    /// in does not change the film.
    pub fn add_splat(&mut self, s: &Splat, filter: &Filter) -> bool {
        let Some(fp) = s.footprint(filter, self.width, self.height) else {
            return false;
        };
        let rows = 0..self.height;
        spread(s, &fp, filter, rows, self.width, &mut self.splats);
        true
    }

    /// Add many splats (as [`Self::add_splat`]), in parallel over bands of rows of the
    /// current rayon pool: each band adds the part of every splat that falls on it, so the
    /// film is the same as when adding them one by one. Returns the number dropped.
    pub fn add_splats(&mut self, splats: &[Splat], filter: &Filter) -> u64 {
        let (w, h) = (self.width, self.height);
        in_bands(splats, filter, w, h, &mut self.splats, spread)
    }

    /// Add one sample index's camera samples under filter splatting: each [`Splat`] is a
    /// sample's film position and radiance. Each pixel `c` of `window` adds to its sums the
    /// group `sum f(p - c)`, `sum f(p - c) L` of the samples whose filter covers it (in
    /// parallel over bands of rows; the same bits in any order of the samples). Pixels outside
    /// the window are another film's, e.g. another machine's: see
    /// `RenderSession::set_window`. Returns the number of samples reaching no pixel and
    /// of groups refused (a term not finite or too large).
    ///
    /// # Panics
    /// When the film is not one of filter splatting ([`Self::for_filter_splatting`]).
    pub fn add_filtered(&mut self, samples: &[Splat], filter: &Filter, window: Footprint) -> u64 {
        let (w, h) = (self.width, self.height);
        let sums = self.filtered.as_mut().expect("a film of filter splatting");
        add_filter_groups(samples, filter, (w, h), window, sums)
    }

    /// Add another film's samples of the same image (e.g. a later wave of samples): the
    /// accumulators, splat sums and sample counts add. (The pixels' floating-point sums do
    /// not associate, so this equals a single render up to rounding; the render session
    /// continues a film instead, which is exact. The splat sums add exactly.)
    ///
    /// # Panics
    /// When the sizes differ, or one film is of filter splatting and the other not.
    pub fn merge(&mut self, other: &Self) {
        assert_eq!(
            (self.width, self.height),
            (other.width, other.height),
            "films of different sizes"
        );
        assert_eq!(
            self.filtered.is_some(),
            other.filtered.is_some(),
            "films of different reconstructions"
        );
        for (a, b) in self.pixels.iter_mut().zip(&other.pixels) {
            a.merge(b);
        }
        for (a, b) in self.splats.iter_mut().zip(&other.splats) {
            a.merge(b);
        }
        self.merge_filtered(other);
        self.samples_per_pixel += other.samples_per_pixel;
    }

    /// Add `other`'s filter-splatting sums to this film's (both have them, or neither).
    fn merge_filtered(&mut self, other: &Self) {
        if let (Some(a), Some(b)) = (&mut self.filtered, &other.filtered) {
            a.iter_mut().zip(b).for_each(|(a, b)| a.merge(b));
        }
    }

    /// Combine the film of another part of the same image rendered with the same samples
    /// (e.g. other tiles, rendered on another machine): each pixel takes the samples (or
    /// filtered sums) of the one film that rendered it, and the splat sums add. Exact, in
    /// any order: the result has the bits of a film rendered whole.
    ///
    /// # Errors
    /// When the sizes, the samples per pixel or the reconstructions differ, or a pixel was
    /// rendered in both.
    pub fn combine_disjoint(&mut self, other: &Self) -> Result<(), String> {
        if self.filtered.is_some() != other.filtered.is_some() {
            return Err("films of different reconstructions (filter sampling and splatting)".into());
        }
        if (self.width, self.height) != (other.width, other.height) {
            return Err(format!(
                "films of different sizes ({}x{} and {}x{})",
                self.width, self.height, other.width, other.height
            ));
        }
        if self.samples_per_pixel != other.samples_per_pixel {
            return Err(format!(
                "films of different sample counts ({} and {} per pixel)",
                self.samples_per_pixel, other.samples_per_pixel
            ));
        }
        let empty = PixelStats::default();
        let rendered =
            |f: &Self, i: usize| f.pixels[i] != empty || f.filtered.as_ref().is_some_and(|s| !s[i].is_zero());
        if let Some(i) = (0..self.pixels.len()).find(|&i| rendered(self, i) && rendered(other, i)) {
            let w = self.width as usize;
            return Err(format!("pixel ({}, {}) was rendered in both films", i % w, i / w));
        }
        for (a, b) in self.pixels.iter_mut().zip(&other.pixels) {
            if *b != empty {
                *a = *b;
            }
        }
        for (a, b) in self.splats.iter_mut().zip(&other.splats) {
            a.merge(b);
        }
        // Under filter splatting each film holds its own window's pixels, whole (the
        // session renders the samples of the neighbours their filter reaches).
        if let (Some(a), Some(b)) = (&mut self.filtered, &other.filtered) {
            for (a, b) in a.iter_mut().zip(b) {
                if !b.is_zero() {
                    *a = *b;
                }
            }
        }
        Ok(())
    }

    /// The estimate of every pixel: the mean of its samples (or, under filter splatting,
    /// the ratio of its filtered sums) plus its splats over the spp.
    #[must_use]
    pub fn mean_image(&self) -> Vec<Rgb> {
        let spp = self.samples_per_pixel as f64;
        (0..self.pixels.len())
            .map(|i| {
                let s = &self.splats[i];
                if s.is_zero() || spp == 0.0 {
                    return match &self.filtered {
                        Some(f) => f[i].mean(),
                        None => self.pixels[i].mean(),
                    };
                }
                let own = match &self.filtered {
                    Some(f) => f[i].mean_f64(),
                    None => self.pixels[i].mean_f64(),
                };
                let s = s.to_f64();
                let m = |c: usize| (own[c] + s[c] / spp) as f32;
                Rgb::new(m(0), m(1), m(2))
            })
            .collect()
    }

    /// The variance of every pixel's estimate (its own samples, or its filtered sums under
    /// filter splatting; splats are not counted).
    #[must_use]
    pub fn variance_image(&self) -> Vec<Rgb> {
        match &self.filtered {
            Some(f) => f.iter().map(|s| s.variance_of_mean(self.samples_per_pixel)).collect(),
            None => self.pixels.iter().map(PixelStats::variance_of_mean).collect(),
        }
    }
}

/// Add `items` to the per-pixel sums `sums` (row-major, `w x h`) in parallel over bands of
/// rows of the current rayon pool, `add(item, footprint, filter, band rows, w, band)` adding
/// the part of one item that falls on a band. Returns the number of items reaching no pixel
/// (or refused by [`Splat::footprint`]).
fn in_bands<S: Send>(
    items: &[Splat],
    filter: &Filter,
    w: u32,
    h: u32,
    sums: &mut [S],
    add: fn(&Splat, &Footprint, &Filter, std::ops::Range<u32>, u32, &mut [S]),
) -> u64 {
    if w == 0 || h == 0 {
        return items.len() as u64;
    }
    let footprints: Vec<Option<Footprint>> = items.par_iter().map(|s| s.footprint(filter, w, h)).collect();
    let dropped = footprints.iter().filter(|f| f.is_none()).count() as u64;
    let band_rows = rows_per_band(h);
    sums.par_chunks_mut(band_rows * w as usize)
        .enumerate()
        .for_each(|(b, band)| {
            let y0 = (b * band_rows) as u32;
            let rows = y0..y0 + (band.len() / w as usize) as u32;
            for (s, fp) in items.iter().zip(&footprints) {
                if let Some(fp) = fp {
                    add(s, fp, filter, rows.clone(), w, band);
                }
            }
        });
    dropped
}

/// Rows per band when a `h`-row image is split among the threads of the current rayon
/// pool: four bands per thread, for balance.
pub(super) fn rows_per_band(h: u32) -> usize {
    let bands = (4 * rayon::current_num_threads()).clamp(1, h as usize);
    (h as usize).div_ceil(bands)
}

/// Add the part of splat `s` (footprint `fp`) that falls on image rows `rows`, whose splat
/// sums are `sums` (row-major, `width` per row, starting at `rows.start`).
fn spread(s: &Splat, fp: &Footprint, filter: &Filter, rows: std::ops::Range<u32>, width: u32, sums: &mut [SplatSum]) {
    let inv_integral = 1.0 / filter.integral();
    for y in fp.y0.max(rows.start)..fp.y1.min(rows.end) {
        let row = (y - rows.start) as usize * width as usize;
        for x in fp.x0..fp.x1 {
            let wgt = s.weight(filter, inv_integral, x, y);
            if wgt != 0.0 {
                // Refused only when l * w overflows the fixed point: that pixel alone.
                sums[row + x as usize].add_weighted(s.l, wgt);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mean_and_variance_of_known_samples() {
        let mut p = PixelStats::default();
        for v in [1.0, 2.0, 3.0, 4.0] {
            p.add(Rgb::splat(v), 1.0);
        }
        assert!((p.mean().r - 2.5).abs() < 1e-6);
        // Sample variance of 1..4 is 5/3; of the mean, 5/12.
        assert!((p.variance_of_mean().g - 5.0 / 12.0).abs() < 1e-6);
    }

    use crate::film::FilterDesc;
    use crate::math::Vec2;

    /// A box one pixel wide: every splat lands on the pixel containing it.
    fn pixel_box() -> Filter {
        Filter::new(&FilterDesc::Box {
            radius: Vec2::splat(0.5),
        })
    }

    #[test]
    fn splats_add_over_the_whole_image_spp() {
        let mut f = Film::new(2, 1);
        f.pixel_mut(0, 0).add(Rgb::splat(1.0), 1.0);
        f.pixel_mut(0, 0).add(Rgb::splat(3.0), 1.0);
        f.add_samples_per_pixel(2);
        let b = pixel_box();
        assert!(f.add_splat(
            &Splat {
                p_film: Vec2::new(1.7, 0.2),
                l: Rgb::splat(4.0),
            },
            &b
        ));
        assert!(!f.add_splat(
            &Splat {
                p_film: Vec2::new(2.01, 0.5),
                l: Rgb::splat(1.0),
            },
            &b
        ));
        assert!(!f.add_splat(
            &Splat {
                p_film: Vec2::new(0.5, 0.5),
                l: Rgb::splat(f32::NAN),
            },
            &b
        ));
        let img = f.mean_image();
        assert_eq!(img[0], Rgb::splat(2.0));
        // No samples of its own, one splat of 4 over 2 spp.
        assert_eq!(img[1], Rgb::splat(2.0));
        let mut g = f.clone();
        g.merge(&f);
        assert_eq!(g.samples_per_pixel(), 4);
        assert_eq!(g.mean_image()[1], Rgb::splat(2.0));
    }

    /// A Gaussian splat adds `L f(offset) / integral` to each pixel within the radius,
    /// including from the margin outside the image that the filter still reaches, and
    /// adding splats in parallel bands gives the bits of adding them one at a time.
    #[test]
    fn splats_spread_over_the_filter() {
        let g = Filter::new(&FilterDesc::default());
        let (w, h) = (7u32, 5u32);
        let one = Splat {
            p_film: Vec2::new(3.2, 2.9),
            l: Rgb::new(1.0, 2.0, 0.5),
        };
        let mut f = Film::new(w, h);
        assert!(f.add_splat(&one, &g));
        let mut touched = 0;
        for y in 0..h {
            for x in 0..w {
                let d = one.p_film - Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                let expected = g.evaluate(d) / g.integral();
                let got = f.splat_sums()[(y * w + x) as usize].to_f64();
                assert!((got[1] - 2.0 * f64::from(expected)).abs() < 1e-6, "({x}, {y})");
                touched += usize::from(expected > 0.0);
            }
        }
        // Centres within 1.5 of (3.2, 2.9): columns 2..=4, rows 1..=3 (at most 4 x 4).
        assert_eq!(touched, 9);
        // From outside the pixel bounds, inside the sample bounds: pixel 0 still gets some.
        let mut margin = Film::new(w, h);
        assert!(margin.add_splat(
            &Splat {
                p_film: Vec2::new(-0.8, 2.5),
                l: Rgb::splat(1.0),
            },
            &g
        ));
        assert!(!margin.splat_sums()[2 * w as usize].is_zero());
        assert!(!margin.add_splat(
            &Splat {
                p_film: Vec2::new(-1.1, 2.5),
                l: Rgb::splat(1.0),
            },
            &g
        ));
        // Many splats, one at a time and in bands (both sizes of pool).
        let splats: Vec<Splat> = (0..500u32)
            .map(|i| Splat {
                p_film: Vec2::new((i * 37 % 97) as f32 / 10.0 - 1.0, (i * 53 % 71) as f32 / 10.0 - 1.0),
                l: Rgb::new(1e-3 * i as f32, 10.0f32.powi(i as i32 % 9 - 4), 1.0),
            })
            .collect();
        let mut serial = Film::new(w, h);
        let serial_dropped = splats.iter().filter(|s| !serial.add_splat(s, &g)).count() as u64;
        for threads in [1, 3] {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            let mut banded = Film::new(w, h);
            let dropped = pool.install(|| banded.add_splats(&splats, &g));
            assert_eq!(dropped, serial_dropped);
            assert_eq!(banded.splat_sums(), serial.splat_sums(), "{threads} threads");
        }
        assert!(serial_dropped > 0);
    }

    #[test]
    fn weights_are_normalised() {
        let mut p = PixelStats::default();
        p.add(Rgb::splat(2.0), 0.5);
        p.add(Rgb::splat(4.0), 1.5);
        assert!((p.mean().b - 3.5).abs() < 1e-6);
    }
}
