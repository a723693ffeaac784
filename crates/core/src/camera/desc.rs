//! What a loader says about the camera: [`CameraDesc`], consumed by [`super::Camera`].

use crate::math::Transform;

/// How camera space is projected onto the film.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Projection {
    /// pbrt `Camera "perspective"`: rays fan out from the lens; `fov_degrees` applies.
    #[default]
    Perspective,
    /// pbrt `Camera "orthographic"`: parallel rays from the screen window on the plane
    /// `z = 0` of camera space (in camera-space units); `fov_degrees` is unused.
    Orthographic,
}

/// A pinhole or thin-lens camera, perspective (pbrt `Camera "perspective"`) or
/// orthographic (`Camera "orthographic"`).
#[derive(Clone, Debug, PartialEq)]
pub struct CameraDesc {
    /// Perspective or orthographic.
    pub projection: Projection,
    /// World-from-camera transform. Camera space is pbrt's: +x right in the image, +y up,
    /// looking down +z.
    pub world_from_camera: Transform,
    /// Full field of view in degrees, spanning the shorter image axis (perspective only).
    pub fov_degrees: f32,
    /// Lens radius (0 = pinhole).
    pub lens_radius: f32,
    /// Distance to the plane in focus (used when `lens_radius > 0`).
    pub focal_distance: f32,
    /// Screen window `[x_min, x_max, y_min, y_max]`; `None` = pbrt's default from the aspect
    /// ratio.
    pub screen_window: Option<[f32; 4]>,
}

impl Default for CameraDesc {
    fn default() -> Self {
        Self {
            projection: Projection::Perspective,
            world_from_camera: Transform::IDENTITY,
            fov_degrees: 90.0,
            lens_radius: 0.0,
            focal_distance: 1e6,
            screen_window: None,
        }
    }
}
