//! mcrender-formats: loaders that turn scene files into the plain
//! [`SceneDescription`](mcrender_core::scene::SceneDescription) the core renders, and the
//! image writers and readers (PNG, EXR).
//!
//! * [`pbrt`]: the pbrt-v4 scene format ([`pbrt::load_file`], [`pbrt::load_str`]);
//! * [`load`]: the front door, any format by extension;
//! * [`mitsuba`]: Mitsuba 3 XML scenes ([`mitsuba::load_file`]);
//! * [`obj`]: Wavefront OBJ meshes; [`obj_scene`]: an OBJ file as a whole scene;
//! * [`gltf`]: glTF 2.0 scenes (`.gltf`, `.glb`);
//! * [`ply`]: PLY triangle meshes (used by pbrt's `plymesh`); [`serialized`]: Mitsuba's
//!   compressed meshes;
//! * shared by the loaders: [`LoadedScene`] (what each returns), [`spectra`] (spectra to
//!   RGB), [`transform`] (transform matrices), [`image_io`], [`limits`], [`source`];
//! * [`image_io`]: [`image_io::write_image`] (PNG or EXR by extension, written atomically),
//!   [`image_io::write_exr_layers`], [`image_io::read_image`] (EXR, PFM, PNG, JPEG, TGA).

mod error;
mod framing;
pub mod fuzzing;
pub mod gltf;
pub mod image_io;
pub mod limits;
mod load;
mod loaded;
pub mod mitsuba;
pub mod obj;
pub mod obj_scene;
pub mod pbrt;
pub mod ply;
pub mod serialized;
pub mod source;
pub mod spectra;
pub mod transform;

pub use error::{escape_control, io_error_text, quoted, tidy_message, Location, SceneError, SceneErrorKind};
pub use image_io::{read_exr, read_image, read_pfm, write_exr_layers, write_image, write_images, ImageError, ImageRgb};
pub use load::{load, load_with, LoadOptions, SceneFormat};
pub use loaded::LoadedScene;
pub use pbrt::{load_file, load_file_with, load_str, load_str_with};
