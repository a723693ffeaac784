//! A Wavefront OBJ file (with its MTL materials) as a whole scene: `mcrender render
//! model.obj`. Each object or group of the file becomes one mesh with its material; the
//! camera and light that OBJ never has are the defaults of [`crate::framing`], said in the
//! warnings.
//!
//! MTL to mcrender (the mapping is also in the README):
//! * `Ke` (emission) > 0: a one-sided area light of radiance `Ke` on the mesh;
//! * transparency `Tr` (or `1 - d`) >= 0.5: a smooth dielectric of index `Ni` (default 1.5);
//! * `Ks` > 0 with a black `Kd`: a rough conductor whose normal-incidence reflectance is
//!   `Ks`; with a non-black `Kd`: a coated diffuse (base `Kd`/`map_Kd`, coat index 1.5);
//!   both with microfacet alpha `sqrt(2 / (Ns + 2))`, the Beckmann roughness equivalent
//!   to a Blinn-Phong exponent `Ns` (Walter et al. 2007, section 5.2);
//! * otherwise Lambertian with `Kd` (or `map_Kd`, sRGB-decoded, bilinear, repeated);
//!   a mesh without material is Lambertian grey 0.5.
//!
//! Other MTL maps (`map_Ks`, `map_Bump`, `map_d`, ...) are ignored with a warning.

use mcrender_core::material::{CoatedDiffuseMaterial, ConductorMaterial, DielectricMaterial, DiffuseMaterial};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use mcrender_core::color::Rgb;
use mcrender_core::scene::{AreaLightDesc, GeometryDesc, MaterialDesc, MaterialId, RgbTexture, ShapeDesc};
use mcrender_core::texture::{BitmapFilter, BitmapTexture, BitmapWrap, Texture, TextureMapping};

use crate::error::{io_error_text, quoted, Location, SceneError};
use crate::image_io::{decode_image, image_dimensions, ColorEncoding, ImageError, ImageFormat};
use crate::limits::{count_image_bytes, image_texture_bytes, LoadLimits};
use crate::obj::parse_obj;
use crate::LoadedScene;

/// Index of refraction of the coat of a glossy MTL material and of a dielectric without `Ni`.
const DEFAULT_IOR: f32 = 1.5;

/// Load `path` as a scene.
///
/// # Errors
/// When the OBJ file cannot be read or parsed, has no faces or bad indices, or a texture
/// it names cannot be read or would pass `limits` (checked from its header, before
/// decoding); the message names the file.
pub fn load_obj_scene(path: &Path, limits: LoadLimits) -> Result<LoadedScene, SceneError> {
    let file: Arc<str> = path.display().to_string().into();
    let loc = Location::file_only(file.clone());
    let dir = path.parent().unwrap_or_else(|| Path::new(""));
    let text = std::fs::read(path)
        .map_err(|e| SceneError::io(&loc, format!("cannot open the OBJ file: {}", io_error_text(&e))))?;
    let (models, materials) = parse_obj(&text, &OPTIONS, |mtl| std::fs::read(dir.join(mtl)).ok())
        .map_err(|e| SceneError::syntax(&loc, format!("cannot parse the OBJ file: {e}")))?;
    build(&file, dir, &models, materials, limits)
}

/// [`load_obj_scene`] on OBJ text in memory, named `file`, whose `mtllib` reads `mtl`
/// (textures are looked for in `dir`).
///
/// # Errors
/// As [`load_obj_scene`].
pub fn load_obj_scene_bytes(
    obj: &[u8],
    mtl: Option<&[u8]>,
    file: &str,
    dir: &Path,
    limits: LoadLimits,
) -> Result<LoadedScene, SceneError> {
    let name: Arc<str> = file.into();
    let loc = Location::file_only(name.clone());
    let (models, materials) = parse_obj(obj, &OPTIONS, |_| mtl.map(<[u8]>::to_vec))
        .map_err(|e| SceneError::syntax(&loc, format!("cannot parse the OBJ file: {e}")))?;
    build(&name, dir, &models, materials, limits)
}

/// How OBJ files are read: one index per vertex, polygons fan-triangulated.
const OPTIONS: tobj::LoadOptions = tobj::LoadOptions {
    single_index: true,
    triangulate: true,
    ignore_points: true,
    ignore_lines: true,
};

