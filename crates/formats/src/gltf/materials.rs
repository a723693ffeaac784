//! glTF materials to mcrender's: the metallic-roughness model
//! ([`MaterialDesc::MetallicRoughness`], the BRDF of the glTF spec's Appendix B) with its
//! base colour and metallic-roughness textures (factors multiplied into the texels), the
//! emission (`emissiveFactor` times `KHR_materials_emissive_strength`, times the mean of
//! an `emissiveTexture`) as an area light, and `KHR_materials_transmission` (factor >= 0.5)
//! with `KHR_materials_ior` as a dielectric of that index and roughness. Textures are
//! bilinear, wrapped as the sampler's `wrapS`, and honour `KHR_texture_transform` without
//! rotation. A `normalTexture` (times its `scale` in x and y) wraps the material in a
//! [`MaterialDesc::NormalMap`]. Its tangent frame is the mesh's: with `TANGENT`s (and
//! normals), the interpolated tangent made orthogonal to the shading normal and the
//! bitangent `w (normal x tangent)`; without them, the frame glTF's sample viewer builds,
//! the tangent dp/du from `TEXCOORD_0` and the bitangent `normal x tangent`.
//! `alphaMode` `MASK` cuts out where the base colour's alpha (factor times texture,
//! interpolated) is below `alphaCutoff`; `BLEND` becomes stochastic coverage, the surface
//! present with probability alpha (pbrt's alpha, `scene::alpha`). Ignored, with a
//! warning: occlusion textures, a second texture coordinate set. Each image is sized from its header and counted against the
//! load's memory limit before it is decoded.

use std::borrow::Cow;
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

use gltf::texture::WrappingMode;
use mcrender_core::color::Rgb;
use mcrender_core::material::{DielectricMaterial, MapStyle, MetallicRoughnessMaterial, NormalMapMaterial};
use mcrender_core::scene::{AreaLightDesc, FloatTexture, MaterialDesc, MaterialId, RgbTexture};
use mcrender_core::texture::{BitmapFilter, BitmapTexture, BitmapWrap, Texture, TextureMapping};

use super::data::{error_text, Buffers};
use crate::limits::{count_image_bytes, image_texture_bytes, LoadLimits};

/// A converted material: its index, and the emission and alpha of the shapes that use it.
#[derive(Clone, Debug)]
pub struct Converted {
    /// Index into the scene's materials.
    pub material: MaterialId,
    /// Emission, when the material is emissive.
    pub area_light: Option<AreaLightDesc>,
    /// The alpha test of the shapes that use it (`alphaMode` `MASK` or `BLEND`).
    pub alpha: Option<FloatTexture>,
}

/// What [`Materials::convert`] makes of one glTF material.
struct Surface {
    desc: MaterialDesc,
    area_light: Option<AreaLightDesc>,
    alpha: Option<FloatTexture>,
}

/// A `MASK` alpha as a texel value of pbrt-style alpha: `1 + (alpha - cutoff) K` is `>= 1`
/// (present) exactly where `alpha >= cutoff` and `<= 0` (absent) where `alpha <= cutoff -
/// 1 / K`. The bitmap interpolates linearly, so the interpolated alpha is what meets the
/// cutoff, as glTF asks; only a band of width `1 / K` in alpha is stochastic.
fn mask_texel(alpha: f32, cutoff: f32) -> f32 {
    const K: f32 = 1e6;
    1.0 + (alpha - cutoff) * K
}

/// A texture as a material refers to it: the texture, its uv set and its
/// `KHR_texture_transform` (offset, scale, rotation).
struct TextureRef<'a> {
    texture: gltf::Texture<'a>,
    tex_coord: u32,
    offset: [f32; 2],
    scale: [f32; 2],
    rotation: f32,
}

impl<'a> TextureRef<'a> {
    fn from_info(info: &gltf::texture::Info<'a>) -> Self {
        let t = info.texture_transform();
        Self {
            texture: info.texture(),
            tex_coord: info.tex_coord(),
            offset: t.as_ref().map_or([0.0, 0.0], gltf::texture::TextureTransform::offset),
            scale: t.as_ref().map_or([1.0, 1.0], gltf::texture::TextureTransform::scale),
            rotation: t.as_ref().map_or(0.0, gltf::texture::TextureTransform::rotation),
        }
    }

    /// A normal texture, whose reference type has no transform accessor: read from its
    /// `KHR_texture_transform` JSON.
    fn from_normal(n: &gltf::material::NormalTexture<'a>) -> Self {
        let t = n.extension_value("KHR_texture_transform");
        let pair = |key: &str, default: [f32; 2]| -> [f32; 2] {
            t.and_then(|t| t.get(key))
                .and_then(|v| v.as_array())
                .filter(|a| a.len() == 2)
                .and_then(|a| Some([a[0].as_f64()? as f32, a[1].as_f64()? as f32]))
                .unwrap_or(default)
        };
        Self {
            texture: n.texture(),
            tex_coord: n.tex_coord(),
            offset: pair("offset", [0.0, 0.0]),
            scale: pair("scale", [1.0, 1.0]),
            rotation: t
                .and_then(|t| t.get("rotation"))
                .and_then(gltf::json::Value::as_f64)
                .map(|r| r as f32)
                .unwrap_or(0.0),
        }
    }
}

