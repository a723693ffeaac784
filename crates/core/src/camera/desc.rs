//! What a loader says about the camera: [`CameraDesc`], consumed by [`super::Camera`].

use crate::math::Transform;

/// A pinhole or thin-lens perspective camera (pbrt `Camera "perspective"`).
#[derive(Clone, Debug, PartialEq)]
pub struct CameraDesc {
    /// World-from-camera transform. Camera space is pbrt's: +x right in the image, +y up,
    /// looking down +z.
    pub world_from_camera: Transform,
    /// Full field of view in degrees, spanning the shorter image axis.
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
            world_from_camera: Transform::IDENTITY,
            fov_degrees: 90.0,
            lens_radius: 0.0,
            focal_distance: 1e6,
            screen_window: None,
        }
    }
}
