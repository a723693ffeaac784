//! Importance of the orthographic camera, for the integrators that connect light paths to
//! the camera (light tracing, BDPT's `t = 1`, MLT through BDPT). pbrt-v4 leaves these
//! unimplemented for its orthographic camera; the derivation follows.
//!
//! Let `A` be the area of the pixel bounds' window (world units) and the camera's points
//! `x0` lie on the window plane `z = 0` of the camera frame. A pixel's measurement is
//! `I = integral W_e(x0, w) L(x0 <- w) cos theta dw dA(x0)`, with `W_e` normalised so that
//! `integral W_e cos theta dw dA = 1` over the film (a pixel is `n_pixels` times that, as for
//! the perspective camera).
//!
//! **Pinhole** (`lens_radius = 0`): every ray leaves its window point along the axis `z`,
//! so `W_e(x0, w) = delta(w - z) / A`, like a directional light run backwards, and
//! `I = (1/A) integral_window L(x0 <- z) dA`. Carried to the surface point `x1` the ray
//! hits (throughput `dA(x0) cos theta0 dw0 = dA(x1) cos theta1 dw1`), a light-path vertex
//! at `x1` connects only along `-z`, to its projection onto the window, and contributes
//! `beta f |cos theta1| / A`: [`OrthographicCamera::sample_wi`] returns that lens point,
//! `We = 1/A` and the delta's weight `pdf = 1` (no distance factor). Generating camera rays
//! picks `x0` uniformly (`pdf_pos = 1/A`) and the direction as a delta (`pdf_dir = 1`), so
//! the first surface point has area density `|cos theta1| / A` (the projected window).
//!
//! **Thin lens** (radius `r`, lens area `A_L = pi r^2`, focal distance `F`): a ray is
//! chosen by a window point `c` (density `1/A`) and a lens offset `l` (density `1/A_L`);
//! it leaves `o = c + l` towards `c + F z`, direction `w ∝ (-l, F)`. For fixed `o`,
//! `l` lies on a plane at distance `F/cos theta` seen at angle `theta`, so
//! `dA_l = F^2 / cos^3 theta dw`, and the joint density per unit area of `o` and solid
//! angle is `p(o, w) = F^2 / (A A_L cos^3 theta)`. The importance whose integral with
//! `cos theta` is 1 is therefore `W_e = F^2 / (A A_L cos^4 theta)` (finite: no delta), and
//! [`OrthographicCamera::pdf_we`] splits the density as `pdf_pos = 1/A_L`,
//! `pdf_dir = F^2 / (A cos^3 theta)`. To see a point `p` at depth `z` from a lens offset
//! `l` chosen uniformly, the origin must be `o = p_xy + l z / F` (the ray from `o`
//! through `p` meets the focal plane at `o - l + F z`), an area density on the window
//! plane of `F^2 / (z^2 A_L)`, or `F^2 d^2 / (z^2 A_L cos theta)` per solid angle at `p`
//! (`d = |p - o| = z / cos theta`). Then `We / pdf = 1 / (A cos theta)`, which tends to the
//! pinhole's `1/A` as `r -> 0`.
//!
//! For BDPT's MIS the camera endpoint's density of the next vertex must be the one that
//! makes the strategies' path densities comparable: with `sample_wi`'s origin density in
//! place of the generation's `p(o)`, the first vertex's area density is
//! `p(o, x1) / p_wi(o | x1) = |cos theta1| / (A cos theta)`
//! ([`OrthographicCamera::pdf_area_per_cos`]), the pinhole's `|cos theta1| / A` at
//! `theta = 0`.

use super::OrthographicCamera;
use crate::camera::CameraWiSample;
use crate::math::{Ray, Vec2, Vec3, PI};
use crate::sampling::sample_uniform_disk_concentric;

impl OrthographicCamera {
    /// Area of the window of the pixel bounds, in world units (`A` above).
    #[must_use]
    pub fn film_area(&self) -> f32 {
        let [x0, x1, y0, y1] = self.screen;
        ((x1 - x0) * (y1 - y0)).abs()
    }

    /// Area of the lens; 1 without a lens.
    #[must_use]
    pub fn lens_area(&self) -> f32 {
        if self.lens_radius > 0.0 {
            PI * self.lens_radius * self.lens_radius
        } else {
            1.0
        }
    }

    /// The raster position of the window point a ray leaving the window plane at `ray.o`
    /// in direction `ray.d` was generated from, and the cosine of its angle to the axis;
    /// `None` for rays that point backwards, need a lens offset beyond the lens, or land
    /// outside the sample bounds. Without a lens the direction is taken to be the axis
    /// (the only one the camera sees).
    #[must_use]
    pub fn raster_position(&self, ray: &Ray) -> Option<(Vec2, f32)> {
        let o = self.camera_from_world.point(ray.o);
        let (c, cos_theta) = if self.lens_radius > 0.0 {
            let d = self.camera_from_world.vector(ray.d).try_normalize()?;
            if d.z <= 0.0 {
                return None;
            }
            let f = o + d * ((self.focal_distance - o.z) / d.z);
            let c = Vec2::new(f.x, f.y);
            let l = Vec2::new(o.x, o.y) - c;
            if l.length() > self.lens_radius * 1.001 {
                return None;
            }
            (c, d.z)
        } else {
            (Vec2::new(o.x, o.y), 1.0)
        };
        let p = self.raster_of(c);
        self.in_sample_bounds(p).then_some((p, cos_theta))
    }

