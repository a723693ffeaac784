//! Materials: `Material`, `MakeNamedMaterial`, `NamedMaterial`.
//!
//! Supported pbrt-v4 material types. Every parameter pbrt-v4 textures may also be given as
//! `"texture name" "tex"` naming a texture of the right type (see [`super::textures`]):
//! reflectances, conductor `eta`/`k`, roughnesses, and the coated materials' `thickness`,
//! `albedo`, `g` and their conductor's parameters, and `mix`'s `amount`. Dielectric `eta`
//! (and `interface.eta`) stays a constant, as in pbrt-v4. Range checks apply to constants.
//!
//! Every material but `mix` and `interface` also takes pbrt-v4's `displacement` (a float
//! texture: a bump map with pbrt's finite differences, `MaterialDesc::BumpMap` with
//! `BumpHeight::Pbrt`) and `string normalmap` (an image read as linear RGB, looked up
//! bilinearly with repeat at `(u, 1 - v)` as pbrt-v4's `NormalMap`:
//! `MaterialDesc::NormalMap`, whose frame is pbrt-v4's, the tangent space of the shading
//! `dp/du` and normal). With both, the displacement is used, as in pbrt-v4, and the
//! normal map is warned about.
//! - `diffuse`: `reflectance` (default 0.5).
//! - `conductor`: `eta` and `k` as `rgb` or as a named spectrum (`metal-Cu-eta`,
//!   `metal-Au-k`, ... for Ag, Al, Au, Cu; see [`crate::spectra`]), default copper; or
//!   `rgb reflectance` instead of both; `float roughness` or `uroughness`/`vroughness`
//!   (default 0); `bool remaproughness` (default true).
//! - `dielectric`: `float eta` or a named glass spectrum (`glass-BK7`, ...; its value at
//!   550 nm), default 1.5; roughness as for `conductor`.
//! - `thindielectric`: `eta` as for `dielectric`.
//! - `diffusetransmission`: `rgb reflectance`, `rgb transmittance` (default 0.25 each),
//!   `float scale` (default 1).
//! - `coateddiffuse`: `rgb reflectance` (default 0.5), roughness as for `conductor`,
//!   `eta` as for `dielectric`, and the slab: `float thickness` (default 0.01),
//!   `rgb albedo` (default 0), `float g` (default 0, in [-1, 1]), `integer maxdepth`
//!   (default 10), `integer nsamples` (default 1).
//! - `coatedconductor`: `interface.roughness`/`interface.uroughness`/`interface.vroughness`,
//!   `interface.eta` (default 1.5), `conductor.eta`/`conductor.k` (default copper) or
//!   `rgb reflectance`, `conductor.roughness`/`conductor.uroughness`/`conductor.vroughness`,
//!   `remaproughness`, and the slab as for `coateddiffuse`.
//! - `mix`: `string materials` (two named materials, resolved with the other names once
//!   the file is read, so they may be defined later; a mix that contains itself is an
//!   error), `float amount` (default 0.5).
//! - `interface` (also `""` and `"none"`, as pbrt-v4): no surface.
//!
//! `hair`, `measured` and `subsurface` are reported as not supported yet.

use mcrender_core::material::{
    BumpHeight, BumpMapMaterial, CoatedConductorMaterial, CoatedDiffuseMaterial, ConductorMaterial, DielectricMaterial,
    DiffuseMaterial, DiffuseTransmissionMaterial, MixMaterial, NormalMapMaterial, ThinDielectricMaterial,
};
use std::collections::HashMap;
use std::sync::Arc;

use mcrender_core::color::Rgb;
use mcrender_core::scene::{FloatTexture, MaterialDesc, MaterialId, RgbTexture};
use mcrender_core::texture::{BitmapFilter, BitmapTexture, BitmapWrap, Texture, TextureMapping};

use super::builder::SceneBuilder;
use super::files::ImageUse;
use super::graphics_state::{FrameMap, MaterialRef};
use super::params::{ParamSet, ParamType};
use crate::error::{Location, SceneError};
use crate::image_io::ColorEncoding;
use crate::spectra::{glass_eta, metal_rgb, sampled_spectrum, spectrum_pairs, SpectrumRole, KNOWN_UNCONVERTED};

