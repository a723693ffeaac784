//! A spot light: a point that emits intensity `I` inside a cone around its axis, with one of
//! two falloffs towards the cone's edge ([`SpotFalloff`]): pbrt-v4's smoothstep in the
//! cosine, `I(theta) = I smoothstep(cos theta; cos theta_end, cos theta_start)`, or
//! Mitsuba 3's linear ramp in the angle, `I(theta) = I (theta_end - theta) / (theta_end -
//! theta_start)` between the two angles (`src/emitters/spot.cpp`). Mitsuba's spot can also
//! project an image along its cone ([`SpotLight::projection`]).

use super::LightLiSample;
use crate::color::Rgb;
use crate::math::{Transform, Vec2, Vec3, PI};
use crate::shape::Interaction;
use crate::texture::{RgbTexture, TextureContext};

/// How a spot light's intensity falls from full (inside the start angle) to zero (at the
/// end angle).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SpotFalloff {
    /// pbrt-v4: smoothstep in `cos theta`.
    #[default]
    SmoothCosine,
    /// Mitsuba 3: linear in `theta`.
    LinearAngle,
}

/// A spot light.
#[derive(Clone, Debug)]
pub struct SpotLight {
    /// World-from-light transform; the cone's axis is light-space +z.
    pub world_from_light: Transform,
    /// Intensity on the axis.
    pub intensity: Rgb,
    /// Cosine of the angle where the falloff starts.
    pub cos_falloff_start: f32,
    /// Cosine of the angle where the intensity reaches zero.
    pub cos_falloff_end: f32,
    /// The falloff's shape.
    pub falloff: SpotFalloff,
    /// An image projected along the cone (Mitsuba's `texture`), multiplying the intensity.
    /// The light-space direction `(x, y, z)` reads it at `u = 1/2 + x / (2 z tan theta_end)`,
    /// `v = 1/2 - y / (2 z tan theta_end)` (mcrender's `v`, which runs up the image; it is
    /// `1 - v` of Mitsuba's), so the image spans the square around the cone's end with
    /// light-space +x towards its right edge and +y towards its bottom row, as in Mitsuba.
    pub projection: Option<RgbTexture>,
}

/// `3 t^2 - 2 t^3` of `t = (x - a) / (b - a)` clamped to [0, 1]; a step at `a` when
/// `a == b`.
#[inline]
#[must_use]
pub fn smooth_step(x: f32, a: f32, b: f32) -> f32 {
    if a == b {
        return if x < a { 0.0 } else { 1.0 };
    }
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Mitsuba's linear falloff at `cos theta`: 1 inside the start angle, `(theta_end - theta)
/// / (theta_end - theta_start)` up to the end angle (exclusive), 0 beyond.
#[inline]
#[must_use]
pub fn linear_angle_falloff(cos_theta: f32, cos_start: f32, cos_end: f32) -> f32 {
    if cos_theta <= cos_end {
        0.0
    } else if cos_theta >= cos_start {
        1.0
    } else {
        let (start, end) = (cos_start.acos(), cos_end.acos());
        ((end - cos_theta.clamp(-1.0, 1.0).acos()) / (end - start)).clamp(0.0, 1.0)
    }
}

impl SpotLight {
    /// World position.
    #[inline]
    #[must_use]
    pub fn position(&self) -> Vec3 {
        self.world_from_light.point(Vec3::ZERO)
    }

    /// Fraction of the axial intensity emitted along the light-space unit direction `w`,
    /// without the projected image.
    #[must_use]
    pub fn falloff_local(&self, w: Vec3) -> f32 {
        match self.falloff {
            SpotFalloff::SmoothCosine => smooth_step(w.z, self.cos_falloff_end, self.cos_falloff_start),
            SpotFalloff::LinearAngle => linear_angle_falloff(w.z, self.cos_falloff_start, self.cos_falloff_end),
        }
    }

    /// Fraction of the axial intensity emitted along the world direction `w`, without the
    /// projected image.
    #[must_use]
    pub fn falloff(&self, w: Vec3) -> f32 {
        match self.world_from_light.inverse().vector(w).try_normalize() {
            Some(w_light) => self.falloff_local(w_light),
            None => 0.0,
        }
    }

    /// Intensity emitted along the world direction `w`: the axial intensity times the
    /// falloff and the projected image.
    #[must_use]
    pub fn intensity_towards(&self, w: Vec3) -> Rgb {
        let Some(w_light) = self.world_from_light.inverse().vector(w).try_normalize() else {
            return Rgb::BLACK;
        };
        let f = self.falloff_local(w_light);
        if f <= 0.0 {
            return Rgb::BLACK;
        }
        let i = self.intensity * f;
        match &self.projection {
            None => i,
            Some(tex) => {
                // tan(theta_end) = sin / cos of the end angle.
                let c = self.cos_falloff_end;
                let uv_factor = (1.0 - c * c).max(0.0).sqrt() / c;
                let k = 0.5 / (w_light.z * uv_factor);
                let ctx = TextureContext {
                    uv: Vec2::new(0.5 + w_light.x * k, 0.5 - w_light.y * k),
                    ..TextureContext::default()
                };
                i * tex.evaluate(&ctx)
            }
        }
    }

    /// The single direction to the light; `u` is unused.
    #[must_use]
    pub fn sample_li(&self, receiver: &Interaction, _u: Vec2) -> Option<LightLiSample> {
        let p = self.position();
        let d = p - receiver.p;
        let r2 = d.length_squared();
        let wi = d.try_normalize()?;
        let l = self.intensity_towards(-wi) * (1.0 / r2);
        if l.is_black() {
            return None;
        }
        Some(LightLiSample {
            l,
            wi,
            pdf: 1.0,
            p_light: Interaction::point(p),
        })
    }

    /// The integral of the intensity over the sphere, without the projected image (which
    /// only changes how often the light is chosen). Smooth: `2 pi I ((1 - cos_start) +
    /// (cos_start - cos_end) / 2)`, the full cone plus the band, whose smoothstep averages
    /// to one half. Linear in angle: `2 pi I (1 - (sin e - sin s) / (e - s))` for start and
    /// end angles `s < e` (integrating `(e - theta) sin theta` by parts), `2 pi I (1 -
    /// cos e)` when they are equal.
    #[must_use]
    pub fn power(&self) -> Rgb {
        let (cs, ce) = (self.cos_falloff_start, self.cos_falloff_end);
        let solid_angle = match self.falloff {
            SpotFalloff::SmoothCosine => 2.0 * PI * ((1.0 - cs) + (cs - ce) / 2.0),
            SpotFalloff::LinearAngle => {
                let (s, e) = (cs.clamp(-1.0, 1.0).acos(), ce.clamp(-1.0, 1.0).acos());
                if e - s > 1e-6 {
                    2.0 * PI * (1.0 - (e.sin() - s.sin()) / (e - s))
                } else {
                    2.0 * PI * (1.0 - ce)
                }
            }
        };
        self.intensity * solid_angle
    }
}

#[cfg(test)]
#[path = "spot_tests.rs"]
mod tests;
