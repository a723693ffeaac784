//! Textures: `Texture "name" "float"|"spectrum" "class" ...` and the `"texture ..."` form
//! of texturable material parameters.
//!
//! Classes (pbrt-v4 semantics; see `mcrender_core::texture`):
//! - `constant`: `value` (default 1).
//! - `scale`: `tex` (default 1) times the float texture `scale` (default 1).
//! - `mix`: `(1 - amount) tex1 + amount tex2`; `tex1` 0, `tex2` 1, float texture
//!   `amount` 0.5.
//! - `checkerboard`: `tex1` (default 1) on even squares, `tex2` (default 0) on odd ones,
//!   box filtered; `dimension` 2 only (3 is reported as not supported).
//! - `imagemap`: `filename` (EXR, PFM, PNG, JPEG, TGA; each file decoded and MIP-mapped
//!   once per encoding and wrap mode), `filter` (`point`, `bilinear` (default),
//!   `trilinear`, `ewa`/`EWA`), `wrap` (`repeat` (default), `black`, `clamp`,
//!   `octahedralsphere`), `scale` (1), `invert` (false), `encoding` (`sRGB`, `linear` or
//!   `gamma g`; default sRGB for PNG and linear for the others, as pbrt-v4), `maxanisotropy` (8). Float image textures read the red channel.
//!
//! The 2-D classes take `mapping` `uv` (default; `uscale`, `vscale`, `udelta`, `vdelta`),
//! `spherical`, `cylindrical` or `planar` (`v1`, `v2`, `udelta`, `vdelta`), the last three
//! in the space of the CTM at the `Texture` directive. Texture names are global per type
//! (float and spectrum), as in pbrt-v4; redefining one is an error. Values of the tree's
//! parameters may themselves be `"texture ..."` references of the right type.
//!
//! Not supported (error naming them): `bilerp`, `directionmix`, `dots`, `fbm`, `marble`,
//! `ptex`, `windy`, `wrinkled`.

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;

use mcrender_core::color::Rgb;
use mcrender_core::math::{Transform, Vec3};
use mcrender_core::texture::{
    CheckerboardTexture, FloatTexture, ImageTexture, MipFilter, MipFilterOptions, MipMap, MixTexture, RgbTexture,
    ScaleTexture, Texture, TextureMapping, TextureValue, WrapMode,
};

use super::builder::SceneBuilder;
use super::files::ImageUse;
use super::params::{color_of, Param, ParamSet, ParamType, ParamValues};
use crate::error::{Location, SceneError};
use crate::image_io::ColorEncoding;
use crate::spectra::SpectrumRole;

/// pbrt-v4 texture classes that are not implemented.
const KNOWN_CLASSES: &[&str] = &[
    "bilerp",
    "directionmix",
    "dots",
    "fbm",
    "marble",
    "ptex",
    "windy",
    "wrinkled",
];

/// The named textures defined so far, and the MIP maps of the image files read.
#[derive(Debug, Default)]
pub struct NamedTextures {
    float: HashMap<String, (FloatTexture, Location)>,
    rgb: HashMap<String, (RgbTexture, Location)>,
    mipmaps: HashMap<(PathBuf, String, WrapModeKey), Arc<MipMap>>,
}

/// [`WrapMode`] as a hash key.
type WrapModeKey = u8;

/// A texture value type as the loader sees it: its pbrt name and how its parameters read.
trait LoaderValue: TextureValue {
    /// `float` or `spectrum`.
    const TYPE: &'static str;
    /// The named textures of this type.
    fn table(t: &NamedTextures) -> &HashMap<String, (Texture<Self>, Location)>;
    /// The named textures of this type, for definition.
    fn table_mut(t: &mut NamedTextures) -> &mut HashMap<String, (Texture<Self>, Location)>;
    /// The names of the other type, for a helpful error.
    fn other_has(t: &NamedTextures, name: &str) -> bool;
    /// A constant given as a plain parameter (`float` or `rgb`), when `p` is one.
    fn constant(p: &Param, owner: &str) -> Result<Self, SceneError>;
    /// The parameter types this value accepts besides `texture`.
    const PLAIN: &'static [ParamType];
}

impl LoaderValue for f32 {
    const TYPE: &'static str = "float";
    const PLAIN: &'static [ParamType] = &[ParamType::Float];
    fn table(t: &NamedTextures) -> &HashMap<String, (Texture<Self>, Location)> {
        &t.float
    }
    fn table_mut(t: &mut NamedTextures) -> &mut HashMap<String, (Texture<Self>, Location)> {
        &mut t.float
    }
    fn other_has(t: &NamedTextures, name: &str) -> bool {
        t.rgb.contains_key(name)
    }
    fn constant(p: &Param, _owner: &str) -> Result<Self, SceneError> {
        p.expect_single()?;
        Ok(p.floats()[0])
    }
}