/// A decoded glTF image: width, height, and linear-or-encoded texel values in [0, 1].
struct Image {
    width: u32,
    height: u32,
    texels: Vec<Rgb>,
    /// The alpha channel, when the image has one.
    alpha: Option<Vec<f32>>,
}

/// Converts the materials of one document, each once.
pub struct Materials<'a> {
    buffers: &'a Buffers,
    dir: &'a Path,
    images: HashMap<usize, Arc<Image>>,
    done: HashMap<Option<usize>, Converted>,
    limits: LoadLimits,
    /// Estimated bytes of the images read so far (`crate::limits` estimates).
    pub image_bytes: u64,
}

/// The sRGB transfer curve, decoded (IEC 61966-2-1).
fn srgb_to_linear(v: f32) -> f32 {
    if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

impl<'a> Materials<'a> {
    /// A converter reading images from `buffers` and files in `dir`, each refused from its
    /// header when decoding it would pass `limits`.
    #[must_use]
    pub fn new(buffers: &'a Buffers, dir: &'a Path, limits: LoadLimits) -> Self {
        Self {
            buffers,
            dir,
            images: HashMap::new(),
            done: HashMap::new(),
            limits,
            image_bytes: 0,
        }
    }

    /// The material `m` (converted on first use), appended to `materials`.
    ///
    /// # Errors
    /// `materials[i]...: ...` when a texture cannot be read.
    pub fn get(
        &mut self,
        m: &gltf::Material<'_>,
        materials: &mut Vec<MaterialDesc>,
        warnings: &mut Vec<String>,
    ) -> Result<Converted, String> {
        if let Some(c) = self.done.get(&m.index()) {
            return Ok(c.clone());
        }
        let path = m
            .index()
            .map_or_else(|| "the default material".to_string(), |i| format!("materials[{i}]"));
        let Surface {
            desc,
            area_light,
            alpha,
        } = self.convert(m, &path, warnings)?;
        materials.push(desc);
        let normal_map = self.normal_map(m, &path, warnings)?;
        if let Some(normal_map) = normal_map {
            let material = (materials.len() - 1) as MaterialId;
            materials.push(MaterialDesc::NormalMap(NormalMapMaterial {
                material,
                normal_map,
                style: MapStyle::Pbrt,
            }));
        }
        let c = Converted {
            material: (materials.len() - 1) as MaterialId,
            area_light,
            alpha,
        };
        self.done.insert(m.index(), c.clone());
        Ok(c)
    }

    fn convert(&mut self, m: &gltf::Material<'_>, path: &str, warnings: &mut Vec<String>) -> Result<Surface, String> {
        if m.occlusion_texture().is_some() {
            warnings.push(format!(
                "{path}.occlusionTexture is ignored (occlusion is computed, not painted)"
            ));
        }
        let pbr = m.pbr_metallic_roughness();
        let [r, g, b, a] = pbr.base_color_factor();
        let factor = Rgb::new(r, g, b);
        // Alpha as pbrt's alpha test reads it (see `mask_texel`); 1 is opaque.
        let mode = m.alpha_mode();
        let cutoff = m.alpha_cutoff().unwrap_or(0.5);
        let test = |alpha: f32| match mode {
            gltf::material::AlphaMode::Opaque => 1.0,
            gltf::material::AlphaMode::Mask => mask_texel(alpha, cutoff),
            gltf::material::AlphaMode::Blend => alpha,
        };
        let mut alpha: Option<FloatTexture> = None;
        let base_color: RgbTexture = match pbr.base_color_texture() {
            Some(info) => {
                let info = TextureRef::from_info(&info);
                let img = self.image(
                    &info,
                    &format!("{path}.pbrMetallicRoughness.baseColorTexture"),
                    warnings,
                )?;
                let texels = img.texels.iter().map(|t| t.map(srgb_to_linear) * factor).collect();
                if let (Some(texel_alpha), false) = (&img.alpha, mode == gltf::material::AlphaMode::Opaque) {
                    let texels = texel_alpha.iter().map(|t| Rgb::splat(test(t * a))).collect();
                    alpha = Some(bitmap(&info, &img, texels));
                }
                bitmap(&info, &img, texels)
            }
            None => factor.into(),
        };
        let alpha = alpha.or_else(|| {
            let constant = test(a);
            (constant < 1.0).then(|| constant.into())
        });
        if mode == gltf::material::AlphaMode::Blend {
            warnings.push(format!(
                "{path}.alphaMode BLEND is rendered as coverage: the surface is hit with probability alpha"
            ));
        }
        let (metallic, roughness): (FloatTexture, FloatTexture) = match pbr.metallic_roughness_texture() {
            Some(info) => {
                let info = TextureRef::from_info(&info);
                let img = self.image(
                    &info,
                    &format!("{path}.pbrMetallicRoughness.metallicRoughnessTexture"),
                    warnings,
                )?;
                // Metalness in the blue channel, roughness in the green (glTF 2.0, 3.9.2).
                let metal = img
                    .texels
                    .iter()
                    .map(|t| Rgb::splat(t.b * pbr.metallic_factor()))
                    .collect();
                let rough = img
                    .texels
                    .iter()
                    .map(|t| Rgb::splat(t.g * pbr.roughness_factor()))
                    .collect();
                (bitmap(&info, &img, metal), bitmap(&info, &img, rough))
            }
            None => (pbr.metallic_factor().into(), pbr.roughness_factor().into()),
        };
        let strength = m.emissive_strength().unwrap_or(1.0);
        let [er, eg, eb] = m.emissive_factor();
        let mut emission = Rgb::new(er, eg, eb) * strength;
        if let Some(info) = m.emissive_texture() {
            let img = self.image(
                &TextureRef::from_info(&info),
                &format!("{path}.emissiveTexture"),
                warnings,
            )?;
            let n = img.texels.len().max(1) as f32;
            let mean = img.texels.iter().fold(Rgb::BLACK, |s, t| s + t.map(srgb_to_linear)) * (1.0 / n);
            warnings.push(format!(
                "{path}.emissiveTexture is averaged to one colour (mean {:.3} {:.3} {:.3})",
                mean.r, mean.g, mean.b
            ));
            emission *= mean;
        }
        let area_light = (emission.max_component() > 0.0 && emission.is_finite()).then_some(AreaLightDesc {
            radiance: emission,
            two_sided: m.double_sided(),
            power: None,
        });
        if let Some(t) = m.transmission() {
            if t.transmission_texture().is_some() {
                warnings.push(format!(
                    "{path}.extensions.KHR_materials_transmission.transmissionTexture is ignored"
                ));
            }
            if t.transmission_factor() >= 0.5 {
                let microfacet_alpha = pbr.roughness_factor().clamp(0.0, 1.0).powi(2);
                let eta = m.ior().filter(|n| *n >= 1.0 && n.is_finite()).unwrap_or(1.5);
                return Ok(Surface {
                    desc: MaterialDesc::Dielectric(DielectricMaterial {
                        eta,
                        u_roughness: microfacet_alpha.into(),
                        v_roughness: microfacet_alpha.into(),
                        remap_roughness: false,
                        microfacet: Default::default(),
                    }),
                    area_light,
                    alpha,
                });
            }
        }
        Ok(Surface {
            desc: MaterialDesc::MetallicRoughness(MetallicRoughnessMaterial {
                base_color,
                metallic,
                roughness,
            }),
            area_light,
            alpha,
        })
    }

    /// The normal map of `m`: its texels (linear, as stored) with `normal = 2 c - 1`
    /// scaled by the texture's `scale` in x and y (glTF 2.0, 3.9.3), written back as
    /// `(normal + 1) / 2` for [`NormalMapMaterial`].
    fn normal_map(
        &mut self,
        m: &gltf::Material<'_>,
        path: &str,
        warnings: &mut Vec<String>,
    ) -> Result<Option<RgbTexture>, String> {
        let Some(n) = m.normal_texture() else {
            return Ok(None);
        };
        let info = TextureRef::from_normal(&n);
        let img = self.image(&info, &format!("{path}.normalTexture"), warnings)?;
        let s = n.scale();
        let texels = img
            .texels
            .iter()
            .map(|c| {
                let scaled = |v: f32, k: f32| 0.5 * ((2.0 * v - 1.0) * k + 1.0);
                Rgb::new(scaled(c.r, s), scaled(c.g, s), c.b)
            })
            .collect();
        Ok(Some(bitmap(&info, &img, texels)))
    }

    /// The image of texture `info`, decoded once (values as stored, in [0, 1]).
    fn image(&mut self, info: &TextureRef<'_>, path: &str, warnings: &mut Vec<String>) -> Result<Arc<Image>, String> {
        if info.rotation != 0.0 {
            warnings.push(format!(
                "{path}.extensions.KHR_texture_transform.rotation {} is ignored (offset and scale are read)",
                info.rotation
            ));
        }
        if info.tex_coord != 0 {
            warnings.push(format!(
                "{path}.texCoord {} is read as TEXCOORD_0 (one uv set)",
                info.tex_coord
            ));
        }
        let source = info.texture.source();
        if let Some(img) = self.images.get(&source.index()) {
            return Ok(img.clone());
        }
        let ipath = format!("images[{}]", source.index());
        let read_error = |e: gltf::Error| format!("{path} ({ipath}): cannot read the image: {}", error_text(&e));
        // The encoded image, to size it from its header before decoding.
        let encoded = match source.source() {
            gltf::image::Source::View { view, .. } => Cow::Borrowed(self.buffers.view(&view)?),
            gltf::image::Source::Uri { uri, .. } => Cow::Owned(
                gltf::buffer::Data::from_source_and_blob(gltf::buffer::Source::Uri(uri), Some(self.dir), &mut None)
                    .map_err(read_error)?
                    .0,
            ),
        };
        let size = image::ImageReader::new(std::io::Cursor::new(&*encoded))
            .with_guessed_format()
            .ok()
            .and_then(|r| r.into_dimensions().ok());
        // An image whose size cannot be read fails to decode below.
        if let Some((w, h)) = size {
            let need = image_texture_bytes(u64::from(w), u64::from(h));
            count_image_bytes(
                &mut self.image_bytes,
                need,
                &format!("{path} ({ipath}, {w}x{h})"),
                &self.limits,
            )?;
        }
        drop(encoded);
        let data =
            gltf::image::Data::from_source(source.source(), Some(self.dir), &self.buffers.0).map_err(read_error)?;
        let img = Arc::new(decode(&data).ok_or_else(|| format!("{ipath}: unexpected pixel data"))?);
        self.images.insert(source.index(), img.clone());
        Ok(img)
    }
}

/// Texels of `data` as RGB in [0, 1] (grey replicated), and the alpha channel apart.
fn decode(data: &gltf::image::Data) -> Option<Image> {
    use gltf::image::Format;
    let (channels, bytes) = match data.format {
        Format::R8 => (1, 1),
        Format::R8G8 => (2, 1),
        Format::R8G8B8 => (3, 1),
        Format::R8G8B8A8 => (4, 1),
        Format::R16 => (1, 2),
        Format::R16G16 => (2, 2),
        Format::R16G16B16 => (3, 2),
        Format::R16G16B16A16 => (4, 2),
        Format::R32G32B32FLOAT => (3, 4),
        Format::R32G32B32A32FLOAT => (4, 4),
    };
    let n = (data.width as usize).checked_mul(data.height as usize)?;
    if data.pixels.len() != n.checked_mul(channels * bytes)? || n == 0 {
        return None;
    }
    let value = |c: &[u8]| -> f32 {
        match bytes {
            1 => f32::from(c[0]) / 255.0,
            2 => f32::from(u16::from_le_bytes([c[0], c[1]])) / 65535.0,
            _ => f32::from_le_bytes([c[0], c[1], c[2], c[3]]),
        }
    };
    let texels = data
        .pixels
        .chunks_exact(channels * bytes)
        .map(|px| {
            let v = |i: usize| value(&px[i * bytes..(i + 1) * bytes]);
            match channels {
                1 | 2 => Rgb::splat(v(0)),
                _ => Rgb::new(v(0), v(1), v(2)),
            }
        })
        .collect();
    let alpha = matches!(channels, 2 | 4).then(|| {
        data.pixels
            .chunks_exact(channels * bytes)
            .map(|px| value(&px[(channels - 1) * bytes..channels * bytes]))
            .collect()
    });
    Some(Image {
        width: data.width,
        height: data.height,
        texels,
        alpha,
    })
}

/// A bilinear bitmap of `texels` (the size of `img`) with `info`'s sampler and transform.
/// Mesh uvs are stored with `v` flipped (`1 - v`, row 0 at the top as in glTF), so a
/// glTF transform `uv' = uv * scale + offset` becomes `s = su u + du`, `t = sv v + dv`
/// with `dv = 1 - scale_v - offset_v`.
fn bitmap<T: mcrender_core::texture::TextureValue>(info: &TextureRef<'_>, img: &Image, texels: Vec<Rgb>) -> Texture<T> {
    let (offset, scale) = (info.offset, info.scale);
    let wrap = match info.texture.sampler().wrap_s() {
        WrappingMode::ClampToEdge => BitmapWrap::Clamp,
        WrappingMode::MirroredRepeat => BitmapWrap::Mirror,
        WrappingMode::Repeat => BitmapWrap::Repeat,
    };
    Texture::Bitmap(Arc::new(BitmapTexture {
        mapping: TextureMapping::Uv {
            su: scale[0],
            sv: scale[1],
            du: offset[0],
            dv: 1.0 - scale[1] - offset[1],
        },
        width: img.width,
        height: img.height,
        texels: Arc::new(texels),
        filter: BitmapFilter::Bilinear,
        wrap,
    }))
}
