//! The independent sampler: plain uniform random numbers, one PCG32 stream per pixel.

use crate::math::{UVec2, Vec2};
use crate::sampling::{hash_u64s, mix_bits, Pcg32};

/// Number of random values reserved for each pixel sample: sample `i` of a pixel starts at
/// offset `i * DIMENSIONS_PER_SAMPLE` of the pixel's stream. A sample that draws more simply
/// runs into the values of the next one; nothing breaks, they are no longer independent.
const DIMENSIONS_PER_SAMPLE: i64 = 1 << 16;

/// Independent uniform random numbers from a PCG32 stream chosen by hashing
/// (pixel, seed) and offset by the sample index (as pbrt-v4's `IndependentSampler`).
#[derive(Clone, Debug)]
pub struct IndependentSampler {
    samples_per_pixel: u32,
    seed: u64,
    rng: Pcg32,
}

impl IndependentSampler {
    /// A sampler taking `samples_per_pixel` samples in each pixel.
    #[must_use]
    pub fn new(samples_per_pixel: u32, seed: u64) -> Self {
        Self {
            samples_per_pixel,
            seed,
            rng: Pcg32::default(),
        }
    }

    /// Number of samples taken in each pixel.
    #[inline]
    #[must_use]
    pub fn samples_per_pixel(&self) -> u32 {
        self.samples_per_pixel
    }

    /// Restarts the stream at sample `sample_index` of `pixel`.
    #[inline]
    pub fn start_pixel_sample(&mut self, pixel: UVec2, sample_index: u32) {
        let stream = hash_u64s(&[u64::from(pixel.x), u64::from(pixel.y), self.seed]);
        self.rng.set_sequence(stream, mix_bits(stream));
        self.rng.advance(i64::from(sample_index) * DIMENSIONS_PER_SAMPLE);
    }

    /// The next value in [0, 1).
    #[inline]
    pub fn get_1d(&mut self) -> f32 {
        self.rng.next_f32()
    }

    /// The next two values in [0, 1)^2.
    #[inline]
    pub fn get_2d(&mut self) -> Vec2 {
        let x = self.rng.next_f32();
        Vec2::new(x, self.rng.next_f32())
    }

    /// Position inside the pixel; the same as [`get_2d`](Self::get_2d) for this sampler.
    #[inline]
    pub fn get_pixel_2d(&mut self) -> Vec2 {
        self.get_2d()
    }
}
