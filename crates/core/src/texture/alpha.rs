//! The stochastic alpha test of cut-outs (pbrt-v4 `GeometricPrimitive::Intersect` and
//! `DiffuseAreaLight::AlphaMasked`): with alpha `a` at a point, the surface is present
//! always for `a >= 1`, never for `a <= 0`, and otherwise when a hash value `u` in `[0, 1)`
//! is `<= a`, so with probability `a`.

use super::FloatTexture;

/// The alpha a shape keeps: `None` (no test at all) for a constant `>= 1`.
#[must_use]
pub fn effective_alpha(alpha: Option<&FloatTexture>) -> Option<FloatTexture> {
    alpha.filter(|a| !matches!(a.constant(), Some(c) if c >= 1.0)).cloned()
}

/// True when the surface is present at alpha `a` for a hash value `u` in `[0, 1)`:
/// always for `a >= 1`, never for `a <= 0`, otherwise when `u <= a`.
#[inline]
#[must_use]
pub fn alpha_keeps(a: f32, u: impl FnOnce() -> f32) -> bool {
    a >= 1.0 || (a > 0.0 && u() <= a)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn alpha_keeps_by_threshold() {
        assert!(alpha_keeps(1.0, || unreachable!()));
        assert!(!alpha_keeps(0.0, || unreachable!()));
        assert!(!alpha_keeps(-1.0, || unreachable!()));
        assert!(alpha_keeps(0.5, || 0.5));
        assert!(alpha_keeps(0.5, || 0.1));
        assert!(!alpha_keeps(0.5, || 0.6));
    }

    #[test]
    fn constant_one_means_no_alpha() {
        assert_eq!(effective_alpha(Some(&FloatTexture::Constant(1.0))), None);
        assert_eq!(effective_alpha(Some(&FloatTexture::Constant(2.0))), None);
        assert_eq!(effective_alpha(None), None);
        assert_eq!(
            effective_alpha(Some(&FloatTexture::Constant(0.5))),
            Some(FloatTexture::Constant(0.5))
        );
    }
}
