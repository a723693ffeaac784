//! BSDF plugins mapped onto mcrender's materials:
//!
//! * `diffuse` (`reflectance`, default 0.5) -> Lambertian;
//! * `twosided` -> its nested BSDF (mcrender's BSDFs already act on both sides);
//! * `dielectric`, `thindielectric` (`int_ior`, `ext_ior`: numbers or Mitsuba's named
//!   IORs; defaults bk7 and air);
//! * `roughdielectric` and `roughconductor` with `distribution="ggx"` (`alpha`, or
//!   `alpha_u`/`alpha_v`; default 0.1) -> the Trowbridge-Reitz (GGX) microfacet lobes;
//! * `conductor` (`material` Ag/Al/Au/Cu or `none` (a perfect mirror, the default), or
//!   `eta`/`k`);
//! * `mask` (`opacity`, default 0.5) -> the shape's alpha cut-out around the nested BSDF.
//!
//! Not rendered (errors naming the plugin): the Beckmann distribution, `plastic`,
//! `roughplastic`, `principled`, `principledthin`, `bumpmap`, `normalmap`, `blendbsdf`,
//! `pplastic`, `hair`, `measured`, `polarizer`, `retarder`, `circular`, `null`.
//!
//! Differences kept: Mitsuba's `diffuse` is black seen from behind (mcrender's reflects on
//! both sides: the same wherever only front faces are seen); Mitsuba's GGX lobes use the
//! separable Smith masking-shadowing term `G1(wo) G1(wi)`, mcrender's (pbrt-v4) the
//! height-correlated one, which is slightly brighter at grazing angles.

use mcrender_core::color::Rgb;
use mcrender_core::scene::MaterialDesc;

use super::builder::{Builder, Named, Surface};
use super::props::Props;
use super::spectra::{conductor_spectra, named_ior};
use super::xml::Element;
use crate::error::SceneError;

impl Builder {
    /// A `<bsdf>` element as a surface (material plus mask).
    pub fn bsdf(&mut self, el: &Element) -> Result<Surface, SceneError> {
        let kind = el.required("type")?;
        let mut p = Props::new(el);
        let surface = match kind {
            "diffuse" => {
                let reflectance = self.rgb_param(&mut p, "reflectance", Rgb::splat(0.5), false)?;
                self.plain(MaterialDesc::Diffuse { reflectance })
            }
            "twosided" | "mask" => {
                let inner: Vec<_> = p.nested("bsdf");
                let mut surfaces = Vec::new();
                for b in inner {
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
                let inner = match surfaces.as_slice() {
                    [s] => s.clone(),
                    [] if kind == "mask" => {
                        return Err(SceneError::syntax(&el.loc, "a mask needs a nested bsdf"));
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
                if kind == "mask" {
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
                    self.plain(MaterialDesc::ThinDielectric { eta })
                } else {
                    let (u, v) = self.roughness(&mut p, kind == "roughdielectric")?;
                    self.plain(MaterialDesc::Dielectric {
                        eta,
                        u_roughness: u.into(),
                        v_roughness: v.into(),
                        remap_roughness: false,
                    })
                }
            }
            "conductor" | "roughconductor" => {
                no_tint(&mut p, "specular_reflectance")?;
                let (u, v) = self.roughness(&mut p, kind == "roughconductor")?;
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
                self.plain(MaterialDesc::Conductor {
                    eta,
                    k,
                    reflectance,
                    u_roughness: u.into(),
                    v_roughness: v.into(),
                    remap_roughness: false,
                })
            }
            "plastic" | "roughplastic" => {
                return Err(Self::unsupported(
                    el,
                    " yet (Mitsuba's plastic, a specular coat over a diffuse base with internal \
                     scattering, is a different model from pbrt's coateddiffuse)",
                ))
            }
            "principled" | "principledthin" | "bumpmap" | "normalmap" | "blendbsdf" | "pplastic" | "hair"
            | "measured" | "polarizer" | "retarder" | "circular" | "null" => return Err(Self::unsupported(el, "")),
            _ => return Err(Self::unsupported(el, " (unknown BSDF plugin)")),
        };
        self.name(el, Named::Bsdf(surface.clone()));
        self.finish(&p);
        Ok(surface)
    }

    /// An unmasked surface of a new material.
    fn plain(&mut self, m: MaterialDesc) -> Surface {
        Surface {
            material: self.add_material(m),
            alpha: None,
        }
    }

    /// Microfacet `(alpha_u, alpha_v)` of a rough plugin (GGX only), or `(0, 0)`.
    fn roughness(&mut self, p: &mut Props, rough: bool) -> Result<(f32, f32), SceneError> {
        if !rough {
            return Ok((0.0, 0.0));
        }
        let dist = p.string("distribution")?;
        match &dist {
            Some((d, _)) if d == "ggx" => {}
            Some((d, l)) if d == "beckmann" => {
                return Err(SceneError::unsupported(
                    l,
                    "the Beckmann microfacet distribution (use ggx)",
                ))
            }
            None => {
                return Err(SceneError::unsupported(
                    &p.el.loc,
                    format!(
                        "{} with Mitsuba's default Beckmann distribution (give distribution=\"ggx\")",
                        p.el.describe()
                    ),
                ))
            }
            Some((d, l)) => {
                return Err(SceneError::syntax(
                    l,
                    format!("unknown distribution \"{d}\" (expected ggx or beckmann)"),
                ))
            }
        }
        let _ = p.bool("sample_visible", true)?;
        if p.has("alpha_u") || p.has("alpha_v") {
            Ok((p.float("alpha_u", 0.1)?, p.float("alpha_v", 0.1)?))
        } else {
            let a = p.float("alpha", 0.1)?;
            Ok((a, a))
        }
    }
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
