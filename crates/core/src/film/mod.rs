//! Layer 2: the film (per-pixel accumulators, per-pixel variance) and pixel filters.

mod accumulator;
mod filter;

pub use accumulator::{Film, PixelStats};
pub use filter::{BoxFilter, Filter, FilterSample, GaussianFilter, TriangleFilter};
