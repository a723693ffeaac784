//! BSDF plugins mapped onto mcrender's materials:
//!
//! * `diffuse` (`reflectance`, default 0.5) -> Lambertian;
//! * `twosided` -> its nested BSDF (mcrender's BSDFs already act on both sides);
//! * `dielectric`, `thindielectric` (`int_ior`, `ext_ior`: numbers or Mitsuba's named
//!   IORs; defaults bk7 and air);
//! * `roughdielectric` and `roughconductor` (`distribution` `beckmann`, Mitsuba's default,
//!   or `ggx`; `alpha`, or `alpha_u`/`alpha_v`; default 0.1) -> the microfacet lobes with
//!   Mitsuba's separable masking-shadowing `G1(wo) G1(wi)` (for Beckmann with Mitsuba's
//!   rational `G1`);
//! * `plastic` and `roughplastic` (`diffuse_reflectance` 0.5, `specular_reflectance` 1,
//!   `nonlinear` false, `int_ior` polypropylene (1.49), `ext_ior` air; `roughplastic` also
//!   `distribution` and an isotropic `alpha`) -> Mitsuba's own plastic model
//!   (`bsdf::PlasticBxdf`), with Mitsuba's specular sampling weight (for a textured
//!   reflectance the texture's mean is taken as 0.5: it only steers sampling);
//! * `conductor` (`material` Ag/Al/Au/Cu or `none` (a perfect mirror, the default), or
//!   `eta`/`k`);
//! * `mask` (`opacity`, default 0.5) -> the shape's alpha cut-out around the nested BSDF.
//!
//! * `normalmap` (`normalmap`: a raw texture, e.g. `bitmap` with `raw` or `rawconstant`)
//!   -> the nested BSDF with Mitsuba's perturbed shading frame
//!   (`MaterialDesc::NormalMap`).
//!
//! * `bumpmap` (one nested texture of any name, `scale` default 1, one nested BSDF) -> the
//!   nested BSDF with the frame tilted by `scale` times the gradient of the texture's
//!   luminance, as Mitsuba (`MaterialDesc::BumpMap`, `BumpHeight::Mitsuba`).
//!
//! * `blendbsdf` (`weight`, a float or texture; two nested BSDFs): Mitsuba evaluates
//!   `(1 - w) f0 + w f1` and samples one lobe by weight. Two `diffuse` BSDFs are exactly a
//!   diffuse of reflectance `(1 - w) r0 + w r1` (both lobes sample the same cosine), which
//!   is what they become; other pairs become mcrender's `mix` material (one of the two per
//!   shading point, chosen with probability `w`: the same expectation, with more noise
//!   than Mitsuba's), with a warning.
//!
//! Not rendered (errors naming the plugin): `principled`, `principledthin`,
//! `pplastic`, `hair`, `measured`, `polarizer`, `retarder`, `circular`, `null`.
//!
//! Differences kept: Mitsuba's `diffuse` is black seen from behind (mcrender's reflects on
//! both sides: the same wherever only front faces are seen), and so is its plastic.

use std::sync::Arc;

use mcrender_core::bsdf::{Masking, MicrofacetModel, MicrofacetStyle, PlasticCoat};
use mcrender_core::color::Rgb;
use mcrender_core::material::{
    BumpHeight, BumpMapMaterial, ConductorMaterial, DielectricMaterial, DiffuseMaterial, MixMaterial,
    NormalMapMaterial, PlasticMaterial, ThinDielectricMaterial,
};
use mcrender_core::scene::MaterialDesc;
use mcrender_core::texture::{MixTexture, RgbTexture, Texture};

use super::builder::{Builder, Named, Surface};
use super::props::Props;
use super::spectra::{conductor_spectra, named_ior};
use super::xml::Element;
use crate::error::SceneError;

impl Builder {
    /// A `<bsdf>` element as a surface (material plus mask). One built with placeholder
    /// mesh attributes is remembered in [`Builder::attribute_bsdfs`].
    pub fn bsdf(&mut self, el: &Element) -> Result<Surface, SceneError> {
        let outer = std::mem::replace(&mut self.deferred_attribute, false);
        let surface = self.bsdf_plugin(el)?;
        let deferred = self.deferred_attribute;
        self.deferred_attribute = outer || deferred;
        if deferred {
            self.attribute_bsdfs.insert(surface.material, el.clone());
        }
        Ok(surface)
    }

