//! From the [`Element`] tree to a [`SceneDescription`]: the scene's top-level plugins in
//! document order, named objects (`id`) for `<ref>`, and the sensor, film, sampler and
//! integrator settings. Shapes, BSDFs, emitters and textures live in their own modules as
//! further `impl Builder` blocks.

use mcrender_core::material::DiffuseMaterial;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use mcrender_core::color::Rgb;
use mcrender_core::math::{Mat4, Transform, Vec2, Vec3};
use mcrender_core::scene::{
    CameraDesc, DirectStrategy, FilmDesc, FilterDesc, IntegratorDesc, IntegratorKind, LightSelection, MaterialDesc,
    MaterialId, Projection, Reconstruction, RussianRoulette, SamplerDesc, SamplerKind, SceneDescription,
};
use mcrender_core::texture::FloatTexture;

use super::props::Props;
use super::xml::{Element, Reader};
use crate::error::{tidy_message, SceneError};
use crate::limits::LoadLimits;
use crate::LoadedScene;

/// Mitsuba's image x runs along the sensor's local -x ("left"), pbrt's camera x along +x:
/// a sensor's `to_world` is mirrored in x before it becomes our camera transform.
const IMAGE_X_MIRROR: Mat4 = Mat4::from_cols(
    glam::Vec4::new(-1.0, 0.0, 0.0, 0.0),
    glam::Vec4::Y,
    glam::Vec4::Z,
    glam::Vec4::W,
);

/// A decoded image: width, height, texels.
pub type ImageEntry = (u32, u32, Arc<Vec<Rgb>>);

/// A resolved BSDF: the material and the cut-out of a `mask` around it.
#[derive(Clone, Debug)]
pub struct Surface {
    /// The material.
    pub material: MaterialId,
    /// Opacity from `mask` (`None`: opaque).
    pub alpha: Option<FloatTexture>,
}

/// Something an `id` names.
#[derive(Clone, Debug)]
pub enum Named {
    /// A BSDF.
    Bsdf(Surface),
    /// A texture (built where it is used, as float or RGB).
    Texture(Box<Element>),
    /// A `shapegroup`: index into [`SceneDescription::objects`].
    ShapeGroup(u32),
    /// Anything else (shapes, emitters, ...), remembered only so that `<ref>`s to it say
    /// what it is.
    Other(String),
}

/// Builds one scene.
pub struct Builder {
    /// The reader (for file resolution).
    pub reader: Reader,
    /// Directory of the top-level file.
    pub dir: PathBuf,
    /// The scene so far.
    pub desc: SceneDescription,
    /// `id` -> object.
    pub named: HashMap<String, Named>,
    /// Warnings, `file:line:col: warning: ...`.
    pub warnings: Vec<String>,
    /// Decoded images (width, height, texels), by (path, raw).
    pub images: HashMap<(PathBuf, bool), ImageEntry>,
    /// The default material (`diffuse`, reflectance 0.5), made on first use.
    default_material: Option<MaterialId>,
    /// The load's memory limit (images are refused from their headers past it).
    pub limits: LoadLimits,
    /// Estimated bytes of the images read so far (`crate::limits` estimates).
    pub image_bytes: u64,
    /// The attributes of the shape whose BSDF is being built (`mesh_attribute` textures
    /// read them), if any.
    pub mesh_attributes: Option<super::attributes::MeshAttributes>,
    /// Set when a `mesh_attribute` was met with no [`Self::mesh_attributes`].
    pub deferred_attribute: bool,
    /// BSDFs built with placeholder mesh attributes: material -> the `<bsdf>` to build
    /// again for each shape that uses it.
    pub attribute_bsdfs: HashMap<MaterialId, Element>,
}

