//! Entry points shared by the cargo-fuzz targets (`fuzz/fuzz_targets/*.rs`) and the test
//! that replays their corpus (`tests/fuzz_corpus.rs`), so that what the fuzzer found is
//! checked by a plain `cargo test` through exactly the same code. Each takes arbitrary
//! bytes and must return, whatever they are: no panic, no abort, no hang, and memory within
//! [`MEMORY_LIMIT`].

use std::path::Path;
use std::sync::Arc;

use crate::image_io::{decode_image, image_dimensions, ColorEncoding, ImageFormat};
use crate::limits::{image_texture_bytes, LoadLimits};
use crate::pbrt::{load_file_with, LoadOptions};
use crate::source::MemoryFiles;

/// Memory the loader may use for images and meshes in a fuzz run.
pub const MEMORY_LIMIT: u64 = 256 << 20;

/// The targets, by the name of their fuzz target and corpus directory.
pub const TARGETS: &[&str] = &[
    "tokenizer",
    "parser",
    "loader",
    "ply",
    "png",
    "exr",
    "pfm",
    "tga",
    "obj",
    "gltf",
    "mitsuba",
];

/// Run `data` through the target named `target` (one of [`TARGETS`]).
///
/// # Panics
/// On an unknown target name (and, by the bug it reveals, on any input that panics).
pub fn run(target: &str, data: &[u8]) {
    match target {
        "tokenizer" => tokenizer(data),
        "parser" => parser(data),
        "loader" => loader(data),
        "ply" => ply(data),
        "png" => image(ImageFormat::Png, data),
        "exr" => image(ImageFormat::Exr, data),
        "pfm" => image(ImageFormat::Pfm, data),
        "tga" => image(ImageFormat::Tga, data),
        "obj" => obj(data),
        "gltf" => gltf(data),
        "mitsuba" => mitsuba(data),
        other => panic!("unknown fuzz target {other}"),
    }
}

/// Split text into pbrt tokens, and print every error as the command line would.
pub fn tokenizer(data: &[u8]) {
    if let Ok(text) = std::str::from_utf8(data) {
        if let Err(e) = crate::pbrt::count_tokens(text, "fuzz.pbrt") {
            check_message(&e.to_string());
        }
    }
}

/// Parse and build a scene with no other files.
pub fn parser(data: &[u8]) {
    let mut files = MemoryFiles::new();
    files.insert("fuzz.pbrt", data.to_vec());
    load(files);
}

/// Marker that starts each extra file in a [`loader`] input: `\n--8<-- NAME\n` then the
/// file's bytes up to the next marker.
pub const FILE_MARKER: &[u8] = b"\n--8<-- ";

/// Load a scene with the files it refers to, all in memory: the input is the scene text,
/// then any number of `FILE_MARKER NAME\n BYTES` parts (PLY meshes, images, includes).
pub fn loader(data: &[u8]) {
    load(split_files(data));
}

/// The in-memory file set of a [`loader`] input: `fuzz.pbrt` and the named parts.
#[must_use]
pub fn split_files(data: &[u8]) -> MemoryFiles {
    split_files_with_top(data, "fuzz.pbrt")
}

/// The in-memory file set of an input whose first part is the file `top`.
#[must_use]
pub fn split_files_with_top(data: &[u8], top: &str) -> MemoryFiles {
    let mut files = MemoryFiles::new();
    let mut parts = split(data, FILE_MARKER).into_iter();
    files.insert(top, parts.next().unwrap_or_default().to_vec());
    for part in parts {
        let (name, bytes) = match part.iter().position(|&b| b == b'\n') {
            Some(i) => (&part[..i], &part[i + 1..]),
            None => (part, &[][..]),
        };
        files.insert(String::from_utf8_lossy(name).trim(), bytes.to_vec());
    }
    files
}

fn split<'a>(data: &'a [u8], marker: &[u8]) -> Vec<&'a [u8]> {
    let mut parts = Vec::new();
    let mut start = 0;
    let mut i = 0;
    while i + marker.len() <= data.len() {
        if &data[i..i + marker.len()] == marker {
            parts.push(&data[start..i]);
            i += marker.len();
            start = i;
        } else {
            i += 1;
        }
    }
    parts.push(&data[start..]);
    parts
}