    /// [`Self::bsdf`] without the bookkeeping of mesh attributes.
    fn bsdf_plugin(&mut self, el: &Element) -> Result<Surface, SceneError> {
        let kind = el.required("type")?;
        let mut p = Props::new(el);
        let surface = match kind {
            "diffuse" => {
                let reflectance = self.rgb_param(&mut p, "reflectance", Rgb::splat(0.5), false)?;
                self.plain(MaterialDesc::Diffuse(DiffuseMaterial { reflectance }))
            }
            "twosided" | "mask" | "normalmap" => {
                let surfaces = self.nested_surfaces(&mut p)?;
                let inner = match surfaces.as_slice() {
                    [s] => s.clone(),
                    [] if kind != "twosided" => {
                        return Err(SceneError::syntax(&el.loc, format!("a {kind} needs a nested bsdf")));
                    }
                    _ => {
                        return Err(SceneError::unsupported(
                            &el.loc,
                            format!(
                                "{} with {} nested BSDFs (one is supported)",
                                el.describe(),
                                surfaces.len()
                            ),
                        ))
                    }
                };
                if kind == "normalmap" {
                    if !p.has("normalmap") {
                        return Err(SceneError::syntax(&el.loc, "a normalmap needs a \"normalmap\" texture"));
                    }
                    let normal_map = self.rgb_param(&mut p, "normalmap", Rgb::new(0.5, 0.5, 1.0), false)?;
                    Surface {
                        material: self.add_material(MaterialDesc::NormalMap(NormalMapMaterial {
                            material: inner.material,
                            normal_map,
                        })),
                        alpha: inner.alpha,
                    }
                } else if kind == "mask" {
                    if inner.alpha.is_some() {
                        return Err(SceneError::unsupported(&el.loc, "a mask inside a mask"));
                    }
                    let opacity = self.float_param(&mut p, "opacity", 0.5)?;
                    Surface {
                        material: inner.material,
                        alpha: Some(opacity),
                    }
                } else {
                    inner
                }
            }
            "dielectric" | "thindielectric" | "roughdielectric" => {
                let int_ior = ior(&mut p, "int_ior", 1.5046)?;
                let ext_ior = ior(&mut p, "ext_ior", 1.000_277)?;
                no_tint(&mut p, "specular_reflectance")?;
                no_tint(&mut p, "specular_transmittance")?;
                let eta = int_ior / ext_ior;
                if kind == "thindielectric" {
                    self.plain(MaterialDesc::ThinDielectric(ThinDielectricMaterial { eta }))
                } else {
                    let (u, v, microfacet) = self.roughness(&mut p, kind == "roughdielectric")?;
                    self.plain(MaterialDesc::Dielectric(DielectricMaterial {
                        eta,
                        u_roughness: u.into(),
                        v_roughness: v.into(),
                        remap_roughness: false,
                        microfacet,
                    }))
                }
            }
            "conductor" | "roughconductor" => {
                no_tint(&mut p, "specular_reflectance")?;
                let (u, v, microfacet) = self.roughness(&mut p, kind == "roughconductor")?;
                let material = p.string("material")?;
                let (eta, k, reflectance) = if p.has("eta") || p.has("k") {
                    let eta = self.rgb_param(&mut p, "eta", Rgb::splat(0.0), false)?;
                    let k = self.rgb_param(&mut p, "k", Rgb::splat(1.0), false)?;
                    (eta, k, None)
                } else {
                    match material {
                        None => (
                            Rgb::splat(1.0).into(),
                            Rgb::splat(0.0).into(),
                            Some(Rgb::splat(1.0).into()),
                        ),
                        Some((m, _)) if m == "none" => (
                            Rgb::splat(1.0).into(),
                            Rgb::splat(0.0).into(),
                            Some(Rgb::splat(1.0).into()),
                        ),
                        Some((m, l)) => match conductor_spectra(&m) {
                            Some((eta, k)) => (eta.into(), k.into(), None),
                            None => {
                                return Err(SceneError::unsupported(
                                    &l,
                                    format!("conductor material \"{m}\" (mcrender has Ag, Al, Au, Cu and none)"),
                                ))
                            }
                        },
                    }
                };
                let ext_eta = p.float("ext_eta", 1.0)?;
                let (eta, k) = if ext_eta == 1.0 {
                    (eta, k)
                } else {
                    return Err(SceneError::unsupported(
                        &el.loc,
                        "a conductor with ext_eta other than 1",
                    ));
                };
                self.plain(MaterialDesc::Conductor(ConductorMaterial {
                    eta,
                    k,
                    reflectance,
                    u_roughness: u.into(),
                    v_roughness: v.into(),
                    remap_roughness: false,
                    microfacet,
                }))
            }
            "plastic" | "roughplastic" => {
                let int_ior = ior(&mut p, "int_ior", 1.49)?;
                let ext_ior = ior(&mut p, "ext_ior", 1.000_277)?;
                if !(int_ior > 0.0 && ext_ior > 0.0) || (kind == "roughplastic" && int_ior == ext_ior) {
                    return Err(SceneError::invalid(
                        &el.loc,
                        format!(
                            "{}: the indices of refraction must be positive and differ",
                            el.describe()
                        ),
                    ));
                }
                let eta = int_ior / ext_ior;
                let diffuse_reflectance = self.rgb_param(&mut p, "diffuse_reflectance", Rgb::splat(0.5), false)?;
                let specular_reflectance = self.rgb_param(&mut p, "specular_reflectance", Rgb::splat(1.0), false)?;
                let nonlinear = p.bool("nonlinear", false)?;
                let coat = if kind == "roughplastic" {
                    let (u, v, style) = self.roughness(&mut p, true)?;
                    if u != v {
                        return Err(SceneError::unsupported(
                            &el.loc,
                            "an anisotropic roughplastic (Mitsuba refuses it too)",
                        ));
                    }
                    PlasticCoat::rough(style.distribution(u.max(1e-4), u.max(1e-4)), eta)
                } else {
                    PlasticCoat::smooth(eta)
                };
                let (d, s) = (texture_mean(&diffuse_reflectance), texture_mean(&specular_reflectance));
                let specular_sampling_weight = if d + s > 0.0 { s / (d + s) } else { 0.5 };
                self.plain(MaterialDesc::Plastic(PlasticMaterial {
                    diffuse_reflectance,
                    specular_reflectance,
                    nonlinear,
                    specular_sampling_weight,
                    coat,
                }))
            }
            "blendbsdf" => self.blendbsdf(el, &mut p)?,
            "bumpmap" => self.bumpmap(el, &mut p)?,
            "principled" | "principledthin" | "pplastic" | "hair" | "measured" | "polarizer" | "retarder"
            | "circular" => return Err(Self::unsupported(el, "")),
            // No surface: rays pass straight through (as pbrt's interface material).
            "null" => self.plain(MaterialDesc::Interface),
            _ => return Err(Self::unsupported(el, " (unknown BSDF plugin)")),
        };
        self.name(el, Named::Bsdf(surface.clone()));
        self.finish(&p);
        Ok(surface)
    }

