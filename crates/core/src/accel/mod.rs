//! Layer 2: the bounding volume hierarchy.

mod bvh;

pub use bvh::{Bvh, BvhNode};
