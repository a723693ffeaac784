//! A loader for glTF 2.0 scenes (`.gltf` with external or embedded buffers, and `.glb`),
//! parsed and validated by the `gltf` crate.
//!
//! Read: the default scene (else the first) and its node hierarchy with each node's
//! matrix or TRS transform; meshes (triangle primitives, indexed or not, with `NORMAL`,
//! `TEXCOORD_0` and `TANGENT`, the last used only with normals as the spec says), moved
//! to world space; the first perspective camera met in the
//! hierarchy (else the default framing of [`crate::framing`]); `KHR_lights_punctual`
//! (see `lights`); materials (see `materials`). A scene without emitters gets a uniform
//! environment light. Unsupported extensions are warnings naming them; malformed input
//! (bad JSON, a missing buffer, an accessor outside its buffer) is an error naming the
//! file and the JSON path of the culprit (`meshes[0].primitives[1].indices`).
//!
//! glTF cameras look along their -z with +y up; mcrender's (pbrt's) along +z, so the
//! camera transform is mirrored in z. Texture coordinates are stored as `(u, 1 - v)`:
//! glTF's `v` runs down the image, mcrender's up.

mod data;
mod lights;
mod materials;

use std::path::Path;
use std::sync::Arc;

use gltf::mesh::{Mode, Semantic};
use mcrender_core::math::{Mat3, Mat4, Transform, Vec2, Vec3, Vec4};
use mcrender_core::scene::{CameraDesc, FilmDesc, GeometryDesc, SceneDescription, ShapeDesc, TriangleMeshDesc};

use crate::error::{io_error_text, Location, SceneError};
use crate::limits::LoadLimits;
use crate::LoadedScene;
use data::Buffers;
use materials::Materials;

/// Extensions mcrender reads.
pub const SUPPORTED_EXTENSIONS: [&str; 5] = [
    "KHR_lights_punctual",
    "KHR_materials_emissive_strength",
    "KHR_materials_transmission",
    "KHR_materials_ior",
    "KHR_texture_transform",
];

/// Most nodes visited (a node shared by several parents is visited once per path, which
/// hostile files could make exponential).
const MAX_NODE_VISITS: usize = 1 << 20;

/// Load the glTF file `path`.
///
/// # Errors
/// When the file cannot be read or is malformed, or a buffer or image it names cannot be
/// read or (sized from its header) would pass `limits`; the display reads `file: json.path: message` (or `file:line:col:` for bad JSON).
pub fn load_gltf(path: &Path, limits: LoadLimits) -> Result<LoadedScene, SceneError> {
    let file: Arc<str> = path.display().to_string().into();
    let bytes = std::fs::read(path).map_err(|e| {
        SceneError::io(
            &Location::file_only(file.clone()),
            format!("cannot open the glTF file: {}", io_error_text(&e)),
        )
    })?;
    load_gltf_slice(&bytes, &file, path.parent().unwrap_or_else(|| Path::new("")), limits)
}

