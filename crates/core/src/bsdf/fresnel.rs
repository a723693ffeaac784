//! Fresnel reflectance of smooth interfaces: dielectric (real relative index of refraction)
//! and conductor (complex index `eta + i k`, per RGB channel), and the reflection and
//! refraction of directions about a normal.
//!
//! Both reflectances are the average of the s- and p-polarised terms (unpolarised light).
//! Angles are given by the cosine of the incident direction with the normal on the side of
//! the incident medium; `eta` is the index of the other side over that of the side the
//! normal points to (pbrt's convention).

use crate::color::Rgb;
use crate::math::{safe_sqrt, sqr, Vec3};

/// Unpolarised Fresnel reflectance of a dielectric interface with relative index `eta`
/// (inside over outside; the normal points outside).
///
/// A negative `cos_theta_i` means the incident direction is inside: the indices swap. Beyond
/// the critical angle (only when going to a lower index) the reflectance is 1.
#[must_use]
pub fn fr_dielectric(cos_theta_i: f32, eta: f32) -> f32 {
    let (cos_i, eta) = if cos_theta_i < 0.0 {
        (-cos_theta_i.max(-1.0), 1.0 / eta)
    } else {
        (cos_theta_i.min(1.0), eta)
    };
    let sin2_t = (1.0 - sqr(cos_i)).max(0.0) / sqr(eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = safe_sqrt(1.0 - sin2_t);
    let r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (sqr(r_parl) + sqr(r_perp))
}

/// A complex number, just enough for the conductor Fresnel equations.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Complex {
    re: f32,
    im: f32,
}

impl Complex {
    const fn new(re: f32, im: f32) -> Self {
        Self { re, im }
    }
    fn add(self, o: Self) -> Self {
        Self::new(self.re + o.re, self.im + o.im)
    }
    fn sub(self, o: Self) -> Self {
        Self::new(self.re - o.re, self.im - o.im)
    }
    fn mul(self, o: Self) -> Self {
        Self::new(self.re * o.re - self.im * o.im, self.re * o.im + self.im * o.re)
    }
    fn scale(self, s: f32) -> Self {
        Self::new(self.re * s, self.im * s)
    }
    fn div(self, o: Self) -> Self {
        let d = sqr(o.re) + sqr(o.im);
        Self::new(
            (self.re * o.re + self.im * o.im) / d,
            (self.im * o.re - self.re * o.im) / d,
        )
    }
    /// Squared magnitude.
    fn norm(self) -> f32 {
        sqr(self.re) + sqr(self.im)
    }
    /// Principal square root (non-negative real part).
    fn sqrt(self) -> Self {
        let n = self.norm().sqrt();
        if n == 0.0 {
            return Self::new(0.0, 0.0);
        }
        let t1 = (0.5 * (n + self.re.abs())).sqrt();
        let t2 = 0.5 * self.im / t1;
        if self.re >= 0.0 {
            Self::new(t1, t2)
        } else {
            Self::new(t2.abs(), t1.copysign(self.im))
        }
    }
}

/// Fresnel reflectance of one channel of a conductor with complex index `eta + i k`, for
/// light arriving from the outside at `cos_theta_i` (clamped to [0, 1]).
#[must_use]
pub fn fr_complex_channel(cos_theta_i: f32, eta: f32, k: f32) -> f32 {
    let cos_i = cos_theta_i.clamp(0.0, 1.0);
    let eta = Complex::new(eta, k);
    let sin2_i = Complex::new(1.0 - sqr(cos_i), 0.0);
    let sin2_t = sin2_i.div(eta.mul(eta));
    let cos_t = Complex::new(1.0, 0.0).sub(sin2_t).sqrt();
    let ci = Complex::new(cos_i, 0.0);
    let r_parl = eta.scale(cos_i).sub(cos_t).div(eta.scale(cos_i).add(cos_t));
    let r_perp = ci.sub(eta.mul(cos_t)).div(ci.add(eta.mul(cos_t)));
    0.5 * (r_parl.norm() + r_perp.norm())
}

/// Conductor Fresnel reflectance per RGB channel.
#[must_use]
pub fn fr_complex(cos_theta_i: f32, eta: Rgb, k: Rgb) -> Rgb {
    Rgb::new(
        fr_complex_channel(cos_theta_i, eta.r, k.r),
        fr_complex_channel(cos_theta_i, eta.g, k.g),
        fr_complex_channel(cos_theta_i, eta.b, k.b),
    )
}

/// Mirror `wo` about the normal `n`.
#[inline]
#[must_use]
pub fn reflect(wo: Vec3, n: Vec3) -> Vec3 {
    -wo + 2.0 * wo.dot(n) * n
}

