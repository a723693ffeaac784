//! What every loader returns.

use mcrender_core::scene::SceneDescription;

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
    /// Estimated bytes the images read (textures, environment maps) take while loading and
    /// rendering; the meshes are in [`Self::description`].
    pub image_bytes: u64,
}
