//! Microfacet distributions: Trowbridge-Reitz (GGX) and Beckmann, anisotropic with
//! roughness `alpha_x` along the shading tangent and `alpha_y` along the bitangent, with
//! Smith masking-shadowing and sampling of the visible normals.
//!
//! Trowbridge-Reitz normals are sampled as Heitz 2018 ("Sampling the GGX distribution of
//! visible normals", in the form pbrt-v4 uses); Beckmann normals by inverting the
//! visible-slope distribution numerically ([`super::beckmann`]).
//!
//! Directions are in the local shading frame (z = macro-surface normal). `d(wm)` is a
//! density of microfacet normals per unit solid angle normalised over projected area,
//! `integral D(wm) cos(theta_m) dwm = 1`; `d_visible(w, wm)` is the density of normals seen
//! from `w`, a pdf per unit solid angle, and the one [`Microfacet::sample_wm`] samples.
//!
//! Masking-shadowing in the BSDF value is pbrt-v4's height-correlated form
//! `1 / (1 + Lambda(wo) + Lambda(wi))` or Mitsuba 3's separable one `G1(wo) G1(wi)`
//! ([`Masking`]); Mitsuba evaluates the Beckmann `G1` with the rational fit of Walter et
//! al. 2007 (eq. 27, under 0.35% relative error), and so does [`Masking::Separable`]. The
//! density of visible normals always uses the exact `G1 = 1 / (1 + Lambda)`, the one the
//! sampler draws from.

use super::beckmann;
use crate::math::{safe_sqrt, sqr, Vec2, Vec3, PI};
use crate::sampling::sample_uniform_disk_polar;

/// Below this roughness a surface is treated as perfectly smooth (specular).
pub const SMOOTH_ALPHA: f32 = 1e-3;

/// The shape of the distribution of microfacet normals.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum MicrofacetModel {
    /// Trowbridge-Reitz (GGX): long tails.
    #[default]
    TrowbridgeReitz,
    /// Beckmann: the slopes of a Gaussian random surface.
    Beckmann,
}

/// How the masking of `wo` and the shadowing of `wi` combine in the BSDF value.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum Masking {
    /// `1 / (1 + Lambda(wo) + Lambda(wi))` (pbrt-v4).
    #[default]
    HeightCorrelated,
    /// `G1(wo) G1(wi)` (Mitsuba 3; the Beckmann `G1` by the rational fit).
    Separable,
}

/// An anisotropic microfacet distribution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Microfacet {
    /// Trowbridge-Reitz or Beckmann.
    pub model: MicrofacetModel,
    /// Roughness along the shading tangent (x).
    pub alpha_x: f32,
    /// Roughness along the bitangent (y).
    pub alpha_y: f32,
    /// The masking-shadowing term of the BSDF value.
    pub masking: Masking,
}

/// Which distribution and masking term a material's rough lobes use; the default is
/// pbrt-v4's (Trowbridge-Reitz, height-correlated).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct MicrofacetStyle {
    /// Trowbridge-Reitz or Beckmann.
    pub model: MicrofacetModel,
    /// The masking-shadowing term.
    pub masking: Masking,
}

impl MicrofacetStyle {
    /// The distribution of this style with the given roughness.
    #[must_use]
    pub const fn distribution(self, alpha_x: f32, alpha_y: f32) -> Microfacet {
        Microfacet {
            model: self.model,
            alpha_x,
            alpha_y,
            masking: self.masking,
        }
    }
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

impl Microfacet {
    /// A Trowbridge-Reitz distribution with height-correlated masking (pbrt-v4's).
    #[must_use]
    pub const fn trowbridge_reitz(alpha_x: f32, alpha_y: f32) -> Self {
        Self {
            model: MicrofacetModel::TrowbridgeReitz,
            alpha_x,
            alpha_y,
            masking: Masking::HeightCorrelated,
        }
    }

    /// A Beckmann distribution with height-correlated masking.
    #[must_use]
    pub const fn beckmann(alpha_x: f32, alpha_y: f32) -> Self {
        Self {
            model: MicrofacetModel::Beckmann,
            alpha_x,
            alpha_y,
            masking: Masking::HeightCorrelated,
        }
    }

