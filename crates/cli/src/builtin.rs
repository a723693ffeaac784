//! The built-in scene: Bitterli's Cornell box (pbrt-v4 version), embedded in the binary so
//! `mcrender` with no arguments renders something meaningful anywhere.

/// Name used in messages about the built-in scene.
pub const NAME: &str = "cornell-box (built-in)";

/// The scene file's text.
pub const SOURCE: &str = include_str!("../../../scenes/cornell-box/scene-v4.pbrt");

/// Resolution of the default quick render.
pub const DEFAULT_RESOLUTION: (u32, u32) = (256, 256);

/// Samples per pixel of the default quick render.
pub const DEFAULT_SPP: u32 = 64;

/// Output file of the default quick render.
pub const DEFAULT_OUTPUT: &str = "cornell-box.png";
