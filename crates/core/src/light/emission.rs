//! Sampling rays leaving the lights (pbrt-v4 `SampleLe` / `PDF_Le`), for the integrators
//! that start paths at the lights (light tracing, bidirectional path tracing, photon
//! mapping).
//!
//! A sample is an origin with its density per unit area (`pdf_pos`; 1 for the single point
//! of a point or spot light) and a direction with its density per unit solid angle
//! (`pdf_dir`; 1 for the single direction of a distant light), so that
//! `Le |cos theta| / (pdf_pos pdf_dir)` estimates the light's power (`cos theta` against
//! the surface normal for area lights, 1 for the others). Per light:
//!
//! * diffuse area: a point uniform by area (the shape's `sample_area`), a cosine-weighted
//!   direction about its normal (either side with probability 1/2 when two-sided, so
//!   `pdf_dir = |cos| / (2 pi)`); points the alpha cut-out removes fail, so the estimate
//!   of power is `a pi A L`;
//! * point: a uniform direction (`pdf_dir = 1 / 4 pi`);
//! * spot: a direction uniform in the cone of `cos_falloff_end` (the falloff in `Le`);
//! * distant: a point uniform on the disk of the scene's bounding sphere perpendicular to
//!   the light's direction, moved back by the scene's radius (`pdf_pos = 1 / pi r^2`);
//! * infinite (uniform and image): the direction as [`Light::sample_li`] chooses it (towards
//!   the light), then a point on the scene-bounding disk perpendicular to it; the ray
//!   travels the opposite way.
//!
//! The light to emit from is chosen with the scene's [`super::PowerLightSampler`] (its
//! `sample` and `pmf`), so light paths carry `1 / pmf` as well.

use super::{DiffuseAreaLight, DistantLight, ImageInfiniteLight, Light, PointLight, SpotLight, UniformInfiniteLight};
use crate::color::Rgb;
use crate::math::{Frame, Ray, Vec2, Vec3, PI};
use crate::sampling::{
    cosine_hemisphere_pdf, sample_cosine_hemisphere, sample_uniform_cone, sample_uniform_disk_concentric,
    sample_uniform_sphere, uniform_cone_pdf, uniform_sphere_pdf, ONE_MINUS_EPSILON,
};
use crate::shape::Interaction;

/// A ray leaving a light, with the emitted radiance and the densities that chose it.
#[derive(Clone, Copy, Debug)]
pub struct LightLeSample {
    /// The emitted ray (unit direction; the origin is offset off the light's surface for
    /// area lights, see [`Self::intr`] for the point itself).
    pub ray: Ray,
    /// Radiance leaving along the ray (intensity for point and spot lights).
    pub le: Rgb,
    /// Density per unit area of the origin (1 for point and spot lights).
    pub pdf_pos: f32,
    /// Density per unit solid angle of the direction (1 for distant lights).
    pub pdf_dir: f32,
    /// The point on the light: position, error bound and the surface normal (`n` is zero
    /// for point, spot and infinite lights; for distant and infinite lights it is the point
    /// on the scene's bounding disk).
    pub intr: Interaction,
}

impl LightLeSample {
    /// The throughput the emitted ray starts with when the light was chosen with
    /// probability `pmf`: `Le |cos| / (pmf pdf_pos pdf_dir)` (pbrt-v4's light subpath
    /// start; no cosine for lights off surfaces, whose `intr.n` is zero).
    #[must_use]
    pub fn initial_throughput(&self, pmf: f32) -> Rgb {
        let cos = if self.intr.n == Vec3::ZERO {
            1.0
        } else {
            self.intr.n.dot(self.ray.d).abs()
        };
        self.le * (cos / (pmf * self.pdf_pos * self.pdf_dir))
    }
}

