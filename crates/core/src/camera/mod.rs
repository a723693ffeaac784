//! Layer 2: cameras. One variant for now: pbrt's perspective camera.

mod perspective;

pub use perspective::PerspectiveCamera;

use crate::math::{Ray, Vec2, Vec3};

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

    /// The change of the surface point `p` with normal `n` per pixel step in x and y on
    /// the image, for a render with `samples_per_pixel` samples (pbrt-v4
    /// `Approximate_dp_dxy`; see [`PerspectiveCamera::approximate_dp_dxy`]).
    #[must_use]
    pub fn approximate_dp_dxy(&self, p: Vec3, n: Vec3, samples_per_pixel: u32) -> (Vec3, Vec3) {
        match self {
            Self::Perspective(c) => c.approximate_dp_dxy(p, n, samples_per_pixel),
        }
    }
}
