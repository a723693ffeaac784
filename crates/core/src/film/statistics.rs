//! Whole-image measurements of an estimate (pixel samples plus splats): mean radiance, the average per-pixel variance
//! (the noise a viewer sees, from each pixel's own samples), and the relative mean squared
//! error against a reference.

use super::Film;
use crate::color::Rgb;

/// Offset in the denominator of the relative squared error, so black reference pixels do
/// not dominate: `(x - r)^2 / (r^2 + REL_MSE_EPSILON)` (as in pbrt's `imgtool diff`).
pub const REL_MSE_EPSILON: f64 = 0.01;

/// Measurements of one rendered image.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilmStatistics {
    /// Mean radiance per channel over the image.
    pub mean: Rgb,
    /// Average over pixels of the estimated variance of the pixel's luminance.
    pub mean_variance: f64,
    /// Relative MSE against the reference (averaged over pixels and channels), when given.
    pub rel_mse: Option<f64>,
}

impl FilmStatistics {
    /// Measure `film`, optionally against `reference` (same size, row-major).
    ///
    /// # Panics
    /// When the reference has a different number of pixels.
    #[must_use]
    pub fn measure(film: &Film, reference: Option<&[Rgb]>) -> Self {
        // The estimate includes the splats (light tracing, BDPT's t = 1); the variance is
        // the pixels' own samples' only.
        let image = film.mean_image();
        let n = image.len().max(1) as f64;
        let mut sum = [0.0f64; 3];
        let mut var = 0.0f64;
        for (v, m) in film.variance_image().iter().zip(&image) {
            for (c, s) in sum.iter_mut().enumerate() {
                *s += f64::from(m[c]);
            }
            var += f64::from(v.luminance());
        }
        let rel_mse = reference.map(|r| {
            assert_eq!(r.len(), image.len(), "reference of a different size");
            let mut e = 0.0f64;
            for (m, r) in image.iter().zip(r) {
                for c in 0..3 {
                    let d = f64::from(m[c]) - f64::from(r[c]);
                    e += d * d / (f64::from(r[c]) * f64::from(r[c]) + REL_MSE_EPSILON);
                }
            }
            e / (3.0 * n)
        });
        Self {
            mean: Rgb::new((sum[0] / n) as f32, (sum[1] / n) as f32, (sum[2] / n) as f32),
            mean_variance: var / n,
            rel_mse,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn measures_mean_variance_and_error() {
        let mut f = Film::new(2, 1);
        for v in [1.0, 3.0] {
            f.pixel_mut(0, 0).add(Rgb::splat(v), 1.0);
            f.pixel_mut(1, 0).add(Rgb::splat(2.0), 1.0);
        }
        let s = FilmStatistics::measure(&f, Some(&[Rgb::splat(2.0), Rgb::splat(1.0)]));
        assert!((s.mean.r - 2.0).abs() < 1e-6);
        // Pixel 0: sample variance 2, variance of the mean 1; pixel 1: 0. Luminance weights sum to 1.
        assert!((s.mean_variance - 0.5).abs() < 1e-5, "{}", s.mean_variance);
        // Pixel 0 exact; pixel 1 off by 1 on a reference of 1: 1 / 1.01 per channel, averaged over 2 pixels.
        assert!((s.rel_mse.unwrap() - 0.5 / 1.01).abs() < 1e-9);
    }

    #[test]
    fn splats_count_in_the_mean_and_the_error() {
        let mut f = Film::new(1, 1);
        f.pixel_mut(0, 0).add(Rgb::splat(1.0), 1.0);
        f.add_samples_per_pixel(2);
        let pixel_box = crate::film::Filter::new(&crate::film::FilterDesc::Box {
            radius: crate::math::Vec2::splat(0.5),
        });
        assert!(f.add_splat(
            &crate::film::Splat {
                p_film: crate::math::Vec2::new(0.5, 0.5),
                l: Rgb::splat(4.0),
            },
            &pixel_box
        ));
        // Estimate 1 + 4 / 2 = 3 against a reference of 3: no error.
        let s = FilmStatistics::measure(&f, Some(&[Rgb::splat(3.0)]));
        assert!((s.mean.r - 3.0).abs() < 1e-6, "{:?}", s.mean);
        assert!(s.rel_mse.unwrap() < 1e-12);
    }
}
