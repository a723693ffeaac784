//! The orthographic camera (pbrt-v4 `OrthographicCamera`, Mitsuba 3 `orthographic`):
//! parallel rays along camera +z leave the screen window on the plane `z = 0` of camera
//! space. Raster (0,0) is the window's top-left corner (`x_min`, `y_max`), raster y grows
//! downwards. The default window is pbrt's, `[-aspect, aspect] x [-1, 1]` (or the transpose
//! for tall images), in camera-space units.
//!
//! A thin lens of radius `r` focusing at distance `F` offsets each ray's origin by a lens
//! point `l` and aims it at the window point moved to the plane of focus, `c + F z`. pbrt-v4
//! (like pbrt-v3) instead starts every lens ray at `l` around the camera's origin, which
//! turns the camera into a perspective one whose image no longer depends continuously on
//! `r` (pbrt-v3 issue 315); we follow the correction, origin `c + l`.
//!
//! A scale in `world_from_camera` (Mitsuba sizes the window with `to_world`'s scale) is
//! folded into the window, the lens and the focal distance at construction, so the camera
//! works in a rigid frame with world-space lengths, which the importance needs (its film
//! area is a world-space area).

#[path = "orthographic_importance.rs"]
mod importance;

use super::CameraDesc;
use crate::film::FilmDesc;
use crate::math::{Mat4, Ray, Transform, Vec2, Vec3};
use crate::sampling::sample_uniform_disk_concentric;

/// Orthographic projection with an optional thin lens.
#[derive(Clone, Debug)]
pub struct OrthographicCamera {
    /// World from a rigid camera frame (the description's scale taken out).
    world_from_camera: Transform,
    camera_from_world: Transform,
    /// Screen window `[x_min, x_max, y_min, y_max]` in world-space lengths.
    screen: [f32; 4],
    resolution: Vec2,
    /// The film's sample bounds in raster space, `[min, max)` (as the perspective camera's).
    sample_bounds: [Vec2; 2],
    lens_radius: f32,
    focal_distance: f32,
}

impl OrthographicCamera {
    /// Build from the description, the film size and the radius of the pixel filter (which
    /// sets the sample bounds).
    #[must_use]
    pub fn new(desc: &CameraDesc, film: &FilmDesc, filter_radius: Vec2) -> Self {
        let aspect = film.width as f32 / film.height as f32;
        let [x0, x1, y0, y1] = desc.screen_window.unwrap_or(if aspect > 1.0 {
            [-aspect, aspect, -1.0, 1.0]
        } else {
            [-1.0, 1.0, -1.0 / aspect, 1.0 / aspect]
        });
        // Lengths of the camera axes in world space: the description's scale.
        let w = &desc.world_from_camera;
        let scale = Vec3::new(
            w.vector(Vec3::X).length(),
            w.vector(Vec3::Y).length(),
            w.vector(Vec3::Z).length(),
        );
        let rigid = Transform::new(w.m * Mat4::from_scale(scale.recip())).unwrap_or(*w);
        Self {
            world_from_camera: rigid,
            camera_from_world: rigid.inverse(),
            screen: [x0 * scale.x, x1 * scale.x, y0 * scale.y, y1 * scale.y],
            resolution: Vec2::new(film.width as f32, film.height as f32),
            sample_bounds: [
                Vec2::splat(0.5) - filter_radius,
                Vec2::new(film.width as f32, film.height as f32) - Vec2::splat(0.5) + filter_radius,
            ],
            lens_radius: desc.lens_radius * scale.x.max(scale.y),
            focal_distance: desc.focal_distance * scale.z,
        }
    }

    /// The camera-space point of the window (on `z = 0`) at raster position `p_film`.
    fn window_point(&self, p_film: Vec2) -> Vec3 {
        let [x0, x1, y0, y1] = self.screen;
        Vec3::new(
            x0 + p_film.x / self.resolution.x * (x1 - x0),
            y1 - p_film.y / self.resolution.y * (y1 - y0),
            0.0,
        )
    }

    /// The raster position of a camera-space point of the window plane.
    fn raster_of(&self, p: Vec2) -> Vec2 {
        let [x0, x1, y0, y1] = self.screen;
        Vec2::new(
            (p.x - x0) / (x1 - x0) * self.resolution.x,
            (y1 - p.y) / (y1 - y0) * self.resolution.y,
        )
    }

    /// True when raster position `p` lies within the sample bounds.
    fn in_sample_bounds(&self, p: Vec2) -> bool {
        let [min, max] = self.sample_bounds;
        p.x >= min.x && p.y >= min.y && p.x < max.x && p.y < max.y
    }

    /// The ray through raster position `p_film`: from the window point along the axis, or
    /// with a lens from the window point offset by a lens point towards the window point
    /// moved to the plane of focus.
    #[must_use]
    pub fn generate_ray(&self, p_film: Vec2, u_lens: Vec2) -> Ray {
        let c = self.window_point(p_film);
        let (o, d) = if self.lens_radius > 0.0 {
            let l = self.lens_radius * sample_uniform_disk_concentric(u_lens);
            let o = c + Vec3::new(l.x, l.y, 0.0);
            (o, (c + Vec3::new(0.0, 0.0, self.focal_distance) - o).normalize())
        } else {
            (c, Vec3::Z)
        };
        Ray::new(self.world_from_camera.point(o), self.world_from_camera.vector(d))
    }

    /// The viewing axis in world space.
    #[must_use]
    pub fn forward(&self) -> Vec3 {
        self.world_from_camera.vector(Vec3::Z)
    }

    /// The film's sample bounds in raster space, `[min, max)`.
    #[must_use]
    pub fn sample_bounds(&self) -> [Vec2; 2] {
        self.sample_bounds
    }

    /// The change of the surface point `p` (normal `n`) per pixel step in x and y: the
    /// window's pixel step (pbrt-v4 `dxCamera`, `dyCamera`) carried along the viewing axis
    /// onto the tangent plane at `p`, scaled by `max(1/8, 1/sqrt(spp))` as pbrt scales its
    /// ray differentials. The lens is ignored, as pbrt-v4's `Approximate_dp_dxy` ignores it.
    #[must_use]
    pub fn approximate_dp_dxy(&self, _p: Vec3, n: Vec3, samples_per_pixel: u32) -> (Vec3, Vec3) {
        let n = self.camera_from_world.normal(n);
        let spp_scale = (1.0 / (samples_per_pixel.max(1) as f32).sqrt()).max(0.125);
        let origin = self.window_point(Vec2::ZERO);
        let footprint = |step: Vec2| {
            let dx = self.window_point(step) - origin;
            // Move along z until the offset lies in the tangent plane: (dx + t z) . n = 0.
            let dp = dx - Vec3::Z * (dx.dot(n) / n.z);
            if dp.is_finite() {
                spp_scale * self.world_from_camera.vector(dp)
            } else {
                Vec3::ZERO
            }
        };
        (footprint(Vec2::X), footprint(Vec2::Y))
    }
}

#[cfg(test)]
#[path = "orthographic_tests.rs"]
mod tests;
