//! The Trowbridge-Reitz (GGX) microfacet distribution, anisotropic with roughness
//! `alpha_x` along the shading tangent and `alpha_y` along the bitangent, with Smith's
//! height-correlated masking-shadowing and sampling of the visible normals (Heitz 2018,
//! "Sampling the GGX distribution of visible normals", in the form pbrt-v4 uses).
//!
//! Directions are in the local shading frame (z = macro-surface normal). `d(wm)` is a
//! density of microfacet normals per unit solid angle normalised over projected area,
//! `integral D(wm) cos(theta_m) dwm = 1`; `d_visible(w, wm)` is the density of normals seen
//! from `w`, a pdf per unit solid angle, and the one [`TrowbridgeReitz::sample_wm`] samples.

use crate::math::{safe_sqrt, sqr, Vec2, Vec3, PI};
use crate::sampling::sample_uniform_disk_polar;

/// Below this roughness a surface is treated as perfectly smooth (specular).
pub const SMOOTH_ALPHA: f32 = 1e-3;

/// Anisotropic Trowbridge-Reitz distribution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrowbridgeReitz {
    /// Roughness along the shading tangent (x).
    pub alpha_x: f32,
    /// Roughness along the bitangent (y).
    pub alpha_y: f32,
}

/// pbrt-v4's map from a user's "roughness" to `alpha`: `sqrt(roughness)`.
#[inline]
#[must_use]
pub fn roughness_to_alpha(roughness: f32) -> f32 {
    roughness.max(0.0).sqrt()
}

#[inline]
fn cos2_theta(w: Vec3) -> f32 {
    sqr(w.z)
}

#[inline]
fn tan2_theta(w: Vec3) -> f32 {
    (1.0 - cos2_theta(w)).max(0.0) / cos2_theta(w)
}

/// (cos phi, sin phi) of `w`, (1, 0) along the normal.
#[inline]
fn cos_sin_phi(w: Vec3) -> (f32, f32) {
    let sin_theta = (sqr(w.x) + sqr(w.y)).sqrt();
    if sin_theta == 0.0 {
        (1.0, 0.0)
    } else {
        ((w.x / sin_theta).clamp(-1.0, 1.0), (w.y / sin_theta).clamp(-1.0, 1.0))
    }
}

impl TrowbridgeReitz {
    /// A distribution with the given roughness per axis.
    #[must_use]
    pub const fn new(alpha_x: f32, alpha_y: f32) -> Self {
        Self { alpha_x, alpha_y }
    }

    /// Roughen a near-smooth distribution (pbrt-v4 `TrowbridgeReitzDistribution::
    /// Regularize`): each alpha below 0.3 is doubled and clamped to [0.1, 0.3].
    pub fn regularize(&mut self) {
        for a in [&mut self.alpha_x, &mut self.alpha_y] {
            if *a < 0.3 {
                *a = (2.0 * *a).clamp(0.1, 0.3);
            }
        }
    }

    /// True when the surface is smooth enough to be treated as a perfect mirror or
    /// refractor (either alpha below [`SMOOTH_ALPHA`]).
    #[must_use]
    pub fn effectively_smooth(&self) -> bool {
        self.alpha_x.min(self.alpha_y) < SMOOTH_ALPHA
    }

    /// Density of microfacet normals `D(wm)` (symmetric in `wm` and `-wm`).
    #[must_use]
    pub fn d(&self, wm: Vec3) -> f32 {
        let tan2 = tan2_theta(wm);
        if !tan2.is_finite() {
            return 0.0;
        }
        let cos4 = sqr(cos2_theta(wm));
        if cos4 < 1e-16 {
            return 0.0;
        }
        let (c, s) = cos_sin_phi(wm);
        let e = tan2 * (sqr(c / self.alpha_x) + sqr(s / self.alpha_y));
        1.0 / (PI * self.alpha_x * self.alpha_y * cos4 * sqr(1.0 + e))
    }

