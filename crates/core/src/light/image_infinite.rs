//! An environment-map light (pbrt-v4 `infinite` with `filename`): radiance from infinitely
//! far away, read from an RGB image that covers the sphere of directions.
//!
//! The image is looked up by nearest pixel, as pbrt-v4 does, so the radiance is constant
//! over each pixel's patch of the sphere; [`EnvMapping::EquirectBilinear`] interpolates as
//! Mitsuba 3's `envmap` does. Directions are sampled in proportion to the pixels' channel
//! average (for the bilinear lookup, the largest average of the pixel and its eight
//! neighbours, so that the density is positive wherever the radiance is) with a
//! [`PiecewiseConstant2D`] over the image's unit square;
//! the solid-angle pdf is the square's pdf divided by the mapping's area element:
//!
//! * [`EnvMapping::EqualArea`] (pbrt-v4's layout): `d omega = 4 pi du dv`, so
//!   `p_omega = p_uv / (4 pi)`;
//! * [`EnvMapping::Equirect`] and [`EnvMapping::EquirectBilinear`]:
//!   `d omega = 2 pi^2 sin(theta) du dv`, so
//!   `p_omega = p_uv / (2 pi^2 sin theta)`; each row's weight is multiplied by the sine at
//!   its centre, so the pdf follows the radiance per solid angle rather than per pixel.
//!
//! The light's transform rotates light space into the world; for a linear part `M` that is
//! not a rotation, directions are renormalised and the pdf carries the Jacobian
//! `|det M^-1| / |M^-1 w|^3` of `w -> normalize(M^-1 w)`.

use super::LightLiSample;
use crate::color::Rgb;
use crate::math::{Bounds3, Mat3, Transform, UVec2, Vec2, Vec3, PI};
use crate::sampling::{equal_area_sphere_to_square, equal_area_square_to_sphere, PiecewiseConstant2D};
use crate::shape::Interaction;

/// How an environment image covers the sphere of directions, in light space.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum EnvMapping {
    /// pbrt-v4's equal-area octahedral mapping of a square image
    /// ([`equal_area_square_to_sphere`]; pixel centres at
    /// `((x + 0.5) / width, (y + 0.5) / height)`, row 0 at the top of the file).
    #[default]
    EqualArea,
    /// Latitude-longitude (pbrt-v3's layout): column `u` is the azimuth
    /// `phi = 2 pi u` from +x towards +y, row `v` the polar angle `theta = pi v` from +z
    /// (the top row is +z).
    Equirect,
    /// [`Self::Equirect`]'s directions with Mitsuba 3's bilinear lookup: columns centred at
    /// `u = (x + 0.5) / width` and wrapping around, rows at `v = y / (height - 1)` (the
    /// first and last rows on the poles), as Mitsuba's `envmap` `eval_spectrum`. The power
    /// is counted as for [`Self::Equirect`] (it only steers light selection).
    EquirectBilinear,
}

/// An environment-map light.
#[derive(Clone, Debug)]
pub struct ImageInfiniteLight {
    width: u32,
    height: u32,
    /// Radiance per pixel, `scale` applied, row 0 at v = 0.
    pixels: Vec<Rgb>,
    mapping: EnvMapping,
    /// Linear part of world-from-light and its inverse.
    world_from_light: Mat3,
    light_from_world: Mat3,
    /// `|det light_from_world|`.
    inv_det: f32,
    distribution: PiecewiseConstant2D,
    /// Radius of the scene's bounding sphere, set by [`Self::preprocess`].
    pub(super) scene_radius: f32,
    /// Centre of the scene's bounding sphere, set by [`Self::preprocess`].
    pub(super) scene_center: Vec3,
}