/// pbrt-v4 material types that exist but are not implemented here yet.
const KNOWN_MATERIALS: &[&str] = &["hair", "measured", "subsurface"];

impl SceneBuilder {
    /// `Material "type" ...`: the material of subsequent shapes in this attribute scope.
    pub fn material(&mut self, kind: &str, params: &mut ParamSet, loc: &Location) -> Result<(), SceneError> {
        self.require_world("Material", loc)?;
        params.add_inherited(&self.state.attributes.material);
        self.state.material = self.material_desc(kind, params, loc)?;
        Ok(())
    }

    /// `MakeNamedMaterial "name" "string type" "..." ...`
    pub fn make_named_material(&mut self, name: &str, params: &mut ParamSet, loc: &Location) -> Result<(), SceneError> {
        self.require_world("MakeNamedMaterial", loc)?;
        params.add_inherited(&self.state.attributes.material);
        if let Some((_, first)) = self.world.named_materials.get(name) {
            return Err(SceneError::invalid(
                loc,
                format!("named material \"{name}\" is already defined at {first}"),
            ));
        }
        let Some((kind, kind_loc)) = params.string("type")? else {
            return Err(SceneError::syntax(
                loc,
                format!("MakeNamedMaterial \"{name}\" needs a \"string type\" parameter"),
            ));
        };
        let material = self.material_desc(&kind, params, &kind_loc)?;
        self.world
            .named_materials
            .insert(name.to_string(), (material, loc.clone()));
        Ok(())
    }

    /// `NamedMaterial "name"`: resolved once the whole scene has been read.
    pub fn named_material(&mut self, name: String, loc: &Location) -> Result<(), SceneError> {
        self.require_world("NamedMaterial", loc)?;
        self.state.material = MaterialRef::Named { name, loc: loc.clone() };
        Ok(())
    }

    /// The material of `kind` from `params`; `loc` is where the type was named.
    fn material_desc(&mut self, kind: &str, params: &ParamSet, loc: &Location) -> Result<MaterialRef, SceneError> {
        if kind == "mix" {
            return self.mix(params);
        }
        let frame = if matches!(kind, "interface" | "" | "none") {
            None
        } else {
            self.frame_map(params)?
        };
        let inner = self.plain_material_desc(kind, params, loc)?;
        Ok(match frame {
            Some(frame) => MaterialRef::Framed { inner, frame },
            None => MaterialRef::Inline(inner),
        })
    }

    /// `displacement` or `normalmap`, when given (module docs).
    fn frame_map(&mut self, params: &ParamSet) -> Result<Option<FrameMap>, SceneError> {
        let displacement = if params.get("displacement").is_some() {
            Some(self.world.textures.float(params, "displacement", 0.0)?)
        } else {
            None
        };
        let Some((file, floc)) = params.string("normalmap")? else {
            return Ok(displacement.map(FrameMap::Displacement));
        };
        if let Some(d) = displacement {
            self.warn(
                &floc,
                format!(
                    "\"string normalmap\" of {} ignored: its \"displacement\" is used, as in pbrt-v4",
                    params.owner
                ),
            );
            return Ok(Some(FrameMap::Displacement(d)));
        }
        let image = self.read_image_file(&file, &floc, ColorEncoding::Linear, ImageUse::Texture)?;
        Ok(Some(FrameMap::NormalMap(Texture::Bitmap(Arc::new(BitmapTexture {
            mapping: TextureMapping::default(),
            width: image.width,
            height: image.height,
            texels: Arc::new(image.pixels),
            filter: BitmapFilter::Bilinear,
            wrap: BitmapWrap::Repeat,
        })))))
    }

    /// `mix`: `string materials` (two names), `float amount` (default 0.5).
    fn mix(&mut self, params: &ParamSet) -> Result<MaterialRef, SceneError> {
        let Some(p) = params.lookup("materials", &[ParamType::String])? else {
            return Err(SceneError::syntax(
                &params.loc,
                format!(
                    "{} of type \"mix\" needs \"string materials\" with two material names",
                    params.owner
                ),
            ));
        };
        let names: [String; 2] = match p.strings() {
            [a, b] => [a.clone(), b.clone()],
            other => {
                return Err(SceneError::syntax(
                    &p.loc,
                    format!(
                        "\"{}\" of {} needs exactly two material names, found {}",
                        p.decl(),
                        params.owner,
                        other.len()
                    ),
                ))
            }
        };
        let loc = p.loc.clone();
        let amount = self.world.textures.float(params, "amount", 0.5)?;
        if amount.constant().is_some_and(|a| !a.is_finite()) {
            let p = params.get("amount").map_or(&params.loc, |p| &p.loc);
            return Err(SceneError::invalid(
                p,
                format!("\"amount\" of {} must be a finite number", params.owner),
            ));
        }
        self.warn_unused(params);
        Ok(MaterialRef::Mix { names, amount, loc })
    }

