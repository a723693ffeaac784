//! Object instancing: `ObjectBegin "name"` ... `ObjectEnd` collects shapes (with the CTM
//! at their definition) into a named object instead of the scene; `ObjectInstance "name"`
//! places it with the CTM at that point. The core shares one BVH per object between all of
//! its instances. As in pbrt-v4, area lights inside objects are an error, and objects do
//! not nest.

use std::collections::HashMap;

use mcrender_core::scene::InstanceDesc;

use super::builder::SceneBuilder;
use super::graphics_state::MaterialRef;
use crate::error::{Location, SceneError};
use mcrender_core::scene::ShapeDesc;

/// An object being defined, or defined.
#[derive(Debug, Default)]
pub struct ObjectDef {
    /// Its shapes with their materials, as for the scene's own shapes.
    pub shapes: Vec<(ShapeDesc, MaterialRef)>,
}

/// The instancing state: objects defined so far, the one being defined, and the
/// placements.
#[derive(Debug, Default)]
pub struct Instancing {
    /// Defined objects, by index; [`Self::ids`] maps names to indices.
    pub defined: Vec<ObjectDef>,
    /// Object name to index into [`Self::defined`].
    pub ids: HashMap<String, u32>,
    /// The object being defined (between `ObjectBegin` and `ObjectEnd`).
    pub open: Option<(String, ObjectDef)>,
    /// `ObjectInstance` placements.
    pub instances: Vec<InstanceDesc>,
}

impl SceneBuilder {
    /// `ObjectBegin "name"`: also opens an attribute scope, as in pbrt-v4.
    pub fn object_begin(&mut self, name: &str, loc: &Location) -> Result<(), SceneError> {
        self.require_world("ObjectBegin", loc)?;
        if let Some((open, _)) = &self.instancing.open {
            return Err(SceneError::syntax(
                loc,
                format!("ObjectBegin \"{name}\" inside the definition of object \"{open}\"; objects do not nest"),
            ));
        }
        if self.instancing.ids.contains_key(name) {
            return Err(SceneError::invalid(loc, format!("object \"{name}\" is defined twice")));
        }
        self.attribute_begin("ObjectBegin", loc)?;
        self.instancing.open = Some((name.to_string(), ObjectDef::default()));
        Ok(())
    }

    /// `ObjectEnd`: closes the definition and its attribute scope.
    pub fn object_end(&mut self, loc: &Location) -> Result<(), SceneError> {
        self.require_world("ObjectEnd", loc)?;
        let Some((name, def)) = self.instancing.open.take() else {
            return Err(SceneError::syntax(loc, "ObjectEnd without a matching ObjectBegin"));
        };
        self.attribute_end("ObjectEnd", loc)?;
        self.instancing.ids.insert(name, self.instancing.defined.len() as u32);
        self.instancing.defined.push(def);
        Ok(())
    }

    /// `ObjectInstance "name"`: place the object with the current transform.
    pub fn object_instance(&mut self, name: &str, loc: &Location) -> Result<(), SceneError> {
        self.require_world("ObjectInstance", loc)?;
        if self.instancing.open.is_some() {
            return Err(SceneError::syntax(
                loc,
                "ObjectInstance inside an object definition; objects do not nest",
            ));
        }
        let Some(&object) = self.instancing.ids.get(name) else {
            return Err(SceneError::invalid(loc, format!("object \"{name}\" is not defined")));
        };
        let world_from_instance = self.ctm_transform(&format!("ObjectInstance \"{name}\""), loc)?;
        self.instancing.instances.push(InstanceDesc {
            object,
            world_from_instance,
        });
        Ok(())
    }

    /// Add a shape to the open object if there is one, else to the scene.
    pub(super) fn add_shape(&mut self, shape: ShapeDesc, loc: &Location) -> Result<(), SceneError> {
        let material = self.state.material.clone();
        match &mut self.instancing.open {
            Some(_) if shape.area_light.is_some() => Err(SceneError::unsupported(
                loc,
                "Area lights not supported with object instancing",
            )),
            Some((_, def)) => {
                def.shapes.push((shape, material));
                Ok(())
            }
            None => {
                self.world.shapes.push((shape, material));
                Ok(())
            }
        }
    }
}
