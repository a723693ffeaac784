//! Sample generators: the [`Sampler`] enum over a closed set of kinds, each in its own file.
//!
//! Every random number is a pure function of (seed, pixel, sample index, dimension), where
//! the dimension is the number of values drawn since [`Sampler::start_pixel_sample`]; so an
//! image does not depend on the thread count, and a failing sample can be replayed alone.

mod independent;

pub use independent::IndependentSampler;

use crate::math::{UVec2, Vec2};
use crate::scene::{SamplerDesc, SamplerKind};

/// A sample generator; one per thread, restarted for every pixel sample.
#[derive(Clone, Debug)]
pub enum Sampler {
    /// Independent uniform random numbers.
    Independent(IndependentSampler),
}

/// Forwards a method call to the variant inside a [`Sampler`].
macro_rules! dispatch {
    ($self:expr, $s:ident => $call:expr) => {
        match $self {
            Sampler::Independent($s) => $call,
        }
    };
}

impl Sampler {
    /// The sampler a scene description asks for.
    #[must_use]
    pub fn new(desc: &SamplerDesc) -> Self {
        match desc.kind {
            SamplerKind::Independent => Self::Independent(IndependentSampler::new(desc.samples_per_pixel, desc.seed)),
        }
    }

    /// Number of samples taken in each pixel.
    #[inline]
    #[must_use]
    pub fn samples_per_pixel(&self) -> u32 {
        dispatch!(self, s => s.samples_per_pixel())
    }

    /// Starts sample `sample_index` of `pixel`: from here on the values drawn depend only on
    /// the seed, `pixel`, `sample_index` and how many values were drawn before.
    #[inline]
    pub fn start_pixel_sample(&mut self, pixel: UVec2, sample_index: u32) {
        dispatch!(self, s => s.start_pixel_sample(pixel, sample_index));
    }

    /// The next sample dimension, in [0, 1).
    #[inline]
    pub fn get_1d(&mut self) -> f32 {
        dispatch!(self, s => s.get_1d())
    }

    /// The next two sample dimensions, in [0, 1)^2.
    #[inline]
    pub fn get_2d(&mut self) -> Vec2 {
        dispatch!(self, s => s.get_2d())
    }

    /// The two dimensions that place the sample inside the pixel (for the filter), in
    /// [0, 1)^2.
    #[inline]
    pub fn get_pixel_2d(&mut self) -> Vec2 {
        dispatch!(self, s => s.get_pixel_2d())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn draw(sampler: &mut Sampler, pixel: UVec2, index: u32) -> Vec<f32> {
        sampler.start_pixel_sample(pixel, index);
        let mut v = vec![sampler.get_1d()];
        let p = sampler.get_pixel_2d();
        let q = sampler.get_2d();
        v.extend([p.x, p.y, q.x, q.y]);
        v.extend((0..11).map(|_| sampler.get_1d()));
        v
    }

    fn sampler(seed: u64) -> Sampler {
        Sampler::new(&SamplerDesc {
            kind: SamplerKind::Independent,
            samples_per_pixel: 4,
            seed,
        })
    }

    #[test]
    fn builds_from_the_description() {
        assert_eq!(sampler(0).samples_per_pixel(), 4);
    }

    #[test]
    fn streams_are_reproducible() {
        let mut a = sampler(7);
        let mut b = sampler(7);
        let first = draw(&mut a, UVec2::new(3, 5), 2);
        // Draw other samples in between: the stream must not depend on history.
        draw(&mut a, UVec2::new(9, 9), 0);
        draw(&mut b, UVec2::new(1, 0), 1);
        assert_eq!(draw(&mut a, UVec2::new(3, 5), 2), first);
        assert_eq!(draw(&mut b, UVec2::new(3, 5), 2), first);
    }

    #[test]
    fn streams_differ_between_pixels_indices_and_seeds() {
        let base = draw(&mut sampler(7), UVec2::new(3, 5), 2);
        let others = [
            draw(&mut sampler(7), UVec2::new(5, 3), 2),
            draw(&mut sampler(7), UVec2::new(4, 5), 2),
            draw(&mut sampler(7), UVec2::new(3, 6), 2),
            draw(&mut sampler(7), UVec2::new(3, 5), 3),
            draw(&mut sampler(8), UVec2::new(3, 5), 2),
        ];
        for other in others {
            // Independent streams agree on a value with probability ~2^-24 per dimension.
            assert!(base.iter().zip(&other).all(|(a, b)| a != b), "{base:?} vs {other:?}");
        }
    }

    #[test]
    fn values_are_in_unit_interval() {
        let mut s = sampler(1);
        for index in 0..64 {
            for v in draw(&mut s, UVec2::new(index % 8, index / 8), index) {
                assert!((0.0..1.0).contains(&v));
            }
        }
    }
}