    /// A material that is not a `mix`.
    fn plain_material_desc(
        &mut self,
        kind: &str,
        params: &ParamSet,
        loc: &Location,
    ) -> Result<MaterialDesc, SceneError> {
        let context = if params.owner.starts_with("MakeNamedMaterial") {
            format!(" (in {})", params.owner)
        } else {
            String::new()
        };
        match kind {
            "diffuse" => {
                let reflectance = self
                    .world
                    .textures
                    .rgb(params, "reflectance")?
                    .unwrap_or_else(|| Rgb::splat(0.5).into());
                if let Some(reflectance) = reflectance
                    .constant()
                    .filter(|r| r.to_array().iter().any(|c| !(0.0..=1.0).contains(c)))
                {
                    let p = params.get("reflectance").map_or(&params.loc, |p| &p.loc);
                    return Err(SceneError::invalid(
                        p,
                        format!(
                            "reflectance ({} {} {}) of {} must be between 0 and 1",
                            reflectance.r, reflectance.g, reflectance.b, params.owner
                        ),
                    ));
                }
                self.warn_unused(params);
                Ok(MaterialDesc::Diffuse(DiffuseMaterial { reflectance }))
            }
            "conductor" => {
                let reflectance = self.spectrum_param(params, "reflectance", SpectrumKind::Albedo)?;
                let eta = self.spectrum_param(params, "eta", SpectrumKind::MetalIndex)?;
                let k = self.spectrum_param(params, "k", SpectrumKind::MetalIndex)?;
                if reflectance.is_some() && (eta.is_some() || k.is_some()) {
                    let p = params.get("reflectance").map_or(&params.loc, |p| &p.loc);
                    return Err(SceneError::invalid(
                        p,
                        format!(
                            "{} has both \"reflectance\" and \"eta\"/\"k\"; give one or the other",
                            params.owner
                        ),
                    ));
                }
                if let Some(r) = reflectance.as_ref().and_then(RgbTexture::constant) {
                    check_unit_interval(params, "reflectance", r)?;
                }
                let (u_roughness, v_roughness) = self.roughness(params)?;
                let remap_roughness = params.bool("remaproughness", true)?;
                self.warn_unused(params);
                Ok(MaterialDesc::Conductor(ConductorMaterial {
                    eta: eta.unwrap_or_else(|| metal_rgb("metal-Cu-eta").unwrap_or(Rgb::WHITE).into()),
                    k: k.unwrap_or_else(|| metal_rgb("metal-Cu-k").unwrap_or(Rgb::BLACK).into()),
                    reflectance,
                    u_roughness,
                    v_roughness,
                    remap_roughness,
                    microfacet: Default::default(),
                }))
            }
            "dielectric" => {
                let eta = dielectric_eta(params)?;
                let (u_roughness, v_roughness) = self.roughness(params)?;
                let remap_roughness = params.bool("remaproughness", true)?;
                self.warn_unused(params);
                Ok(MaterialDesc::Dielectric(DielectricMaterial {
                    eta,
                    u_roughness,
                    v_roughness,
                    remap_roughness,
                    microfacet: Default::default(),
                }))
            }
            "thindielectric" => {
                let eta = dielectric_eta(params)?;
                self.warn_unused(params);
                Ok(MaterialDesc::ThinDielectric(ThinDielectricMaterial { eta }))
            }
            "diffusetransmission" => {
                let default = || RgbTexture::from(Rgb::splat(0.25));
                let reflectance = self.world.textures.rgb(params, "reflectance")?.unwrap_or_else(default);
                let transmittance = self
                    .world
                    .textures
                    .rgb(params, "transmittance")?
                    .unwrap_or_else(default);
                for (name, t) in [("reflectance", &reflectance), ("transmittance", &transmittance)] {
                    if let Some(c) = t.constant() {
                        check_unit_interval(params, name, c)?;
                    }
                }
                let scale = params.float("scale", 1.0)?;
                if scale < 0.0 {
                    let p = params.get("scale").map_or(&params.loc, |p| &p.loc);
                    return Err(SceneError::invalid(
                        p,
                        format!("\"scale\" of {} must not be negative", params.owner),
                    ));
                }
                self.warn_unused(params);
                Ok(MaterialDesc::DiffuseTransmission(DiffuseTransmissionMaterial {
                    reflectance,
                    transmittance,
                    scale,
                }))
            }
            "coateddiffuse" => {
                let reflectance = self
                    .spectrum_param(params, "reflectance", SpectrumKind::Albedo)?
                    .unwrap_or_else(|| Rgb::splat(0.5).into());
                if let Some(r) = reflectance.constant() {
                    check_unit_interval(params, "reflectance", r)?;
                }
                let (u_roughness, v_roughness) = self.roughness(params)?;
                let remap_roughness = params.bool("remaproughness", true)?;
                let eta = dielectric_eta(params)?;
                let slab = slab(self, params)?;
                self.warn_unused(params);
                Ok(MaterialDesc::CoatedDiffuse(CoatedDiffuseMaterial {
                    reflectance,
                    u_roughness,
                    v_roughness,
                    remap_roughness,
                    thickness: slab.thickness,
                    eta,
                    albedo: slab.albedo,
                    g: slab.g,
                    max_depth: slab.max_depth,
                    n_samples: slab.n_samples,
                }))
            }
            "coatedconductor" => {
                let (interface_u_roughness, interface_v_roughness) = self.prefixed_roughness(params, "interface.")?;
                let interface_eta = dielectric_eta_named(params, "interface.eta")?;
                let reflectance = self.spectrum_param(params, "reflectance", SpectrumKind::Albedo)?;
                let eta = self.spectrum_param(params, "conductor.eta", SpectrumKind::MetalIndex)?;
                let k = self.spectrum_param(params, "conductor.k", SpectrumKind::MetalIndex)?;
                if reflectance.is_some() && (eta.is_some() || k.is_some()) {
                    let p = params.get("reflectance").map_or(&params.loc, |p| &p.loc);
                    return Err(SceneError::invalid(
                        p,
                        format!(
                            "{} has both \"reflectance\" and \"conductor.eta\"/\"conductor.k\"; give one or the other",
                            params.owner
                        ),
                    ));
                }
                if let Some(r) = reflectance.as_ref().and_then(RgbTexture::constant) {
                    check_unit_interval(params, "reflectance", r)?;
                }
                let (conductor_u_roughness, conductor_v_roughness) = self.prefixed_roughness(params, "conductor.")?;
                let remap_roughness = params.bool("remaproughness", true)?;
                let slab = slab(self, params)?;
                self.warn_unused(params);
                Ok(MaterialDesc::CoatedConductor(CoatedConductorMaterial {
                    interface_u_roughness,
                    interface_v_roughness,
                    interface_eta,
                    conductor_eta: eta.unwrap_or_else(|| metal_rgb("metal-Cu-eta").unwrap_or(Rgb::WHITE).into()),
                    conductor_k: k.unwrap_or_else(|| metal_rgb("metal-Cu-k").unwrap_or(Rgb::BLACK).into()),
                    reflectance,
                    conductor_u_roughness,
                    conductor_v_roughness,
                    remap_roughness,
                    thickness: slab.thickness,
                    albedo: slab.albedo,
                    g: slab.g,
                    max_depth: slab.max_depth,
                    n_samples: slab.n_samples,
                }))
            }
            // pbrt-v4: no material at all; rays pass through (medium boundaries).
            "interface" | "" | "none" => {
                self.warn_unused(params);
                Ok(MaterialDesc::Interface)
            }
            _ if KNOWN_MATERIALS.contains(&kind) => Err(SceneError::unsupported(
                loc,
                format!("material type \"{kind}\" is not supported yet{context}"),
            )),
            _ => Err(SceneError::syntax(
                loc,
                format!("unknown material type \"{kind}\"{context}"),
            )),
        }
    }
}

