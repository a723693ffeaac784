//! Alpha cut-outs (pbrt-v4 `GeometricPrimitive::Intersect` in `cpu/primitive.cpp`): a hit
//! on a primitive whose alpha texture gives `a` there is ignored when `a <= 0`, and when
//! `0 < a < 1` it is ignored if a hash of the ray (origin and direction, pbrt-v4
//! `HashFloat(r.o, r.d)`) exceeds `a`, so the surface is present with probability `a`,
//! deterministically per ray. An ignored hit continues the ray from just past it, to find
//! farther hits on the same shape (the back of a sphere). Shadow rays use the same test, so
//! a cut-out casts no shadow and half alpha half a shadow in expectation.

use super::Primitive;
use crate::math::Ray;
use crate::sampling::hash_float;
use crate::shape::ShapeHit;
use crate::texture::{alpha_keeps, FloatTexture, TextureContext};

/// Most ignored hits followed on one primitive before the ray is taken to miss it (a
/// shape is hit at most twice; this only guards against rounding loops).
const MAX_SKIPS: u32 = 8;

impl Primitive {
    /// Closest hit of `ray` on this primitive in `(0, t_max)` that survives its alpha
    /// test; the hit's `t` is along `ray`. Primitives without alpha are the plain shape
    /// test.
    #[inline]
    #[must_use]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        let hit = self.shape.intersect(ray, t_max)?;
        match &self.alpha {
            None => Some(hit),
            Some(alpha) => self.alpha_tested(alpha, ray, t_max, hit),
        }
    }

    /// Follow `ray` past hits that the alpha test ignores.
    #[cold]
    fn alpha_tested(&self, alpha: &FloatTexture, ray: &Ray, t_max: f32, mut hit: ShapeHit) -> Option<ShapeHit> {
        let mut r = *ray;
        let mut t_before = 0.0;
        for _ in 0..MAX_SKIPS {
            let si = self.shape.interaction(&r, &hit);
            let a = alpha.evaluate(&TextureContext::at_point(&si));
            if alpha_keeps(a, || hash_float(&[r.o.x, r.o.y, r.o.z, r.d.x, r.d.y, r.d.z])) {
                hit.t += t_before;
                return Some(hit);
            }
            // Ignore this hit and continue the ray from just past it (same direction, so
            // parameters add up).
            t_before += hit.t;
            r = si.spawn_ray(r.d);
            hit = self.shape.intersect(&r, t_max - t_before)?;
        }
        None
    }
}
