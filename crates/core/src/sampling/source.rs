//! [`SampleSource`]: the two calls a random walk draws its numbers with, shared by the
//! per-pixel [`super::Sampler`] and the Metropolis sampler [`super::MltSampler`], so that
//! the bidirectional subpath and connection code serves both.

use crate::math::Vec2;

/// A source of sample values in [0, 1).
pub trait SampleSource {
    /// The next sample dimension, in [0, 1).
    fn get_1d(&mut self) -> f32;
    /// The next two sample dimensions, in [0, 1)^2.
    fn get_2d(&mut self) -> Vec2;
}

impl SampleSource for super::Sampler {
    #[inline]
    fn get_1d(&mut self) -> f32 {
        super::Sampler::get_1d(self)
    }

    #[inline]
    fn get_2d(&mut self) -> Vec2 {
        super::Sampler::get_2d(self)
    }
}