impl Builder {
    /// A builder for a scene read by `reader` from a file in `dir`, its images within
    /// `limits`.
    #[must_use]
    pub fn new(reader: Reader, dir: &Path, limits: LoadLimits) -> Self {
        let desc = SceneDescription {
            camera: CameraDesc::default(),
            film: FilmDesc {
                width: 768,
                height: 576,
            },
            filter: gaussian_filter(0.5),
            reconstruction: Reconstruction::FilterSampling,
            sampler: SamplerDesc {
                kind: SamplerKind::Independent,
                samples_per_pixel: 4,
                seed: 0,
            },
            integrator: IntegratorDesc {
                max_depth: UNLIMITED_DEPTH,
                light_selection: LightSelection::Uniform,
                ..IntegratorDesc::default()
            },
            materials: Vec::new(),
            shapes: Vec::new(),
            lights: Vec::new(),
            objects: Vec::new(),
            instances: Vec::new(),
        };
        Self {
            reader,
            dir: dir.to_path_buf(),
            desc,
            named: HashMap::new(),
            warnings: Vec::new(),
            images: HashMap::new(),
            default_material: None,
            limits,
            image_bytes: 0,
            mesh_attributes: None,
            deferred_attribute: false,
            attribute_bsdfs: HashMap::new(),
        }
    }

    /// Build the scene from its `<scene>` element.
    ///
    /// # Errors
    /// The first invalid or unsupported element.
    pub fn build(mut self, scene: &Element) -> Result<LoadedScene, SceneError> {
        let mut sensors = 0;
        for el in &scene.children {
            match el.tag.as_str() {
                "sensor" => {
                    sensors += 1;
                    if sensors > 1 {
                        self.warnings.push(format!(
                            "{}: warning: more than one <sensor>; mcrender renders the first",
                            el.loc
                        ));
                        continue;
                    }
                    self.sensor(el)?;
                }
                "integrator" => self.integrator(el)?,
                "shape" => self.shape(el, None)?,
                "emitter" => self.emitter(el)?,
                "bsdf" => {
                    let s = self.bsdf(el)?;
                    self.name(el, Named::Bsdf(s));
                }
                "texture" => {
                    let Some(id) = el.attr("id") else {
                        self.warnings.push(format!(
                            "{}: warning: a top-level <texture> without id is unused",
                            el.loc
                        ));
                        continue;
                    };
                    self.named.insert(id.to_string(), Named::Texture(Box::new(el.clone())));
                }
                "medium" | "phase" | "volume" => {
                    return Err(SceneError::unsupported(
                        &el.loc,
                        format!("{} (participating media)", el.describe()),
                    ))
                }
                _ => {
                    return Err(SceneError::syntax(
                        &el.loc,
                        format!("unexpected {} in <scene>", el.describe()),
                    ))
                }
            }
        }
        if sensors == 0 {
            self.warnings.push(format!(
                "{}: warning: no <sensor>; using Mitsuba's default perspective camera",
                scene.loc
            ));
        }
        // Mitsuba's film splats every sample through its filter. With the box of radius
        // one half that equals filter sampling (same positions, weight one), which is kept.
        let boxed = matches!(self.desc.filter, FilterDesc::Box { radius } if radius == Vec2::splat(0.5));
        if !boxed {
            self.desc.reconstruction = Reconstruction::FilterSplatting;
        }
        Ok(LoadedScene {
            description: self.desc,
            output_filename: None,
            // Warnings quote the scene's text: cut long parts, escape control characters.
            warnings: self.warnings.iter().map(|w| tidy_message(w)).collect(),
            image_bytes: self.image_bytes,
        })
    }

    /// Remember `el`'s `id`, if any.
    pub fn name(&mut self, el: &Element, what: Named) {
        if let Some(id) = el.attr("id") {
            self.named.insert(id.to_string(), what);
        }
    }

    /// The object a `<ref id>` names.
    pub fn lookup(&self, r: &Element) -> Result<&Named, SceneError> {
        let id = r.required("id")?;
        self.named
            .get(id)
            .ok_or_else(|| SceneError::invalid(&r.loc, format!("<ref id=\"{id}\"> names nothing defined before it")))
    }

    /// Add a material.
    pub fn add_material(&mut self, m: MaterialDesc) -> MaterialId {
        self.desc.materials.push(m);
        (self.desc.materials.len() - 1) as MaterialId
    }

    /// Mitsuba's default BSDF: diffuse with reflectance 0.5.
    pub fn default_surface(&mut self) -> Surface {
        let material = match self.default_material {
            Some(m) => m,
            None => {
                let m = self.add_material(MaterialDesc::Diffuse(DiffuseMaterial {
                    reflectance: Rgb::splat(0.5).into(),
                }));
                self.default_material = Some(m);
                m
            }
        };
        Surface { material, alpha: None }
    }

