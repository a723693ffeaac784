//! Layer 2: cameras. One variant for now: pbrt's perspective camera.

mod perspective;

pub use perspective::PerspectiveCamera;

use crate::math::{Ray, Vec2};

/// The closed set of cameras.
#[derive(Clone, Debug)]
pub enum Camera {
    /// Pinhole or thin-lens perspective projection.
    Perspective(PerspectiveCamera),
}

impl Camera {
    /// The world-space ray through film position `p_film` (in raster pixels, (0,0) at the
    /// top-left corner of the image) and lens sample `u_lens`.
    #[must_use]
    pub fn generate_ray(&self, p_film: Vec2, u_lens: Vec2) -> Ray {
        match self {
            Self::Perspective(c) => c.generate_ray(p_film, u_lens),
        }
    }
}