    /// The same distribution with another masking-shadowing term.
    #[must_use]
    pub const fn with_masking(self, masking: Masking) -> Self {
        Self { masking, ..self }
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
        match self.model {
            MicrofacetModel::TrowbridgeReitz => 1.0 / (PI * self.alpha_x * self.alpha_y * cos4 * sqr(1.0 + e)),
            MicrofacetModel::Beckmann => (-e).exp() / (PI * self.alpha_x * self.alpha_y * cos4),
        }
    }

    /// `alpha tan(theta)` of `w`, with alpha projected on the azimuth of `w`; `None` at
    /// the horizon.
    fn alpha_tan(&self, w: Vec3) -> Option<f32> {
        let tan2 = tan2_theta(w);
        if !tan2.is_finite() {
            return None;
        }
        let (c, s) = cos_sin_phi(w);
        Some(((sqr(c * self.alpha_x) + sqr(s * self.alpha_y)) * tan2).sqrt())
    }

    /// Smith's auxiliary function `Lambda(w)`: the masked projected area of microfacets
    /// over the visible one.
    #[must_use]
    pub fn lambda(&self, w: Vec3) -> f32 {
        let Some(at) = self.alpha_tan(w) else {
            return 0.0;
        };
        match self.model {
            MicrofacetModel::TrowbridgeReitz => 0.5 * ((1.0 + sqr(at)).sqrt() - 1.0),
            MicrofacetModel::Beckmann => beckmann::lambda(at),
        }
    }

    /// Masking: the fraction of microfacets visible from `w`, `1 / (1 + Lambda(w))`.
    #[must_use]
    pub fn g1(&self, w: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(w))
    }

    /// `G1(w)` as Mitsuba 3 evaluates it: exact for Trowbridge-Reitz, the rational fit for
    /// Beckmann.
    #[must_use]
    pub fn g1_separable(&self, w: Vec3) -> f32 {
        match self.model {
            MicrofacetModel::TrowbridgeReitz => self.g1(w),
            MicrofacetModel::Beckmann => self.alpha_tan(w).map_or(0.0, beckmann::g1_rational),
        }
    }