fn build(
    file: &Arc<str>,
    dir: &Path,
    models: &[tobj::Model],
    materials: Result<Vec<tobj::Material>, tobj::LoadError>,
    limits: LoadLimits,
) -> Result<LoadedScene, SceneError> {
    let loc = Location::file_only(file.clone());
    let mut warnings = Vec::new();
    let materials = materials.unwrap_or_else(|e| {
        if !models.iter().all(|m| m.mesh.material_id.is_none()) || !matches!(e, tobj::LoadError::OpenFileFailed) {
            warnings.push(format!(
                "{file}: warning: cannot read its MTL file ({e}); using grey diffuse"
            ));
        }
        Vec::new()
    });
    let mut desc = crate::framing::model_scene();
    let mut converter = Converter {
        file: file.clone(),
        dir: dir.to_path_buf(),
        images: HashMap::new(),
        ids: HashMap::new(),
        limits,
        image_bytes: 0,
    };
    for model in models {
        if model.mesh.indices.is_empty() {
            continue;
        }
        let mesh = crate::obj::mesh_of(&[&model.mesh]).map_err(|m| SceneError::invalid(&loc, m))?;
        let mtl = model.mesh.material_id.and_then(|i| materials.get(i));
        let (material, area_light) =
            converter.material(mtl, model.mesh.material_id, &mut desc.materials, &mut warnings)?;
        desc.shapes.push(ShapeDesc {
            geometry: GeometryDesc::TriangleMesh(mesh),
            material,
            area_light,
            flip_normals: false,
            alpha: None,
        });
    }
    if desc.shapes.is_empty() {
        return Err(SceneError::invalid(&loc, "the OBJ file has no faces"));
    }
    crate::framing::add_defaults(&mut desc, file, false, &mut warnings);
    Ok(LoadedScene {
        description: desc,
        output_filename: None,
        warnings,
        image_bytes: converter.image_bytes,
    })
}

/// MTL materials to [`MaterialDesc`]s, each converted once.
struct Converter {
    file: Arc<str>,
    dir: PathBuf,
    images: HashMap<PathBuf, RgbTexture>,
    ids: HashMap<Option<usize>, (MaterialId, Option<AreaLightDesc>)>,
    /// The memory limit of the load.
    limits: LoadLimits,
    /// Estimated bytes of the textures read so far.
    image_bytes: u64,
}

fn rgb(c: Option<[f32; 3]>) -> Option<Rgb> {
    c.map(|c| Rgb::new(c[0], c[1], c[2]))
}

fn positive(c: Option<Rgb>) -> Option<Rgb> {
    c.filter(|c| c.max_component() > 0.0 && c.is_finite())
}

impl Converter {
    fn material(
        &mut self,
        mtl: Option<&tobj::Material>,
        id: Option<usize>,
        materials: &mut Vec<MaterialDesc>,
        warnings: &mut Vec<String>,
    ) -> Result<(MaterialId, Option<AreaLightDesc>), SceneError> {
        let key = mtl.map(|_| id.unwrap_or(usize::MAX));
        if let Some(m) = self.ids.get(&key) {
            return Ok(*m);
        }
        let (desc, light) = match mtl {
            None => (
                MaterialDesc::Diffuse(DiffuseMaterial {
                    reflectance: Rgb::splat(0.5).into(),
                }),
                None,
            ),
            Some(m) => self.convert(m, warnings)?,
        };
        materials.push(desc);
        let out = ((materials.len() - 1) as MaterialId, light);
        self.ids.insert(key, out);
        Ok(out)
    }