/// The slab parameters shared by `coateddiffuse` and `coatedconductor`.
struct Slab {
    thickness: FloatTexture,
    albedo: RgbTexture,
    g: FloatTexture,
    max_depth: u32,
    n_samples: u32,
}

/// `float thickness` (default 0.01, >= 0), `rgb albedo` (default 0, in [0, 1]), `float g`
/// (default 0, in [-1, 1]), each also a texture (the bounds then checked on constants
/// only), `integer maxdepth` (default 10, >= 0), `integer nsamples` (default 1, >= 1).
fn slab(builder: &SceneBuilder, params: &ParamSet) -> Result<Slab, SceneError> {
    let bad = |name: &str, what: &str| {
        let p = params.get(name).map_or(&params.loc, |p| &p.loc);
        Err(SceneError::invalid(
            p,
            format!("\"{name}\" of {} must be {what}", params.owner),
        ))
    };
    let thickness = builder.world.textures.float(params, "thickness", 0.01)?;
    if thickness.constant().is_some_and(|t| !(t >= 0.0 && t.is_finite())) {
        return bad("thickness", "a finite number >= 0");
    }
    let albedo = builder
        .spectrum_param(params, "albedo", SpectrumKind::Albedo)?
        .unwrap_or_else(|| Rgb::BLACK.into());
    if let Some(a) = albedo.constant() {
        check_unit_interval(params, "albedo", a)?;
    }
    let g = builder.world.textures.float(params, "g", 0.0)?;
    if g.constant().is_some_and(|g| !(-1.0..=1.0).contains(&g)) {
        return bad("g", "between -1 and 1");
    }
    let max_depth = params.int("maxdepth", 10)?;
    let Ok(max_depth) = u32::try_from(max_depth) else {
        return bad("maxdepth", "at least 0");
    };
    let n_samples = params.int("nsamples", 1)?;
    let n_samples = match u32::try_from(n_samples) {
        Ok(n) if n >= 1 => n,
        _ => return bad("nsamples", "at least 1"),
    };
    Ok(Slab {
        thickness,
        albedo,
        g,
        max_depth,
        n_samples,
    })
}