    /// Smith's auxiliary function `Lambda(w)`: the masked projected area of microfacets
    /// over the visible one.
    #[must_use]
    pub fn lambda(&self, w: Vec3) -> f32 {
        let tan2 = tan2_theta(w);
        if !tan2.is_finite() {
            return 0.0;
        }
        let (c, s) = cos_sin_phi(w);
        let alpha2 = sqr(c * self.alpha_x) + sqr(s * self.alpha_y);
        0.5 * ((1.0 + alpha2 * tan2).sqrt() - 1.0)
    }

    /// Masking: the fraction of microfacets visible from `w`.
    #[must_use]
    pub fn g1(&self, w: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(w))
    }

    /// Height-correlated masking-shadowing for the pair `wo`, `wi`.
    #[must_use]
    pub fn g(&self, wo: Vec3, wi: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(wo) + self.lambda(wi))
    }

    /// Density of normals visible from `w`, per unit solid angle of `wm`:
    /// `G1(w) max(0, w.wm) D(wm) / |cos theta(w)|`, with `wm` taken on the side of `w`.
    #[must_use]
    pub fn d_visible(&self, w: Vec3, wm: Vec3) -> f32 {
        let cos_w = w.z.abs();
        if cos_w == 0.0 {
            return 0.0;
        }
        // Normals face the side of w; a normal on the other side is seen as its negation.
        let wm = if wm.z * w.z < 0.0 { -wm } else { wm };
        self.g1(w) * w.dot(wm).max(0.0) * self.d(wm) / cos_w
    }

    /// Sample a microfacet normal visible from `w` (either side), in the upper hemisphere,
    /// with density [`Self::pdf`].
    #[must_use]
    pub fn sample_wm(&self, w: Vec3, u: Vec2) -> Vec3 {
        // Stretch to the configuration where the distribution is the unit hemisphere.
        let mut wh = Vec3::new(self.alpha_x * w.x, self.alpha_y * w.y, w.z).normalize();
        if wh.z < 0.0 {
            wh = -wh;
        }
        // An orthonormal basis around wh, then a point on the projected hemisphere.
        let t1 = if wh.z < 0.99999 {
            Vec3::Z.cross(wh).normalize()
        } else {
            Vec3::X
        };
        let t2 = wh.cross(t1);
        let mut p = sample_uniform_disk_polar(u);
        let h = safe_sqrt(1.0 - sqr(p.x));
        let t = 0.5 * (1.0 + wh.z);
        p.y = (1.0 - t) * h + t * p.y;
        let pz = safe_sqrt(1.0 - p.length_squared());
        let nh = p.x * t1 + p.y * t2 + pz * wh;
        // Back to the ellipsoid's configuration.
        Vec3::new(self.alpha_x * nh.x, self.alpha_y * nh.y, nh.z.max(1e-6)).normalize()
    }

    /// Density of [`Self::sample_wm`] producing `wm`: the visible-normal density
    /// `D(wm) G1(w) |w.wm| / |cos theta(w)|`.
    #[must_use]
    pub fn pdf(&self, w: Vec3, wm: Vec3) -> f32 {
        let cos_w = w.z.abs();
        if cos_w == 0.0 {
            return 0.0;
        }
        self.d(wm) * self.g1(w) * w.dot(wm).abs() / cos_w
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::tests::test_directions;
    use crate::sampling::chi2::{suite_seed, Chi2Test, SphereGrid, SIGNIFICANCE};

    const ALPHAS: [(f32, f32); 4] = [(0.05, 0.05), (0.2, 0.2), (0.6, 0.6), (0.1, 0.5)];

    /// Integral of `f` over the sphere by the midpoint rule in (theta, phi).
    fn integrate_sphere(f: impl Fn(Vec3) -> f64) -> f64 {
        let (nt, np) = (4000, 256);
        let (dt, dp) = (
            std::f64::consts::PI / f64::from(nt),
            std::f64::consts::TAU / f64::from(np),
        );
        let mut sum = 0.0;
        for i in 0..nt {
            let theta = (f64::from(i) + 0.5) * dt;
            let (st, ct) = theta.sin_cos();
            for j in 0..np {
                let (sp, cp) = ((f64::from(j) + 0.5) * dp).sin_cos();
                let w = Vec3::new((st * cp) as f32, (st * sp) as f32, ct as f32);
                sum += f(w) * st;
            }
        }
        sum * dt * dp
    }

    #[test]
    fn d_integrates_to_one_over_projected_area() {
        for (ax, ay) in [(0.1, 0.1), (0.3, 0.3), (0.8, 0.8), (0.15, 0.6)] {
            let m = TrowbridgeReitz::new(ax, ay);
            let i = integrate_sphere(|wm| if wm.z > 0.0 { f64::from(m.d(wm) * wm.z) } else { 0.0 });
            assert!((i - 1.0).abs() < 2e-3, "alpha ({ax}, {ay}): {i}");
        }
    }

    #[test]
    fn visible_normals_integrate_to_one() {
        // Equivalent to G1 being consistent with D: integral G1(w) max(0, w.wm) D(wm) dwm = cos(w).
        for (ax, ay) in [(0.3, 0.3), (0.15, 0.6)] {
            let m = TrowbridgeReitz::new(ax, ay);
            for w in test_directions() {
                let i = integrate_sphere(|wm| if wm.z > 0.0 { f64::from(m.pdf(w, wm)) } else { 0.0 });
                // pdf uses |w.wm|; only normals facing w are visible.
                let v = integrate_sphere(|wm| if wm.z > 0.0 { f64::from(m.d_visible(w, wm)) } else { 0.0 });
                assert!((v - 1.0).abs() < 3e-3, "alpha ({ax}, {ay}), w = {w}: {v}");
                assert!(i >= v - 1e-3, "{i} < {v}");
            }
        }
    }

    #[test]
    fn sampled_visible_normals_match_their_density() {
        let dirs = test_directions();
        let count = (dirs.len() * ALPHAS.len()) as u32;
        for (k, &(ax, ay)) in ALPHAS.iter().enumerate() {
            let m = TrowbridgeReitz::new(ax, ay);
            for (i, &w) in dirs.iter().enumerate() {
                let seed = suite_seed() + (k * dirs.len() + i) as u64;
                let report = Chi2Test::new(100_000, seed).with_test_count(count).sphere(
                    SphereGrid::default(),
                    |u, _| Some(m.sample_wm(w, u)),
                    |wm| if wm.z > 0.0 { m.d_visible(w, wm) } else { 0.0 },
                );
                assert!(report.passes(SIGNIFICANCE), "alpha ({ax}, {ay}), w = {w}: {report}");
            }
        }
    }

    #[test]
    fn masking_is_one_at_normal_incidence_and_falls_at_grazing() {
        let m = TrowbridgeReitz::new(0.3, 0.3);
        assert!((m.g1(Vec3::Z) - 1.0).abs() < 1e-6);
        let grazing = Vec3::new(0.999, 0.0, 0.0447).normalize();
        assert!(m.g1(grazing) < 0.5);
        assert!(m.g(Vec3::Z, grazing) <= m.g1(grazing) + 1e-6);
        assert!(TrowbridgeReitz::new(5e-4, 0.3).effectively_smooth());
        assert!(!TrowbridgeReitz::new(0.01, 0.01).effectively_smooth());
        // Regularizing roughens near-smooth surfaces into [0.1, 0.3] and leaves rough ones.
        let mut d = TrowbridgeReitz::new(0.0, 0.2);
        d.regularize();
        assert_eq!((d.alpha_x, d.alpha_y), (0.1, 0.3));
        assert!(!d.effectively_smooth());
        let mut d = TrowbridgeReitz::new(0.5, 0.12);
        d.regularize();
        assert_eq!((d.alpha_x, d.alpha_y), (0.5, 0.24));
        assert_eq!(roughness_to_alpha(0.25), 0.5);
    }
}