    /// The BSDFs nested in `p` (inline `<bsdf>`s and `<ref>`s to named ones), in order.
    fn nested_surfaces(&mut self, p: &mut Props) -> Result<Vec<Surface>, SceneError> {
        let mut surfaces = Vec::new();
        for b in p.nested("bsdf") {
            surfaces.push(if b.tag == "bsdf" {
                self.bsdf(b)?
            } else {
                match self.lookup(b)? {
                    Named::Bsdf(s) => s.clone(),
                    _ => return Err(SceneError::invalid(&b.loc, "this <ref> must name a bsdf")),
                }
            });
        }
        p.use_refs();
        Ok(surfaces)
    }

    /// `bumpmap` (module docs): one nested BSDF and one texture of any name.
    fn bumpmap(&mut self, el: &Element, p: &mut Props) -> Result<Surface, SceneError> {
        let textures: Vec<&Element> = el.children.iter().filter(|c| c.tag == "texture").collect();
        let [tex] = textures.as_slice() else {
            return Err(SceneError::syntax(
                &el.loc,
                format!("a bumpmap needs one nested texture, found {}", textures.len()),
            ));
        };
        match tex.attr("name") {
            Some(name) => {
                p.get(name);
            }
            None => {
                p.nested("texture");
            }
        }
        let texture = self.rgb_texture(tex)?;
        let scale = p.float("scale", 1.0)?;
        let surfaces = self.nested_surfaces(p)?;
        let [inner] = surfaces.as_slice() else {
            return Err(SceneError::syntax(
                &el.loc,
                format!("a bumpmap needs one nested bsdf, found {}", surfaces.len()),
            ));
        };
        Ok(Surface {
            material: self.add_material(MaterialDesc::BumpMap(BumpMapMaterial {
                material: inner.material,
                height: BumpHeight::Mitsuba { texture, scale },
            })),
            alpha: inner.alpha.clone(),
        })
    }

