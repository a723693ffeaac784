//! Layer 2: cameras: pbrt's perspective and orthographic cameras. Cameras generate rays
//! from film positions and, for light tracing, report the importance of rays reaching them
//! ([`Camera::we`], [`Camera::pdf_we`], [`Camera::sample_wi`]).

mod desc;
mod orthographic;
mod perspective;

pub use desc::{CameraDesc, Projection};
pub use orthographic::OrthographicCamera;
pub use perspective::{CameraWiSample, PerspectiveCamera};

use crate::film::FilmDesc;

use crate::math::{Ray, Vec2, Vec3};

/// The closed set of cameras.
#[derive(Clone, Debug)]
pub enum Camera {
    /// Pinhole or thin-lens perspective projection.
    Perspective(PerspectiveCamera),
    /// Orthographic projection, pinhole or thin lens.
    Orthographic(OrthographicCamera),
}

impl Camera {
    /// The camera `desc` describes, for a film of `film`'s size and a pixel filter of
    /// `filter_radius` (which sets the sample bounds).
    #[must_use]
    pub fn new(desc: &CameraDesc, film: &FilmDesc, filter_radius: Vec2) -> Self {
        match desc.projection {
            Projection::Perspective => Self::Perspective(PerspectiveCamera::new(desc, film, filter_radius)),
            Projection::Orthographic => Self::Orthographic(OrthographicCamera::new(desc, film, filter_radius)),
        }
    }

    /// True for the orthographic camera.
    #[must_use]
    pub fn is_orthographic(&self) -> bool {
        matches!(self, Self::Orthographic(_))
    }

    /// The area density at `p_next` of the camera endpoint at `p_cam` choosing it as the
    /// next vertex of a camera subpath, divided by the cosine at `p_next` (for BDPT's MIS):
    /// `pdf_dir / r^2` for the perspective camera, and for the orthographic one the density
    /// of [`OrthographicCamera::pdf_area_per_cos`].
    #[must_use]
    pub fn pdf_area_per_cos(&self, p_cam: Vec3, p_next: Vec3) -> f32 {
        match self {
            Self::Perspective(c) => {
                let w = p_next - p_cam;
                let d2 = w.length_squared();
                if d2 == 0.0 {
                    return 0.0;
                }
                c.pdf_we(&Ray::new(p_cam, w / d2.sqrt())).1 / d2
            }
            Self::Orthographic(c) => c.pdf_area_per_cos(p_cam, p_next),
        }
    }
    /// The world-space ray through film position `p_film` (in raster pixels, (0,0) at the
    /// top-left corner of the image) and lens sample `u_lens`.
    #[must_use]
    pub fn generate_ray(&self, p_film: Vec2, u_lens: Vec2) -> Ray {
        match self {
            Self::Perspective(c) => c.generate_ray(p_film, u_lens),
            Self::Orthographic(c) => c.generate_ray(p_film, u_lens),
        }
    }

    /// The change of the surface point `p` with normal `n` per pixel step in x and y on
    /// the image, for a render with `samples_per_pixel` samples (pbrt-v4
    /// `Approximate_dp_dxy`; see [`PerspectiveCamera::approximate_dp_dxy`]).
    #[must_use]
    pub fn approximate_dp_dxy(&self, p: Vec3, n: Vec3, samples_per_pixel: u32) -> (Vec3, Vec3) {
        match self {
            Self::Perspective(c) => c.approximate_dp_dxy(p, n, samples_per_pixel),
            Self::Orthographic(c) => c.approximate_dp_dxy(p, n, samples_per_pixel),
        }
    }

    /// The film's sample bounds in raster space, `[min, max)`: where camera samples land
    /// and the importance is non-zero (see [`PerspectiveCamera::sample_bounds`]).
    #[must_use]
    pub fn sample_bounds(&self) -> [Vec2; 2] {
        match self {
            Self::Perspective(c) => c.sample_bounds(),
            Self::Orthographic(c) => c.sample_bounds(),
        }
    }

    /// Importance of `ray` leaving the lens, and where it lands on the film (raster
    /// coordinates); `None` when it misses the film (see [`PerspectiveCamera::we`]).
    #[must_use]
    pub fn we(&self, ray: &Ray) -> Option<(f32, Vec2)> {
        match self {
            Self::Perspective(c) => c.we(ray),
            Self::Orthographic(c) => c.we(ray),
        }
    }

    /// Densities `(pdf_pos, pdf_dir)` of generating `ray` (see [`PerspectiveCamera::pdf_we`]).
    #[must_use]
    pub fn pdf_we(&self, ray: &Ray) -> (f32, f32) {
        match self {
            Self::Perspective(c) => c.pdf_we(ray),
            Self::Orthographic(c) => c.pdf_we(ray),
        }
    }

    /// A lens point that sees `p_ref`, with its importance and density (see
    /// [`PerspectiveCamera::sample_wi`]).
    #[must_use]
    pub fn sample_wi(&self, p_ref: Vec3, u: Vec2) -> Option<CameraWiSample> {
        match self {
            Self::Perspective(c) => c.sample_wi(p_ref, u),
            Self::Orthographic(c) => c.sample_wi(p_ref, u),
        }
    }
}
