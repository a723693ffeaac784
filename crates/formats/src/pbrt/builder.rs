//! [`SceneBuilder`]: the semantic side of the pbrt-v4 loader. The parser calls one method
//! per directive; the builder keeps the graphics state, the rendering options and the
//! shapes, and [`SceneBuilder::finish`] turns them into a [`SceneDescription`].
//!
//! This file owns the block structure (options block, `WorldBegin`, attribute scopes),
//! transforms and named coordinate systems; options, materials, lights and shapes live in
//! their own files as further `impl SceneBuilder` blocks.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::Mat4;
use mcrender_core::math::Transform;
use mcrender_core::scene::{
    LightDesc, MaterialDesc, MaterialId, ObjectDesc, Reconstruction, SceneDescription, ShapeDesc,
};

use super::files::InputFiles;
use super::graphics_state::{GraphicsState, MaterialRef};
use super::instancing::Instancing;
use super::materials::resolve_material;
use super::options::SceneOptions;
use super::params::ParamSet;
use super::LoadedScene;
use crate::error::{Location, SceneError};
use crate::limits::{format_bytes, LoadLimits};
use crate::source::FileSource;

/// Where in the file we are: before or after `WorldBegin`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Block {
    Options,
    World,
}

/// An open `AttributeBegin` (or `TransformBegin`) and the state it saved.
#[derive(Debug)]
struct Scope {
    saved: GraphicsState,
    loc: Location,
    directive: &'static str,
}

/// What the world block adds: named materials and textures, shapes and lights.
#[derive(Debug, Default)]
pub struct WorldContents {
    /// `MakeNamedMaterial`s, with where each was defined.
    pub named_materials: HashMap<String, (MaterialRef, Location)>,
    /// Named textures and the MIP maps of the images read.
    pub textures: super::textures::NamedTextures,
    /// Shapes outside objects, with their materials.
    pub shapes: Vec<(ShapeDesc, MaterialRef)>,
    /// Lights that are not shapes.
    pub lights: Vec<LightDesc>,
}

/// Collects the scene while the parser walks the directives. The block structure,
/// graphics state and named coordinate systems are this file's; the rest is grouped by
/// the files that fill it: [`SceneOptions`] (options.rs), [`WorldContents`] (materials,
/// textures, shapes, lights), [`Instancing`] (instancing.rs), [`InputFiles`] (files.rs).
#[derive(Debug)]
pub struct SceneBuilder {
    block: Block,
    pub(super) state: GraphicsState,
    scopes: Vec<Scope>,
    named_coordinate_systems: HashMap<String, Mat4>,
    /// The options block's settings.
    pub(super) options: SceneOptions,
    /// The world block's materials, textures, shapes and lights.
    pub(super) world: WorldContents,
    /// Objects and their instances.
    pub(super) instancing: Instancing,
    /// Files and memory.
    pub(super) input: InputFiles,
    warnings: Vec<String>,
    warned_transform_begin: bool,
}

impl SceneBuilder {
    /// A builder for a scene whose top-level file lives in `search_dir`.
    #[must_use]
    pub fn new(search_dir: &Path, files: Arc<dyn FileSource>, limits: LoadLimits) -> Self {
        Self {
            block: Block::Options,
            state: GraphicsState::default(),
            scopes: Vec::new(),
            named_coordinate_systems: HashMap::new(),
            options: SceneOptions::default(),
            world: WorldContents::default(),
            instancing: Instancing::default(),
            input: InputFiles::new(search_dir, files, limits),
            warnings: Vec::new(),
            warned_transform_begin: false,
        }
    }

    /// Count `bytes` about to be allocated for `what` against the memory limit.
    ///
    /// # Errors
    /// When the total would pass [`LoadLimits::max_memory`]; the message names both figures.
    pub fn reserve_memory(&mut self, bytes: u64, what: &str, loc: &Location) -> Result<(), SceneError> {
        let total = self.input.memory_used.saturating_add(bytes);
        if total > self.input.limits.max_memory {
            return Err(SceneError::invalid(
                loc,
                format!(
                    "{what} needs about {} (scene so far: {}), over the memory limit of {} (see --max-memory)",
                    format_bytes(bytes),
                    format_bytes(self.input.memory_used),
                    format_bytes(self.input.limits.max_memory)
                ),
            ));
        }
        self.input.memory_used = total;
        Ok(())
    }