fn load(files: MemoryFiles) {
    let options = LoadOptions {
        files: Arc::new(files),
        limits: LoadLimits {
            max_memory: MEMORY_LIMIT,
        },
    };
    match load_file_with(Path::new("fuzz.pbrt"), &options) {
        Ok(scene) => {
            // What the renderer would do next: build the render-ready scene.
            if let Err(e) = mcrender_core::scene::Scene::build(&scene.description) {
                check_message(&e.to_string());
            }
        }
        Err(e) => check_message(&e.to_string()),
    }
}

/// A directory no fuzz input can name files in: the OBJ and glTF targets read no files.
const NO_DIR: &str = "/nonexistent-mcrender-fuzz-dir";

/// An OBJ scene: the OBJ text, then optionally `FILE_MARKER scene.mtl\n` and the MTL text.
pub fn obj(data: &[u8]) {
    let parts = split(data, FILE_MARKER);
    let mtl = parts.get(1).map(|p| match p.iter().position(|&b| b == b'\n') {
        Some(i) => &p[i + 1..],
        None => &[][..],
    });
    built(crate::obj_scene::load_obj_scene_bytes(
        parts[0],
        mtl,
        "fuzz.obj",
        Path::new(NO_DIR),
        LoadLimits {
            max_memory: MEMORY_LIMIT,
        },
    ));
}

/// A glTF document (JSON or GLB) with embedded buffers and images.
pub fn gltf(data: &[u8]) {
    let limits = LoadLimits {
        max_memory: MEMORY_LIMIT,
    };
    built(crate::gltf::load_gltf_slice(
        data,
        "fuzz.gltf",
        Path::new(NO_DIR),
        limits,
    ));
}

/// The name of a [`mitsuba`] input's scene file.
pub const MITSUBA_SCENE: &str = "fuzz.xml";

/// Load a Mitsuba XML scene with the files it names, all in memory: the input is the XML
/// text (the file [`MITSUBA_SCENE`]), then any number of `FILE_MARKER NAME\n BYTES` parts
/// (includes, OBJ, MTL and PLY meshes, images), as for [`loader`].
pub fn mitsuba(data: &[u8]) {
    let limits = LoadLimits {
        max_memory: MEMORY_LIMIT,
    };
    let files = Arc::new(split_files_with_top(data, MITSUBA_SCENE));
    built(crate::mitsuba::load_file_from(
        Path::new(MITSUBA_SCENE),
        &[],
        limits,
        files,
    ));
}

/// Build the render-ready scene of a loaded one, checking every error message.
fn built(loaded: Result<crate::pbrt::LoadedScene, crate::error::SceneError>) {
    match loaded {
        Ok(scene) => {
            if let Err(e) = mcrender_core::scene::Scene::build(&scene.description) {
                check_message(&e.to_string());
            }
        }
        Err(e) => check_message(&e.to_string()),
    }
}

/// Read a PLY mesh.
pub fn ply(data: &[u8]) {
    if let Err(e) = crate::ply::read_ply_bytes(data) {
        check_message(&e.to_string());
    }
}

/// Decode an image as the loader does: header first, refused when too large, then decoded.
pub fn image(format: ImageFormat, data: &[u8]) {
    let path = Path::new("fuzz.img");
    match image_dimensions(path, format, data) {
        Ok((w, h)) if image_texture_bytes(w, h) <= MEMORY_LIMIT => {
            if let Ok(img) = decode_image(path, format, data, ColorEncoding::Srgb) {
                assert_eq!(img.pixels.len() as u64, u64::from(img.width) * u64::from(img.height));
            }
        }
        Ok(_) => {}
        Err(e) => check_message(&e.to_string()),
    }
}

/// Error messages are one line without control characters, and short.
fn check_message(message: &str) {
    assert!(
        !message.chars().any(char::is_control),
        "control character in message: {message:?}"
    );
    assert!(message.len() < 4000, "message of {} bytes", message.len());
}
