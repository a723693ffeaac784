//! Texturable parameters and textures: a parameter is an `<rgb>`, `<spectrum>`, `<float>`,
//! a nested `<texture>` or a named `<ref>` to one. Texture plugins: `bitmap` (`filename`,
//! `raw`, `filter_type` bilinear/nearest, `wrap_mode` repeat/mirror/clamp, `to_uv` scale and
//! translation), `checkerboard` (`color0`, `color1`, `to_uv`), `rawconstant` (`value`,
//! a float or a vector, used as is) and `mesh_attribute` (`name`, `scale`; see `attributes`).
//!
//! Mitsuba's `uv` has `v` pointing down the image (row 0 at `v = 0`); mcrender's meshes
//! carry pbrt's `v = 1 - v_mitsuba` (see `shapes`) and its image textures put row 0 at
//! `t = 1`, so `to_uv` (`u' = a u + b`) becomes the uv mapping `s = a_u u + b_u`,
//! `t = a_v v + 1 - a_v - b_v`. Mitsuba's checkerboard has squares of side 0.5 with
//! `color0` where both coordinates fall in the same half; that is pbrt's (side 1, `tex1`
//! on even squares) at twice the scale.
//!
//! Bitmaps are read at full resolution without MIP mapping, as Mitsuba does
//! ([`BitmapTexture`]). Difference: mcrender's checkerboard is box filtered (Mitsuba's is
//! not), which keeps the mean over a pixel but not every detail within it.

use std::sync::Arc;

use mcrender_core::color::Rgb;
use mcrender_core::math::Mat4;
use mcrender_core::texture::{
    BitmapFilter, BitmapTexture, BitmapWrap, CheckerboardTexture, FloatTexture, RgbTexture, Texture, TextureMapping,
    TextureValue,
};

use super::builder::{Builder, Named};
use super::images::ImageUse;
use super::props::{numbers, Props};
use super::spectra::pairs_to_rgb;
use super::xml::Element;
use crate::error::SceneError;
use crate::image_io::ColorEncoding;

/// Builds textures of one value type.
trait Value: TextureValue {
    /// From an RGB constant.
    fn from_rgb(c: Rgb, e: &Element) -> Result<Self, SceneError>;
    /// From an RGB texture image.
    fn bitmap(t: BitmapTexture) -> Texture<Self>;
}

impl Value for Rgb {
    fn from_rgb(c: Rgb, _: &Element) -> Result<Self, SceneError> {
        Ok(c)
    }
    fn bitmap(t: BitmapTexture) -> Texture<Self> {
        Texture::Bitmap(Arc::new(t))
    }
}

impl Value for f32 {
    fn from_rgb(c: Rgb, e: &Element) -> Result<Self, SceneError> {
        if c.r == c.g && c.g == c.b {
            Ok(c.r)
        } else {
            Err(SceneError::invalid(
                &e.loc,
                format!("{} must be a single number here", e.describe()),
            ))
        }
    }
    fn bitmap(t: BitmapTexture) -> Texture<Self> {
        Texture::Bitmap(Arc::new(t))
    }
}

impl Builder {
    /// An RGB parameter: constant, texture or named texture; `default` when absent.
    /// `emission` selects the spectrum conversion.
    pub fn rgb_param(
        &mut self,
        p: &mut Props,
        name: &str,
        default: Rgb,
        emission: bool,
    ) -> Result<RgbTexture, SceneError> {
        match p.get(name) {
            None => Ok(default.into()),
            Some(e) => self.param::<Rgb>(e, emission),
        }
    }

    /// A float parameter: constant, texture or named texture; `default` when absent.
    pub fn float_param(&mut self, p: &mut Props, name: &str, default: f32) -> Result<FloatTexture, SceneError> {
        match p.get(name) {
            None => Ok(default.into()),
            Some(e) => self.param::<f32>(e, false),
        }
    }