    /// Resolve a file name against `<path>` directories and the scene's directory.
    #[must_use]
    pub fn resolve(&self, file: &str) -> PathBuf {
        self.reader.resolve_from(file, &self.dir)
    }

    /// Keep the unused-property warnings of `p`.
    pub fn finish(&mut self, p: &Props) {
        self.warnings.extend(p.unused_warnings());
    }

    /// A plugin type that mcrender does not render.
    pub fn unsupported(el: &Element, why: &str) -> SceneError {
        SceneError::unsupported(&el.loc, format!("{} is not supported{why}", el.describe()))
    }

    /// `<sensor>`: perspective or thin-lens camera, with its film and sampler.
    fn sensor(&mut self, el: &Element) -> Result<(), SceneError> {
        let kind = el.required("type")?;
        if kind != "perspective" && kind != "thinlens" && kind != "orthographic" {
            return Err(Self::unsupported(el, " (cameras: perspective, thinlens, orthographic)"));
        }
        let mut p = Props::new(el);
        for film in p.nested("film") {
            if film.tag == "film" {
                self.film(film)?;
            }
        }
        for s in p.nested("sampler") {
            if s.tag == "sampler" {
                self.sampler(s)?;
            }
        }
        let to_world = p.transform("to_world")?.unwrap_or(Mat4::IDENTITY);
        if kind == "orthographic" {
            self.desc.camera = self.orthographic(el, &mut p, to_world)?;
            self.finish(&p);
            return Ok(());
        }
        if p.has("focal_length") {
            let e = p.get("focal_length").expect("checked");
            return Err(SceneError::unsupported(
                &e.loc,
                "\"focal_length\" (give \"fov\" instead)",
            ));
        }
        // Mitsuba's default is a 50 mm lens on 35 mm film, measured along the diagonal.
        let (fov, axis) = match p.get("fov") {
            Some(e) => (super::props::scalar(e, &["float"])?, None),
            None => (
                2.0 * (43.266_6_f32 / 100.0).atan().to_degrees(),
                Some("diagonal".to_string()),
            ),
        };
        let axis = match axis {
            Some(a) => a,
            None => p.string("fov_axis")?.map_or_else(|| "x".to_string(), |(a, _)| a),
        };
        let (w, h) = (self.desc.film.width as f32, self.desc.film.height as f32);
        let half = (fov.to_radians() / 2.0).tan();
        let tan_x = match axis.as_str() {
            "x" => half,
            "y" => half * w / h,
            "diagonal" => half * w / (w * w + h * h).sqrt(),
            "smaller" if w <= h => half,
            "smaller" => half * w / h,
            "larger" if w >= h => half,
            "larger" => half * w / h,
            other => {
                return Err(SceneError::syntax(
                    &el.loc,
                    format!("unknown fov_axis \"{other}\" (expected x, y, diagonal, smaller or larger)"),
                ))
            }
        };
        let tan_short = if w <= h { tan_x } else { tan_x * h / w };
        let m = to_world * IMAGE_X_MIRROR;
        let world_from_camera =
            Transform::new(m).ok_or_else(|| SceneError::invalid(&el.loc, "the sensor's to_world is singular"))?;
        let (lens_radius, focal_distance) = if kind == "thinlens" {
            (p.float("aperture_radius", 0.03)?, p.float("focus_distance", 0.0)?)
        } else {
            (0.0, 1e6)
        };
        for silent in ["near_clip", "far_clip"] {
            let _ = p.get(silent);
        }
        self.desc.camera = CameraDesc {
            projection: Projection::Perspective,
            world_from_camera,
            fov_degrees: 2.0 * tan_short.atan().to_degrees(),
            lens_radius,
            focal_distance,
            screen_window: None,
        };
        self.finish(&p);
        Ok(())
    }

