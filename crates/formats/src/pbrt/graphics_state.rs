//! The graphics state that `AttributeBegin`/`AttributeEnd` save and restore: the current
//! transformation matrix, `ReverseOrientation`, the current material and area light, and
//! the parameters set by `Attribute` directives.

use glam::Mat4;
use mcrender_core::color::Rgb;
use mcrender_core::material::DiffuseMaterial;
use mcrender_core::scene::{AreaLightDesc, FloatTexture, MaterialDesc, RgbTexture};

use super::params::Param;
use crate::error::Location;

/// The material shapes get: a material given inline by `Material`, or a name from
/// `NamedMaterial`, resolved when the whole file has been read (as pbrt does, so the
/// definition may come later in the file).
#[derive(Clone, Debug, PartialEq)]
pub enum MaterialRef {
    /// `Material "type" ...` (or the default material).
    Inline(MaterialDesc),
    /// `NamedMaterial "name"`, with where it was selected.
    Named {
        /// The name.
        name: String,
        /// Location of the `NamedMaterial` directive.
        loc: Location,
    },
    /// A material under pbrt-v4's `displacement` or `normalmap` (interned as the inner
    /// material and a wrapper naming it).
    Framed {
        /// The material shaded in the moved frame.
        inner: MaterialDesc,
        /// How the frame moves.
        frame: FrameMap,
    },
    /// A `mix` of two named materials, resolved like [`MaterialRef::Named`].
    Mix {
        /// The names of the two materials.
        names: [String; 2],
        /// Probability of the second.
        amount: FloatTexture,
        /// Location of the `materials` parameter.
        loc: Location,
    },
}

/// Parameters set by `Attribute "target" ...`, per target.
#[derive(Clone, Debug, Default)]
pub struct Attributes {
    /// `Attribute "shape"`
    pub shape: Vec<Param>,
    /// `Attribute "light"`
    pub light: Vec<Param>,
    /// `Attribute "material"`
    pub material: Vec<Param>,
    /// `Attribute "medium"`
    pub medium: Vec<Param>,
    /// `Attribute "texture"`
    pub texture: Vec<Param>,
}

/// The state scoped by `AttributeBegin`/`AttributeEnd`.
#[derive(Clone, Debug)]
pub struct GraphicsState {
    /// Current transformation matrix (object to world inside the world block).
    pub ctm: Mat4,
    /// `ReverseOrientation` toggled an odd number of times.
    pub reverse_orientation: bool,
    /// Material for subsequent shapes.
    pub material: MaterialRef,
    /// Area light for subsequent shapes.
    pub area_light: Option<AreaLightDesc>,
    /// Parameters from `Attribute`.
    pub attributes: Attributes,
}

impl Default for GraphicsState {
    fn default() -> Self {
        Self {
            ctm: Mat4::IDENTITY,
            reverse_orientation: false,
            // pbrt-v4's material before any Material directive: diffuse, reflectance 0.5.
            material: MaterialRef::Inline(MaterialDesc::Diffuse(DiffuseMaterial {
                reflectance: Rgb::splat(0.5).into(),
            })),
            area_light: None,
            attributes: Attributes::default(),
        }
    }
}

/// pbrt-v4's per-material shading-frame parameters.
#[derive(Clone, Debug, PartialEq)]
pub enum FrameMap {
    /// `texture displacement` (or `float displacement`): a bump map.
    Displacement(FloatTexture),
    /// `string normalmap`: the image, linear, as a bilinear repeating bitmap.
    NormalMap(RgbTexture),
}