    fn convert(
        &mut self,
        m: &tobj::Material,
        warnings: &mut Vec<String>,
    ) -> Result<(MaterialDesc, Option<AreaLightDesc>), SceneError> {
        for (name, map) in [
            ("map_Ka", &m.ambient_texture),
            ("map_Ks", &m.specular_texture),
            ("map_Bump / norm", &m.normal_texture),
            ("map_Ns", &m.shininess_texture),
            ("map_d", &m.dissolve_texture),
        ] {
            if map.is_some() {
                warnings.push(format!(
                    "{}: warning: material \"{}\": {name} is ignored",
                    self.file, m.name
                ));
            }
        }
        let param = |k: &str| m.unknown_param.get(k).and_then(|v| v.trim().parse::<f32>().ok());
        let emission = positive(rgb(m.emissive)).or_else(|| {
            let v: Vec<f32> = m
                .unknown_param
                .get("Ke")?
                .split_whitespace()
                .filter_map(|t| t.parse().ok())
                .collect();
            positive(match v.as_slice() {
                [a] => Some(Rgb::splat(*a)),
                [r, g, b] => Some(Rgb::new(*r, *g, *b)),
                _ => None,
            })
        });
        let light = emission.map(|radiance| AreaLightDesc {
            radiance,
            two_sided: false,
            power: None,
        });
        let transparency = param("Tr").or_else(|| m.dissolve.map(|d| 1.0 - d)).unwrap_or(0.0);
        if transparency >= 0.5 {
            let eta = m
                .optical_density
                .filter(|n| *n > 0.0 && n.is_finite())
                .unwrap_or(DEFAULT_IOR);
            return Ok((
                MaterialDesc::Dielectric(DielectricMaterial {
                    eta,
                    u_roughness: 0.0.into(),
                    v_roughness: 0.0.into(),
                    remap_roughness: false,
                    microfacet: Default::default(),
                }),
                light,
            ));
        }
        let kd: RgbTexture = match &m.diffuse_texture {
            Some(name) => self.texture(name)?,
            None => rgb(m.diffuse)
                .unwrap_or(Rgb::splat(0.5))
                .map(|v| v.clamp(0.0, 1.0))
                .into(),
        };
        let kd_black = kd.constant().is_some_and(|c| c.max_component() <= 0.0);
        let Some(ks) = positive(rgb(m.specular)) else {
            return Ok((MaterialDesc::Diffuse(DiffuseMaterial { reflectance: kd }), light));
        };
        let ns = m.shininess.filter(|n| n.is_finite()).unwrap_or(0.0).max(0.0);
        let alpha = (2.0 / (ns + 2.0)).sqrt();
        let desc = if kd_black {
            MaterialDesc::Conductor(ConductorMaterial {
                eta: Rgb::WHITE.into(),
                k: Rgb::BLACK.into(),
                reflectance: Some(ks.map(|v| v.clamp(0.0, 1.0)).into()),
                u_roughness: alpha.into(),
                v_roughness: alpha.into(),
                remap_roughness: false,
                microfacet: Default::default(),
            })
        } else {
            MaterialDesc::CoatedDiffuse(CoatedDiffuseMaterial {
                reflectance: kd,
                u_roughness: alpha.into(),
                v_roughness: alpha.into(),
                remap_roughness: false,
                thickness: 0.01.into(),
                eta: DEFAULT_IOR,
                albedo: Rgb::BLACK.into(),
                g: 0.0.into(),
                max_depth: 10,
                n_samples: 1,
            })
        };
        Ok((desc, light))
    }

    /// `map_Kd`: an sRGB image, bilinear, repeated.
    fn texture(&mut self, name: &str) -> Result<RgbTexture, SceneError> {
        let path = self.dir.join(name.trim());
        if let Some(t) = self.images.get(&path) {
            return Ok(t.clone());
        }
        let loc = Location::file_only(self.file.clone());
        let error = |err: ImageError| {
            let why = match &err {
                ImageError::Io { source, .. } => io_error_text(source),
                other => other.to_string(),
            };
            SceneError::io(&loc, format!("cannot read texture {}: {why}", path.display()))
        };
        let format = ImageFormat::from_path(&path).map_err(error)?;
        let bytes = std::fs::read(&path).map_err(|source| {
            error(ImageError::Io {
                path: path.clone(),
                source,
            })
        })?;
        // Refused from the header when decoding would pass the memory limit.
        let (w, h) = image_dimensions(&path, format, &bytes).map_err(error)?;
        let what = format!("texture {} ({w}x{h})", quoted(&path.display().to_string()));
        count_image_bytes(&mut self.image_bytes, image_texture_bytes(w, h), &what, &self.limits)
            .map_err(|m| SceneError::invalid(&loc, m))?;
        let img = decode_image(&path, format, &bytes, ColorEncoding::Srgb).map_err(error)?;
        let t = Texture::Bitmap(Arc::new(BitmapTexture {
            mapping: TextureMapping::Uv {
                su: 1.0,
                sv: 1.0,
                du: 0.0,
                dv: 0.0,
            },
            width: img.width,
            height: img.height,
            texels: Arc::new(img.pixels),
            filter: BitmapFilter::Bilinear,
            wrap: BitmapWrap::Repeat,
        }));
        self.images.insert(path, t.clone());
        Ok(t)
    }
}