impl Light {
    /// Sample a ray leaving the light from four uniform numbers: `u_pos` chooses the origin,
    /// `u_dir` the direction (some lights use only one of them). `None` when the sample
    /// carries nothing (a masked or back-facing point, a zero pdf).
    #[must_use]
    pub fn sample_le(&self, u_pos: Vec2, u_dir: Vec2) -> Option<LightLeSample> {
        let s = match self {
            Self::DiffuseArea(l) => l.sample_le(u_pos, u_dir),
            Self::Point(l) => Some(l.sample_le(u_dir)),
            Self::Spot(l) => l.sample_le(u_dir),
            Self::Distant(l) => Some(l.sample_le(u_pos)),
            Self::UniformInfinite(l) => Some(l.sample_le(u_pos, u_dir)),
            Self::ImageInfinite(l) => l.sample_le(u_pos, u_dir),
        }?;
        (s.pdf_pos > 0.0 && s.pdf_dir > 0.0 && s.pdf_pos.is_finite() && s.pdf_dir.is_finite() && !s.le.is_black())
            .then_some(s)
    }

    /// Densities `(pdf_pos, pdf_dir)` of [`Self::sample_le`] producing a ray from the point
    /// `ray.o` (on the light's surface, normal `n`, for area lights) in direction `ray.d`
    /// (unit length). A delta component reports 0 (the point of a point light, the
    /// direction of a distant light), as pbrt-v4.
    #[must_use]
    pub fn pdf_le(&self, ray: &Ray, n: Vec3) -> (f32, f32) {
        match self {
            Self::DiffuseArea(l) => l.pdf_le(ray, n),
            Self::Point(_) => (0.0, uniform_sphere_pdf()),
            Self::Spot(l) => (0.0, l.pdf_le_dir(ray.d)),
            Self::Distant(l) => (disk_pdf(l.scene_radius), 0.0),
            Self::UniformInfinite(l) => (disk_pdf(l.scene_radius), uniform_sphere_pdf()),
            Self::ImageInfinite(l) => (disk_pdf(l.scene_radius), l.pdf_li(-ray.d)),
        }
    }
}

/// `1 / (pi r^2)`: the density of a point uniform on a disk of radius `r`.
fn disk_pdf(r: f32) -> f32 {
    let pdf = 1.0 / (PI * r * r);
    if pdf.is_finite() {
        pdf
    } else {
        0.0
    }
}

/// A ray travelling along `d` through a point uniform on the disk of radius `r` about
/// `center` perpendicular to `d`, started `r` behind the disk (outside the scene's bounding
/// sphere), with the point on the disk.
fn ray_through_scene_disk(center: Vec3, r: f32, d: Vec3, u: Vec2) -> (Ray, Interaction) {
    let frame = Frame::from_z(d);
    let c = sample_uniform_disk_concentric(u);
    let p_disk = center + r * frame.from_local(Vec3::new(c.x, c.y, 0.0));
    (Ray::new(p_disk - r * d, d), Interaction::point(p_disk))
}

impl DiffuseAreaLight {
    /// A point by area and a cosine-weighted direction about its normal (either side for
    /// two-sided lights).
    fn sample_le(&self, u_pos: Vec2, u_dir: Vec2) -> Option<LightLeSample> {
        let ss = self.shape.sample_area(u_pos);
        if self.alpha_masked(ss.intr.p, ss.uv) {
            return None;
        }
        let n = ss.intr.n;
        // Two-sided: the first coordinate picks the side, then is stretched back to [0, 1).
        let (u, flip, side_pdf) = if self.two_sided {
            if u_dir.x < 0.5 {
                (Vec2::new((u_dir.x * 2.0).min(ONE_MINUS_EPSILON), u_dir.y), false, 0.5)
            } else {
                (
                    Vec2::new(((u_dir.x - 0.5) * 2.0).min(ONE_MINUS_EPSILON), u_dir.y),
                    true,
                    0.5,
                )
            }
        } else {
            (u_dir, false, 1.0)
        };
        let mut w_local = sample_cosine_hemisphere(u);
        if flip {
            w_local.z = -w_local.z;
        }
        let pdf_dir = cosine_hemisphere_pdf(w_local.z.abs()) * side_pdf;
        let w = Frame::from_z(n).from_local(w_local).try_normalize()?;
        Some(LightLeSample {
            ray: ss.intr.spawn_ray(w),
            le: self.l(n, w),
            pdf_pos: ss.pdf_area,
            pdf_dir,
            intr: ss.intr,
        })
    }

