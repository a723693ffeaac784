//! Bump mapping: another material with its shading frame tilted by the gradient of a
//! height field, as Mitsuba 3's `bumpmap` and pbrt-v4's `displacement` parameter do.
//!
//! Both displace the surface along the shading normal `n` by a height `d(u, v)` and take
//! the normal of the displaced surface, ignoring the (small) derivatives of `n` itself:
//! `dp/du' = P(dp/du) + (dd/du) n`, `dp/dv' = P(dp/dv) + (dd/dv) n` with `P` the
//! projection onto the plane normal to `n` (pbrt-v4 eq. 10.12; Mitsuba's `frame`), and
//! `n' = normalize(dp/du' x dp/dv')` turned to the side of the geometric normal. The new
//! tangent is `dp/du` made orthogonal to `n'` (Gram-Schmidt). They differ in the
//! gradient:
//!
//! - Mitsuba: `scale` times the analytic gradient of the texture's luminance
//!   (`eval_1_grad`; for a bilinear `bitmap` the derivative of its bilinear patch,
//!   [`crate::texture::BitmapTexture::luminance_gradient`]; zero for a constant);
//! - pbrt-v4 (`BumpMap` in materials.h): forward differences of the float texture at
//!   offsets `du = (|du/dx| + |du/dy|) / 2` (`0.0005` when zero) and likewise `dv`, the
//!   pixel footprint coming from the camera.
//!
//! A zero gradient leaves the frame untouched (bit for bit), so a constant height changes
//! nothing. pbrt-v4's term `d dn/du` is left out (mcrender's interactions carry no `dn/du`).

use super::checks::{check_finite, check_reference, InvalidParameter};
use super::MaterialId;
use crate::math::{Frame, Vec2, Vec3};
use crate::shape::SurfaceInteraction;
use crate::texture::{FloatTexture, RgbTexture, Texture, TextureContext};

/// Where the height field comes from and how its gradient is taken.
#[derive(Clone, Debug, PartialEq)]
pub enum BumpHeight {
    /// Mitsuba 3's `bumpmap`: the luminance of `texture`, its gradient times `scale`.
    Mitsuba {
        /// The height field (its luminance; a `raw` bitmap in Mitsuba's scenes).
        texture: RgbTexture,
        /// Gradient multiplier (Mitsuba's `scale`, default 1).
        scale: f32,
    },
    /// pbrt-v4's `displacement`: finite differences of a float texture.
    Pbrt {
        /// The displacement along the normal, in scene units.
        displacement: FloatTexture,
    },
}

/// Another material under a bump map (module docs). Applied where rays hit the surface
/// (`Scene::intersect`), as [`super::NormalMapMaterial`].
#[derive(Clone, Debug, PartialEq)]
pub struct BumpMapMaterial {
    /// The material shaded with the new frame.
    pub material: MaterialId,
    /// The height field.
    pub height: BumpHeight,
}

impl BumpMapMaterial {
    /// Check the parameters of material `index` among `count` materials.
    pub fn validate(&self, index: usize, count: usize) -> Result<(), InvalidParameter> {
        check_reference(index, "bump-maps", self.material, count)?;
        match &self.height {
            BumpHeight::Mitsuba { scale, .. } => check_finite(&format!("material {index} bump scale"), &[*scale]),
            BumpHeight::Pbrt { .. } => Ok(()),
        }
    }

    /// True when the gradient needs the pixel footprint at the hit (pbrt's offsets).
    #[must_use]
    pub fn needs_footprint(&self) -> bool {
        matches!(&self.height, BumpHeight::Pbrt { displacement } if !displacement.is_constant())
    }

    /// The height's gradient `(dd/du, dd/dv)` at `si` (`ctx` the texture context there).
    #[must_use]
    pub fn gradient(&self, si: &SurfaceInteraction, ctx: &TextureContext) -> Vec2 {
        match &self.height {
            BumpHeight::Mitsuba { texture, scale } => {
                let g = match texture {
                    Texture::Constant(_) => Vec2::ZERO,
                    Texture::Bitmap(b) => b.luminance_gradient(ctx, si.dp_du, si.dp_dv),
                    // Other textures: forward differences of the luminance at pbrt's
                    // fallback step.
                    t => {
                        let f = |c: &TextureContext| t.evaluate(c).luminance();
                        forward_differences(si, ctx, f)
                    }
                };
                g * *scale
            }
            BumpHeight::Pbrt { displacement } => match displacement {
                Texture::Constant(_) => Vec2::ZERO,
                t => forward_differences(si, ctx, |c| t.evaluate(c)),
            },
        }
    }