/// The id of the material `r` names, interning it (and, for a `mix`, the materials it
/// names) into `materials`. `stack` holds the named materials being resolved, to report
/// a `mix` that contains itself.
pub(super) fn resolve_material(
    named: &HashMap<String, (MaterialRef, Location)>,
    r: &MaterialRef,
    materials: &mut Vec<MaterialDesc>,
    ids: &mut HashMap<String, MaterialId>,
    stack: &mut Vec<String>,
) -> Result<MaterialId, SceneError> {
    match r {
        MaterialRef::Inline(desc) => Ok(intern_material(materials, ids, desc.clone())),
        MaterialRef::Framed { inner, frame } => {
            let material = intern_material(materials, ids, inner.clone());
            let desc = match frame {
                FrameMap::Displacement(displacement) => MaterialDesc::BumpMap(BumpMapMaterial {
                    material,
                    height: BumpHeight::Pbrt {
                        displacement: displacement.clone(),
                    },
                }),
                FrameMap::NormalMap(normal_map) => MaterialDesc::NormalMap(NormalMapMaterial {
                    material,
                    normal_map: normal_map.clone(),
                }),
            };
            Ok(intern_material(materials, ids, desc))
        }
        MaterialRef::Named { name, loc } => {
            let Some((target, _)) = named.get(name) else {
                return Err(SceneError::invalid(
                    loc,
                    format!("named material \"{name}\" is not defined"),
                ));
            };
            if stack.contains(name) {
                return Err(SceneError::invalid(
                    loc,
                    format!(
                        "mix material \"{name}\" contains itself (through {})",
                        stack.join(" -> ")
                    ),
                ));
            }
            stack.push(name.clone());
            let id = resolve_material(named, target, materials, ids, stack);
            stack.pop();
            id
        }
        MaterialRef::Mix { names, amount, loc } => {
            let mut pair = [0; 2];
            for (id, name) in pair.iter_mut().zip(names) {
                let r = MaterialRef::Named {
                    name: name.clone(),
                    loc: loc.clone(),
                };
                *id = resolve_material(named, &r, materials, ids, stack)?;
            }
            let desc = MaterialDesc::Mix(MixMaterial {
                materials: pair,
                amount: amount.clone(),
            });
            Ok(intern_material(materials, ids, desc))
        }
    }
}