impl LoaderValue for Rgb {
    const TYPE: &'static str = "spectrum";
    const PLAIN: &'static [ParamType] = &[ParamType::Rgb, ParamType::Spectrum, ParamType::Blackbody];
    fn table(t: &NamedTextures) -> &HashMap<String, (Texture<Self>, Location)> {
        &t.rgb
    }
    fn table_mut(t: &mut NamedTextures) -> &mut HashMap<String, (Texture<Self>, Location)> {
        &mut t.rgb
    }
    fn other_has(t: &NamedTextures, name: &str) -> bool {
        t.float.contains_key(name)
    }
    fn constant(p: &Param, owner: &str) -> Result<Self, SceneError> {
        if p.ty == ParamType::Spectrum && !matches!(p.values, ParamValues::Floats(_)) {
            return Err(SceneError::unsupported(
                &p.loc,
                format!(
                    "\"{}\" of {owner} (a named spectrum) is not supported yet; give \"rgb {}\", \"spectrum {}\" as (wavelength, value) pairs or \"texture {}\"",
                    p.decl(),
                    p.name,
                    p.name,
                    p.name
                ),
            ));
        }
        // Texture values may be indices as well as albedos: not clamped here (materials
        // clamp their reflectances).
        let c = color_of(p, owner, SpectrumRole::Unbounded)?;
        if c.to_array().iter().any(|v| *v < 0.0) {
            return Err(SceneError::invalid(
                &p.loc,
                format!("\"{}\" of {owner} must not be negative", p.decl()),
            ));
        }
        Ok(c)
    }
}

impl NamedTextures {
    /// The texture a `"texture name" "tex"` parameter `p` refers to.
    fn resolve<T: LoaderValue>(&self, p: &Param, owner: &str) -> Result<Texture<T>, SceneError> {
        p.expect_single()?;
        let tex = &p.strings()[0];
        if let Some((t, _)) = T::table(self).get(tex) {
            return Ok(t.clone());
        }
        let other = if T::TYPE == "float" { "spectrum" } else { "float" };
        if T::other_has(self, tex) {
            return Err(SceneError::invalid(
                &p.loc,
                format!(
                    "\"{}\" of {owner} needs a {} texture, but texture \"{tex}\" is a {other} texture",
                    p.decl(),
                    T::TYPE
                ),
            ));
        }
        Err(SceneError::invalid(
            &p.loc,
            format!(
                "\"{}\" of {owner} refers to texture \"{tex}\", which is not defined (define it with Texture \"{tex}\" \"{}\" ... first)",
                p.decl(),
                T::TYPE
            ),
        ))
    }

    /// The parameter `name` of `params` as a texture: a plain value or a `texture`
    /// reference; `None` when absent.
    fn param<T: LoaderValue>(&self, params: &ParamSet, name: &str) -> Result<Option<Texture<T>>, SceneError> {
        let mut accepted = T::PLAIN.to_vec();
        accepted.push(ParamType::Texture);
        let Some(p) = params.lookup(name, &accepted)? else {
            return Ok(None);
        };
        if p.ty == ParamType::Texture {
            self.resolve(p, &params.owner).map(Some)
        } else {
            T::constant(p, &params.owner).map(|v| Some(Texture::Constant(v)))
        }
    }

    /// A float-texture parameter (`float` or `texture`), `default` when absent.
    ///
    /// # Errors
    /// Wrong type, unknown texture or a spectrum texture.
    pub fn float(&self, params: &ParamSet, name: &str, default: f32) -> Result<FloatTexture, SceneError> {
        Ok(self.param(params, name)?.unwrap_or(Texture::Constant(default)))
    }

    /// A spectrum-texture parameter given as `rgb` or `texture`; `None` when absent.
    ///
    /// # Errors
    /// Wrong type, unknown texture or a float texture; `spectrum` and `blackbody` values
    /// are reported as not supported.
    pub fn rgb(&self, params: &ParamSet, name: &str) -> Result<Option<RgbTexture>, SceneError> {
        self.param(params, name)
    }

    /// The spectrum texture a `texture` parameter `p` of `owner` names.
    ///
    /// # Errors
    /// Unknown texture or a float texture.
    pub fn rgb_reference(&self, p: &Param, owner: &str) -> Result<RgbTexture, SceneError> {
        self.resolve(p, owner)
    }
}