impl ImageInfiniteLight {
    /// The light of a `width` x `height` image (`pixels` row by row from the top) times
    /// `scale`, laid out by `mapping` and turned into the world by `world_from_light`.
    ///
    /// # Panics
    /// When the image is empty, the pixel count does not match, or a pixel is not finite.
    #[must_use]
    pub fn new(
        width: u32,
        height: u32,
        pixels: &[Rgb],
        scale: f32,
        mapping: EnvMapping,
        world_from_light: &Transform,
    ) -> Self {
        let (w, h) = (width, height);
        assert!(
            w > 0 && h > 0 && pixels.len() == (w * h) as usize,
            "bad environment image size"
        );
        let pixels: Vec<Rgb> = pixels.iter().map(|p| *p * scale).collect();
        let brightness = |x: u32, y: u32| pixels[(y * w + x) as usize].average().max(0.0);
        let values: Vec<f32> = (0..w * h)
            .map(|i| {
                let (x, y) = (i % w, i / w);
                let sine = (PI * (y as f32 + 0.5) / h as f32).sin();
                match mapping {
                    EnvMapping::EqualArea => brightness(x, y),
                    EnvMapping::Equirect => brightness(x, y) * sine,
                    EnvMapping::EquirectBilinear => {
                        let mut m = 0.0f32;
                        for dy in [-1i64, 0, 1] {
                            let yy = (i64::from(y) + dy).clamp(0, i64::from(h) - 1) as u32;
                            for dx in [-1i64, 0, 1] {
                                let xx = (i64::from(x) + dx).rem_euclid(i64::from(w)) as u32;
                                m = m.max(brightness(xx, yy));
                            }
                        }
                        m * sine
                    }
                }
            })
            .collect();
        let distribution = PiecewiseConstant2D::new(&values, UVec2::new(w, h), Vec2::ZERO, Vec2::ONE);
        let world_from_light_m = Mat3::from_mat4(world_from_light.m);
        let light_from_world = Mat3::from_mat4(world_from_light.m_inv);
        Self {
            width: w,
            height: h,
            pixels,
            mapping,
            world_from_light: world_from_light_m,
            light_from_world,
            inv_det: light_from_world.determinant().abs(),
            distribution,
            scene_radius: 0.0,
            scene_center: Vec3::ZERO,
        }
    }

    /// Remember the scene's size: shadow rays end outside it, and the power depends on it.
    pub fn preprocess(&mut self, scene_bounds: &Bounds3) {
        self.scene_radius = super::scene_radius(scene_bounds);
        self.scene_center = super::scene_center(scene_bounds);
    }

    /// The light-space direction of the point `uv` of the image square.
    #[must_use]
    pub fn direction(&self, uv: Vec2) -> Vec3 {
        match self.mapping {
            EnvMapping::EqualArea => equal_area_square_to_sphere(uv),
            EnvMapping::Equirect | EnvMapping::EquirectBilinear => {
                let (sin_t, cos_t) = (PI * uv.y).sin_cos();
                let (sin_p, cos_p) = (2.0 * PI * uv.x).sin_cos();
                Vec3::new(sin_t * cos_p, sin_t * sin_p, cos_t)
            }
        }
    }

    /// The point of the image square of the unit light-space direction `w`.
    #[must_use]
    pub fn uv(&self, w: Vec3) -> Vec2 {
        match self.mapping {
            EnvMapping::EqualArea => equal_area_sphere_to_square(w),
            EnvMapping::Equirect | EnvMapping::EquirectBilinear => {
                let phi = w.y.atan2(w.x).rem_euclid(2.0 * PI);
                // atan2 rather than acos(z): accurate near the poles too.
                let theta = w.x.hypot(w.y).atan2(w.z);
                Vec2::new((phi / (2.0 * PI)).min(1.0), (theta / PI).clamp(0.0, 1.0))
            }
        }
    }

    /// Solid angle per unit area of the square at `uv` (`d omega / du dv`).
    fn area_element(&self, uv: Vec2) -> f32 {
        match self.mapping {
            EnvMapping::EqualArea => 4.0 * PI,
            EnvMapping::Equirect | EnvMapping::EquirectBilinear => 2.0 * PI * PI * (PI * uv.y).sin(),
        }
    }

    /// The radiance at `uv`: the pixel holding it (nearest lookup, as pbrt-v4), or for
    /// [`EnvMapping::EquirectBilinear`] Mitsuba's bilinear interpolation.
    #[must_use]
    pub fn lookup(&self, uv: Vec2) -> Rgb {
        if self.mapping == EnvMapping::EquirectBilinear {
            return self.lookup_bilinear(uv);
        }
        let x = ((uv.x * self.width as f32) as u32).min(self.width - 1);
        let y = ((uv.y * self.height as f32) as u32).min(self.height - 1);
        self.pixels[(y * self.width + x) as usize]
    }