    /// The `orthographic` sensor (Mitsuba 3 `OrthographicCamera`): parallel rays along
    /// local +z from the region `[-1, 1] x [-1/aspect, 1/aspect]` of the plane
    /// `z = near_clip`, all in the local space that `to_world` (whose scale sizes the
    /// region) maps to the world. Mitsuba's image x runs along local -x, so x is mirrored
    /// as for the perspective sensor. `far_clip` is not applied (rays are unbounded).
    fn orthographic(&mut self, el: &Element, p: &mut Props, to_world: Mat4) -> Result<CameraDesc, SceneError> {
        let far_given = p.has("far_clip");
        let near = p.float("near_clip", 1e-2)?;
        let far = p.float("far_clip", 1e4)?;
        if !(near >= 0.0 && far > near) {
            return Err(SceneError::invalid(
                &el.loc,
                format!("orthographic sensor: need 0 <= near_clip < far_clip (got {near} and {far})"),
            ));
        }
        if far_given {
            self.warnings.push(format!(
                "{}: warning: far_clip of the orthographic sensor is not applied (rays are unbounded)",
                el.loc
            ));
        }
        // The window is sized by to_world's scale; a shear would skew the parallel rays.
        let axes = [0, 1, 2].map(|i| to_world.col(i).truncate());
        let sheared = [(0, 1), (0, 2), (1, 2)]
            .iter()
            .any(|&(i, j)| axes[i].dot(axes[j]).abs() > 1e-4 * axes[i].length() * axes[j].length());
        if sheared {
            return Err(SceneError::invalid(
                &el.loc,
                "orthographic sensor: to_world must not shear (scale before rotating)",
            ));
        }
        let m = to_world * IMAGE_X_MIRROR * Mat4::from_translation(Vec3::new(0.0, 0.0, near));
        let world_from_camera =
            Transform::new(m).ok_or_else(|| SceneError::invalid(&el.loc, "the sensor's to_world is singular"))?;
        let aspect = self.desc.film.width as f32 / self.desc.film.height as f32;
        Ok(CameraDesc {
            projection: Projection::Orthographic,
            world_from_camera,
            screen_window: Some([-1.0, 1.0, -1.0 / aspect, 1.0 / aspect]),
            ..CameraDesc::default()
        })
    }

    /// `<film>`: size and reconstruction filter.
    fn film(&mut self, el: &Element) -> Result<(), SceneError> {
        let mut p = Props::new(el);
        let w = p.int("width", 768)?;
        let h = p.int("height", 576)?;
        if !(1..=1 << 16).contains(&w) || !(1..=1 << 16).contains(&h) {
            return Err(SceneError::invalid(&el.loc, format!("film size {w}x{h} out of range")));
        }
        self.desc.film = FilmDesc {
            width: w as u32,
            height: h as u32,
        };
        for silent in ["pixel_format", "component_format", "file_format", "rfilter"] {
            let _ = p.get(silent);
        }
        for f in p.nested("rfilter") {
            if f.tag != "rfilter" {
                continue;
            }
            let mut fp = Props::new(f);
            self.desc.filter = match f.required("type")? {
                "box" => FilterDesc::Box {
                    radius: Vec2::splat(0.5),
                },
                "tent" => FilterDesc::Triangle {
                    radius: Vec2::splat(fp.float("radius", 1.0)?),
                },
                "gaussian" => gaussian_filter(fp.float("stddev", 0.5)?),
                // Mitsuba's Mitchell-Netravali and Catmull-Rom cubics span 2 pixels.
                "mitchell" => FilterDesc::Mitchell {
                    radius: Vec2::splat(2.0),
                    b: fp.float("B", 1.0 / 3.0)?,
                    c: fp.float("C", 1.0 / 3.0)?,
                },
                "catmullrom" => FilterDesc::Mitchell {
                    radius: Vec2::splat(2.0),
                    b: 0.0,
                    c: 0.5,
                },
                _ => {
                    return Err(Self::unsupported(
                        f,
                        " (filters: box, tent, gaussian, mitchell, catmullrom)",
                    ))
                }
            };
            self.finish(&fp);
        }
        self.finish(&p);
        Ok(())
    }

    /// `<sampler>`: kind, sample count and seed.
    fn sampler(&mut self, el: &Element) -> Result<(), SceneError> {
        let mut p = Props::new(el);
        let kind = match el.required("type")? {
            "independent" => SamplerKind::Independent,
            "stratified" | "multijitter" | "orthogonal" | "ldsampler" | "correlated" => {
                self.warnings.push(format!(
                    "{}: warning: {} is rendered with mcrender's Owen-scrambled Sobol' sampler",
                    el.loc,
                    el.describe()
                ));
                let _ = p.bool("jitter", true)?;
                SamplerKind::OwenSobol
            }
            _ => {
                return Err(Self::unsupported(
                    el,
                    " (samplers: independent, stratified, multijitter, ldsampler)",
                ))
            }
        };
        let spp = p.int("sample_count", 4)?;
        if !(1..=1 << 24).contains(&spp) {
            return Err(SceneError::invalid(&el.loc, format!("sample_count {spp} out of range")));
        }
        let seed = p.int("seed", 0)?;
        self.desc.sampler = SamplerDesc {
            kind,
            samples_per_pixel: spp as u32,
            seed: seed as u64,
        };
        self.finish(&p);
        Ok(())
    }