impl SceneBuilder {
    /// `Texture "name" "type" "class" ...`: define a named float or spectrum texture.
    pub fn texture(
        &mut self,
        name: &str,
        (ty, ty_loc): (&str, &Location),
        class: &str,
        params: &mut ParamSet,
        loc: &Location,
    ) -> Result<(), SceneError> {
        self.require_world("Texture", loc)?;
        params.add_inherited(&self.state.attributes.texture);
        match ty {
            "float" => self.define_texture::<f32>(name, class, params, loc),
            "spectrum" => self.define_texture::<Rgb>(name, class, params, loc),
            _ => Err(SceneError::syntax(
                ty_loc,
                format!("texture type \"{ty}\" of Texture \"{name}\": expected \"float\" or \"spectrum\""),
            )),
        }
    }

    /// Build and name a texture of value type `T`.
    fn define_texture<T: LoaderValue>(
        &mut self,
        name: &str,
        class: &str,
        params: &ParamSet,
        loc: &Location,
    ) -> Result<(), SceneError> {
        if let Some((_, first)) = T::table(&self.world.textures).get(name) {
            return Err(SceneError::invalid(
                loc,
                format!("{} texture \"{name}\" is already defined at {first}", T::TYPE),
            ));
        }
        let one = || T::from_texel(Rgb::WHITE);
        let t = &self.world.textures;
        let tex: Texture<T> = match class {
            "constant" => t.param(params, "value")?.unwrap_or(Texture::Constant(one())),
            "scale" => {
                let tex = t.param(params, "tex")?.unwrap_or(Texture::Constant(one()));
                let scale = t.float(params, "scale", 1.0)?;
                match (tex.constant(), scale.constant()) {
                    (Some(v), Some(s)) => Texture::Constant(v * s),
                    _ => Texture::Scale(Arc::new(ScaleTexture { tex, scale })),
                }
            }
            "mix" => Texture::Mix(Arc::new(MixTexture {
                tex1: t.param(params, "tex1")?.unwrap_or(Texture::Constant(T::ZERO)),
                tex2: t.param(params, "tex2")?.unwrap_or(Texture::Constant(one())),
                amount: t.float(params, "amount", 0.5)?,
            })),
            "checkerboard" => {
                let dimension = params.int("dimension", 2)?;
                if dimension != 2 {
                    let p = params.get("dimension").map_or(loc, |p| &p.loc);
                    return Err(if dimension == 3 {
                        SceneError::unsupported(p, "3-D checkerboard textures (\"dimension\" 3) are not supported yet")
                    } else {
                        SceneError::invalid(p, format!("checkerboard \"dimension\" must be 2 or 3, found {dimension}"))
                    });
                }
                Texture::Checkerboard(Arc::new(CheckerboardTexture {
                    mapping: self.mapping(params)?,
                    tex1: t.param(params, "tex1")?.unwrap_or(Texture::Constant(one())),
                    tex2: t.param(params, "tex2")?.unwrap_or(Texture::Constant(T::ZERO)),
                }))
            }
            "imagemap" => Texture::Image(Arc::new(self.image_texture(params, loc)?)),
            _ if KNOWN_CLASSES.contains(&class) => {
                return Err(SceneError::unsupported(
                    loc,
                    format!("texture class \"{class}\" (Texture \"{name}\") is not supported yet"),
                ))
            }
            _ => {
                return Err(SceneError::syntax(
                    loc,
                    format!("unknown texture class \"{class}\" of Texture \"{name}\" (expected constant, scale, mix, checkerboard or imagemap)"),
                ))
            }
        };
        self.warn_unused(params);
        T::table_mut(&mut self.world.textures).insert(name.to_string(), (tex, loc.clone()));
        Ok(())
    }

    /// The 2-D mapping of a texture (`"string mapping"` and its parameters).
    fn mapping(&self, params: &ParamSet) -> Result<TextureMapping, SceneError> {
        let (kind, kind_loc) = params
            .string("mapping")?
            .unwrap_or_else(|| ("uv".to_string(), params.loc.clone()));
        let texture_from_world = || -> Result<Transform, SceneError> {
            Ok(self.ctm_transform("the texture mapping", &params.loc)?.inverse())
        };
        Ok(match kind.as_str() {
            "uv" => TextureMapping::Uv {
                su: params.float("uscale", 1.0)?,
                sv: params.float("vscale", 1.0)?,
                du: params.float("udelta", 0.0)?,
                dv: params.float("vdelta", 0.0)?,
            },
            "spherical" => TextureMapping::Spherical {
                texture_from_world: texture_from_world()?,
            },
            "cylindrical" => TextureMapping::Cylindrical {
                texture_from_world: texture_from_world()?,
            },
            "planar" => TextureMapping::Planar {
                texture_from_world: texture_from_world()?,
                vs: vector3(params, "v1", Vec3::X)?,
                vt: vector3(params, "v2", Vec3::Y)?,
                ds: params.float("udelta", 0.0)?,
                dt: params.float("vdelta", 0.0)?,
            },
            _ => {
                return Err(SceneError::syntax(
                    &kind_loc,
                    format!(
                        "unknown texture mapping \"{kind}\" of {} (expected uv, spherical, cylindrical or planar)",
                        params.owner
                    ),
                ))
            }
        })
    }