    /// Record a warning: `file:line:col: warning: message`.
    pub fn warn(&mut self, loc: &Location, message: impl AsRef<str>) {
        self.warnings.push(format!("{loc}: warning: {}", message.as_ref()));
    }

    /// Record the warnings for every parameter of `params` that was not read.
    pub fn warn_unused(&mut self, params: &ParamSet) {
        self.warnings.extend(params.unused_warnings());
    }

    /// Resolve a file name from the scene as pbrt-v4 does: relative to the directory of the
    /// top-level scene file. When it does not exist there, the directory of the file being
    /// parsed is tried as well.
    #[must_use]
    pub fn resolve(&self, name: &str) -> PathBuf {
        let primary = self.input.search_dir.join(name);
        if self.input.files.exists(&primary) {
            return primary;
        }
        let secondary = self.input.current_dir.join(name);
        if self.input.files.exists(&secondary) {
            secondary
        } else {
            primary
        }
    }

    /// Error unless we are in the options block (before `WorldBegin`).
    pub fn require_options(&self, directive: &str, loc: &Location) -> Result<(), SceneError> {
        if self.block == Block::World {
            return Err(SceneError::syntax(
                loc,
                format!("options cannot be set inside the world block; \"{directive}\" must come before WorldBegin"),
            ));
        }
        Ok(())
    }

    /// Error unless we are in the world block (after `WorldBegin`).
    pub fn require_world(&self, directive: &str, loc: &Location) -> Result<(), SceneError> {
        if self.block == Block::Options {
            return Err(SceneError::syntax(
                loc,
                format!("\"{directive}\" is only allowed inside the world block, after WorldBegin"),
            ));
        }
        Ok(())
    }

    /// The current transformation as a [`Transform`]; an error at `loc` when it is singular.
    pub fn ctm_transform(&self, what: &str, loc: &Location) -> Result<Transform, SceneError> {
        Transform::new(self.state.ctm).ok_or_else(|| {
            SceneError::invalid(
                loc,
                format!("the current transformation of {what} is singular or not finite"),
            )
        })
    }

    // --- Transforms -------------------------------------------------------------------

    /// `Identity`
    pub fn identity(&mut self) {
        self.state.ctm = Mat4::IDENTITY;
    }

    /// `Translate`, `Scale`, `Rotate`, `LookAt`, `ConcatTransform`: `CTM = CTM * m`.
    pub fn concat(&mut self, m: Mat4) {
        self.state.ctm *= m;
    }

    /// `Transform`: replace the CTM.
    pub fn set_transform(&mut self, m: Mat4) {
        self.state.ctm = m;
    }

    /// `CoordinateSystem "name"`
    pub fn coordinate_system(&mut self, name: String) {
        self.named_coordinate_systems.insert(name, self.state.ctm);
    }

    /// `CoordSysTransform "name"`; an unknown name is a warning, as in pbrt.
    pub fn coord_sys_transform(&mut self, name: &str, loc: &Location) {
        match self.named_coordinate_systems.get(name) {
            Some(m) => self.state.ctm = *m,
            None => self.warn(
                loc,
                format!("unknown coordinate system \"{name}\"; CoordSysTransform ignored"),
            ),
        }
    }

    /// Remember the camera's coordinate system (`CoordSysTransform "camera"`).
    pub fn set_camera_coordinate_system(&mut self, world_from_camera: Mat4) {
        self.named_coordinate_systems.insert("camera".into(), world_from_camera);
    }

    // --- Blocks -----------------------------------------------------------------------

    /// `WorldBegin`: reset the CTM and start the world block.
    pub fn world_begin(&mut self, loc: &Location) -> Result<(), SceneError> {
        if self.block == Block::World {
            return Err(SceneError::syntax(loc, "WorldBegin appears twice"));
        }
        self.block = Block::World;
        self.state.ctm = Mat4::IDENTITY;
        self.named_coordinate_systems.insert("world".into(), Mat4::IDENTITY);
        Ok(())
    }

    /// `AttributeBegin`, or the deprecated `TransformBegin` (which pbrt-v4 treats the same).
    pub fn attribute_begin(&mut self, directive: &'static str, loc: &Location) -> Result<(), SceneError> {
        self.require_world(directive, loc)?;
        if directive == "TransformBegin" && !self.warned_transform_begin {
            self.warned_transform_begin = true;
            self.warn(
                loc,
                "TransformBegin/TransformEnd are deprecated; treated as AttributeBegin/AttributeEnd",
            );
        }
        if self.scopes.len() >= 10_000 {
            return Err(SceneError::invalid(loc, format!("{directive} nested too deeply")));
        }
        self.scopes.push(Scope {
            saved: self.state.clone(),
            loc: loc.clone(),
            directive,
        });
        Ok(())
    }