    /// Tilt the shading frame of `si` by the gradient at `ctx` (module docs).
    pub fn apply(&self, si: &mut SurfaceInteraction, ctx: &TextureContext) {
        let g = self.gradient(si, ctx);
        if g == Vec2::ZERO || !g.is_finite() {
            return;
        }
        let n = si.ns;
        let dpdu = si.dp_du - n * n.dot(si.dp_du) + n * g.x;
        let dpdv = si.dp_dv - n * n.dot(si.dp_dv) + n * g.y;
        let Some(mut ns) = dpdu.cross(dpdv).try_normalize() else {
            return;
        };
        if ns.dot(si.n()) < 0.0 {
            ns = -ns;
        }
        if ns.dot(si.n()) == 0.0 {
            return;
        }
        si.dpdu = (si.dp_du - ns * ns.dot(si.dp_du))
            .try_normalize()
            .unwrap_or_else(|| Frame::from_z(ns).x);
        si.ns = ns;
    }
}

/// pbrt-v4's forward differences of `f` along `u` and `v` (module docs); the shifted
/// points move along `dp/du` and `dp/dv` projected onto the shading tangent plane.
fn forward_differences(si: &SurfaceInteraction, ctx: &TextureContext, f: impl Fn(&TextureContext) -> f32) -> Vec2 {
    let step = |a: f32, b: f32| {
        let d = 0.5 * (a.abs() + b.abs());
        if d == 0.0 {
            0.0005
        } else {
            d
        }
    };
    let (du, dv) = (step(ctx.dudx, ctx.dudy), step(ctx.dvdx, ctx.dvdy));
    let n = si.ns;
    let (tu, tv) = (si.dp_du - n * n.dot(si.dp_du), si.dp_dv - n * n.dot(si.dp_dv));
    let d = f(ctx);
    let shifted = |dp: Vec3, duv: Vec2| TextureContext {
        p: ctx.p + dp,
        uv: ctx.uv + duv,
        ..*ctx
    };
    let d_u = f(&shifted(tu * du, Vec2::new(du, 0.0)));
    let d_v = f(&shifted(tv * dv, Vec2::new(0.0, dv)));
    Vec2::new((d_u - d) / du, (d_v - d) / dv)
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::super::test_support::hit;
    use super::super::{DiffuseMaterial, MaterialDesc};
    use super::*;
    use crate::bsdf::Bsdf;
    use crate::color::Rgb;
    use crate::math::Vec2;
    use crate::sampling::chi2::{suite_seed, Chi2Test, SphereGrid, SIGNIFICANCE};
    use crate::sampling::{sample_uniform_sphere, uniform_sphere_pdf, Pcg32};
    use crate::texture::{BitmapFilter, BitmapTexture, BitmapWrap, TextureMapping};

    /// A plane z = 0 hit at uv (0.3, 0.6), with u along x scaled by 2 (dp/du = 2 x).
    fn plane() -> SurfaceInteraction {
        let mut si = hit();
        si.dp_du = 2.0 * Vec3::X;
        si.uv = Vec2::new(0.3, 0.6);
        si
    }

    /// A 16 x 16 bitmap whose luminance is `a x + b y` in texel units (x right, y down).
    fn ramp_bitmap(a: f32, b: f32) -> RgbTexture {
        let texels = (0..256)
            .map(|i| Rgb::splat(0.2 + a * (i % 16) as f32 + b * (i / 16) as f32))
            .collect();
        Texture::Bitmap(Arc::new(BitmapTexture {
            mapping: TextureMapping::default(),
            width: 16,
            height: 16,
            texels: Arc::new(texels),
            filter: BitmapFilter::Bilinear,
            wrap: BitmapWrap::Clamp,
        }))
    }

    fn bump(height: BumpHeight) -> MaterialDesc {
        MaterialDesc::BumpMap(BumpMapMaterial { material: 1, height })
    }

    #[test]
    fn a_constant_height_changes_nothing() {
        let inner = MaterialDesc::Diffuse(DiffuseMaterial {
            reflectance: Rgb::splat(0.5).into(),
        });
        let mut si = plane();
        si.ns = Vec3::new(0.1, 0.2, 0.9).normalize();
        si.dpdu = (Vec3::X - si.ns * si.ns.x).normalize();
        for height in [
            BumpHeight::Mitsuba {
                texture: Rgb::splat(0.7).into(),
                scale: 3.0,
            },
            BumpHeight::Mitsuba {
                texture: super::super::test_support::scaled(Rgb::splat(0.7), 1.0),
                scale: 3.0,
            },
            BumpHeight::Pbrt {
                displacement: 0.25.into(),
            },
            BumpHeight::Pbrt {
                displacement: super::super::test_support::scaled(0.25, 1.0),
            },
        ] {
            let mut s = si;
            let ctx = TextureContext::at_point(&s);
            assert_eq!(bump(height.clone()).apply_frame(&mut s, &ctx), Some(1));
            assert_eq!(s, si, "{height:?}");
            let (a, b) = (
                inner.bsdf(&si, &ctx).unwrap(),
                inner.bsdf(&s, &TextureContext::at_point(&s)).unwrap(),
            );
            let (wo, wi) = (
                Vec3::new(0.3, 0.1, 0.9).normalize(),
                Vec3::new(-0.5, 0.2, 0.6).normalize(),
            );
            assert_eq!(a.f(wo, wi), b.f(wo, wi));
            assert_eq!(a.pdf(wo, wi), b.pdf(wo, wi));
        }
    }

    #[test]
    fn a_linear_ramp_tilts_the_normal_by_the_analytic_angle() {
        // Mitsuba: luminance 0.01 per texel along x over 16 texels: dd/du = 0.16 scale.
        // With dp/du = 2 x the height rises by 0.08 scale per unit of x, so the normal
        // tilts by atan(0.08 scale) away from +x.
        let scale = 5.0;
        let m = bump(BumpHeight::Mitsuba {
            texture: ramp_bitmap(0.01, 0.0),
            scale,
        });
        let mut si = plane();
        let ctx = TextureContext::at_point(&si);
        let _ = m.apply_frame(&mut si, &ctx);
        let slope = 0.08 * scale;
        let expected = Vec3::new(-slope, 0.0, 1.0).normalize();
        assert!((si.ns - expected).length() < 1e-4, "{} vs {expected}", si.ns);
        assert!(si.dpdu.dot(si.ns).abs() < 1e-6 && si.dpdu.x > 0.9, "{}", si.dpdu);
        // Rows run down the image, so a rise down the rows is a fall along v (dp/dv = y):
        // 0.02 per texel, dd/dv = -0.32, the normal tilts towards +y.
        let m = bump(BumpHeight::Mitsuba {
            texture: ramp_bitmap(0.0, 0.02),
            scale: 1.0,
        });
        let mut si = plane();
        let ctx = TextureContext::at_point(&si);
        let _ = m.apply_frame(&mut si, &ctx);
        let expected = Vec3::new(0.0, 0.32, 1.0).normalize();
        assert!((si.ns - expected).length() < 1e-4, "{} vs {expected}", si.ns);
        // pbrt: displacement 0.3 u + 0.1 v (a ramp the finite differences take exactly).
        let ramp: FloatTexture = Texture::Bitmap(Arc::new(BitmapTexture {
            mapping: TextureMapping::default(),
            width: 2,
            height: 2,
            texels: Arc::new(vec![Rgb::splat(0.1), Rgb::splat(0.4), Rgb::splat(0.0), Rgb::splat(0.3)]),
            filter: BitmapFilter::Bilinear,
            wrap: BitmapWrap::Clamp,
        }));
        // (Texel centres at 1/4 and 3/4: between them d = 0.3 * 2 (u - 1/4) + ....)
        let m = bump(BumpHeight::Pbrt { displacement: ramp });
        let mut si = plane();
        let ctx = TextureContext {
            dudx: 0.01,
            dudy: 0.01,
            dvdx: 0.002,
            dvdy: 0.0,
            ..TextureContext::at_point(&si)
        };
        let g = match &m {
            MaterialDesc::BumpMap(b) => b.gradient(&si, &ctx),
            _ => unreachable!(),
        };
        assert!((g - Vec2::new(0.6, 0.2)).length() < 1e-3, "{g}");
        let _ = m.apply_frame(&mut si, &ctx);
        // dp/du' = (2, 0, 0.6), dp/dv' = (0, 1, 0.2).
        let expected = Vec3::new(2.0, 0.0, 0.6).cross(Vec3::new(0.0, 1.0, 0.2)).normalize();
        assert!((si.ns - expected).length() < 1e-3, "{} vs {expected}", si.ns);
    }

    /// The bump-mapped BSDF (a diffuse in the tilted frame, guarded by the geometric
    /// normal): its sampling passes the chi-square test against its pdf, sampled values
    /// equal evaluated ones, f is reciprocal, and the albedo estimated by sampling equals
    /// the one by uniform directions (within 5 standard errors) and stays below one.
    #[test]
    fn the_bump_mapped_bsdf_is_consistent_and_conserves_energy() {
        let inner = MaterialDesc::Diffuse(DiffuseMaterial {
            reflectance: Rgb::splat(0.9).into(),
        });
        let m = bump(BumpHeight::Mitsuba {
            texture: ramp_bitmap(0.01, -0.02),
            scale: 4.0,
        });
        let mut si = plane();
        let ctx = TextureContext::at_point(&si);
        let _ = m.apply_frame(&mut si, &ctx);
        assert!(si.ns.dot(Vec3::Z) < 0.9, "a real tilt: {}", si.ns);
        let bsdf: Bsdf = inner.bsdf(&si, &TextureContext::at_point(&si)).unwrap();
        let mut rng = Pcg32::new(11, 3);
        let dirs = [
            Vec3::Z,
            Vec3::new(0.5, 0.3, 0.8).normalize(),
            Vec3::new(-0.8, 0.1, 0.3).normalize(),
        ];
        for (i, &wo) in dirs.iter().enumerate() {
            let test = Chi2Test::new(200_000, suite_seed() + i as u64).with_test_count(dirs.len() as u32);
            let report = test.sphere(
                SphereGrid::default(),
                |u, rng: &mut Pcg32| {
                    bsdf.sample_f(wo, rng.next_f32(), u)
                        .filter(|s| s.pdf > 0.0)
                        .map(|s| s.wi)
                },
                |wi| bsdf.pdf(wo, wi),
            );
            assert!(report.passes(SIGNIFICANCE), "wo = {wo}: {report}");
            let n = 100_000;
            let (mut a, mut a2, mut b, mut b2) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
            for _ in 0..n {
                let u = Vec2::new(rng.next_f32(), rng.next_f32());
                if let Some(s) = bsdf.sample_f(wo, rng.next_f32(), u) {
                    let f = bsdf.f(wo, s.wi);
                    assert!((f - s.f).max_component().abs() < 1e-4, "{f:?} vs {:?}", s.f);
                    assert!((bsdf.pdf(wo, s.wi) - s.pdf).abs() < 1e-4 * (1.0 + s.pdf));
                    assert!((bsdf.f(s.wi, wo) - f).max_component().abs() < 1e-5, "reciprocity");
                    let v = f64::from((s.f * (s.wi.dot(si.ns).abs() / s.pdf)).average());
                    a += v;
                    a2 += v * v;
                }
                let wi = sample_uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()));
                let v = f64::from((bsdf.f(wo, wi) * (wi.dot(si.ns).abs() / uniform_sphere_pdf())).average());
                b += v;
                b2 += v * v;
            }
            let n = f64::from(n);
            let (a, b) = (a / n, b / n);
            let se = ((a2 / n - a * a + b2 / n - b * b) / n).sqrt();
            assert!(a <= 1.0 + 1e-3, "albedo {a}");
            assert!((a - b).abs() < 5.0 * se + 1e-3, "wo {wo}: {a} vs {b} (se {se})");
        }
    }
}
