//! Layer 2: the film (per-pixel accumulators, per-pixel variance) and pixel filters.
