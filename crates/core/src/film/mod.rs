//! Layer 2: the film (per-pixel accumulators, per-pixel variance) and pixel filters.

mod filter;

pub use filter::{BoxFilter, Filter, FilterSample, GaussianFilter, TriangleFilter};
