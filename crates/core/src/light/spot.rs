//! A spot light (pbrt-v4 `spot`): a point that emits intensity `I` inside a cone around its
//! axis, with pbrt-v4's smoothstep falloff between the falloff-start and cone angles:
//! `I(theta) = I smoothstep(cos theta; cos theta_end, cos theta_start)`.

use super::LightLiSample;
use crate::color::Rgb;
use crate::math::{Transform, Vec2, Vec3, PI};
use crate::shape::Interaction;

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

impl SpotLight {
    /// World position.
    #[inline]
    #[must_use]
    pub fn position(&self) -> Vec3 {
        self.world_from_light.point(Vec3::ZERO)
    }

    /// Fraction of the axial intensity emitted along the world direction `w`.
    #[must_use]
    pub fn falloff(&self, w: Vec3) -> f32 {
        let Some(w_light) = self.world_from_light.inverse().vector(w).try_normalize() else {
            return 0.0;
        };
        smooth_step(w_light.z, self.cos_falloff_end, self.cos_falloff_start)
    }

    /// The single direction to the light; `u` is unused.
    #[must_use]
    pub fn sample_li(&self, receiver: &Interaction, _u: Vec2) -> Option<LightLiSample> {
        let p = self.position();
        let d = p - receiver.p;
        let r2 = d.length_squared();
        let wi = d.try_normalize()?;
        let l = self.intensity * (self.falloff(-wi) / r2);
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

    /// `2 pi I ((1 - cos_start) + (cos_start - cos_end) / 2)`: the full cone plus the
    /// falloff band, whose smoothstep averages to one half.
    #[must_use]
    pub fn power(&self) -> Rgb {
        let (s, e) = (self.cos_falloff_start, self.cos_falloff_end);
        self.intensity * (2.0 * PI * ((1.0 - s) + (s - e) / 2.0))
    }
}