/// Load a glTF document from `bytes` (JSON or GLB), named `file` in messages, resolving
/// relative URIs against `dir`.
///
/// # Errors
/// As [`load_gltf`].
pub fn load_gltf_slice(bytes: &[u8], file: &str, dir: &Path, limits: LoadLimits) -> Result<LoadedScene, SceneError> {
    let file: Arc<str> = file.into();
    let loc = Location::file_only(file.clone());
    // gltf 1.4.1 subtracts 12 from a GLB's declared length unchecked (a panic where
    // overflow is checked).
    if let Some(h) = bytes.get(..12).filter(|h| h.starts_with(b"glTF")) {
        let length = u32::from_le_bytes([h[8], h[9], h[10], h[11]]);
        if length < 12 {
            return Err(SceneError::syntax(
                &loc,
                format!("invalid GLB: header length {length} is below the header's 12 bytes"),
            ));
        }
    }
    // gltf-json 1.4.1's validation indexes the accessors by each primitive's POSITION
    // before checking the index (and panics on a bad one): check those first.
    let raw = gltf::Gltf::from_slice_without_validation(bytes).map_err(|e| parse_error(&file, e))?;
    let accessors = raw.as_json().accessors.len();
    for (m, mesh) in raw.as_json().meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            for (semantic, index) in &prim.attributes {
                if index.value() >= accessors {
                    let name = match semantic {
                        gltf::json::validation::Checked::Valid(s) => s.to_string(),
                        gltf::json::validation::Checked::Invalid => "?".to_string(),
                    };
                    return Err(SceneError::invalid(
                        &loc,
                        format!(
                            "meshes[{m}].primitives[{p}].attributes.{name}: accessor {} does not exist ({accessors} accessors)",
                            index.value()
                        ),
                    ));
                }
            }
        }
    }
    let gltf::Gltf { document, blob } = gltf::Gltf::from_slice(bytes).map_err(|e| parse_error(&file, e))?;
    let invalid = |m: String| SceneError::invalid(&loc, m);
    let mut warnings = Vec::new();
    for ext in document.extensions_used() {
        if !SUPPORTED_EXTENSIONS.contains(&ext) {
            warnings.push(format!("extensionsUsed: {ext} is not supported and is ignored"));
        }
    }
    let buffers = Buffers::load(&document, dir, blob).map_err(invalid)?;
    let scene = document
        .default_scene()
        .or_else(|| document.scenes().next())
        .ok_or_else(|| SceneError::invalid(&loc, "scenes: the file has no scene"))?;
    let mut walk = Walk {
        buffers: &buffers,
        materials: Materials::new(&buffers, dir, limits),
        desc: crate::framing::model_scene(),
        camera: None,
        warnings: Vec::new(),
        visits: 0,
    };
    let mut on_path = Vec::new();
    for node in scene.nodes() {
        walk.node(&node, Mat4::IDENTITY, &mut on_path).map_err(invalid)?;
    }
    let Walk {
        mut desc,
        camera,
        warnings: walk_warnings,
        materials,
        ..
    } = walk;
    warnings.extend(walk_warnings);
    let mut warnings: Vec<String> = warnings.into_iter().map(|w| format!("{file}: warning: {w}")).collect();
    let has_camera = camera.is_some();
    if let Some((camera, film)) = camera {
        desc.camera = camera;
        desc.film = film;
    }
    crate::framing::add_defaults(&mut desc, &file, has_camera, &mut warnings);
    if desc.shapes.is_empty() && desc.lights.len() <= 1 {
        warnings.push(format!("{file}: warning: the scene has no triangles"));
    }
    Ok(LoadedScene {
        description: desc,
        output_filename: None,
        warnings,
        image_bytes: materials.image_bytes,
    })
}

/// A `gltf` parse or validation error as a [`SceneError`].
fn parse_error(file: &Arc<str>, e: gltf::Error) -> SceneError {
    match e {
        gltf::Error::Deserialize(j) => SceneError::syntax(
            &Location::new(file.clone(), j.line() as u32, j.column() as u32),
            format!("invalid glTF JSON: {j}"),
        ),
        gltf::Error::Validation(errors) => {
            let more = match errors.len() {
                0 | 1 => String::new(),
                n => format!(" (and {} more)", n - 1),
            };
            let first = errors
                .first()
                .map_or_else(|| "invalid glTF".to_string(), |(p, e)| format!("{p}: {e}"));
            SceneError::invalid(&Location::file_only(file.clone()), format!("{first}{more}"))
        }
        gltf::Error::Binary(b) => SceneError::syntax(&Location::file_only(file.clone()), format!("invalid GLB: {b}")),
        other => SceneError::invalid(&Location::file_only(file.clone()), data::error_text(&other)),
    }
}

/// The state of one traversal of the node hierarchy.
struct Walk<'a> {
    buffers: &'a Buffers,
    materials: Materials<'a>,
    desc: SceneDescription,
    camera: Option<(CameraDesc, FilmDesc)>,
    warnings: Vec<String>,
    visits: usize,
}

