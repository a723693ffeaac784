//! Materials: `Material`, `MakeNamedMaterial`, `NamedMaterial` (and `Texture`, which is
//! not supported yet). Only pbrt's `diffuse` with an `rgb reflectance` is supported now.

use mcrender_core::color::Rgb;
use mcrender_core::scene::MaterialDesc;

use super::builder::SceneBuilder;
use super::graphics_state::MaterialRef;
use super::params::ParamSet;
use crate::error::{Location, SceneError};

/// pbrt-v4 material types that exist but are not implemented here yet.
const KNOWN_MATERIALS: &[&str] = &[
    "coateddiffuse",
    "coatedconductor",
    "conductor",
    "dielectric",
    "thindielectric",
    "diffusetransmission",
    "hair",
    "measured",
    "mix",
    "subsurface",
    "interface",
];

impl SceneBuilder {
    /// `Material "type" ...`: the material of subsequent shapes in this attribute scope.
    pub fn material(&mut self, kind: &str, params: &mut ParamSet, loc: &Location) -> Result<(), SceneError> {
        self.require_world("Material", loc)?;
        params.add_inherited(&self.state.attributes.material);
        let desc = self.material_desc(kind, params, loc)?;
        self.state.material = MaterialRef::Inline(desc);
        Ok(())
    }

    /// `MakeNamedMaterial "name" "string type" "..." ...`
    pub fn make_named_material(&mut self, name: &str, params: &mut ParamSet, loc: &Location) -> Result<(), SceneError> {
        self.require_world("MakeNamedMaterial", loc)?;
        params.add_inherited(&self.state.attributes.material);
        if let Some((_, first)) = self.named_materials.get(name) {
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
        let desc = self.material_desc(&kind, params, &kind_loc)?;
        self.named_materials.insert(name.to_string(), (desc, loc.clone()));
        Ok(())
    }

    /// `NamedMaterial "name"`: resolved once the whole scene has been read.
    pub fn named_material(&mut self, name: String, loc: &Location) -> Result<(), SceneError> {
        self.require_world("NamedMaterial", loc)?;
        self.state.material = MaterialRef::Named { name, loc: loc.clone() };
        Ok(())
    }

    /// `Texture "name" "type" "class" ...`: not supported yet.
    pub fn texture(&mut self, name: &str, class: &str, loc: &Location) -> Result<(), SceneError> {
        self.require_world("Texture", loc)?;
        Err(SceneError::unsupported(
            loc,
            format!("Texture \"{name}\" (\"{class}\"): textures are not supported yet"),
        ))
    }

    /// The material of `kind` from `params`; `loc` is where the type was named.
    fn material_desc(&mut self, kind: &str, params: &ParamSet, loc: &Location) -> Result<MaterialDesc, SceneError> {
        let context = if params.owner.starts_with("MakeNamedMaterial") {
            format!(" (in {})", params.owner)
        } else {
            String::new()
        };
        match kind {
            "diffuse" => {
                let reflectance = params.rgb("reflectance", Rgb::splat(0.5))?;
                if reflectance.to_array().iter().any(|c| !(0.0..=1.0).contains(c)) {
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
                Ok(MaterialDesc::Diffuse { reflectance })
            }
            "" | "none" => Err(SceneError::unsupported(
                loc,
                format!("interface materials (material type \"{kind}\") are not supported yet{context}"),
            )),
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
