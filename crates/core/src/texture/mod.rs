//! Layer 2: textures (pbrt-v4 chapter 10). A [`Texture<T>`] is a small tree of texture
//! nodes, shared by `Arc`, evaluated at a [`TextureContext`] (point, uv and their
//! screen-space derivatives) to a float ([`FloatTexture`]) or a linear RGB value
//! ([`RgbTexture`]). The same trees are the scene description (loaders build them; images
//! arrive already decoded to linear RGB) and what materials evaluate at render time.
//!
//! Classes: `constant`, `scale`, `mix`, `checkerboard` (2-D, box filtered), `imagemap`
//! (MIP-mapped; point, bilinear, trilinear or EWA lookups; see [`mipmap`]), `bitmap`
//! (Mitsuba's: full resolution, nearest or bilinear), `mesh_attribute` (Mitsuba's: values
//! per vertex or per face of one mesh, [`MeshAttributeTexture`]). Mappings: uv,
//! spherical, cylindrical, planar ([`TextureMapping`]).

mod alpha;
mod bitmap;
mod checkerboard;
mod context;
mod image;
mod mapping;
mod mesh_attribute;
pub mod mipmap;
mod mix;
mod scale;
#[cfg(test)]
mod tests;

use std::fmt::Debug;
use std::ops::{Add, Mul};
use std::sync::Arc;

pub use alpha::{alpha_keeps, effective_alpha};
pub use bitmap::{BitmapFilter, BitmapTexture, BitmapWrap};
pub use checkerboard::{checkerboard_weight, CheckerboardTexture};
pub use context::TextureContext;
pub use image::ImageTexture;
pub use mapping::{TexCoord2D, TextureMapping};
pub use mesh_attribute::{AttributeRate, MeshAttributeTexture};
pub use mipmap::{MipFilter, MipFilterOptions, MipLevel, MipMap, WrapMode};
pub use mix::MixTexture;
pub use scale::ScaleTexture;

use crate::color::Rgb;

/// What a texture evaluates to: `f32` or [`Rgb`].
pub trait TextureValue: Copy + Debug + PartialEq + Add<Output = Self> + Mul<f32, Output = Self> {
    /// Zero.
    const ZERO: Self;
    /// The value of an RGB texel (a float reads the first channel, as pbrt-v4).
    fn from_texel(rgb: Rgb) -> Self;
}

impl TextureValue for f32 {
    const ZERO: Self = 0.0;
    fn from_texel(rgb: Rgb) -> Self {
        rgb.r
    }
}

impl TextureValue for Rgb {
    const ZERO: Self = Rgb::BLACK;
    fn from_texel(rgb: Rgb) -> Self {
        rgb
    }
}

/// A texture: a constant or a node of the texture graph.
#[derive(Clone, Debug, PartialEq)]
pub enum Texture<T: TextureValue> {
    /// The same value everywhere.
    Constant(T),
    /// Product with a float texture.
    Scale(Arc<ScaleTexture<T>>),
    /// Interpolation of two textures.
    Mix(Arc<MixTexture<T>>),
    /// Two textures in a checkerboard.
    Checkerboard(Arc<CheckerboardTexture<T>>),
    /// A MIP-mapped image.
    Image(Arc<ImageTexture>),
    /// An unfiltered full-resolution image (Mitsuba's `bitmap`).
    Bitmap(Arc<BitmapTexture>),
    /// Values attached to the vertices or faces of one mesh (Mitsuba's `mesh_attribute`).
    MeshAttribute(Arc<MeshAttributeTexture>),
}

/// A texture of floats (roughness, mix amounts, ...).
pub type FloatTexture = Texture<f32>;
/// A texture of linear RGB values (reflectances, indices of refraction).
pub type RgbTexture = Texture<Rgb>;

impl<T: TextureValue> From<T> for Texture<T> {
    fn from(v: T) -> Self {
        Self::Constant(v)
    }
}

impl<T: TextureValue> Texture<T> {
    /// The value at `ctx`.
    #[must_use]
    pub fn evaluate(&self, ctx: &TextureContext) -> T {
        match self {
            Self::Constant(v) => *v,
            Self::Scale(t) => t.evaluate(ctx),
            Self::Mix(t) => t.evaluate(ctx),
            Self::Checkerboard(t) => t.evaluate(ctx),
            Self::Image(t) => T::from_texel(t.evaluate_rgb(ctx)),
            Self::Bitmap(t) => T::from_texel(t.evaluate_rgb(ctx)),
            Self::MeshAttribute(t) => T::from_texel(t.evaluate_rgb(ctx)),
        }
    }

    /// The value when the texture is a constant.
    #[must_use]
    pub fn constant(&self) -> Option<T> {
        match self {
            Self::Constant(v) => Some(*v),
            _ => None,
        }
    }

    /// True when the texture is a constant (needs no texture context).
    #[must_use]
    pub fn is_constant(&self) -> bool {
        matches!(self, Self::Constant(_))
    }
}