    fn pdf_le(&self, ray: &Ray, n: Vec3) -> (f32, f32) {
        let intr = Interaction {
            p: ray.o,
            p_error: Vec3::ZERO,
            n,
        };
        let cos = n.dot(ray.d);
        let pdf_dir = if self.two_sided {
            0.5 * cosine_hemisphere_pdf(cos.abs())
        } else if cos > 0.0 {
            cosine_hemisphere_pdf(cos)
        } else {
            0.0
        };
        (self.shape.pdf_area(&intr), pdf_dir)
    }
}

impl PointLight {
    /// A uniform direction from the light's position.
    fn sample_le(&self, u: Vec2) -> LightLeSample {
        LightLeSample {
            ray: Ray::new(self.position, sample_uniform_sphere(u)),
            le: self.intensity,
            pdf_pos: 1.0,
            pdf_dir: uniform_sphere_pdf(),
            intr: Interaction::point(self.position),
        }
    }
}

impl SpotLight {
    /// A direction uniform in the cone the light reaches.
    fn sample_le(&self, u: Vec2) -> Option<LightLeSample> {
        let w_light = sample_uniform_cone(u, self.cos_falloff_end);
        let w = self.world_from_light.vector(w_light).try_normalize()?;
        let p = self.position();
        Some(LightLeSample {
            ray: Ray::new(p, w),
            le: self.intensity_towards(w),
            pdf_pos: 1.0,
            pdf_dir: uniform_cone_pdf(self.cos_falloff_end),
            intr: Interaction::point(p),
        })
    }

    /// Solid-angle density of [`Self::sample_le`] choosing the world direction `w`.
    fn pdf_le_dir(&self, w: Vec3) -> f32 {
        match self.world_from_light.inverse().vector(w).try_normalize() {
            Some(w_light) if w_light.z >= self.cos_falloff_end => uniform_cone_pdf(self.cos_falloff_end),
            _ => 0.0,
        }
    }
}

impl DistantLight {
    /// Parallel rays through the disk that covers the scene, travelling away from the light.
    fn sample_le(&self, u: Vec2) -> LightLeSample {
        let (ray, intr) = ray_through_scene_disk(self.scene_center, self.scene_radius, -self.direction, u);
        LightLeSample {
            ray,
            le: self.radiance,
            pdf_pos: disk_pdf(self.scene_radius),
            pdf_dir: 1.0,
            intr,
        }
    }
}

impl UniformInfiniteLight {
    /// A uniform direction, then a point on the disk that covers the scene across it.
    fn sample_le(&self, u_pos: Vec2, u_dir: Vec2) -> LightLeSample {
        let w_to_light = sample_uniform_sphere(u_dir);
        let (ray, intr) = ray_through_scene_disk(self.scene_center, self.scene_radius, -w_to_light, u_pos);
        LightLeSample {
            ray,
            le: self.radiance,
            pdf_pos: disk_pdf(self.scene_radius),
            pdf_dir: uniform_sphere_pdf(),
            intr,
        }
    }
}

impl ImageInfiniteLight {
    /// A direction in proportion to the image's brightness, then a point on the disk that
    /// covers the scene across it.
    fn sample_le(&self, u_pos: Vec2, u_dir: Vec2) -> Option<LightLeSample> {
        let li = self.sample_li(&Interaction::point(self.scene_center), u_dir)?;
        let (ray, intr) = ray_through_scene_disk(self.scene_center, self.scene_radius, -li.wi, u_pos);
        Some(LightLeSample {
            ray,
            le: li.l,
            pdf_pos: disk_pdf(self.scene_radius),
            pdf_dir: li.pdf,
            intr,
        })
    }
}

#[cfg(test)]
#[path = "emission_tests.rs"]
mod tests;
