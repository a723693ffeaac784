//! Uniform emission from a shape's surface (pbrt `AreaLightSource "diffuse"`). Sampled by
//! choosing a point uniformly by area and converting to solid angle at the receiver:
//! `p_omega = p_A r^2 / |cos theta_l|`.
//!
//! A shape with an alpha texture emits nowhere it is cut out: a sampled point is dropped
//! by pbrt-v4's `DiffuseAreaLight::AlphaMasked` (never where alpha `<= 0`, with probability
//! `1 - a` by a hash of the point where `0 < a < 1`). Rays that hit the shape have already
//! passed the same alpha test in the intersection (see `scene::Primitive::intersect`), so
//! [`DiffuseAreaLight::l`] does not test again: pbrt-v4 does, which counts a fractional
//! alpha twice (`a^2`) for emission found by rays but once for light samples; testing once
//! keeps both strategies estimating the same `a L`.

use super::LightLiSample;
use crate::color::Rgb;
use crate::math::{Vec2, Vec3, PI};
use crate::sampling::hash_float;
use crate::shape::{Interaction, Shape};
use crate::texture::{alpha_keeps, FloatTexture, TextureContext};

/// An emitting shape.
#[derive(Clone, Debug)]
pub struct DiffuseAreaLight {
    /// The emitting surface.
    pub shape: Shape,
    /// Emitted radiance.
    pub radiance: Rgb,
    /// Emit on both sides instead of only along the normal.
    pub two_sided: bool,
    /// The shape's alpha cut-out, `None` when opaque.
    pub alpha: Option<FloatTexture>,
}

impl DiffuseAreaLight {
    /// Radiance leaving the surface point with normal `n` in direction `w`.
    #[inline]
    #[must_use]
    pub fn l(&self, n: Vec3, w: Vec3) -> Rgb {
        if !self.two_sided && n.dot(w) < 0.0 {
            Rgb::BLACK
        } else {
            self.radiance
        }
    }

    /// True when the alpha test removes the surface point `p` with parameters `uv`
    /// (pbrt-v4 `AlphaMasked`: the hash is of the point).
    #[must_use]
    pub fn alpha_masked(&self, p: Vec3, uv: Vec2) -> bool {
        self.alpha.as_ref().is_some_and(|alpha| {
            let ctx = TextureContext {
                p,
                uv,
                ..TextureContext::default()
            };
            !alpha_keeps(alpha.evaluate(&ctx), || hash_float(&[p.x, p.y, p.z]))
        })
    }

    /// Sample a point on the surface by area; `None` where the alpha test removes it.
    #[must_use]
    pub fn sample_li(&self, receiver: &Interaction, u: Vec2) -> Option<LightLiSample> {
        let ss = self.shape.sample_area(u);
        if self.alpha_masked(ss.intr.p, ss.uv) {
            return None;
        }
        let d = ss.intr.p - receiver.p;
        let r2 = d.length_squared();
        let wi = d.try_normalize()?;
        let cos_l = ss.intr.n.dot(-wi).abs();
        if cos_l == 0.0 || ss.pdf_area == 0.0 {
            return None;
        }
        let pdf = ss.pdf_area * r2 / cos_l;
        let l = self.l(ss.intr.n, -wi);
        if l.is_black() || !pdf.is_finite() {
            return None;
        }
        Some(LightLiSample {
            l,
            wi,
            pdf,
            p_light: ss.intr,
        })
    }

    /// Solid-angle density at `receiver` of having sampled `p_light`.
    #[must_use]
    pub fn pdf_li(&self, receiver: &Interaction, p_light: &Interaction) -> f32 {
        let d = p_light.p - receiver.p;
        let r2 = d.length_squared();
        let cos_l = p_light.n.dot(d).abs() / r2.sqrt();
        if cos_l == 0.0 {
            return 0.0;
        }
        let pdf = self.shape.pdf_area(p_light) * r2 / cos_l;
        if pdf.is_finite() {
            pdf
        } else {
            0.0
        }
    }

    /// `pi A L`, doubled when two-sided.
    #[must_use]
    pub fn power(&self) -> Rgb {
        let sides = if self.two_sided { 2.0 } else { 1.0 };
        self.radiance * (PI * sides * self.shape.area())
    }
}