    /// `<integrator>`: path, direct, or `moment` around one of them (mcrender's film
    /// always records the per-pixel variance, which is what `moment` adds).
    fn integrator(&mut self, el: &Element) -> Result<(), SceneError> {
        let mut p = Props::new(el);
        match el.required("type")? {
            "moment" => {
                let inner: Vec<_> = p
                    .nested("integrator")
                    .into_iter()
                    .filter(|e| e.tag == "integrator")
                    .collect();
                match inner.as_slice() {
                    [i] => self.integrator(i)?,
                    _ => {
                        return Err(SceneError::syntax(
                            &el.loc,
                            "<integrator type=\"moment\"> needs exactly one nested integrator",
                        ))
                    }
                }
            }
            kind @ ("path" | "volpath" | "direct") => {
                if kind == "volpath" {
                    self.warnings.push(format!(
                        "{}: warning: volpath is rendered as path (no participating media)",
                        el.loc
                    ));
                }
                if p.bool("hide_emitters", false)? {
                    return Err(SceneError::unsupported(&el.loc, "\"hide_emitters\" = true"));
                }
                // Mitsuba chooses emitters uniformly (`Scene::sample_emitter`).
                let mut d = IntegratorDesc {
                    light_selection: LightSelection::Uniform,
                    ..IntegratorDesc::default()
                };
                if kind == "direct" {
                    d.kind = IntegratorKind::Direct;
                    d.max_depth = 1;
                    let es = p.int("emitter_samples", 1)?;
                    let bs = p.int("bsdf_samples", 1)?;
                    if es < 1 || es != bs {
                        self.warnings.push(format!(
                            "{}: warning: emitter_samples {es} and bsdf_samples {bs} are rendered as {} MIS pairs",
                            el.loc,
                            es.max(1)
                        ));
                    }
                    d.light_samples = es.max(1) as u32;
                    d.direct = DirectStrategy::Mis;
                } else {
                    // Mitsuba counts the camera ray's hit as depth 1 (max_depth 1 = emission
                    // only); mcrender counts scattering events (0 = emission only).
                    let depth = p.int("max_depth", -1)?;
                    d.max_depth = match depth {
                        -1 => UNLIMITED_DEPTH,
                        0 => {
                            return Err(SceneError::unsupported(
                                &el.loc,
                                "max_depth 0 (an image without even emission)",
                            ))
                        }
                        n if n > 0 => (n - 1).min(i64::from(UNLIMITED_DEPTH)) as u32,
                        n => {
                            return Err(SceneError::invalid(
                                &el.loc,
                                format!("max_depth {n} (expected -1 or >= 1)"),
                            ))
                        }
                    };
                    // Mitsuba's own roulette rule, from its `rr_depth`.
                    let rr_depth = p.int("rr_depth", 5)?;
                    d.russian_roulette = RussianRoulette::Delayed {
                        start_depth: u32::try_from(rr_depth).map_err(|_| {
                            SceneError::invalid(&el.loc, format!("rr_depth {rr_depth} (expected >= 0)"))
                        })?,
                    };
                }
                self.desc.integrator = d;
            }
            _ => {
                return Err(Self::unsupported(
                    el,
                    " (integrators: path, direct, volpath as path, moment)",
                ))
            }
        }
        self.finish(&p);
        Ok(())
    }
}

/// Depth standing in for Mitsuba's `max_depth = -1` (paths end by Russian roulette).
pub const UNLIMITED_DEPTH: u32 = 1024;

/// Mitsuba's `gaussian` filter: standard deviation `stddev`, radius `4 stddev`, minus its
/// value at the radius (as pbrt-v4's).
fn gaussian_filter(stddev: f32) -> FilterDesc {
    FilterDesc::Gaussian {
        radius: Vec2::splat(4.0 * stddev),
        sigma: stddev,
    }
}
