//! pbrt-v4's perspective camera: `fov` spans the shorter image axis; the screen window is
//! `[-aspect, aspect] x [-1, 1]` (or the transpose for tall images); raster y grows
//! downwards while camera +y is up; the camera looks down +z. A thin lens of `lens_radius`
//! focuses at `focal_distance`.

use crate::math::{Ray, Transform, Vec2, Vec3};
use crate::sampling::sample_uniform_disk_concentric;
use crate::scene::{CameraDesc, FilmDesc};

/// Perspective projection with an optional thin lens.
#[derive(Clone, Debug)]
pub struct PerspectiveCamera {
    world_from_camera: Transform,
    /// Screen window `[x_min, x_max, y_min, y_max]`.
    screen: [f32; 4],
    resolution: Vec2,
    tan_half_fov: f32,
    lens_radius: f32,
    focal_distance: f32,
}

impl PerspectiveCamera {
    /// Build from the description and the film size.
    #[must_use]
    pub fn new(desc: &CameraDesc, film: &FilmDesc) -> Self {
        let aspect = film.width as f32 / film.height as f32;
        let screen = desc.screen_window.unwrap_or(if aspect > 1.0 {
            [-aspect, aspect, -1.0, 1.0]
        } else {
            [-1.0, 1.0, -1.0 / aspect, 1.0 / aspect]
        });
        Self {
            world_from_camera: desc.world_from_camera,
            screen,
            resolution: Vec2::new(film.width as f32, film.height as f32),
            tan_half_fov: (desc.fov_degrees.to_radians() * 0.5).tan(),
            lens_radius: desc.lens_radius,
            focal_distance: desc.focal_distance,
        }
    }

    /// The ray through raster position `p_film`.
    #[must_use]
    pub fn generate_ray(&self, p_film: Vec2, u_lens: Vec2) -> Ray {
        let [x0, x1, y0, y1] = self.screen;
        let sx = x0 + p_film.x / self.resolution.x * (x1 - x0);
        let sy = y1 - p_film.y / self.resolution.y * (y1 - y0);
        let dir = Vec3::new(sx * self.tan_half_fov, sy * self.tan_half_fov, 1.0);
        let (o, d) = if self.lens_radius > 0.0 {
            // Thin lens: aim through the point on the plane of focus.
            let p_lens = self.lens_radius * sample_uniform_disk_concentric(u_lens);
            let p_focus = dir * self.focal_distance;
            let o = Vec3::new(p_lens.x, p_lens.y, 0.0);
            (o, p_focus - o)
        } else {
            (Vec3::ZERO, dir)
        };
        Ray::new(
            self.world_from_camera.point(o),
            self.world_from_camera.vector(d).normalize(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centre_ray_looks_down_z_and_x_grows_to_the_right() {
        let cam = PerspectiveCamera::new(
            &CameraDesc {
                fov_degrees: 90.0,
                ..Default::default()
            },
            &FilmDesc {
                width: 200,
                height: 100,
            },
        );
        let r = cam.generate_ray(Vec2::new(100.0, 50.0), Vec2::ZERO);
        assert!((r.d - Vec3::Z).length() < 1e-6);
        // Top-left corner: -x (left), +y (up); fov spans the shorter (vertical) axis.
        let r = cam.generate_ray(Vec2::ZERO, Vec2::ZERO);
        let d = r.d / r.d.z;
        assert!((d - Vec3::new(-2.0, 1.0, 1.0)).length() < 1e-5, "{d}");
    }

    #[test]
    fn thin_lens_rays_meet_on_the_focal_plane() {
        let desc = CameraDesc {
            fov_degrees: 40.0,
            lens_radius: 0.5,
            focal_distance: 3.0,
            ..Default::default()
        };
        let cam = PerspectiveCamera::new(&desc, &FilmDesc { width: 64, height: 64 });
        let p = Vec2::new(10.0, 20.0);
        let a = cam.generate_ray(p, Vec2::new(0.1, 0.9));
        let b = cam.generate_ray(p, Vec2::new(0.8, 0.3));
        let pa = a.at((3.0 - a.o.z) / a.d.z);
        let pb = b.at((3.0 - b.o.z) / b.d.z);
        assert!((pa - pb).length() < 1e-4);
    }
}