impl Walk<'_> {
    fn node(&mut self, node: &gltf::Node<'_>, parent: Mat4, on_path: &mut Vec<usize>) -> Result<(), String> {
        let path = format!("nodes[{}]", node.index());
        if on_path.contains(&node.index()) {
            return Err(format!("{path}: the node hierarchy has a cycle"));
        }
        self.visits += 1;
        if self.visits > MAX_NODE_VISITS {
            return Err(format!(
                "{path}: more than {MAX_NODE_VISITS} node visits (nodes shared by many parents?)"
            ));
        }
        let local = Mat4::from_cols_array_2d(&node.transform().matrix());
        let m = parent * local;
        if !m.is_finite() {
            return Err(format!("{path}: the transform is not finite"));
        }
        if let Some(mesh) = node.mesh() {
            self.mesh(&mesh, m)?;
        }
        if let Some(camera) = node.camera() {
            self.camera(&camera, m, &path)?;
        }
        if let Some(l) = node.light() {
            let light = lights::light(&l, m, &mut self.warnings)?;
            self.desc.lights.push(light);
        }
        on_path.push(node.index());
        for child in node.children() {
            self.node(&child, m, on_path)?;
        }
        on_path.pop();
        Ok(())
    }

    /// The first perspective camera wins; later ones and orthographic ones are warnings.
    fn camera(&mut self, camera: &gltf::Camera<'_>, m: Mat4, node_path: &str) -> Result<(), String> {
        let path = format!("cameras[{}]", camera.index());
        if self.camera.is_some() {
            self.warnings
                .push(format!("{path} (at {node_path}): only the first camera is rendered"));
            return Ok(());
        }
        let gltf::camera::Projection::Perspective(p) = camera.projection() else {
            self.warnings
                .push(format!("{path}: orthographic cameras are not supported; ignored"));
            return Ok(());
        };
        let yfov = p.yfov();
        if !(yfov > 0.0 && yfov < std::f32::consts::PI) {
            return Err(format!(
                "{path}.perspective.yfov: expected radians in (0, pi), found {yfov}"
            ));
        }
        let aspect = p.aspect_ratio().unwrap_or(4.0 / 3.0);
        if !(aspect > 1e-3 && aspect < 1e3) {
            return Err(format!(
                "{path}.perspective.aspectRatio: expected a positive ratio, found {aspect}"
            ));
        }
        let width = 640u32;
        let height = ((width as f32 / aspect).round() as u32).clamp(1, 1 << 16);
        // mcrender's field of view spans the shorter image axis.
        let fov = if aspect >= 1.0 {
            yfov
        } else {
            2.0 * (aspect * (0.5 * yfov).tan()).atan()
        };
        let world_from_camera = Transform::new(m * Mat4::from_scale(Vec3::new(1.0, 1.0, -1.0)))
            .ok_or_else(|| format!("{node_path}: the camera's transform is singular"))?;
        self.camera = Some((
            CameraDesc {
                world_from_camera,
                fov_degrees: fov.to_degrees(),
                ..CameraDesc::default()
            },
            FilmDesc { width, height },
        ));
        Ok(())
    }

    fn mesh(&mut self, mesh: &gltf::Mesh<'_>, m: Mat4) -> Result<(), String> {
        let normal_matrix = Mat3::from_mat4(m).inverse().transpose();
        let flips = Mat3::from_mat4(m).determinant() < 0.0;
        for prim in mesh.primitives() {
            let path = format!("meshes[{}].primitives[{}]", mesh.index(), prim.index());
            if prim.mode() != Mode::Triangles {
                self.warnings
                    .push(format!("{path}.mode {:?} is not triangles; skipped", prim.mode()));
                continue;
            }
            let Some(pos) = prim.get(&Semantic::Positions) else {
                return Err(format!("{path}.attributes: no POSITION"));
            };
            let p = data::read(self.buffers, &pos, 3, &format!("{path}.attributes.POSITION"))?;
            let positions: Vec<Vec3> = p
                .chunks_exact(3)
                .map(|c| m.transform_point3(Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32)))
                .collect();
            if positions.iter().any(|p| !p.is_finite()) {
                return Err(format!("{path}.attributes.POSITION: non-finite vertex position"));
            }
            let n = positions.len();
            let indices = match prim.indices() {
                Some(a) => data::read_indices(self.buffers, &a, n, &format!("{path}.indices"))?,
                None => (0..n as u32).collect(),
            };
            if indices.len() % 3 != 0 {
                return Err(format!(
                    "{path}.indices: {} indices is not a multiple of 3",
                    indices.len()
                ));
            }
            if indices.is_empty() {
                continue;
            }
            let normals = match prim.get(&Semantic::Normals) {
                Some(a) => {
                    let v = data::read(self.buffers, &a, 3, &format!("{path}.attributes.NORMAL"))?;
                    let normals: Vec<Vec3> = v
                        .chunks_exact(3)
                        .map(|c| (normal_matrix * Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32)).normalize_or_zero())
                        .collect();
                    if normals.len() != n {
                        return Err(format!(
                            "{path}.attributes.NORMAL: {} normals for {n} positions",
                            normals.len()
                        ));
                    }
                    normals
                        .iter()
                        .all(|v| v.is_finite() && *v != Vec3::ZERO)
                        .then_some(normals)
                }
                None => None,
            };
            let uvs = match prim.get(&Semantic::TexCoords(0)) {
                Some(a) => {
                    let v = data::read(self.buffers, &a, 2, &format!("{path}.attributes.TEXCOORD_0"))?;
                    let uvs: Vec<Vec2> = v
                        .chunks_exact(2)
                        .map(|c| Vec2::new(c[0] as f32, 1.0 - c[1] as f32))
                        .collect();
                    if uvs.len() != n {
                        return Err(format!(
                            "{path}.attributes.TEXCOORD_0: {} uvs for {n} positions",
                            uvs.len()
                        ));
                    }
                    uvs.iter().all(|v| v.is_finite()).then_some(uvs)
                }
                None => None,
            };
            // The spec: without normals, tangents are ignored.
            let tangents = match prim.get(&Semantic::Tangents).filter(|_| normals.is_some()) {
                Some(a) => Some(tangents(self.buffers, &a, m, n, &format!("{path}.attributes.TANGENT"))?),
                None => None,
            };
            let c = self
                .materials
                .get(&prim.material(), &mut self.desc.materials, &mut self.warnings)?;
            self.desc.shapes.push(ShapeDesc {
                geometry: GeometryDesc::TriangleMesh(TriangleMeshDesc {
                    positions,
                    indices,
                    normals,
                    uvs,
                    tangents,
                }),
                material: c.material,
                area_light: c.area_light,
                flip_normals: flips,
                alpha: c.alpha,
            });
        }
        Ok(())
    }
}

/// A primitive's `TANGENT`s (`xyz` the tangent, `w` = +-1 the handedness of the bitangent
/// `w (normal x tangent)`) in world space: `xyz` moves as a surface vector, and a mirroring
/// `m` turns the handedness around (the cross product of mirrored vectors changes sign).
fn tangents(buffers: &Buffers, a: &gltf::Accessor<'_>, m: Mat4, n: usize, path: &str) -> Result<Vec<Vec4>, String> {
    let v = data::read(buffers, a, 4, path)?;
    if v.iter().any(|x| !x.is_finite()) {
        return Err(format!("{path}: non-finite tangent"));
    }
    let linear = Mat3::from_mat4(m);
    let handedness = linear.determinant().signum();
    let t: Vec<Vec4> = v
        .chunks_exact(4)
        .map(|c| {
            let xyz = (linear * Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32)).normalize_or_zero();
            let w = if c[3] < 0.0 { -handedness } else { handedness };
            xyz.extend(w)
        })
        .collect();
    if t.len() != n {
        return Err(format!("{path}: {} tangents for {n} positions", t.len()));
    }
    Ok(t)
}
