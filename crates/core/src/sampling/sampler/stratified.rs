//! The stratified sampler (pbrt-v4's `StratifiedSampler`): in every dimension the pixel's
//! samples fall in distinct strata, matched to sample indices by a hashed permutation per
//! (pixel, dimension, seed), and jittered inside their stratum.

use crate::math::{UVec2, Vec2};
use crate::sampling::{hash_u64s, mix_bits, permutation_element, Pcg32};

/// Random values reserved for the jitter of each pixel sample (as the independent sampler).
const DIMENSIONS_PER_SAMPLE: i64 = 1 << 16;

/// Jittered stratified samples over an `x_samples` x `y_samples` grid.
///
/// A 1-D value uses `x_samples * y_samples` intervals, a 2-D value the grid; the stratum of
/// sample `i` is element `i` of a permutation hashed from (pixel, dimension, seed), so each
/// dimension is stratified on its own and the dimensions are decorrelated. Sample indices
/// at or beyond `samples_per_pixel` wrap around the strata.
#[derive(Clone, Debug)]
pub struct StratifiedSampler {
    x_samples: u32,
    y_samples: u32,
    jitter: bool,
    seed: u64,
    pixel: UVec2,
    sample_index: u32,
    dimension: u32,
    rng: Pcg32,
}

impl StratifiedSampler {
    /// A sampler taking `x_samples * y_samples` samples in each pixel (both at least 1).
    #[must_use]
    pub fn new(x_samples: u32, y_samples: u32, jitter: bool, seed: u64) -> Self {
        Self {
            x_samples: x_samples.max(1),
            y_samples: y_samples.max(1),
            jitter,
            seed,
            pixel: UVec2::ZERO,
            sample_index: 0,
            dimension: 0,
            rng: Pcg32::default(),
        }
    }

    /// Number of samples taken in each pixel.
    #[inline]
    #[must_use]
    pub fn samples_per_pixel(&self) -> u32 {
        self.x_samples * self.y_samples
    }

    /// Restarts at sample `sample_index` of `pixel`.
    #[inline]
    pub fn start_pixel_sample(&mut self, pixel: UVec2, sample_index: u32) {
        self.pixel = pixel;
        self.sample_index = sample_index;
        self.dimension = 0;
        let stream = hash_u64s(&[u64::from(pixel.x), u64::from(pixel.y), self.seed]);
        self.rng.set_sequence(stream, mix_bits(stream));
        self.rng.advance(i64::from(sample_index) * DIMENSIONS_PER_SAMPLE);
    }

    /// The stratum of the current sample for the next dimension, among `n`.
    #[inline]
    fn stratum(&mut self, n: u32) -> u32 {
        let hash = hash_u64s(&[
            u64::from(self.pixel.x),
            u64::from(self.pixel.y),
            u64::from(self.dimension),
            self.seed,
        ]);
        permutation_element(self.sample_index % n, n, hash as u32)
    }

    /// Offset inside a stratum: uniform, or its centre.
    #[inline]
    fn offset(&mut self) -> f32 {
        if self.jitter {
            self.rng.next_f32()
        } else {
            0.5
        }
    }

    /// The next value in [0, 1).
    #[inline]
    pub fn get_1d(&mut self) -> f32 {
        let n = self.samples_per_pixel();
        let stratum = self.stratum(n);
        self.dimension += 1;
        to_unit(stratum, self.offset(), n)
    }

    /// The next two values in [0, 1)^2.
    #[inline]
    pub fn get_2d(&mut self) -> Vec2 {
        let stratum = self.stratum(self.samples_per_pixel());
        self.dimension += 2;
        let (x, y) = (stratum % self.x_samples, stratum / self.x_samples);
        let dx = self.offset();
        let dy = self.offset();
        Vec2::new(to_unit(x, dx, self.x_samples), to_unit(y, dy, self.y_samples))
    }

    /// Position inside the pixel; the same as [`get_2d`](Self::get_2d) for this sampler.
    #[inline]
    pub fn get_pixel_2d(&mut self) -> Vec2 {
        self.get_2d()
    }
}

/// `(stratum + offset) / n`, kept below 1 where rounding would reach it.
#[inline]
fn to_unit(stratum: u32, offset: f32, n: u32) -> f32 {
    ((stratum as f32 + offset) / n as f32).min(crate::sampling::ONE_MINUS_EPSILON)
}
