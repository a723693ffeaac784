//! Sample generators: the [`Sampler`] enum over a closed set of kinds, each in its own file.
//!
//! Every random number is a pure function of (seed, pixel, sample index, dimension), where
//! the dimension is the number of values drawn since [`Sampler::start_pixel_sample`]; so an
//! image does not depend on the thread count, and a failing sample can be replayed alone.

mod desc;
mod independent;
mod sobol;
mod stratified;
#[cfg(test)]
mod tests_quality;

pub use desc::{SamplerDesc, SamplerKind};
pub use independent::IndependentSampler;
pub use sobol::OwenSobolSampler;
pub use stratified::StratifiedSampler;

use crate::math::{UVec2, Vec2};

/// A sample generator; one per thread, restarted for every pixel sample.
// The Sobol' variant carries its per-pixel digit cache (about 270 bytes); a sampler is made
// once per tile and never moved in the sample loop, and a box would put an indirection on
// every value drawn.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug)]
pub enum Sampler {
    /// Independent uniform random numbers.
    Independent(IndependentSampler),
    /// Jittered stratified samples.
    Stratified(StratifiedSampler),
    /// Owen-scrambled Sobol' points.
    OwenSobol(OwenSobolSampler),
}

/// Forwards a method call to the variant inside a [`Sampler`].
macro_rules! dispatch {
    ($self:expr, $s:ident => $call:expr) => {
        match $self {
            Sampler::Independent($s) => $call,
            Sampler::Stratified($s) => $call,
            Sampler::OwenSobol($s) => $call,
        }
    };
}

impl Sampler {
    /// The sampler a scene description asks for.
    ///
    /// A stratified sampler whose grid does not multiply to `desc.samples_per_pixel` (the
    /// count was overridden after loading) takes the most nearly square grid of that count.
    #[must_use]
    pub fn new(desc: &SamplerDesc) -> Self {
        let spp = desc.samples_per_pixel.max(1);
        match desc.kind {
            SamplerKind::Independent => Self::Independent(IndependentSampler::new(desc.samples_per_pixel, desc.seed)),
            SamplerKind::Stratified {
                x_samples,
                y_samples,
                jitter,
            } => {
                let (x, y) = if x_samples.checked_mul(y_samples) == Some(spp) {
                    (x_samples, y_samples)
                } else {
                    square_grid(spp)
                };
                Self::Stratified(StratifiedSampler::new(x, y, jitter, desc.seed))
            }
            SamplerKind::OwenSobol => Self::OwenSobol(OwenSobolSampler::new(desc.samples_per_pixel, desc.seed)),
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

/// The factorisation `x * y = n` with `x <= y` and `x` as large as possible.
fn square_grid(n: u32) -> (u32, u32) {
    let mut x = (f64::from(n).sqrt() as u32).max(1);
    while !n.is_multiple_of(x) {
        x -= 1;
    }
    (x, n / x)
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

    /// Every kind, with 4 samples per pixel.
    const KINDS: [SamplerKind; 4] = [
        SamplerKind::Independent,
        SamplerKind::Stratified {
            x_samples: 2,
            y_samples: 2,
            jitter: true,
        },
        SamplerKind::Stratified {
            x_samples: 2,
            y_samples: 2,
            jitter: false,
        },
        SamplerKind::OwenSobol,
    ];

    fn sampler_of(kind: SamplerKind, seed: u64) -> Sampler {
        Sampler::new(&SamplerDesc {
            kind,
            samples_per_pixel: 4,
            seed,
        })
    }

    fn sampler(seed: u64) -> Sampler {
        sampler_of(SamplerKind::Independent, seed)
    }

    #[test]
    fn builds_from_the_description() {
        for kind in KINDS {
            let s = sampler_of(kind, 0);
            assert_eq!(s.samples_per_pixel(), 4);
            let matches = matches!(
                (kind, &s),
                (SamplerKind::Independent, Sampler::Independent(_))
                    | (SamplerKind::Stratified { .. }, Sampler::Stratified(_))
                    | (SamplerKind::OwenSobol, Sampler::OwenSobol(_))
            );
            assert!(matches, "{kind:?} built {s:?}");
        }
    }

    #[test]
    fn stratified_grid_follows_an_overridden_sample_count() {
        assert_eq!(square_grid(12), (3, 4));
        assert_eq!(square_grid(7), (1, 7));
        assert_eq!(square_grid(16), (4, 4));
        let s = Sampler::new(&SamplerDesc {
            kind: SamplerKind::Stratified {
                x_samples: 3,
                y_samples: 5,
                jitter: true,
            },
            samples_per_pixel: 8,
            seed: 0,
        });
        assert_eq!(s.samples_per_pixel(), 8);
    }

    #[test]
    fn streams_are_reproducible() {
        for kind in KINDS {
            let mut a = sampler_of(kind, 7);
            let mut b = sampler_of(kind, 7);
            let first = draw(&mut a, UVec2::new(3, 5), 2);
            // Draw other samples in between: the stream must not depend on history.
            draw(&mut a, UVec2::new(9, 9), 0);
            draw(&mut b, UVec2::new(1, 0), 1);
            assert_eq!(draw(&mut a, UVec2::new(3, 5), 2), first, "{kind:?}");
            assert_eq!(draw(&mut b, UVec2::new(3, 5), 2), first, "{kind:?}");
        }
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
        for kind in KINDS {
            let mut s = sampler_of(kind, 1);
            for index in 0..64 {
                let mut values = draw(&mut s, UVec2::new(index % 8, index / 8), index);
                // Run past the Sobol' table into the padded dimensions.
                values.extend((0..100).map(|_| s.get_1d()));
                for v in values {
                    assert!((0.0..1.0).contains(&v), "{kind:?}: {v}");
                }
            }
        }
    }

    #[test]
    fn seeds_and_pixels_change_the_scrambled_streams() {
        for kind in [KINDS[1], KINDS[3]] {
            let base = draw(&mut sampler_of(kind, 7), UVec2::new(3, 5), 2);
            for other in [
                draw(&mut sampler_of(kind, 8), UVec2::new(3, 5), 2),
                draw(&mut sampler_of(kind, 7), UVec2::new(4, 5), 2),
            ] {
                assert_ne!(base, other, "{kind:?}");
            }
        }
    }
}
