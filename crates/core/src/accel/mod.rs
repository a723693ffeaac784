//! Layer 2: the bounding volume hierarchy the scene traces, 8-wide ([`WideBvh`]), over
//! primitives known by index and bounds, with leaf
//! triangles precomputed for testing four at a time ([`TriBlock`]) and the instruction set
//! of the queries chosen at run time ([`Isa`]).

mod packet;
mod paged;
mod simd;
mod tri_block;
mod wide;
mod wide_build;

pub use crate::math::simd::Isa;
pub use packet::PACKET;
pub use tri_block::{TriBlock, TriangleHit};
pub use wide::{WideBvh, WideNode, WIDTH};