    /// Importance `We` of `ray` (leaving the window plane) and its raster position: `1/A`
    /// (the factor of the direction's delta) without a lens, `F^2 / (A A_L cos^4)` with one.
    #[must_use]
    pub fn we(&self, ray: &Ray) -> Option<(f32, Vec2)> {
        let (p, cos) = self.raster_position(ray)?;
        let f2 = if self.lens_radius > 0.0 {
            self.focal_distance * self.focal_distance / (cos * cos * cos * cos)
        } else {
            1.0
        };
        Some((f2 / (self.film_area() * self.lens_area()), p))
    }

    /// Densities `(pdf_pos, pdf_dir)` of generating `ray`: `(1/A, 1)` without a lens (a
    /// delta direction), `(1/A_L, F^2 / (A cos^3))` with one; zeros outside the bounds.
    #[must_use]
    pub fn pdf_we(&self, ray: &Ray) -> (f32, f32) {
        match self.raster_position(ray) {
            None => (0.0, 0.0),
            Some(_) if self.lens_radius <= 0.0 => (1.0 / self.film_area(), 1.0),
            Some((_, cos)) => (
                1.0 / self.lens_area(),
                self.focal_distance * self.focal_distance / (self.film_area() * cos * cos * cos),
            ),
        }
    }

    /// The area density at `p_next` of the camera endpoint at `p_cam` choosing it as the
    /// first vertex, divided by `|cos|` at `p_next`: `1 / (A cos theta)` (see the module
    /// docs); zero when `p_next` is not seen from `p_cam`.
    #[must_use]
    pub fn pdf_area_per_cos(&self, p_cam: Vec3, p_next: Vec3) -> f32 {
        let Some(d) = (p_next - p_cam).try_normalize() else {
            return 0.0;
        };
        let ray = Ray::new(p_cam, d);
        let ray = if self.lens_radius > 0.0 {
            ray
        } else {
            // The pinhole's connection runs along the axis; use the projection of p_next.
            let q = self.camera_from_world.point(p_next);
            if q.z <= 0.0 {
                return 0.0;
            }
            Ray::new(self.world_from_camera.point(Vec3::new(q.x, q.y, 0.0)), self.forward())
        };
        match self.raster_position(&ray) {
            Some((_, cos)) => 1.0 / (self.film_area() * cos),
            None => 0.0,
        }
    }

    /// A window point that sees `p_ref`: its projection along the axis without a lens
    /// (`We = 1/A`, `pdf = 1`), or with a lens the origin `p_xy + l z / F` for a uniform
    /// lens offset `l` (from `u`), with `We` and its solid-angle density at `p_ref` (see the
    /// module docs). `None` behind the camera or outside the sample bounds.
    #[must_use]
    pub fn sample_wi(&self, p_ref: Vec3, u: Vec2) -> Option<CameraWiSample> {
        let q = self.camera_from_world.point(p_ref);
        if q.z <= 0.0 {
            return None;
        }
        let n = self.forward();
        let (o, c) = if self.lens_radius > 0.0 {
            let l = self.lens_radius * sample_uniform_disk_concentric(u);
            let o = Vec2::new(q.x, q.y) + l * (q.z / self.focal_distance);
            (o, o - l)
        } else {
            (Vec2::new(q.x, q.y), Vec2::new(q.x, q.y))
        };
        let p_raster = self.raster_of(c);
        if !self.in_sample_bounds(p_raster) {
            return None;
        }
        let p_lens = self.world_from_camera.point(Vec3::new(o.x, o.y, 0.0));
        let (we, wi, pdf) = if self.lens_radius > 0.0 {
            let to_lens = p_lens - p_ref;
            let dist2 = to_lens.length_squared();
            let wi = to_lens.try_normalize()?;
            let cos = n.dot(-wi);
            let f2 = self.focal_distance * self.focal_distance;
            let we = f2 / (self.film_area() * self.lens_area() * cos * cos * cos * cos);
            let pdf = f2 * dist2 / (q.z * q.z * self.lens_area() * cos);
            (we, wi, pdf)
        } else {
            (1.0 / self.film_area(), -n, 1.0)
        };
        if !(pdf > 0.0 && pdf.is_finite() && we.is_finite()) {
            return None;
        }
        Some(CameraWiSample {
            we,
            wi,
            pdf,
            p_raster,
            p_lens,
            n_lens: n,
        })
    }
}