    /// An emitter's constant colour (`rgb`, `spectrum` or `float`; default 1).
    pub fn emitter_color(&mut self, p: &mut Props, name: &str) -> Result<Rgb, SceneError> {
        match p.get(name) {
            None => Ok(Rgb::splat(1.0)),
            Some(e) => match self.param::<Rgb>(e, true)? {
                Texture::Constant(c) => Ok(c),
                _ => Err(SceneError::unsupported(
                    &e.loc,
                    format!("a textured {} on an emitter", e.describe()),
                )),
            },
        }
    }

    /// A texture (or colour) from its element `e` (a nested plugin of any name).
    pub fn rgb_texture(&mut self, e: &Element) -> Result<RgbTexture, SceneError> {
        self.param::<Rgb>(e, false)
    }

    fn param<T: Value>(&mut self, e: &Element, emission: bool) -> Result<Texture<T>, SceneError> {
        match e.tag.as_str() {
            "rgb" | "spectrum" | "float" => Ok(Texture::Constant(T::from_rgb(constant_color(e, emission)?, e)?)),
            "texture" => self.texture(e),
            "ref" => match self.lookup(e)? {
                Named::Texture(t) => {
                    let t = t.clone();
                    self.texture(&t)
                }
                _ => Err(SceneError::invalid(&e.loc, "this <ref> must name a texture")),
            },
            _ => Err(SceneError::syntax(
                &e.loc,
                format!("{} cannot give a colour or a number", e.describe()),
            )),
        }
    }

    fn texture<T: Value>(&mut self, e: &Element) -> Result<Texture<T>, SceneError> {
        let mut p = Props::new(e);
        let to_uv = p.transform("to_uv")?.unwrap_or(Mat4::IDENTITY);
        let (a, b) = axis_aligned(&to_uv).ok_or_else(|| {
            SceneError::unsupported(&e.loc, "a to_uv with rotation or shear (only scale and translation)")
        })?;
        let t = match e.required("type")? {
            "bitmap" => {
                let (file, floc) = p
                    .string("filename")?
                    .ok_or_else(|| SceneError::syntax(&e.loc, "a bitmap needs a \"filename\""))?;
                let raw = p.bool("raw", false)?;
                let filter = match p.string("filter_type")? {
                    None => BitmapFilter::Bilinear,
                    Some((f, l)) => match f.as_str() {
                        "bilinear" => BitmapFilter::Bilinear,
                        "nearest" => BitmapFilter::Nearest,
                        _ => {
                            return Err(SceneError::syntax(
                                &l,
                                format!("unknown filter_type \"{f}\" (expected bilinear or nearest)"),
                            ))
                        }
                    },
                };
                let wrap = match p.string("wrap_mode")? {
                    None => BitmapWrap::Repeat,
                    Some((w, l)) => match w.as_str() {
                        "repeat" => BitmapWrap::Repeat,
                        "mirror" => BitmapWrap::Mirror,
                        "clamp" => BitmapWrap::Clamp,
                        _ => {
                            return Err(SceneError::syntax(
                                &l,
                                format!("unknown wrap_mode \"{w}\" (expected repeat, mirror or clamp)"),
                            ))
                        }
                    },
                };
                let _ = p.string("format")?;
                let path = self.resolve(&file);
                let key = (path.clone(), raw);
                let (width, height, texels) = match self.images.get(&key) {
                    Some(i) => i.clone(),
                    None => {
                        let encoding = if raw {
                            ColorEncoding::Linear
                        } else {
                            ColorEncoding::Srgb
                        };
                        let img = self.read_image_counted(&file, "image", encoding, ImageUse::Texture, &floc)?;
                        let i = (img.width, img.height, Arc::new(img.pixels));
                        self.images.insert(key, i.clone());
                        i
                    }
                };
                T::bitmap(BitmapTexture {
                    mapping: TextureMapping::Uv {
                        su: a[0],
                        sv: a[1],
                        du: b[0],
                        dv: 1.0 - a[1] - b[1],
                    },
                    width,
                    height,
                    texels,
                    filter,
                    wrap,
                })
            }
            "checkerboard" => {
                let c0 = self.param_or::<T>(&mut p, "color0", 0.4)?;
                let c1 = self.param_or::<T>(&mut p, "color1", 0.2)?;
                Texture::Checkerboard(Arc::new(CheckerboardTexture {
                    mapping: TextureMapping::Uv {
                        su: 2.0 * a[0],
                        sv: -2.0 * a[1],
                        du: 2.0 * b[0],
                        dv: 2.0 * (a[1] + b[1]),
                    },
                    tex1: c0,
                    tex2: c1,
                }))
            }
            "rawconstant" => {
                // A constant taken as is (no colour conversion): a `float` or a `vector`.
                let c = match p.get("value") {
                    Some(v) if v.tag == "float" => Rgb::splat(super::props::scalar(v, &["float"])?),
                    Some(_) => {
                        let v = p.vec3("value")?.unwrap_or_default();
                        Rgb::new(v.x, v.y, v.z)
                    }
                    None => return Err(SceneError::syntax(&e.loc, "a rawconstant needs a \"value\"")),
                };
                Texture::Constant(T::from_rgb(c, e)?)
            }
            "mesh_attribute" => self.mesh_attribute_texture::<T>(e, &mut p)?,
            _ => {
                return Err(Builder::unsupported(
                    e,
                    " (textures: bitmap, checkerboard, rawconstant, mesh_attribute)",
                ));
            }
        };
        self.finish(&p);
        Ok(t)
    }