    /// `AttributeEnd` / `TransformEnd`: restore the saved state.
    pub fn attribute_end(&mut self, directive: &'static str, loc: &Location) -> Result<(), SceneError> {
        self.require_world(directive, loc)?;
        let Some(scope) = self.scopes.pop() else {
            return Err(SceneError::syntax(
                loc,
                format!("{directive} without a matching AttributeBegin"),
            ));
        };
        self.state = scope.saved;
        Ok(())
    }

    /// `Attribute "target" ...`: default parameters for later directives of that kind in
    /// this attribute scope.
    pub fn attribute(&mut self, target: &str, params: ParamSet, loc: &Location) -> Result<(), SceneError> {
        let attributes = &mut self.state.attributes;
        let list = match target {
            "shape" => &mut attributes.shape,
            "light" => &mut attributes.light,
            "material" => &mut attributes.material,
            "medium" => &mut attributes.medium,
            "texture" => &mut attributes.texture,
            _ => {
                return Err(SceneError::syntax(
                    loc,
                    format!(
                        "unknown attribute target \"{target}\" (expected \"shape\", \"light\", \"material\", \"medium\" or \"texture\")"
                    ),
                ))
            }
        };
        // Newer values take precedence: put them first.
        let mut new = params.into_params();
        new.append(list);
        *list = new;
        Ok(())
    }

    /// `ReverseOrientation`
    pub fn reverse_orientation(&mut self, loc: &Location) -> Result<(), SceneError> {
        self.require_world("ReverseOrientation", loc)?;
        self.state.reverse_orientation = !self.state.reverse_orientation;
        Ok(())
    }

    // --- End of input -----------------------------------------------------------------

    /// Check that the file was complete and assemble the scene. `end` is the location of
    /// the end of the top-level file.
    pub fn finish(mut self, end: &Location) -> Result<LoadedScene, SceneError> {
        if self.block == Block::Options {
            return Err(SceneError::syntax(end, "end of file before \"WorldBegin\""));
        }
        if let Some(scope) = self.scopes.last() {
            let end_directive = match scope.directive {
                "TransformBegin" => "TransformEnd",
                "ObjectBegin" => "ObjectEnd",
                _ => "AttributeEnd",
            };
            return Err(SceneError::syntax(
                &scope.loc,
                format!("{} has no matching {end_directive}", scope.directive),
            ));
        }

        let mut materials: Vec<MaterialDesc> = Vec::new();
        let mut material_ids: HashMap<String, MaterialId> = HashMap::new();
        let named = &self.world.named_materials;
        let mut resolve = |list: Vec<(ShapeDesc, MaterialRef)>| -> Result<Vec<ShapeDesc>, SceneError> {
            let mut shapes = Vec::with_capacity(list.len());
            for (mut shape, material) in list {
                shape.material =
                    resolve_material(named, &material, &mut materials, &mut material_ids, &mut Vec::new())?;
                shapes.push(shape);
            }
            Ok(shapes)
        };
        let shapes = resolve(std::mem::take(&mut self.world.shapes))?;
        let objects = std::mem::take(&mut self.instancing.defined)
            .into_iter()
            .map(|o| resolve(o.shapes).map(|shapes| ObjectDesc { shapes }))
            .collect::<Result<Vec<_>, _>>()?;

        if self.world.lights.is_empty() && !shapes.iter().any(|s| s.area_light.is_some()) {
            self.warnings.push(format!(
                "{end}: warning: the scene has no lights; the image will be black"
            ));
        }

        let options = self.options;
        let mut sampler = options.sampler;
        // pbrt: the Sampler's "seed" parameter, else Option "seed", else 0. Negative seeds keep
        // their 32-bit pattern.
        sampler.seed = u64::from(options.sampler_seed.or(options.option_seed).unwrap_or(0) as u32);

        Ok(LoadedScene {
            description: SceneDescription {
                camera: options.camera,
                film: options.film,
                filter: options.filter,
                reconstruction: Reconstruction::default(),
                sampler,
                integrator: options.integrator,
                materials,
                shapes,
                lights: self.world.lights,
                objects,
                instances: self.instancing.instances,
            },
            output_filename: options.output_filename,
            warnings: self.warnings,
            image_bytes: self.input.image_bytes,
        })
    }
}
