//! mcrender-core: everything that renders. Sampling, shapes, the BVH, BSDFs, lights,
//! integrators and the parallel renderer. No file or string parsing: scenes arrive as a
//! [`scene::SceneDescription`] built by a loader (see the `mcrender-formats` crate).
//!
//! Conventions (as pbrt-v4, whose scene format we read): BSDF values `f` exclude the cosine
//! factor; all directional pdfs are per unit solid angle; `wo` and `wi` point away from the
//! surface.

pub mod accel;
pub mod bsdf;
pub mod bytes;
pub mod camera;
pub mod color;
pub mod film;
pub mod integrator;
pub mod lab;
pub mod light;
pub mod material;
pub mod math;
pub mod render;
pub mod sampling;
pub mod scene;
pub mod shape;
pub mod texture;