    fn param_or<T: Value>(&mut self, p: &mut Props, name: &str, default: f32) -> Result<Texture<T>, SceneError> {
        match p.get(name) {
            None => Ok(Texture::Constant(T::from_rgb(Rgb::splat(default), p.el)?)),
            Some(e) => self.param::<T>(e, false),
        }
    }
}

/// The constant of an `<rgb>`, `<spectrum>` or `<float>` element.
pub fn constant_color(e: &Element, emission: bool) -> Result<Rgb, SceneError> {
    if e.tag == "spectrum" && e.attr("filename").is_some() {
        return Err(SceneError::unsupported(&e.loc, "a <spectrum> read from a file"));
    }
    let value = e.required("value")?;
    if e.tag == "spectrum" && value.contains(':') {
        let mut pairs = Vec::new();
        for item in value.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            let (l, v) = item
                .split_once(':')
                .ok_or_else(|| SceneError::syntax(&e.loc, format!("expected wavelength:value, found \"{item}\"")))?;
            let l: f32 = l
                .trim()
                .parse()
                .map_err(|_| SceneError::syntax(&e.loc, format!("bad wavelength \"{l}\"")))?;
            let v: f32 = v
                .trim()
                .parse()
                .map_err(|_| SceneError::syntax(&e.loc, format!("bad value \"{v}\"")))?;
            pairs.push((l, v));
        }
        if pairs.is_empty() || pairs.windows(2).any(|w| w[1].0 <= w[0].0) {
            return Err(SceneError::invalid(&e.loc, "spectrum wavelengths must increase"));
        }
        return Ok(pairs_to_rgb(&pairs, emission));
    }
    let n = numbers(e, value)?;
    match (e.tag.as_str(), n.as_slice()) {
        (_, [v]) => Ok(Rgb::splat(*v)),
        ("rgb", [r, g, b]) => Ok(Rgb::new(*r, *g, *b)),
        _ => Err(SceneError::syntax(
            &e.loc,
            format!("{} needs 1 or 3 numbers", e.describe()),
        )),
    }
}

/// `(scale, offset)` of a 2-D `to_uv` without rotation or shear.
fn axis_aligned(m: &Mat4) -> Option<([f32; 2], [f32; 2])> {
    let c = m.to_cols_array_2d();
    (c[1][0] == 0.0 && c[0][1] == 0.0).then_some(([c[0][0], c[1][1]], [c[3][0], c[3][1]]))
}
