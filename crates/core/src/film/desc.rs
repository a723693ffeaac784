//! What a loader says about the film: its size ([`FilmDesc`]) and pixel filter
//! ([`FilterDesc`], consumed by [`super::Filter`]).

use crate::math::Vec2;

/// Image size in pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FilmDesc {
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
}

impl Default for FilmDesc {
    fn default() -> Self {
        Self {
            width: 1280,
            height: 720,
        }
    }
}

/// Pixel reconstruction filter; radii are in pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FilterDesc {
    /// Constant over `[-r, r]^2`.
    Box {
        /// Radius per axis.
        radius: Vec2,
    },
    /// Separable tent `max(0, r - |x|)`.
    Triangle {
        /// Radius per axis.
        radius: Vec2,
    },
    /// Separable Gaussian minus its value at the radius (pbrt-v4's `gaussian`).
    Gaussian {
        /// Radius per axis.
        radius: Vec2,
        /// Standard deviation in pixels.
        sigma: f32,
    },
    /// Separable Mitchell-Netravali cubic (pbrt-v4's `mitchell`), negative in its lobes.
    Mitchell {
        /// Radius per axis (pbrt default 2).
        radius: Vec2,
        /// The cubic's `B` (pbrt default 1/3).
        b: f32,
        /// The cubic's `C` (pbrt default 1/3).
        c: f32,
    },
}

impl Default for FilterDesc {
    fn default() -> Self {
        Self::Gaussian {
            radius: Vec2::splat(1.5),
            sigma: 0.5,
        }
    }
}
