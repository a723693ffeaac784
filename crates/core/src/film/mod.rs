//! Layer 2: the film (per-pixel accumulators, per-pixel variance, splat sums) and pixel filters.

mod accumulator;
mod compare;
mod desc;
mod filter;
mod filter_groups;
mod filtered_sums;
mod splat;
mod splat_sum;
mod statistics;

pub use accumulator::{Film, PixelStats};
pub use compare::{
    block_means_of, downsample_box, pixel_rel_error, CompareError, ImageComparison, BLOCK_REL_EPSILON, DEFAULT_BLOCK,
};
pub use desc::{FilmDesc, FilterDesc, Reconstruction};
pub use filter::{BoxFilter, Filter, FilterSample, GaussianFilter, MitchellFilter, TriangleFilter};
pub use filtered_sums::{FilterGroup, FilteredSums, FILTERED_SUMS_LEN};
pub use splat::{Footprint, Splat};
pub use splat_sum::{SplatSum, MAX_SPLAT};
pub use statistics::{FilmStatistics, REL_MSE_EPSILON};
