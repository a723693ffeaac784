//! Layer 3: materials turn a surface interaction into a BSDF. A [`Material`] is its
//! description ([`MaterialDesc`]), whose parameters are textures ([`crate::texture`])
//! evaluated at each hit's [`TextureContext`]; [`Material::from_desc`] copies it and
//! [`Material::bsdf`] resolves them (alphas from roughness, conductor indices from a
//! reflectance) per hit. Constant textures give the same BSDF at every hit.
//!
//! The coated materials build their stochastic [`LayeredBxdf`] per hit from their
//! evaluated textures (it is a small `Copy` value).
//!
//! Two materials are not surfaces themselves: [`Material::Mix`] names two others and
//! picks one per shading point ([`Material::mix_choice`]; the scene follows the choice,
//! see `Scene::bsdf`), and [`Material::Interface`] has no BSDF at all, so rays pass
//! through it.

use crate::bsdf::{
    roughness_to_alpha, Bsdf, Bxdf, ConductorBxdf, DielectricBxdf, DiffuseBxdf, DiffuseTransmissionBxdf, LayeredBxdf,
    MetallicRoughnessBxdf, Microfacet, PlasticBxdf, ThinDielectricBxdf,
};
use crate::color::Rgb;
use crate::math::Vec3;
use crate::sampling::hash_u64s;
use crate::scene::MaterialDesc;
use crate::shape::SurfaceInteraction;
use crate::texture::{RgbTexture, TextureContext};

/// A material: its description, whose parameters are textures that [`Material::bsdf`]
/// evaluates per hit, so building one is a copy (see [`MaterialDesc`] for the variants).
pub type Material = MaterialDesc;

/// The largest `|g|` a slab keeps: pbrt clamps `g` to [-1, 1], but the Henyey-Greenstein
/// formula is 0/0 at the ends (a Dirac delta), so we stop just short of them.
const MAX_ABS_G: f32 = 0.999;

/// The conductor index `(eta, k)` whose normal-incidence reflectance is `r` (pbrt-v4,
/// with `eta = 1`: `((eta-1)^2 + k^2) / ((eta+1)^2 + k^2) = r` gives `k = 2 sqrt(r) /
/// sqrt(1 - r)`), `r` clamped to [0, 0.9999].
fn index_from_reflectance(r: Rgb) -> (Rgb, Rgb) {
    let r = r.map(|v| v.clamp(0.0, 0.9999));
    (Rgb::WHITE, r.map(|v| 2.0 * v.sqrt() / (1.0 - v).max(0.0).sqrt()))
}

/// Microfacet alpha from a user roughness, remapped as pbrt does when asked.
fn alpha(roughness: f32, remap: bool) -> f32 {
    if remap {
        roughness_to_alpha(roughness)
    } else {
        roughness.max(0.0)
    }
}

impl Material {
    /// The material a (validated) description asks for: the description itself.
    #[must_use]
    pub fn from_desc(desc: &MaterialDesc) -> Self {
        desc.clone()
    }

    /// For [`Self::Mix`], the index of the material used at `si` (pbrt-v4
    /// `MixMaterial::ChooseMaterial`), with `amount` evaluated at `ctx`: the first when
    /// `amount <= 0`, the second when `amount >= 1`, else the second when a hash of the
    /// point, `wo` and the two indices, mapped to [0, 1), is below `amount`. `None` for
    /// every other material.
    #[must_use]
    pub fn mix_choice(&self, si: &SurfaceInteraction, ctx: &TextureContext) -> Option<u32> {
        let Self::Mix { materials, amount } = self else {
            return None;
        };
        let (materials, amount) = (*materials, amount.evaluate(ctx));
        if amount <= 0.0 {
            return Some(materials[0]);
        }
        if amount >= 1.0 {
            return Some(materials[1]);
        }
        let p = si.p();
        let bits = |v: f32| u64::from(v.to_bits());
        let h = hash_u64s(&[
            bits(p.x),
            bits(p.y),
            bits(p.z),
            bits(si.wo.x),
            bits(si.wo.y),
            bits(si.wo.z),
            u64::from(materials[0]),
            u64::from(materials[1]),
        ]);
        // The top 24 bits: a uniform number in [0, 1) exactly representable as f32.
        let u = (h >> 40) as f32 / 16_777_216.0;
        Some(if amount < u { materials[0] } else { materials[1] })
    }

