//! A loader for the pbrt-v4 scene format (the subset mcrender renders so far).
//!
//! [`load_file`] and [`load_str`] parse a scene into a
//! [`SceneDescription`], plus the output file name
//! from `Film` and warnings for everything that was accepted but ignored. Anything that
//! would change the image and is not supported is an error naming the feature and its
//! `file:line:column`.
//!
//! Supported now: the transform directives, `CoordinateSystem`/`CoordSysTransform`,
//! attribute scopes (`TransformBegin`/`End` as in pbrt-v4), `ReverseOrientation`,
//! `Camera "perspective"`, `Film "rgb"`, `PixelFilter` box/triangle/gaussian, `Sampler`
//! independent/stratified and the low-discrepancy ones (one Owen-scrambled Sobol' sampler
//! for all), `Integrator "path"`/`"direct"` (others fall back to path), `Material`/
//! `MakeNamedMaterial` (see `materials`), `Texture` (constant, scale, mix, checkerboard,
//! imagemap; see `textures`) and `"texture ..."` parameters, `AreaLightSource "diffuse"`,
//! `LightSource` point/spot/distant/infinite (see `lights`), shapes `trianglemesh`,
//! `plymesh`, `sphere`, `disk`, `bilinearmesh` with `alpha`, `Include`/`Import`,
//! `ObjectBegin`/`ObjectEnd`/`ObjectInstance`, `Attribute`, `Option "seed"`, `ColorSpace
//! "srgb"`. Other materials, texture classes, lights, shapes, media and motion blur are
//! errors naming the feature; the full list is `docs/pbrt-support.md`.
//!
//! Relative file names resolve as in pbrt-v4: against the directory of the top-level scene
//! file (then, as a fallback, against the directory of the including file).
//!
//! Layout: `tokenizer` splits text into tokens, `params` types parameter lists, `parser`
//! reads directives, `builder` (with `graphics_state`, `options`, `materials`, `lights`,
//! `shapes`, `textures`) gives them meaning, `transform` has pbrt's transform matrices.

mod builder;
mod graphics_state;
mod instancing;
mod lights;
mod materials;
mod options;
mod params;
mod parser;
mod shapes;
pub(crate) mod spectra;
pub(crate) mod spectrum_rgb;
mod textures;
mod tokenizer;
mod transform;

use std::path::Path;
use std::sync::Arc;

use mcrender_core::scene::SceneDescription;

use crate::error::{io_error_text, Location, SceneError};

/// A loaded scene: what the renderer needs, where pbrt would write the image, and the
/// warnings to show the user.
#[derive(Clone, Debug)]
pub struct LoadedScene {
    /// The scene.
    pub description: SceneDescription,
    /// `Film "string filename"`, when given (as written in the file).
    pub output_filename: Option<String>,
    /// Warnings, each `file:line:col: warning: ...`.
    pub warnings: Vec<String>,
}

/// Load a pbrt-v4 scene file. Relative paths in it (`Include`, `plymesh` files) are
/// resolved against the file's directory.
///
/// # Errors
/// When the file cannot be read, or on the first malformed, invalid or unsupported input;
/// the error's display reads `file:line:col: message`.
pub fn load_file(path: &Path) -> Result<LoadedScene, SceneError> {
    let name: Arc<str> = path.display().to_string().into();
    let bytes = std::fs::read(path).map_err(|e| {
        SceneError::io(
            &Location::file_only(name.clone()),
            format!("cannot open scene file: {}", io_error_text(&e)),
        )
    })?;
    let source = parser::decode(&bytes, &name)?;
    let base_dir = path.parent().unwrap_or_else(|| Path::new(""));
    load_str(&source, &name, base_dir)
}

/// Load a pbrt-v4 scene from text. `name` is the file name used in messages; `base_dir`
/// resolves relative paths (`Include`, `plymesh` files).
///
/// # Errors
/// On the first malformed, invalid or unsupported input; the error's display reads
/// `name:line:col: message`.
pub fn load_str(source: &str, name: &str, base_dir: &Path) -> Result<LoadedScene, SceneError> {
    parser::Parser::new(source, name, base_dir).run()
}
