//! pbrt-v4's perspective camera: `fov` spans the shorter image axis; the screen window is
//! `[-aspect, aspect] x [-1, 1]` (or the transpose for tall images); raster y grows
//! downwards while camera +y is up; the camera looks down +z. A thin lens of `lens_radius`
//! focuses at `focal_distance`.

#[path = "importance.rs"]
mod importance;

pub use importance::CameraWiSample;

use super::CameraDesc;
use crate::film::FilmDesc;
use crate::math::{Frame, Ray, Transform, Vec2, Vec3};
use crate::sampling::sample_uniform_disk_concentric;

/// Perspective projection with an optional thin lens.
#[derive(Clone, Debug)]
pub struct PerspectiveCamera {
    world_from_camera: Transform,
    camera_from_world: Transform,
    /// Smallest change of the unit ray direction per pixel step in x and y over the image,
    /// in a frame whose z axis is the ray (pbrt-v4 `minDirDifferentialX/Y`).
    min_dir_differential: [Vec3; 2],
    /// Screen window `[x_min, x_max, y_min, y_max]`.
    screen: [f32; 4],
    resolution: Vec2,
    /// The film's sample bounds in raster space, `[min, max)`: the pixel bounds grown by
    /// the pixel filter's radius less half a pixel (pbrt-v4 `FilmBase::SampleBounds`),
    /// where camera samples land and where the importance is non-zero.
    sample_bounds: [Vec2; 2],
    tan_half_fov: f32,
    lens_radius: f32,
    focal_distance: f32,
}

impl PerspectiveCamera {
    /// Build from the description, the film size and the radius of the pixel filter (which
    /// sets the sample bounds: a pixel's samples reach `radius` beyond its centre).
    #[must_use]
    pub fn new(desc: &CameraDesc, film: &FilmDesc, filter_radius: Vec2) -> Self {
        let aspect = film.width as f32 / film.height as f32;
        let screen = desc.screen_window.unwrap_or(if aspect > 1.0 {
            [-aspect, aspect, -1.0, 1.0]
        } else {
            [-1.0, 1.0, -1.0 / aspect, 1.0 / aspect]
        });
        let mut camera = Self {
            world_from_camera: desc.world_from_camera,
            camera_from_world: desc.world_from_camera.inverse(),
            min_dir_differential: [Vec3::ZERO; 2],
            screen,
            resolution: Vec2::new(film.width as f32, film.height as f32),
            sample_bounds: [
                Vec2::splat(0.5) - filter_radius,
                Vec2::new(film.width as f32, film.height as f32) - Vec2::splat(0.5) + filter_radius,
            ],
            tan_half_fov: (desc.fov_degrees.to_radians() * 0.5).tan(),
            lens_radius: desc.lens_radius,
            focal_distance: desc.focal_distance,
        };
        camera.min_dir_differential = camera.find_minimum_differentials();
        camera
    }

    /// Camera-space direction (not normalised) through raster position `p_film`, from the
    /// lens centre.
    fn camera_direction(&self, p_film: Vec2) -> Vec3 {
        let [x0, x1, y0, y1] = self.screen;
        let sx = x0 + p_film.x / self.resolution.x * (x1 - x0);
        let sy = y1 - p_film.y / self.resolution.y * (y1 - y0);
        Vec3::new(sx * self.tan_half_fov, sy * self.tan_half_fov, 1.0)
    }

    /// pbrt-v4 `CameraBase::FindMinimumDifferentials`: over 512 points along the image
    /// diagonal, the shortest change of the unit ray direction for a one-pixel step in x
    /// and in y, expressed in a frame whose z axis is the ray. Rays from the lens centre
    /// (pbrt's lens sample (0.5, 0.5)) all start at the origin, so the position
    /// differentials are zero and left out.
    fn find_minimum_differentials(&self) -> [Vec3; 2] {
        const N: usize = 512;
        let mut min = [Vec3::splat(f32::INFINITY); 2];
        for i in 0..N {
            let p = self.resolution * (i as f32 / (N - 1) as f32);
            let d = self.camera_direction(p).normalize();
            let frame = Frame::from_z(d);
            for (axis, step) in [Vec2::X, Vec2::Y].into_iter().enumerate() {
                let dd = frame.to_local(self.camera_direction(p + step).normalize()) - Vec3::Z;
                if dd.length_squared() < min[axis].length_squared() {
                    min[axis] = dd;
                }
            }
        }
        min
    }

    /// pbrt-v4 `CameraBase::Approximate_dp_dxy`: the change of a surface point `p` (normal
    /// `n`) per pixel step in x and y, from the camera's minimal ray differentials turned
    /// towards `p` and intersected with the tangent plane at `p`, scaled by
    /// `max(1/8, 1/sqrt(spp))` as pbrt scales its ray differentials. pbrt rotates `p` onto
    /// +z with `RotateFromTo`; we use [`Frame::from_z`], which differs by a roll about the
    /// ray.
    #[must_use]
    pub fn approximate_dp_dxy(&self, p: Vec3, n: Vec3, samples_per_pixel: u32) -> (Vec3, Vec3) {
        let p_camera = self.camera_from_world.point(p);
        let Some(dir) = p_camera.try_normalize() else {
            return (Vec3::ZERO, Vec3::ZERO);
        };
        let down_z = Frame::from_z(dir);
        let p_down_z = down_z.to_local(p_camera);
        let n_down_z = down_z.to_local(self.camera_from_world.normal(n));
        let d = n_down_z.z * p_down_z.z;
        let spp_scale = (1.0 / (samples_per_pixel.max(1) as f32).sqrt()).max(0.125);
        let footprint = |dir_differential: Vec3| {
            let ray_d = Vec3::Z + dir_differential;
            let t = d / n_down_z.dot(ray_d);
            let dp = ray_d * t - p_down_z;
            if dp.is_finite() {
                spp_scale * self.world_from_camera.vector(down_z.from_local(dp))
            } else {
                Vec3::ZERO
            }
        };
        (
            footprint(self.min_dir_differential[0]),
            footprint(self.min_dir_differential[1]),
        )
    }

    /// The ray through raster position `p_film`.
    #[must_use]
    pub fn generate_ray(&self, p_film: Vec2, u_lens: Vec2) -> Ray {
        let dir = self.camera_direction(p_film);
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
            Vec2::splat(0.5),
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
        let cam = PerspectiveCamera::new(&desc, &FilmDesc { width: 64, height: 64 }, Vec2::splat(0.5));
        let p = Vec2::new(10.0, 20.0);
        let a = cam.generate_ray(p, Vec2::new(0.1, 0.9));
        let b = cam.generate_ray(p, Vec2::new(0.8, 0.3));
        let pa = a.at((3.0 - a.o.z) / a.d.z);
        let pb = b.at((3.0 - b.o.z) / b.d.z);
        assert!((pa - pb).length() < 1e-4);
    }
}