    /// An `imagemap` texture: read (or reuse) the image's MIP map and the lookup settings.
    fn image_texture(&mut self, params: &ParamSet, loc: &Location) -> Result<ImageTexture, SceneError> {
        let Some((filename, file_loc)) = params.string("filename")? else {
            return Err(SceneError::syntax(
                loc,
                format!("{} needs a \"string filename\" parameter", params.owner),
            ));
        };
        let filter = match params.string("filter")? {
            None => MipFilter::Bilinear,
            Some((f, f_loc)) => match f.as_str() {
                "point" => MipFilter::Point,
                "bilinear" => MipFilter::Bilinear,
                "trilinear" => MipFilter::Trilinear,
                "ewa" | "EWA" => MipFilter::Ewa,
                _ => {
                    return Err(SceneError::syntax(
                        &f_loc,
                        format!(
                            "unknown filter \"{f}\" of {} (expected point, bilinear, trilinear or ewa)",
                            params.owner
                        ),
                    ))
                }
            },
        };
        let wrap = match params.string("wrap")? {
            None => WrapMode::Repeat,
            Some((w, w_loc)) => match w.as_str() {
                "repeat" => WrapMode::Repeat,
                "black" => WrapMode::Black,
                "clamp" => WrapMode::Clamp,
                "octahedralsphere" => WrapMode::OctahedralSphere,
                _ => {
                    return Err(SceneError::syntax(
                        &w_loc,
                        format!(
                            "unknown wrap mode \"{w}\" of {} (expected repeat, black, clamp or octahedralsphere)",
                            params.owner
                        ),
                    ))
                }
            },
        };
        let encoding = match params.string("encoding")? {
            // pbrt-v4: sRGB for PNG files, linear for the others (EXR and PFM are linear
            // anyway; 8-bit JPEG and TGA are read as linear unless told otherwise).
            None if filename.to_ascii_lowercase().ends_with(".png") => ColorEncoding::Srgb,
            None => ColorEncoding::Linear,
            Some((e, e_loc)) => parse_encoding(&e).ok_or_else(|| {
                SceneError::syntax(
                    &e_loc,
                    format!(
                        "unknown encoding \"{e}\" of {} (expected sRGB, linear or \"gamma <value>\")",
                        params.owner
                    ),
                )
            })?,
        };
        let max_anisotropy = params.float("maxanisotropy", 8.0)?;
        let scale = params.float("scale", 1.0)?;
        let invert = params.bool("invert", false)?;
        let mapping = self.mapping(params)?;
        let mipmap = self.mipmap(&filename, &file_loc, encoding, wrap)?;
        Ok(ImageTexture {
            mapping,
            mipmap,
            filter: MipFilterOptions { filter, max_anisotropy },
            scale,
            invert,
        })
    }

    /// The MIP map of an image file, read and built once per (file, encoding, wrap).
    fn mipmap(
        &mut self,
        filename: &str,
        loc: &Location,
        encoding: ColorEncoding,
        wrap: WrapMode,
    ) -> Result<Arc<MipMap>, SceneError> {
        let path = self.resolve(filename);
        let key = (path.clone(), format!("{encoding:?}"), wrap as u8);
        if let Some(m) = self.world.textures.mipmaps.get(&key) {
            return Ok(m.clone());
        }
        let image = self.read_image_file(filename, loc, encoding, ImageUse::Texture)?;
        let mipmap = Arc::new(MipMap::new(image.width, image.height, &image.pixels, wrap));
        self.world.textures.mipmaps.insert(key, mipmap.clone());
        Ok(mipmap)
    }
}

/// `sRGB`, `linear` or `gamma <value>`.
fn parse_encoding(e: &str) -> Option<ColorEncoding> {
    match e {
        "sRGB" | "srgb" => Some(ColorEncoding::Srgb),
        "linear" => Some(ColorEncoding::Linear),
        _ => {
            let g: f32 = e.strip_prefix("gamma ")?.trim().parse().ok()?;
            (g > 0.0 && g.is_finite()).then_some(ColorEncoding::Gamma(g))
        }
    }
}

/// A single `vector3` parameter.
fn vector3(params: &ParamSet, name: &str, default: Vec3) -> Result<Vec3, SceneError> {
    match params.lookup(name, &[ParamType::Vector3])? {
        Some(p) => p.expect_single().map(|()| Vec3::from_slice(p.floats())),
        None => Ok(default),
    }
}
