//! Reading the files a scene refers to (PLY meshes, images) through the builder's
//! [`FileSource`](crate::source::FileSource), with their memory counted against the load's
//! limit *before* decoding: an image's size comes from its header, a PLY mesh's from its
//! file size.

use crate::error::{io_error_text, Location, SceneError};
use crate::image_io::{decode_image, image_dimensions, ColorEncoding, ImageError, ImageFormat, ImageRgb};
use crate::ply::{read_ply_bytes, PlyError, PlyMesh};

use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::builder::SceneBuilder;
use crate::limits::LoadLimits;
use crate::source::FileSource;

/// Peak bytes of parsing a PLY file per byte of file: `ply-rs` keeps a property map per
/// vertex and a list per face, several times the binary size.
const PLY_PARSE_BYTES_PER_FILE_BYTE: u64 = 8;

/// What an image is read for, which decides the memory it needs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageUse {
    /// A MIP-mapped texture.
    Texture,
    /// An environment light (image plus sampling distribution).
    Environment,
}

/// Where the scene's files come from and the memory the load has reserved so far.
#[derive(Debug)]
pub struct InputFiles {
    /// Where files are read from.
    pub files: Arc<dyn FileSource>,
    /// What the loader may read and allocate.
    pub limits: LoadLimits,
    /// Directory of the top-level file: pbrt resolves relative file names against it.
    pub search_dir: PathBuf,
    /// Directory of the file being parsed (tried second).
    pub current_dir: PathBuf,
    /// Bytes reserved so far for images and meshes ([`SceneBuilder::reserve_memory`]).
    pub memory_used: u64,
    /// The part of [`Self::memory_used`] that images take.
    pub image_bytes: u64,
}

impl InputFiles {
    /// Files from `files` for a scene whose top-level file lives in `search_dir`.
    #[must_use]
    pub fn new(search_dir: &Path, files: Arc<dyn FileSource>, limits: LoadLimits) -> Self {
        Self {
            files,
            limits,
            search_dir: search_dir.to_path_buf(),
            current_dir: search_dir.to_path_buf(),
            memory_used: 0,
            image_bytes: 0,
        }
    }
}

impl SceneBuilder {
    /// The bytes of the file `filename` (as written in the scene) refers to.
    fn read_scene_file(&self, filename: &str, what: &str, loc: &Location) -> Result<Vec<u8>, SceneError> {
        let path = self.resolve(filename);
        self.input
            .files
            .read(&path)
            .map_err(|e| SceneError::io(loc, format!("cannot open {what} \"{filename}\": {}", io_error_text(&e))))
    }

    /// Read and parse a PLY mesh, counting its memory.
    pub(super) fn read_ply_file(&mut self, filename: &str, loc: &Location) -> Result<PlyMesh, SceneError> {
        let path = self.resolve(filename);
        let what = format!("PLY file \"{filename}\"");
        // Parsing needs a multiple of the file size; checked before the file is read.
        let transient = self
            .input
            .files
            .len(&path)
            .unwrap_or(0)
            .saturating_mul(PLY_PARSE_BYTES_PER_FILE_BYTE);
        self.reserve_memory(transient, &what, loc)?;
        let parsed = self.read_scene_file(filename, "PLY file", loc).and_then(|bytes| {
            read_ply_bytes(&bytes).map_err(|e| match e {
                PlyError::Io(io) => SceneError::io(
                    loc,
                    format!("cannot read PLY file \"{filename}\": {}", io_error_text(&io)),
                ),
                PlyError::Format(msg) => {
                    SceneError::invalid(loc, format!("cannot read PLY file \"{filename}\": {msg}"))
                }
            })
        });
        self.input.memory_used -= transient;
        let mesh = parsed?;
        let triangles = mesh.indices.len() as u64 / 3;
        self.reserve_memory(
            crate::limits::mesh_bytes(mesh.positions.len() as u64, triangles),
            &what,
            loc,
        )?;
        Ok(mesh)
    }

    /// Read an image file for `purpose`, refusing it from its header alone when decoding it
    /// would pass the memory limit. Pixels that are not finite are an error.
    pub(super) fn read_image_file(
        &mut self,
        filename: &str,
        loc: &Location,
        encoding: ColorEncoding,
        purpose: ImageUse,
    ) -> Result<ImageRgb, SceneError> {
        let path = self.resolve(filename);
        let image_error = |e: ImageError| match e {
            ImageError::Io { source, .. } => SceneError::io(
                loc,
                format!("cannot open image \"{filename}\": {}", io_error_text(&source)),
            ),
            ImageError::Codec { message, .. } | ImageError::InvalidImage { message, .. } => {
                SceneError::invalid(loc, format!("cannot read image \"{filename}\": {message}"))
            }
            other @ ImageError::UnsupportedFormat { .. } => {
                SceneError::invalid(loc, format!("cannot read image \"{filename}\": {other}"))
            }
        };
        let format = ImageFormat::from_path(&path).map_err(image_error)?;
        let bytes = self.read_scene_file(filename, "image", loc)?;
        let (w, h) = image_dimensions(&path, format, &bytes).map_err(image_error)?;
        let need = match purpose {
            ImageUse::Texture => crate::limits::image_texture_bytes(w, h),
            ImageUse::Environment => crate::limits::env_image_bytes(w, h),
        };
        self.reserve_memory(need, &format!("image \"{filename}\" ({w}x{h})"), loc)?;
        self.input.image_bytes = self.input.image_bytes.saturating_add(need);
        let image = decode_image(&path, format, &bytes, encoding).map_err(image_error)?;
        drop(bytes);
        if image.pixels.iter().any(|p| !p.is_finite()) {
            return Err(SceneError::invalid(
                loc,
                match purpose {
                    ImageUse::Texture => format!("image \"{filename}\" has infinite or not-a-number pixels"),
                    ImageUse::Environment => format!(
                        "image \"{filename}\" has infinite or not-a-number pixels and so is not suitable as a light"
                    ),
                },
            ));
        }
        Ok(image)
    }
}