    /// `blendbsdf` (module docs).
    fn blendbsdf(&mut self, el: &Element, p: &mut Props) -> Result<Surface, SceneError> {
        let surfaces = self.nested_surfaces(p)?;
        let [a, b] = surfaces.as_slice() else {
            return Err(SceneError::syntax(
                &el.loc,
                format!("a blendbsdf needs two nested BSDFs, found {}", surfaces.len()),
            ));
        };
        if a.alpha.is_some() || b.alpha.is_some() {
            return Err(SceneError::unsupported(&el.loc, "a blendbsdf of masked BSDFs"));
        }
        if !p.has("weight") {
            return Err(SceneError::syntax(&el.loc, "a blendbsdf needs a \"weight\""));
        }
        let weight = self.float_param(p, "weight", 0.5)?;
        let materials = &self.desc.materials;
        if let (MaterialDesc::Diffuse(d0), MaterialDesc::Diffuse(d1)) =
            (&materials[a.material as usize], &materials[b.material as usize])
        {
            let reflectance = Texture::Mix(Arc::new(MixTexture {
                tex1: d0.reflectance.clone(),
                tex2: d1.reflectance.clone(),
                amount: weight,
            }));
            return Ok(self.plain(MaterialDesc::Diffuse(DiffuseMaterial { reflectance })));
        }
        self.warnings.push(format!(
            "{}: warning: a blendbsdf of other than two diffuse BSDFs is rendered as a stochastic mix (same mean, more noise than Mitsuba's)",
            el.loc
        ));
        Ok(self.plain(MaterialDesc::Mix(MixMaterial {
            materials: [a.material, b.material],
            amount: weight,
        })))
    }

    /// An unmasked surface of a new material.
    fn plain(&mut self, m: MaterialDesc) -> Surface {
        Surface {
            material: self.add_material(m),
            alpha: None,
        }
    }

    /// Microfacet `(alpha_u, alpha_v)` and distribution of a rough plugin (Beckmann by
    /// default, as Mitsuba), or `(0, 0)`; Mitsuba's separable masking in both cases.
    fn roughness(&mut self, p: &mut Props, rough: bool) -> Result<(f32, f32, MicrofacetStyle), SceneError> {
        let mut style = MicrofacetStyle {
            model: MicrofacetModel::Beckmann,
            masking: Masking::Separable,
        };
        if !rough {
            return Ok((0.0, 0.0, style));
        }
        match p.string("distribution")? {
            None => {}
            Some((d, _)) if d == "beckmann" => {}
            Some((d, _)) if d == "ggx" => style.model = MicrofacetModel::TrowbridgeReitz,
            Some((d, l)) => {
                return Err(SceneError::syntax(
                    &l,
                    format!("unknown distribution \"{d}\" (expected ggx or beckmann)"),
                ))
            }
        }
        let _ = p.bool("sample_visible", true)?;
        let (u, v) = if p.has("alpha_u") || p.has("alpha_v") {
            (p.float("alpha_u", 0.1)?, p.float("alpha_v", 0.1)?)
        } else {
            let a = p.float("alpha", 0.1)?;
            (a, a)
        };
        if !(u.is_finite() && v.is_finite() && u >= 0.0 && v >= 0.0) {
            return Err(SceneError::invalid(
                &p.el.loc,
                format!("{}: alpha must be finite and >= 0, found ({u}, {v})", p.el.describe()),
            ));
        }
        Ok((u, v, style))
    }
}

/// Mitsuba's `Texture::mean` for a constant: the mean of its channels; 0.5 for other
/// textures (only the plastic's sampling uses it).
fn texture_mean(t: &RgbTexture) -> f32 {
    t.constant().map_or(0.5, |c| c.average().max(0.0))
}

/// An index of refraction: a number or one of Mitsuba's names.
fn ior(p: &mut Props, name: &str, default: f32) -> Result<f32, SceneError> {
    match p.get(name) {
        None => Ok(default),
        Some(e) if e.tag == "string" => {
            let v = e.required("value")?;
            named_ior(v).ok_or_else(|| SceneError::invalid(&e.loc, format!("unknown index of refraction \"{v}\"")))
        }
        Some(e) => super::props::scalar(e, &["float", "string"]),
    }
}

/// An error unless the colour parameter `name` is absent or 1.
fn no_tint(p: &mut Props, name: &str) -> Result<(), SceneError> {
    if let Some(e) = p.get(name) {
        if super::textures::constant_color(e, false).ok() != Some(Rgb::splat(1.0)) {
            return Err(SceneError::unsupported(&e.loc, format!("\"{name}\" other than 1")));
        }
    }
    Ok(())
}