    /// For [`Self::NormalMap`], move the shading frame of `si` to the map's normal (see
    /// [`MaterialDesc::NormalMap`]) and return the inner material; `None` for every other
    /// material.
    #[must_use]
    pub fn apply_normal_map(&self, si: &mut SurfaceInteraction) -> Option<u32> {
        let Self::NormalMap { material, normal_map } = self else {
            return None;
        };
        let c = normal_map.evaluate(&TextureContext::at_point(si));
        let frame = crate::math::Frame::from_zx(si.ns, si.dpdu);
        let n_local = Vec3::new(2.0 * c.r - 1.0, 2.0 * c.g - 1.0, 2.0 * c.b - 1.0).try_normalize();
        if let Some(n_local) = n_local {
            // The old tangent projected onto the new tangent plane.
            let s_local = (Vec3::X - n_local * n_local.x)
                .try_normalize()
                .unwrap_or_else(|| crate::math::Frame::from_z(n_local).x);
            let ns = frame.from_local(n_local).normalize();
            let dpdu = frame.from_local(s_local).normalize();
            // Keep the shading normal on the side of the geometric one (a map pointing
            // below the surface leaves the frame unchanged).
            if ns.dot(si.n()) * si.ns.dot(si.n()) > 0.0 {
                si.ns = ns;
                si.dpdu = dpdu;
            }
        }
        Some(*material)
    }

    /// True when some parameter is a non-constant texture, so [`Self::bsdf`] needs a
    /// texture context with a footprint.
    #[must_use]
    pub fn is_textured(&self) -> bool {
        match self {
            Self::Diffuse { reflectance } => !reflectance.is_constant(),
            Self::Conductor {
                eta,
                k,
                reflectance,
                u_roughness,
                v_roughness,
                ..
            } => {
                !(eta.is_constant()
                    && k.is_constant()
                    && reflectance.as_ref().is_none_or(RgbTexture::is_constant)
                    && u_roughness.is_constant()
                    && v_roughness.is_constant())
            }
            Self::Dielectric {
                u_roughness,
                v_roughness,
                ..
            } => !(u_roughness.is_constant() && v_roughness.is_constant()),
            Self::ThinDielectric { .. } => false,
            Self::DiffuseTransmission {
                reflectance,
                transmittance,
                ..
            } => !(reflectance.is_constant() && transmittance.is_constant()),
            Self::CoatedDiffuse {
                reflectance,
                u_roughness,
                v_roughness,
                thickness,
                albedo,
                g,
                ..
            } => {
                !(reflectance.is_constant()
                    && u_roughness.is_constant()
                    && v_roughness.is_constant()
                    && thickness.is_constant()
                    && albedo.is_constant()
                    && g.is_constant())
            }
            Self::CoatedConductor {
                interface_u_roughness,
                interface_v_roughness,
                conductor_eta,
                conductor_k,
                reflectance,
                conductor_u_roughness,
                conductor_v_roughness,
                thickness,
                albedo,
                g,
                ..
            } => {
                !(interface_u_roughness.is_constant()
                    && interface_v_roughness.is_constant()
                    && conductor_eta.is_constant()
                    && conductor_k.is_constant()
                    && reflectance.as_ref().is_none_or(RgbTexture::is_constant)
                    && conductor_u_roughness.is_constant()
                    && conductor_v_roughness.is_constant()
                    && thickness.is_constant()
                    && albedo.is_constant()
                    && g.is_constant())
            }
            Self::MetallicRoughness {
                base_color,
                metallic,
                roughness,
            } => !(base_color.is_constant() && metallic.is_constant() && roughness.is_constant()),
            Self::Plastic {
                diffuse_reflectance,
                specular_reflectance,
                ..
            } => !(diffuse_reflectance.is_constant() && specular_reflectance.is_constant()),
            Self::Mix { amount, .. } => !amount.is_constant(),
            // (Resolved to the inner material before a BSDF is built.)
            Self::NormalMap { .. } => false,
            Self::Interface => false,
        }
    }

