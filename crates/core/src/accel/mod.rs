//! Layer 2: the bounding volume hierarchies: a binary one ([`Bvh`]) and the 4-wide one the
//! scene traces ([`WideBvh`]), both over primitives known by index and bounds, with leaf
//! triangles precomputed for testing four at a time ([`TriBlock`]) and the instruction set
//! of the queries chosen at run time ([`Isa`]).

mod bvh;
mod simd;
mod tri_block;
mod wide;
mod wide_build;

pub use bvh::{Bvh, BvhNode};
pub use simd::Isa;
pub use tri_block::{TriBlock, TriangleHit};
pub use wide::{WideBvh, WideNode, WIDTH};