/// Index of `desc` in `materials`, adding it when it is new.
pub(super) fn intern_material(
    materials: &mut Vec<MaterialDesc>,
    ids: &mut HashMap<String, MaterialId>,
    desc: MaterialDesc,
) -> MaterialId {
    // The key is the description's text with -0 folded into +0, so equal values share it.
    let key = format!("{desc:?}").replace("-0.0,", "0.0,").replace("-0.0 ", "0.0 ");
    if let Some(&id) = ids.get(&key) {
        return id;
    }
    // There are never more distinct materials than shapes, far below 2^32.
    let id = materials.len() as MaterialId;
    materials.push(desc);
    ids.insert(key, id);
    id
}

/// What a spectrum parameter describes, which decides the named spectra it accepts.
#[derive(Clone, Copy, PartialEq, Eq)]
enum SpectrumKind {
    /// A reflectance: `rgb` only.
    Albedo,
    /// A metal's complex index: `rgb` or a named `metal-*` spectrum.
    MetalIndex,
}

impl SceneBuilder {
    /// A colour parameter given as `rgb`, as a `texture` or (for metal indices) a named
    /// spectrum; `None` when absent. Blackbodies and spectra given as wavelength-value pairs
    /// are reported as not supported yet.
    fn spectrum_param(
        &self,
        params: &ParamSet,
        name: &str,
        kind: SpectrumKind,
    ) -> Result<Option<RgbTexture>, SceneError> {
        let forms = [
            ParamType::Rgb,
            ParamType::Spectrum,
            ParamType::Blackbody,
            ParamType::Texture,
        ];
        let Some(p) = params.lookup(name, &forms)? else {
            return Ok(None);
        };
        let unsupported = |what: &str| {
            Err(SceneError::unsupported(
                &p.loc,
                format!("\"{}\" of {} ({what}) is not supported yet", p.decl(), params.owner),
            ))
        };
        match p.ty {
        ParamType::Rgb => {
            let v = p.floats();
            if v.len() != 3 {
                return Err(SceneError::syntax(
                    &p.loc,
                    format!("\"{}\" of {} needs exactly 3 values", p.decl(), params.owner),
                ));
            }
            let rgb = Rgb::new(v[0], v[1], v[2]);
            if v.iter().any(|c| *c < 0.0) {
                return Err(SceneError::invalid(
                    &p.loc,
                    format!("\"{}\" of {} must not be negative", p.decl(), params.owner),
                ));
            }
            Ok(Some(rgb.into()))
        }
        ParamType::Spectrum if kind == SpectrumKind::MetalIndex => match p.strings() {
            [named] => match metal_rgb(named) {
                Some(rgb) => Ok(Some(rgb.into())),
                None if KNOWN_UNCONVERTED.contains(&named.as_str()) => unsupported(&format!("named spectrum \"{named}\"")),
                None => Err(SceneError::invalid(
                    &p.loc,
                    format!(
                        "unknown named spectrum \"{named}\" for \"{}\" of {}; known: metal-Ag-eta, metal-Ag-k, metal-Al-eta, metal-Al-k, metal-Au-eta, metal-Au-k, metal-Cu-eta, metal-Cu-k",
                        p.decl(),
                        params.owner
                    ),
                )),
            },
            [] => params
                .color(name, Rgb::WHITE, SpectrumRole::Unbounded)
                .map(|c| Some(c.into())),
            _ => Err(SceneError::syntax(
                &p.loc,
                format!("\"{}\" of {} needs exactly one spectrum name", p.decl(), params.owner),
            )),
        },
        ParamType::Spectrum if p.strings().is_empty() => params
            .color(name, Rgb::WHITE, SpectrumRole::Albedo)
            .map(|c| Some(c.into())),
        ParamType::Spectrum => unsupported("a named spectrum; give an rgb value or (wavelength, value) pairs"),
        ParamType::Texture => self.world.textures.rgb_reference(p, &params.owner).map(Some),
        _ => unsupported("a blackbody"),
    }
    }