    /// The BSDF at a hit, in the shading frame of `si.ns` with `si.dpdu` as first tangent,
    /// guarded by the geometric normal `si.n()`, with the textures evaluated at `ctx`; `None` for [`Self::Interface`] and for
    /// [`Self::Mix`] (resolve it with [`Self::mix_choice`] first).
    #[must_use]
    pub fn bsdf(&self, si: &SurfaceInteraction, ctx: &TextureContext) -> Option<Bsdf> {
        let bxdf = match self {
            Self::Diffuse { reflectance } => Bxdf::Diffuse(DiffuseBxdf {
                r: reflectance.evaluate(ctx).map(|v| v.clamp(0.0, 1.0)),
            }),
            Self::Conductor {
                eta,
                k,
                reflectance,
                u_roughness,
                v_roughness,
                remap_roughness,
                microfacet,
            } => {
                let (eta, k) = match reflectance {
                    Some(r) => index_from_reflectance(r.evaluate(ctx)),
                    None => (eta.evaluate(ctx), k.evaluate(ctx)),
                };
                let distrib = microfacet.distribution(
                    alpha(u_roughness.evaluate(ctx), *remap_roughness),
                    alpha(v_roughness.evaluate(ctx), *remap_roughness),
                );
                Bxdf::Conductor(ConductorBxdf { distrib, eta, k })
            }
            Self::Dielectric {
                eta,
                u_roughness,
                v_roughness,
                remap_roughness,
                microfacet,
            } => Bxdf::Dielectric(DielectricBxdf {
                eta: *eta,
                distrib: microfacet.distribution(
                    alpha(u_roughness.evaluate(ctx), *remap_roughness),
                    alpha(v_roughness.evaluate(ctx), *remap_roughness),
                ),
            }),
            Self::ThinDielectric { eta } => Bxdf::ThinDielectric(ThinDielectricBxdf { eta: *eta }),
            Self::DiffuseTransmission {
                reflectance,
                transmittance,
                scale,
            } => Bxdf::DiffuseTransmission(DiffuseTransmissionBxdf {
                r: (reflectance.evaluate(ctx) * *scale).map(|v| v.clamp(0.0, 1.0)),
                t: (transmittance.evaluate(ctx) * *scale).map(|v| v.clamp(0.0, 1.0)),
            }),
            Self::CoatedDiffuse {
                reflectance,
                u_roughness,
                v_roughness,
                remap_roughness,
                thickness,
                eta,
                albedo,
                g,
                max_depth,
                n_samples,
            } => Bxdf::CoatedDiffuse(LayeredBxdf {
                top: coat(
                    *eta,
                    u_roughness.evaluate(ctx),
                    v_roughness.evaluate(ctx),
                    *remap_roughness,
                ),
                bottom: DiffuseBxdf {
                    r: reflectance.evaluate(ctx).map(|v| v.clamp(0.0, 1.0)),
                },
                thickness: thickness.evaluate(ctx).max(f32::MIN_POSITIVE),
                albedo: albedo.evaluate(ctx).map(|v| v.clamp(0.0, 1.0)),
                g: g.evaluate(ctx).clamp(-MAX_ABS_G, MAX_ABS_G),
                max_depth: *max_depth,
                n_samples: (*n_samples).max(1),
            }),
            Self::CoatedConductor {
                interface_u_roughness,
                interface_v_roughness,
                interface_eta,
                conductor_eta,
                conductor_k,
                reflectance,
                conductor_u_roughness,
                conductor_v_roughness,
                remap_roughness,
                thickness,
                albedo,
                g,
                max_depth,
                n_samples,
            } => {
                let top = coat(
                    *interface_eta,
                    interface_u_roughness.evaluate(ctx),
                    interface_v_roughness.evaluate(ctx),
                    *remap_roughness,
                );
                let (eta, k) = match reflectance {
                    Some(r) => index_from_reflectance(r.evaluate(ctx)),
                    None => (conductor_eta.evaluate(ctx), conductor_k.evaluate(ctx)),
                };
                Bxdf::CoatedConductor(LayeredBxdf {
                    top,
                    // pbrt-v4: the base's index is relative to the coat above it.
                    bottom: ConductorBxdf {
                        distrib: Microfacet::trowbridge_reitz(
                            alpha(conductor_u_roughness.evaluate(ctx), *remap_roughness),
                            alpha(conductor_v_roughness.evaluate(ctx), *remap_roughness),
                        ),
                        eta: eta / top.eta,
                        k: k / top.eta,
                    },
                    thickness: thickness.evaluate(ctx).max(f32::MIN_POSITIVE),
                    albedo: albedo.evaluate(ctx).map(|v| v.clamp(0.0, 1.0)),
                    g: g.evaluate(ctx).clamp(-MAX_ABS_G, MAX_ABS_G),
                    max_depth: *max_depth,
                    n_samples: (*n_samples).max(1),
                })
            }
            Self::MetallicRoughness {
                base_color,
                metallic,
                roughness,
            } => Bxdf::MetallicRoughness(MetallicRoughnessBxdf::new(
                base_color.evaluate(ctx),
                metallic.evaluate(ctx),
                roughness.evaluate(ctx),
            )),
            Self::Plastic {
                diffuse_reflectance,
                specular_reflectance,
                nonlinear,
                specular_sampling_weight,
                coat,
            } => Bxdf::Plastic(PlasticBxdf {
                coat: *coat,
                diffuse: diffuse_reflectance.evaluate(ctx).map(|v| v.clamp(0.0, 1.0)),
                specular: specular_reflectance.evaluate(ctx).map(|v| v.max(0.0)),
                nonlinear: *nonlinear,
                specular_sampling_weight: specular_sampling_weight.clamp(0.0, 1.0),
            }),
            Self::Mix { .. } | Self::NormalMap { .. } | Self::Interface => return None,
        };
        Some(Bsdf::new(si.ns, si.dpdu, si.n(), bxdf))
    }
}