/// Refract `wi` through an interface with normal `n` and relative index `eta` (the side `n`
/// points to is outside). `wi` may be on either side; the normal and index are flipped as
/// needed. Returns the transmitted direction and the relative index it saw (`eta` when
/// entering, `1 / eta` when leaving), or `None` on total internal reflection.
#[must_use]
pub fn refract(wi: Vec3, n: Vec3, eta: f32) -> Option<(Vec3, f32)> {
    let mut cos_i = n.dot(wi);
    let (n, eta) = if cos_i < 0.0 {
        cos_i = -cos_i;
        (-n, 1.0 / eta)
    } else {
        (n, eta)
    };
    let sin2_t = (1.0 - sqr(cos_i)).max(0.0) / sqr(eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = safe_sqrt(1.0 - sin2_t);
    Some((-wi / eta + (cos_i / eta - cos_t) * n, eta))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dielectric_fresnel_at_normal_incidence_and_grazing() {
        // ((eta - 1) / (eta + 1))^2 = 0.04 for glass, from either side.
        assert!((fr_dielectric(1.0, 1.5) - 0.04).abs() < 1e-6);
        assert!((fr_dielectric(-1.0, 1.5) - 0.04).abs() < 1e-6);
        assert!((fr_dielectric(1.0, 1.0 / 1.5) - 0.04).abs() < 1e-6);
        assert!(fr_dielectric(1e-4, 1.5) > 0.99);
        assert_eq!(fr_dielectric(0.7, 1.0), 0.0);
    }

    #[test]
    fn total_internal_reflection_beyond_the_critical_angle() {
        // Inside glass: critical angle asin(1 / 1.5) = 41.8 degrees, cos = 0.745.
        assert_eq!(fr_dielectric(-0.7, 1.5), 1.0);
        assert!(fr_dielectric(-0.8, 1.5) < 1.0);
        // The same with eta < 1 seen from the outside.
        assert_eq!(fr_dielectric(0.7, 1.0 / 1.5), 1.0);
        assert!(refract(Vec3::new(0.72, 0.0, -0.7).normalize(), Vec3::Z, 1.5).is_none());
    }

    #[test]
    fn fresnel_is_the_same_on_both_sides_for_matching_angles() {
        // Snell: light entering at theta_i leaves at theta_t; both see the same reflectance.
        let eta = 1.33f32;
        for cos_i in [0.2f32, 0.5, 0.9] {
            let sin_t = (1.0 - cos_i * cos_i).sqrt() / eta;
            let cos_t = (1.0 - sin_t * sin_t).sqrt();
            assert!((fr_dielectric(cos_i, eta) - fr_dielectric(-cos_t, eta)).abs() < 1e-5);
        }
    }

    #[test]
    fn conductor_fresnel_reduces_to_dielectric_for_k_zero() {
        for cos_i in [0.05f32, 0.3, 0.7, 1.0] {
            let a = fr_complex_channel(cos_i, 1.5, 0.0);
            let b = fr_dielectric(cos_i, 1.5);
            assert!((a - b).abs() < 1e-5, "{cos_i}: {a} vs {b}");
        }
        // Normal incidence: ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2).
        let (n, k) = (0.2f32, 3.9f32);
        let r0 = ((n - 1.0).powi(2) + k * k) / ((n + 1.0).powi(2) + k * k);
        assert!((fr_complex_channel(1.0, n, k) - r0).abs() < 1e-5);
        assert!((fr_complex_channel(0.0, n, k) - 1.0).abs() < 1e-5);
        let rgb = fr_complex(0.5, Rgb::new(0.2, 0.9, 1.1), Rgb::new(3.9, 2.4, 2.1));
        assert!(rgb.r > rgb.g && rgb.g > rgb.b, "copper is red: {rgb:?}");
    }

    #[test]
    fn refraction_obeys_snell() {
        let wi = Vec3::new(0.6, 0.0, 0.8);
        let (wt, etap) = refract(wi, Vec3::Z, 1.5).unwrap();
        assert_eq!(etap, 1.5);
        assert!((wt.length() - 1.0).abs() < 1e-5 && wt.z < 0.0);
        assert!((wi.x - 1.5 * (-wt.x)).abs() < 1e-5, "sin_i = eta sin_t");
        // And back out again.
        let (back, etap) = refract(wt, Vec3::Z, 1.5).unwrap();
        assert!((etap - 1.0 / 1.5).abs() < 1e-6);
        assert!((back - wi).length() < 1e-5);
        assert!((reflect(wi, Vec3::Z) - Vec3::new(-0.6, 0.0, 0.8)).length() < 1e-6);
    }
}