    /// Masking-shadowing for the pair `wo`, `wi` (see [`Masking`]).
    #[must_use]
    pub fn g(&self, wo: Vec3, wi: Vec3) -> f32 {
        match self.masking {
            Masking::HeightCorrelated => 1.0 / (1.0 + self.lambda(wo) + self.lambda(wi)),
            Masking::Separable => self.g1_separable(wo) * self.g1_separable(wi),
        }
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
        // Stretch to the configuration where alpha = 1 (both distributions are invariant
        // under stretching of the surface).
        let mut wh = Vec3::new(self.alpha_x * w.x, self.alpha_y * w.y, w.z).normalize();
        if wh.z < 0.0 {
            wh = -wh;
        }
        let nh = match self.model {
            MicrofacetModel::TrowbridgeReitz => sample_visible_hemisphere(wh, u),
            MicrofacetModel::Beckmann => {
                let (sx, sy) = beckmann::sample_visible_slopes(wh.z, u);
                let (c, s) = cos_sin_phi(wh);
                // Rotate the slopes to the azimuth of wh; slope (x, y) is the normal (-x, -y, 1).
                Vec3::new(-(c * sx - s * sy), -(s * sx + c * sy), 1.0)
            }
        };
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

/// A normal of the unit hemisphere visible from `wh` (upper hemisphere), by Heitz 2018:
/// a point on the projected hemisphere, seen along `wh`.
fn sample_visible_hemisphere(wh: Vec3, u: Vec2) -> Vec3 {
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
    p.x * t1 + p.y * t2 + pz * wh
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

    /// Both models with the given roughness.
    fn models(ax: f32, ay: f32) -> [Microfacet; 2] {
        [Microfacet::trowbridge_reitz(ax, ay), Microfacet::beckmann(ax, ay)]
    }

    #[test]
    fn d_integrates_to_one_over_projected_area() {
        for (ax, ay) in [(0.1, 0.1), (0.3, 0.3), (0.8, 0.8), (0.15, 0.6)] {
            for m in models(ax, ay) {
                let i = integrate_sphere(|wm| if wm.z > 0.0 { f64::from(m.d(wm) * wm.z) } else { 0.0 });
                assert!((i - 1.0).abs() < 2e-3, "{m:?}: {i}");
            }
        }
    }

    #[test]
    fn visible_normals_integrate_to_one() {
        // Equivalent to G1 being consistent with D: integral G1(w) max(0, w.wm) D(wm) dwm = cos(w).
        for m in [(0.3, 0.3), (0.15, 0.6)]
            .into_iter()
            .flat_map(|(ax, ay)| models(ax, ay))
        {
            let (ax, ay) = (m.alpha_x, m.alpha_y);
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
        let count = (2 * dirs.len() * ALPHAS.len()) as u32;
        let all = ALPHAS.iter().flat_map(|&(ax, ay)| models(ax, ay));
        for (k, m) in all.enumerate() {
            let (ax, ay) = (m.alpha_x, m.alpha_y);
            for (i, &w) in dirs.iter().enumerate() {
                let seed = suite_seed() + (k * dirs.len() + i) as u64;
                let report = Chi2Test::new(100_000, seed).with_test_count(count).sphere(
                    SphereGrid::default(),
                    |u, _| Some(m.sample_wm(w, u)),
                    |wm| if wm.z > 0.0 { m.d_visible(w, wm) } else { 0.0 },
                );
                assert!(
                    report.passes(SIGNIFICANCE),
                    "{:?} ({ax}, {ay}), w = {w}: {report}",
                    m.model
                );
            }
        }
    }

    #[test]
    fn masking_is_one_at_normal_incidence_and_falls_at_grazing() {
        let m = Microfacet::trowbridge_reitz(0.3, 0.3);
        assert!((m.g1(Vec3::Z) - 1.0).abs() < 1e-6);
        let grazing = Vec3::new(0.999, 0.0, 0.0447).normalize();
        assert!(m.g1(grazing) < 0.5);
        assert!(m.g(Vec3::Z, grazing) <= m.g1(grazing) + 1e-6);
        assert!(Microfacet::trowbridge_reitz(5e-4, 0.3).effectively_smooth());
        assert!(!Microfacet::trowbridge_reitz(0.01, 0.01).effectively_smooth());
        // Regularizing roughens near-smooth surfaces into [0.1, 0.3] and leaves rough ones.
        let mut d = Microfacet::trowbridge_reitz(0.0, 0.2);
        d.regularize();
        assert_eq!((d.alpha_x, d.alpha_y), (0.1, 0.3));
        assert!(!d.effectively_smooth());
        let mut d = Microfacet::trowbridge_reitz(0.5, 0.12);
        d.regularize();
        assert_eq!((d.alpha_x, d.alpha_y), (0.5, 0.24));
        assert_eq!(roughness_to_alpha(0.25), 0.5);
    }

    #[test]
    fn beckmann_separable_masking_is_mitsubas() {
        let m = Microfacet::beckmann(0.3, 0.3).with_masking(Masking::Separable);
        let grazing = Vec3::new(0.95, 0.0, 0.312).normalize();
        // Mitsuba's fit, a = 1 / (alpha tan theta).
        let a = grazing.z / (0.3 * (1.0 - sqr(grazing.z)).sqrt());
        let fit = (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a);
        assert!(
            (m.g(Vec3::Z, grazing) - fit).abs() < 1e-6,
            "{} vs {fit}",
            m.g(Vec3::Z, grazing)
        );
        assert!((m.g(grazing, grazing) - fit * fit).abs() < 1e-6);
        // Within the fit's error of the exact separable product.
        assert!((m.g(grazing, grazing) - sqr(m.g1(grazing))).abs() < 8e-3);
        // Trowbridge-Reitz separable: the exact G1 product, above the height-correlated form.
        let t = Microfacet::trowbridge_reitz(0.3, 0.3);
        let ts = t.with_masking(Masking::Separable);
        assert!((ts.g(grazing, grazing) - sqr(t.g1(grazing))).abs() < 1e-6);
        assert!(ts.g(grazing, grazing) < t.g(grazing, grazing));
    }
}
