//! Layer 2: the bounding volume hierarchies: a binary one ([`Bvh`]) and the 4-wide one the
//! scene traces ([`WideBvh`]), both over primitives known by index and bounds.

mod bvh;
mod wide;
mod wide_build;

pub use bvh::{Bvh, BvhNode};
pub use wide::{WideBvh, WideNode, WIDTH};
