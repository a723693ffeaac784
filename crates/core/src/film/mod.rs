//! Layer 2: the film (per-pixel accumulators, per-pixel variance) and pixel filters.

mod accumulator;
mod filter;
mod statistics;

pub use accumulator::{Film, PixelStats};
pub use filter::{BoxFilter, Filter, FilterSample, GaussianFilter, TriangleFilter};
pub use statistics::{FilmStatistics, REL_MSE_EPSILON};
