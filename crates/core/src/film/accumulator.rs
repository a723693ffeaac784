//! Per-pixel accumulation of weighted radiance samples, with the second moments needed to
//! report the variance of each pixel's estimate.
//!
//! Each sample is `(w, L)` with `w` the filter weight (about 1, see [`super::Filter`]). The
//! pixel value is the weighted mean `sum(w L) / sum(w)`. Its variance is estimated from the
//! samples' own spread: with `n` samples, `Var[mean] ~= s^2 / n` where `s^2` is the unbiased
//! sample variance of the `w L / mean(w)` values.
//!
//! Beside the samples, each pixel has a splat sum ([`super::Splat`], kept exactly and in any
//! order by [`SplatSum`]); the displayed value is `mean + splat_sum / spp` with `spp` the
//! samples per pixel of the whole film. The variance covers the pixel's own samples only.

use super::{Splat, SplatSum};
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
        if self.sum_w == 0.0 {
            return Rgb::BLACK;
        }
        let m = |c: usize| (self.sum_wl[c] / self.sum_w) as f32;
        Rgb::new(m(0), m(1), m(2))
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
            samples_per_pixel: 0,
        }
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

    /// Add a splat to the pixel containing its position. Splats outside the image, or with
    /// a non-finite or huge value ([`SplatSum::add`]), are dropped (returns `false`). The
    /// order splats are added in does not change the film.
    pub fn add_splat(&mut self, s: &Splat) -> bool {
        let (x, y) = (s.p_film.x.floor(), s.p_film.y.floor());
        let inside = x >= 0.0 && y >= 0.0 && x < self.width as f32 && y < self.height as f32;
        inside && self.splats[y as usize * self.width as usize + x as usize].add(s.l)
    }

    /// Add another film's samples of the same image (e.g. a later wave of samples): the
    /// accumulators, splat sums and sample counts add. (The pixels' floating-point sums do
    /// not associate, so this equals a single render up to rounding; the render session
    /// continues a film instead, which is exact. The splat sums add exactly.)
    ///
    /// # Panics
    /// When the sizes differ.
    pub fn merge(&mut self, other: &Self) {
        assert_eq!(
            (self.width, self.height),
            (other.width, other.height),
            "films of different sizes"
        );
        for (a, b) in self.pixels.iter_mut().zip(&other.pixels) {
            a.merge(b);
        }
        for (a, b) in self.splats.iter_mut().zip(&other.splats) {
            a.merge(b);
        }
        self.samples_per_pixel += other.samples_per_pixel;
    }

    /// Combine the film of another part of the same image rendered with the same samples
    /// (e.g. other tiles, rendered on another machine): each pixel takes the samples of the
    /// one film that rendered it, and the splat sums add. Exact, in any order: the result
    /// has the bits of a film rendered whole.
    ///
    /// # Errors
    /// When the sizes or the samples per pixel differ, or a pixel was rendered in both.
    pub fn combine_disjoint(&mut self, other: &Self) -> Result<(), String> {
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
        if let Some(i) = (0..self.pixels.len()).find(|&i| self.pixels[i] != empty && other.pixels[i] != empty) {
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
        Ok(())
    }

    /// The estimate of every pixel: the mean of its samples plus its splats over the spp.
    #[must_use]
    pub fn mean_image(&self) -> Vec<Rgb> {
        let spp = self.samples_per_pixel as f64;
        self.pixels
            .iter()
            .zip(&self.splats)
            .map(|(p, s)| {
                if s.is_zero() || spp == 0.0 {
                    return p.mean();
                }
                let s = s.to_f64();
                let m = |c: usize| {
                    let mean = if p.sum_w == 0.0 { 0.0 } else { p.sum_wl[c] / p.sum_w };
                    (mean + s[c] / spp) as f32
                };
                Rgb::new(m(0), m(1), m(2))
            })
            .collect()
    }

    /// The variance of every pixel's estimate (its own samples; splats are not counted).
    #[must_use]
    pub fn variance_image(&self) -> Vec<Rgb> {
        self.pixels.iter().map(PixelStats::variance_of_mean).collect()
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

    #[test]
    fn splats_add_over_the_whole_image_spp() {
        let mut f = Film::new(2, 1);
        f.pixel_mut(0, 0).add(Rgb::splat(1.0), 1.0);
        f.pixel_mut(0, 0).add(Rgb::splat(3.0), 1.0);
        f.add_samples_per_pixel(2);
        assert!(f.add_splat(&Splat {
            p_film: crate::math::Vec2::new(1.7, 0.2),
            l: Rgb::splat(4.0),
        }));
        assert!(!f.add_splat(&Splat {
            p_film: crate::math::Vec2::new(2.0, 0.5),
            l: Rgb::splat(1.0),
        }));
        assert!(!f.add_splat(&Splat {
            p_film: crate::math::Vec2::new(0.5, 0.5),
            l: Rgb::splat(f32::NAN),
        }));
        let img = f.mean_image();
        assert_eq!(img[0], Rgb::splat(2.0));
        // No samples of its own, one splat of 4 over 2 spp.
        assert_eq!(img[1], Rgb::splat(2.0));
        let mut g = f.clone();
        g.merge(&f);
        assert_eq!(g.samples_per_pixel(), 4);
        assert_eq!(g.mean_image()[1], Rgb::splat(2.0));
    }

    #[test]
    fn weights_are_normalised() {
        let mut p = PixelStats::default();
        p.add(Rgb::splat(2.0), 0.5);
        p.add(Rgb::splat(4.0), 1.5);
        assert!((p.mean().b - 3.5).abs() < 1e-6);
    }
}
