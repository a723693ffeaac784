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
//! for all), `Integrator "path"`/`"direct"`/`"bdpt"` (others fall back to path), `Material`/
//! `MakeNamedMaterial` (see `materials`), `Texture` (constant, scale, mix, checkerboard,
//! imagemap; see `textures`) and `"texture ..."` parameters, `AreaLightSource "diffuse"`,
//! `LightSource` point/spot/distant/infinite (see `lights`), shapes `trianglemesh`,
//! `plymesh`, `sphere`, `disk`, `cylinder`, `bilinearmesh` with `alpha`, `Include`/`Import`,
//! `ObjectBegin`/`ObjectEnd`/`ObjectInstance`, `Attribute`, `Option "seed"`, `ColorSpace
//! "srgb"`. Other materials, texture classes, lights, shapes, media and motion blur are
//! errors naming the feature; the full list is `docs/pbrt-support.md`.
//!
//! Relative file names resolve as in pbrt-v4: against the directory of the top-level scene
//! file (then, as a fallback, against the directory of the including file).
//!
//! Layout: `tokenizer` splits text into tokens, `params` types parameter lists, `parser`
//! reads directives, `builder` (with `graphics_state`, `options`, `materials`, `lights`,
//! `shapes`, `textures`) gives them meaning, `crate::transform` has pbrt's transform matrices.

mod builder;
mod files;
mod graphics_state;
mod instancing;
mod lights;
mod materials;
mod options;
mod params;
mod parser;
mod shapes;
mod textures;
mod tokenizer;

use std::path::Path;
use std::sync::Arc;

use crate::error::{io_error_text, Location, SceneError};
use crate::limits::LoadLimits;
pub use crate::loaded::LoadedScene;
use crate::source::{DiskFiles, FileSource};

/// How to load: where files come from and what the load may cost.
#[derive(Clone, Debug)]
pub struct LoadOptions {
    /// The files (the disk by default; [`MemoryFiles`](crate::source::MemoryFiles) for
    /// scenes held in memory).
    pub files: Arc<dyn FileSource>,
    /// Memory limit for images and meshes.
    pub limits: LoadLimits,
}

impl Default for LoadOptions {
    fn default() -> Self {
        Self {
            files: Arc::new(DiskFiles),
            limits: LoadLimits::default(),
        }
    }
}

/// Load a pbrt-v4 scene file. Relative paths in it (`Include`, `plymesh` files) are
/// resolved against the file's directory.
///
/// # Errors
/// When the file cannot be read, or on the first malformed, invalid or unsupported input;
/// the error's display reads `file:line:col: message`.
pub fn load_file(path: &Path) -> Result<LoadedScene, SceneError> {
    load_file_with(path, &LoadOptions::default())
}

/// Load a pbrt-v4 scene file as [`load_file`] does, reading it and every file it refers to
/// from `options.files` and within `options.limits`.
///
/// # Errors
/// As [`load_file`], and when the images and meshes would pass the memory limit.
pub fn load_file_with(path: &Path, options: &LoadOptions) -> Result<LoadedScene, SceneError> {
    let name: Arc<str> = path.display().to_string().into();
    let bytes = options.files.read(path).map_err(|e| {
        SceneError::io(
            &Location::file_only(name.clone()),
            format!("cannot open scene file: {}", io_error_text(&e)),
        )
    })?;
    let source = parser::decode(&bytes, &name)?;
    let base_dir = path.parent().unwrap_or_else(|| Path::new(""));
    load_str_with(&source, &name, base_dir, options)
}

/// Load a pbrt-v4 scene from text. `name` is the file name used in messages; `base_dir`
/// resolves relative paths (`Include`, `plymesh` files).
///
/// # Errors
/// On the first malformed, invalid or unsupported input; the error's display reads
/// `name:line:col: message`.
pub fn load_str(source: &str, name: &str, base_dir: &Path) -> Result<LoadedScene, SceneError> {
    load_str_with(source, name, base_dir, &LoadOptions::default())
}

/// Load a pbrt-v4 scene from text as [`load_str`] does, with the files and limits of
/// `options`.
///
/// # Errors
/// As [`load_str`], and when the images and meshes would pass the memory limit.
pub fn load_str_with(
    source: &str,
    name: &str,
    base_dir: &Path,
    options: &LoadOptions,
) -> Result<LoadedScene, SceneError> {
    parser::Parser::new(source, name, base_dir, options).run()
}

/// The number of tokens in `source` (shown as `name` in messages): a check that the text
/// splits into pbrt tokens, for tools and the tokenizer's fuzz target.
///
/// # Errors
/// The first unterminated string or bad escape.
pub fn count_tokens(source: &str, name: &str) -> Result<usize, SceneError> {
    let mut tokens = tokenizer::Tokenizer::new(source, name.into());
    let mut n = 0;
    while tokens.next_token()?.is_some() {
        n += 1;
    }
    Ok(n)
}