    /// Mitsuba 3's envmap interpolation (see [`EnvMapping::EquirectBilinear`]).
    fn lookup_bilinear(&self, uv: Vec2) -> Rgb {
        let (w, h) = (self.width, self.height);
        let mut x = uv.x - 0.5 / w as f32;
        x -= x.floor();
        let x = x * w as f32;
        let y = uv.y.clamp(0.0, 1.0) * h.saturating_sub(1) as f32;
        let x0 = (x as u32).min(w - 1);
        let y0 = (y as u32).min(h.saturating_sub(2));
        let (fx, fy) = (x - x0 as f32, y - y0 as f32);
        let (x1, y1) = ((x0 + 1) % w, (y0 + 1).min(h - 1));
        let px = |x: u32, y: u32| self.pixels[(y * w + x) as usize];
        let top = px(x0, y0) * (1.0 - fx) + px(x1, y0) * fx;
        let bottom = px(x0, y1) * (1.0 - fx) + px(x1, y1) * fx;
        top * (1.0 - fy) + bottom * fy
    }

    /// The unit light-space direction of the world direction `w`, and the Jacobian of the
    /// map (1 for rotations).
    fn to_light(&self, w: Vec3) -> Option<(Vec3, f32)> {
        let v = self.light_from_world * w.try_normalize()?;
        let len = v.length();
        let w_light = (v / len).try_normalize()?;
        Some((w_light, self.inv_det / (len * len * len)))
    }

    /// A direction in proportion to the image's brightness.
    #[must_use]
    pub fn sample_li(&self, receiver: &Interaction, u: Vec2) -> Option<LightLiSample> {
        let (uv, pdf_uv, _) = self.distribution.sample(u);
        if pdf_uv == 0.0 {
            return None;
        }
        let w_light = self.direction(uv);
        let m = self.world_from_light * w_light;
        let len = m.length();
        let wi = (m / len).try_normalize()?;
        let area = self.area_element(uv);
        let pdf = pdf_uv / area * self.inv_det * len * len * len;
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        Some(LightLiSample {
            l: self.lookup(uv),
            wi,
            pdf,
            p_light: Interaction::point(receiver.p + wi * (2.0 * self.scene_radius)),
        })
    }

    /// Solid-angle density of [`Self::sample_li`] choosing the world direction `w`.
    #[must_use]
    pub fn pdf_li(&self, w: Vec3) -> f32 {
        let Some((w_light, jacobian)) = self.to_light(w) else {
            return 0.0;
        };
        let uv = self.uv(w_light);
        let area = self.area_element(uv);
        if area <= 0.0 {
            return 0.0;
        }
        let pdf = self.distribution.pdf(uv) / area * jacobian;
        if pdf.is_finite() {
            pdf
        } else {
            0.0
        }
    }

    /// Radiance arriving along a ray that leaves the scene in world direction `w`.
    #[must_use]
    pub fn le(&self, w: Vec3) -> Rgb {
        match self.to_light(w) {
            Some((w_light, _)) => self.lookup(self.uv(w_light)),
            None => Rgb::BLACK,
        }
    }

    /// `pi r^2` times the radiance integrated over the sphere (each pixel times its solid
    /// angle), as pbrt-v4 defines the power of an infinite light.
    #[must_use]
    pub fn power(&self) -> Rgb {
        let (w, h) = (self.width as usize, self.height as usize);
        let mut sum = Rgb::BLACK;
        for (y, row) in self.pixels.chunks_exact(w).enumerate() {
            let row_sum = row.iter().fold(Rgb::BLACK, |a, p| a + *p);
            let solid_angle = match self.mapping {
                EnvMapping::EqualArea => 4.0 * PI / (w * h) as f32,
                EnvMapping::Equirect | EnvMapping::EquirectBilinear => {
                    let (t0, t1) = (PI * y as f32 / h as f32, PI * (y + 1) as f32 / h as f32);
                    2.0 * PI / w as f32 * (t0.cos() - t1.cos())
                }
            };
            sum += row_sum * solid_angle;
        }
        sum * (PI * self.scene_radius * self.scene_radius)
    }
}