/// The dielectric coat of a layered material; an index of 0 means 1, as in pbrt-v4.
fn coat(eta: f32, u_roughness: f32, v_roughness: f32, remap: bool) -> DielectricBxdf {
    DielectricBxdf {
        eta: if eta == 0.0 { 1.0 } else { eta },
        distrib: Microfacet::trowbridge_reitz(alpha(u_roughness, remap), alpha(v_roughness, remap)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::fresnel::fr_complex;
    use crate::math::{Vec2, Vec3};
    use crate::shape::Interaction;

    fn hit() -> SurfaceInteraction {
        SurfaceInteraction {
            intr: Interaction {
                p: Vec3::ZERO,
                p_error: Vec3::ZERO,
                n: Vec3::Z,
            },
            ns: Vec3::Z,
            dpdu: Vec3::X,
            dp_du: Vec3::X,
            dp_dv: Vec3::Y,
            uv: Vec2::splat(0.5),
            wo: Vec3::Z,
            t: 1.0,
        }
    }

    fn bxdf(m: &Material) -> Bxdf {
        let si = hit();
        *m.bsdf(&si, &TextureContext::at_point(&si)).unwrap().bxdf()
    }

    #[test]
    fn conductor_reflectance_becomes_an_index_with_that_normal_reflectance() {
        let r = Rgb::new(0.9, 0.5, 0.0);
        let m = Material::from_desc(&MaterialDesc::Conductor {
            eta: Rgb::splat(0.2).into(),
            k: Rgb::splat(3.0).into(),
            reflectance: Some(r.into()),
            u_roughness: 0.0.into(),
            v_roughness: 0.0.into(),
            remap_roughness: true,
            microfacet: Default::default(),
        });
        let Bxdf::Conductor(ConductorBxdf { eta, k, .. }) = bxdf(&m) else {
            panic!("{m:?}")
        };
        assert_eq!(eta, Rgb::WHITE);
        let f0 = fr_complex(1.0, eta, k);
        assert!(
            (f0 - r).max_component().abs() < 1e-5 && (r - f0).max_component().abs() < 1e-5,
            "{f0:?}"
        );
    }

    #[test]
    fn roughness_is_remapped_only_when_asked() {
        for (remap, expected) in [(true, 0.5), (false, 0.25)] {
            let m = Material::from_desc(&MaterialDesc::Dielectric {
                eta: 1.5,
                u_roughness: 0.25.into(),
                v_roughness: 0.0.into(),
                remap_roughness: remap,
                microfacet: Default::default(),
            });
            let Bxdf::Dielectric(DielectricBxdf { distrib, .. }) = bxdf(&m) else {
                panic!()
            };
            assert_eq!((distrib.alpha_x, distrib.alpha_y), (expected, 0.0));
        }
    }

    /// A texture that is not a constant (so `is_textured` sees it) evaluating to `v * s`.
    fn scaled<T: crate::texture::TextureValue>(v: T, s: f32) -> crate::texture::Texture<T> {
        crate::texture::Texture::Scale(std::sync::Arc::new(crate::texture::ScaleTexture {
            tex: v.into(),
            scale: s.into(),
        }))
    }

    #[test]
    fn coated_parameters_are_textures_evaluated_per_hit() {
        let m = Material::from_desc(&MaterialDesc::CoatedDiffuse {
            reflectance: scaled(Rgb::new(0.2, 0.4, 0.6), 2.0),
            u_roughness: scaled(0.1, 2.0),
            v_roughness: 0.3.into(),
            remap_roughness: false,
            thickness: scaled(0.25, 2.0),
            eta: 1.5,
            albedo: scaled(Rgb::splat(0.25), 2.0),
            g: scaled(0.3, -1.0),
            max_depth: 7,
            n_samples: 0,
        });
        assert!(m.is_textured());
        let Bxdf::CoatedDiffuse(b) = bxdf(&m) else { panic!() };
        assert_eq!(b.bottom.r, Rgb::new(0.4, 0.8, 1.0));
        assert_eq!(
            (b.top.eta, b.top.distrib.alpha_x, b.top.distrib.alpha_y),
            (1.5, 0.2, 0.3)
        );
        assert_eq!((b.thickness, b.albedo, b.g), (0.5, Rgb::splat(0.5), -0.3));
        assert_eq!((b.max_depth, b.n_samples), (7, 1));

        let m = Material::from_desc(&MaterialDesc::CoatedConductor {
            interface_u_roughness: scaled(0.1, 2.0),
            interface_v_roughness: 0.1.into(),
            interface_eta: 2.0,
            conductor_eta: scaled(Rgb::splat(0.5), 2.0),
            conductor_k: scaled(Rgb::splat(2.0), 2.0),
            reflectance: None,
            conductor_u_roughness: scaled(0.2, 2.0),
            conductor_v_roughness: 0.2.into(),
            remap_roughness: false,
            thickness: scaled(0.1, 3.0),
            albedo: Rgb::BLACK.into(),
            g: 0.0.into(),
            max_depth: 10,
            n_samples: 1,
        });
        assert!(m.is_textured());
        let Bxdf::CoatedConductor(b) = bxdf(&m) else { panic!() };
        assert_eq!((b.top.eta, b.top.distrib.alpha_x), (2.0, 0.2));
        // The base's index relative to the coat.
        assert_eq!((b.bottom.eta, b.bottom.k), (Rgb::splat(0.5), Rgb::splat(2.0)));
        assert_eq!((b.bottom.distrib.alpha_x, b.bottom.distrib.alpha_y), (0.4, 0.2));
        assert!((b.thickness - 0.3).abs() < 1e-6);

        // Constants everywhere: no footprint needed.
        let m = Material::from_desc(&MaterialDesc::CoatedDiffuse {
            reflectance: Rgb::splat(0.5).into(),
            u_roughness: 0.0.into(),
            v_roughness: 0.0.into(),
            remap_roughness: true,
            thickness: 0.01.into(),
            eta: 1.5,
            albedo: Rgb::BLACK.into(),
            g: 0.0.into(),
            max_depth: 10,
            n_samples: 1,
        });
        assert!(!m.is_textured());
    }

    #[test]
    fn mix_amount_is_a_texture_evaluated_per_hit() {
        let si = hit();
        let ctx = TextureContext::at_point(&si);
        for (amount, expected) in [(scaled(1.0, 0.0), 3), (scaled(0.5, 2.0), 4)] {
            let m = Material::from_desc(&MaterialDesc::Mix {
                materials: [3, 4],
                amount,
            });
            assert!(m.is_textured());
            assert_eq!(m.mix_choice(&si, &ctx), Some(expected));
        }
    }

    #[test]
    fn normal_maps_move_the_shading_frame_in_its_own_coordinates() {
        let inner = Material::from_desc(&MaterialDesc::Diffuse {
            reflectance: Rgb::splat(0.5).into(),
        });
        assert_eq!(inner.apply_normal_map(&mut hit()), None);
        // A tilted surface, so that local and world coordinates differ.
        let mut si = hit();
        si.ns = Vec3::new(0.0, 0.6, 0.8);
        si.intr.n = si.ns;
        si.dpdu = Vec3::X;
        // The identity map leaves the frame as it is.
        let identity = Material::from_desc(&MaterialDesc::NormalMap {
            material: 3,
            normal_map: Rgb::new(0.5, 0.5, 1.0).into(),
        });
        let mut s = si;
        assert_eq!(identity.apply_normal_map(&mut s), Some(3));
        assert!((s.ns - si.ns).length() < 1e-6 && (s.dpdu - si.dpdu).length() < 1e-6);
        // Tilt 45 degrees towards the tangent: local normal (1, 0, 1) / sqrt 2.
        let c = 0.5 + 0.5 * std::f32::consts::FRAC_1_SQRT_2;
        let tilted = Material::from_desc(&MaterialDesc::NormalMap {
            material: 3,
            normal_map: Rgb::new(c, 0.5, c).into(),
        });
        let mut s = si;
        assert_eq!(tilted.apply_normal_map(&mut s), Some(3));
        let expected = (Vec3::X + si.ns).normalize();
        assert!((s.ns - expected).length() < 1e-3, "{}", s.ns);
        assert!(s.dpdu.dot(s.ns).abs() < 1e-5 && s.dpdu.dot(Vec3::X) > 0.5, "{}", s.dpdu);
        // A map pointing below the geometric surface is ignored.
        let below = Material::from_desc(&MaterialDesc::NormalMap {
            material: 3,
            normal_map: Rgb::new(0.5, 0.5, 0.0).into(),
        });
        let mut s = si;
        assert_eq!(below.apply_normal_map(&mut s), Some(3));
        assert_eq!(s.ns, si.ns);
    }

    #[test]
    fn diffuse_transmission_scales_then_clamps() {
        let m = Material::from_desc(&MaterialDesc::DiffuseTransmission {
            reflectance: Rgb::splat(0.25).into(),
            transmittance: Rgb::new(0.25, 0.5, 0.75).into(),
            scale: 2.0,
        });
        let Bxdf::DiffuseTransmission(DiffuseTransmissionBxdf { r, t }) = bxdf(&m) else {
            panic!()
        };
        assert_eq!((r, t), (Rgb::splat(0.5), Rgb::new(0.5, 1.0, 1.0)));
    }
}
