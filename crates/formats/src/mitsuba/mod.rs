//! A loader for Mitsuba 3 (and 2) XML scenes, read with `roxmltree`.
//!
//! [`load_file`] reads a scene (with `-D name=value` defines for its `$name`
//! parameters) into the same [`LoadedScene`] as the pbrt loader. Supported:
//! `<default>`, `$name`, `<include>` (cycles are errors), `<path>`, `id`/`<ref>`,
//! transforms (`translate`, `scale`, `rotate`, `matrix`, `lookat`), sensors `perspective`
//! and `thinlens` (`fov`, `fov_axis`, `to_world`), film `hdrfilm` with `box`, `tent`,
//! `gaussian` filters, samplers, integrators `path`, `direct`, `volpath` (as path) and
//! `moment` (its inner integrator; mcrender's film always records the per-pixel variance),
//! shapes (see `shapes`), BSDFs (see `bsdfs`), emitters (see `emitters`), textures (see
//! `textures`). Unsupported plugins are errors naming the element and its
//! `file:line:col`; parameters mcrender does not read are warnings. What differs from
//! Mitsuba, and why a Mitsuba test scene fails, is in `docs/mitsuba-conformance.md`.
//!
//! Conventions bridged here: Mitsuba's camera looks along +z with image x along camera
//! -x (pbrt's along +x), so the camera transform is mirrored in x; Mitsuba's `max_depth`
//! counts the camera ray (1 = emission only), mcrender's counts scattering events.

mod attributes;
mod bsdfs;
mod builder;
mod emitters;
mod images;
mod props;
mod shapes;
mod spectra;
mod textures;
mod xml;

use std::path::Path;
use std::sync::Arc;

use crate::error::SceneError;
use crate::limits::LoadLimits;
use crate::source::{DiskFiles, FileSource};
use crate::LoadedScene;

/// Load a Mitsuba XML scene; `defines` are `(name, value)` pairs that override the scene's
/// `<default>`s.
///
/// # Errors
/// On the first unreadable file, malformed XML, undefined `$name`, missing `<ref>`, cyclic
/// include, invalid value or unsupported plugin; the error's display reads
/// `file:line:col: message`.
pub fn load_file(path: &Path, defines: &[(String, String)]) -> Result<LoadedScene, SceneError> {
    load_file_with(path, defines, LoadLimits::default())
}

/// [`load_file`] within `limits`: a bitmap texture or envmap that would pass the memory
/// limit is refused from its header, before it is decoded; the images' estimated bytes are
/// [`LoadedScene::image_bytes`].
///
/// # Errors
/// As [`load_file`], and an image over the limit.
pub fn load_file_with(
    path: &Path,
    defines: &[(String, String)],
    limits: LoadLimits,
) -> Result<LoadedScene, SceneError> {
    load_file_from(path, defines, limits, Arc::new(DiskFiles))
}

/// [`load_file_with`] reading the scene and every file it names (includes, meshes,
/// images) from `files` (e.g. [`MemoryFiles`](crate::source::MemoryFiles), for fuzzing).
///
/// # Errors
/// As [`load_file_with`].
pub fn load_file_from(
    path: &Path,
    defines: &[(String, String)],
    limits: LoadLimits,
    files: Arc<dyn FileSource>,
) -> Result<LoadedScene, SceneError> {
    let mut reader = xml::Reader::new(defines, files);
    let scene = reader.read_scene(path)?;
    let dir = path.parent().unwrap_or_else(|| Path::new(""));
    builder::Builder::new(reader, dir, limits).build(&scene)
}
