//! Layer 4: the render-ready scene. Built from a [`SceneDescription`]: shapes, materials
//! and lights in flat arrays with integer handles, and the BVH over all primitives.

mod description;

pub use description::*;
