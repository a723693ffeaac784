//! The front door: [`load`] reads any supported scene format, chosen by the file's
//! extension (`.pbrt` and anything unknown: pbrt-v4; `.xml`: Mitsuba; `.obj`: OBJ
//! as a whole scene; `.gltf`, `.glb`: glTF 2.0).

use std::path::Path;

use crate::error::SceneError;
use crate::limits::LoadLimits;
use crate::LoadedScene;

/// Options of [`load_with`].
#[derive(Clone, Debug, Default)]
pub struct LoadOptions {
    /// `name=value` overrides of a Mitsuba scene's `<default>`s (`-D` on the command line).
    pub defines: Vec<(String, String)>,
    /// Memory limit for images and meshes (the Mitsuba, OBJ and glTF loaders count their
    /// images only; the command line adds their meshes, film and BVH before rendering).
    pub limits: LoadLimits,
}

/// The scene formats [`load`] knows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneFormat {
    /// pbrt-v4.
    Pbrt,
    /// Mitsuba 3 XML.
    Mitsuba,
    /// Wavefront OBJ (with MTL) as a whole scene.
    Obj,
    /// glTF 2.0 (`.gltf` or `.glb`).
    Gltf,
}

impl SceneFormat {
    /// The format of `path`, by extension.
    #[must_use]
    pub fn of(path: &Path) -> Self {
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .as_deref()
        {
            Some("xml") => Self::Mitsuba,
            Some("obj") => Self::Obj,
            Some("gltf" | "glb") => Self::Gltf,
            _ => Self::Pbrt,
        }
    }
}

/// Load a scene file of any supported format.
///
/// # Errors
/// As the format's loader: the display reads `file:line:col: message`.
pub fn load(path: &Path) -> Result<LoadedScene, SceneError> {
    load_with(path, &LoadOptions::default())
}

/// [`load`] with options.
///
/// # Errors
/// As [`load`].
pub fn load_with(path: &Path, options: &LoadOptions) -> Result<LoadedScene, SceneError> {
    match SceneFormat::of(path) {
        SceneFormat::Pbrt => crate::pbrt::load_file_with(
            path,
            &crate::pbrt::LoadOptions {
                limits: options.limits,
                ..crate::pbrt::LoadOptions::default()
            },
        ),
        SceneFormat::Mitsuba => crate::mitsuba::load_file_with(path, &options.defines, options.limits),
        SceneFormat::Obj => crate::obj_scene::load_obj_scene(path, options.limits),
        SceneFormat::Gltf => crate::gltf::load_gltf(path, options.limits),
    }
}
