//! Layer 1: random numbers, samplers, warps from the unit square with their pdfs and
//! inverses, piecewise-constant 1-D and 2-D distributions, MIS heuristics, and the
//! chi-square harness that tests every sampling routine against its pdf.

pub mod chi2;
mod distribution;
mod distribution_2d;
mod hash;
mod mis;
mod mlt;
mod rng;
mod sampler;
mod scramble;
mod source;
mod warp;

pub use distribution::PiecewiseConstant1D;
pub use distribution_2d::PiecewiseConstant2D;
pub use hash::{hash_absorb, hash_float, hash_u64s, mix_bits};
pub use mis::{balance_heuristic, power_heuristic};
pub use mlt::MltSampler;
pub use rng::Pcg32;
pub use sampler::{IndependentSampler, OwenSobolSampler, Sampler, SamplerDesc, SamplerKind, StratifiedSampler};
pub use scramble::{nested_uniform_scramble, nested_uniform_scramble_reversed, permutation_element};
pub use source::SampleSource;
pub use warp::*;

/// The largest `f32` below 1: the upper end of every sample value.
pub const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;