    /// `uroughness` and `vroughness` (float textures), each defaulting to `roughness`, which
    /// defaults to 0. Constant roughnesses must not be negative.
    fn roughness(&self, params: &ParamSet) -> Result<(FloatTexture, FloatTexture), SceneError> {
        self.prefixed_roughness(params, "")
    }

    /// [`Self::roughness`] with the parameter names prefixed (`interface.`, `conductor.`).
    fn prefixed_roughness(&self, params: &ParamSet, prefix: &str) -> Result<(FloatTexture, FloatTexture), SceneError> {
        let names = [
            format!("{prefix}roughness"),
            format!("{prefix}uroughness"),
            format!("{prefix}vroughness"),
        ];
        let r = self.world.textures.float(params, &names[0], 0.0)?;
        let u = match params.get(&names[1]) {
            Some(_) => self.world.textures.float(params, &names[1], 0.0)?,
            None => r.clone(),
        };
        let v = match params.get(&names[2]) {
            Some(_) => self.world.textures.float(params, &names[2], 0.0)?,
            None => r.clone(),
        };
        for (name, value) in names.iter().zip([&r, &u, &v]) {
            if value.constant().is_some_and(|c| c < 0.0) {
                let p = params.get(name).map_or(&params.loc, |p| &p.loc);
                return Err(SceneError::invalid(
                    p,
                    format!("\"{name}\" of {} must not be negative", params.owner),
                ));
            }
        }
        Ok((u, v))
    }
}

/// `eta` of a dielectric: `float eta` or a named glass spectrum; default 1.5. pbrt treats
/// an index of 0 as 1.
fn dielectric_eta(params: &ParamSet) -> Result<f32, SceneError> {
    dielectric_eta_named(params, "eta")
}

/// [`dielectric_eta`] for the parameter `name` (`interface.eta` of `coatedconductor`).
fn dielectric_eta_named(params: &ParamSet, name: &str) -> Result<f32, SceneError> {
    let Some(p) = params.lookup(name, &[ParamType::Float, ParamType::Spectrum, ParamType::Texture])? else {
        return Ok(1.5);
    };
    let eta = match p.ty {
        ParamType::Float => params.float(name, 1.5)?,
        ParamType::Spectrum => match p.strings() {
            [named] => glass_eta(named).ok_or_else(|| {
                SceneError::invalid(
                    &p.loc,
                    format!(
                        "unknown named spectrum \"{named}\" for \"{}\" of {}; known: glass-BK7, glass-BAF10, glass-FK51A, glass-LASF9, glass-F5, glass-F10, glass-F11",
                        p.decl(),
                        params.owner
                    ),
                )
            })?,
            [] => {
                // As for the named glasses: the index at 550 nm.
                let pairs = spectrum_pairs(p.floats());
                let s = sampled_spectrum(&pairs)
                    .map_err(|e| SceneError::invalid(&p.loc, format!("\"{}\" of {}: {e}", p.decl(), params.owner)))?;
                s(550.0) as f32
            }
            _ => {
                return Err(SceneError::syntax(
                    &p.loc,
                    format!("\"{}\" of {} needs exactly one spectrum name", p.decl(), params.owner),
                ))
            }
        },
        _ => {
            return Err(SceneError::unsupported(
                &p.loc,
                format!(
                    "\"{}\" of {}: a dielectric's index of refraction cannot be a texture (as in pbrt-v4); give a float or a named glass",
                    p.decl(),
                    params.owner
                ),
            ))
        }
    };
    if !(eta >= 0.0 && eta.is_finite()) {
        return Err(SceneError::invalid(
            &p.loc,
            format!(
                "\"{name}\" of {} must be a finite number > 0, found {eta}",
                params.owner
            ),
        ));
    }
    Ok(if eta == 0.0 { 1.0 } else { eta })
}

/// Error unless every channel of `value` (the parameter `name`) is in [0, 1].
fn check_unit_interval(params: &ParamSet, name: &str, value: Rgb) -> Result<(), SceneError> {
    if value.to_array().iter().all(|c| (0.0..=1.0).contains(c)) {
        return Ok(());
    }
    let p = params.get(name).map_or(&params.loc, |p| &p.loc);
    Err(SceneError::invalid(
        p,
        format!(
            "{name} ({} {} {}) of {} must be between 0 and 1",
            value.r, value.g, value.b, params.owner
        ),
    ))
}
