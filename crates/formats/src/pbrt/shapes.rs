//! Shapes: `trianglemesh`, `plymesh`, `sphere`, `disk`, `cylinder` and `bilinearmesh`
//! (all-planar meshes as triangle pairs, others as bilinear patches). Meshes are moved to
//! world space here (points by the CTM, normals by its inverse transpose, negated under
//! `ReverseOrientation` as pbrt does, then normalised); spheres, disks and cylinders keep
//! their transform. Every shape takes an alpha cut-out (`"float alpha"` or `"texture alpha"`).

use glam::{Vec2, Vec3};
use mcrender_core::math::Transform;
use mcrender_core::scene::{BilinearMeshDesc, GeometryDesc, ShapeDesc, TriangleMeshDesc};
use mcrender_core::texture::effective_alpha;

use super::builder::SceneBuilder;
use super::params::{ParamSet, ParamType};
use crate::error::{Location, SceneError};

/// A mesh in object space, before the CTM is applied.
struct ObjectMesh {
    positions: Vec<Vec3>,
    indices: Vec<u32>,
    normals: Option<Vec<Vec3>>,
    uvs: Option<Vec<Vec2>>,
}

impl SceneBuilder {
    /// `Shape "name" ...`
    pub fn shape(&mut self, kind: &str, params: &mut ParamSet, loc: &Location) -> Result<(), SceneError> {
        self.require_world("Shape", loc)?;
        match kind {
            "trianglemesh" | "plymesh" | "sphere" | "disk" | "cylinder" | "bilinearmesh" => {}
            "loopsubdiv" | "curve" => {
                return Err(SceneError::unsupported(
                    loc,
                    format!("shape \"{kind}\" is not supported yet"),
                ));
            }
            _ => return Err(SceneError::syntax(loc, format!("unknown shape \"{kind}\""))),
        }
        params.add_inherited(&self.state.attributes.shape);
        let world_from_object = self.ctm_transform(&format!("Shape \"{kind}\""), loc)?;
        let reverse = self.state.reverse_orientation;
        let geometry = match kind {
            "trianglemesh" => {
                let mesh = self.mesh_params(kind, 3, params, loc)?;
                to_world(mesh, &world_from_object, reverse, loc)?
            }
            "bilinearmesh" => {
                let mesh = self.mesh_params(kind, 4, params, loc)?;
                if all_planar(&mesh) {
                    to_world(split_planar_patches(mesh), &world_from_object, reverse, loc)?
                } else {
                    bilinear_to_world(mesh, &world_from_object, reverse, loc)?
                }
            }
            "plymesh" => {
                let Some(mesh) = self.ply_mesh(params, loc)? else {
                    self.warn_unused(params);
                    return Ok(());
                };
                to_world(mesh, &world_from_object, reverse, loc)?
            }
            "disk" => disk(params, world_from_object)?,
            "cylinder" => cylinder(params, world_from_object)?,
            _ => self.sphere(params, world_from_object)?,
        };
        // pbrt-v4 `scene.cpp`: a `texture alpha`, else a `float alpha` below 1; opaque
        // shapes get no alpha test at all.
        let alpha = self.world.textures.float(params, "alpha", 1.0)?;
        let alpha = effective_alpha(Some(&alpha));
        for name in ["displacement", "emissionfilename"] {
            if let Some(p) = params.get(name) {
                p.mark_used();
                self.warn(
                    &p.loc,
                    format!(
                        "parameter \"{}\" of {} is not supported yet and was ignored",
                        p.decl(),
                        params.owner
                    ),
                );
            }
        }
        self.warn_unused(params);
        let flip_normals = self.state.reverse_orientation ^ world_from_object.swaps_handedness();
        let shape = ShapeDesc {
            geometry,
            material: 0,
            area_light: self.state.area_light,
            flip_normals,
            alpha,
        };
        self.add_shape(shape, loc)
    }

    /// `P`, `indices` (`per_face` a face), `N` and `uv` of a `trianglemesh` (3) or a
    /// `bilinearmesh` (4).
    fn mesh_params(
        &mut self,
        kind: &str,
        per_face: usize,
        params: &ParamSet,
        loc: &Location,
    ) -> Result<ObjectMesh, SceneError> {
        let Some((positions, _)) = params.point3s("P")? else {
            return Err(SceneError::syntax(
                loc,
                format!("Shape \"{kind}\" needs a \"point3 P\" parameter"),
            ));
        };
        let n = positions.len();
        let indices: Vec<u32> = match params.ints("indices")? {
            Some(p) => {
                if p.ints().is_empty() || p.ints().len() % per_face != 0 {
                    return Err(SceneError::invalid(
                        &p.loc,
                        format!(
                            "\"integer indices\" needs a non-zero multiple of {per_face} values, found {}",
                            p.ints().len()
                        ),
                    ));
                }
                p.ints()
                    .iter()
                    .map(|&i| {
                        usize::try_from(i)
                            .ok()
                            .filter(|&i| i < n)
                            .map(|i| i as u32)
                            .ok_or_else(|| {
                                SceneError::invalid(
                                    &p.loc,
                                    format!("vertex index {i} is out of range (P has {n} points)"),
                                )
                            })
                    })
                    .collect::<Result<_, _>>()?
            }
            None if n == per_face => (0..n as u32).collect(),
            None => {
                return Err(SceneError::syntax(
                    loc,
                    format!("Shape \"{kind}\" needs \"integer indices\" (P has {n} points, not {per_face})"),
                ))
            }
        };
        let normals = match params.normals("N")? {
            Some((normals, nloc)) => {
                check_count(normals.len(), n, "normal N", &nloc)?;
                Some(normals)
            }
            None => None,
        };
        let uvs = self.uvs(params, n)?;
        Ok(ObjectMesh {
            positions,
            indices,
            normals,
            uvs,
        })
    }

    /// Texture coordinates: pbrt-v4's `point2 uv`, or the legacy `float uv` / `float st`.
    fn uvs(&mut self, params: &ParamSet, n: usize) -> Result<Option<Vec<Vec2>>, SceneError> {
        if let Some(p) = params.lookup("uv", &[ParamType::Point2, ParamType::Float])? {
            let uvs: Vec<Vec2> = p.floats().chunks_exact(2).map(Vec2::from_slice).collect();
            if p.ty == ParamType::Float {
                if p.floats().len() % 2 != 0 {
                    return Err(SceneError::syntax(
                        &p.loc,
                        "parameter \"float uv\" needs an even number of values",
                    ));
                }
                let loc = p.loc.clone();
                self.warn(&loc, "\"float uv\" is pbrt-v3 syntax; read as \"point2 uv\"");
            }
            check_count(uvs.len(), n, &p.decl(), &p.loc)?;
            return Ok(Some(uvs));
        }
        if let Some(p) = params.lookup("st", &[ParamType::Point2, ParamType::Float])? {
            if p.floats().len() % 2 != 0 {
                return Err(SceneError::syntax(
                    &p.loc,
                    format!("parameter \"{}\" needs an even number of values", p.decl()),
                ));
            }
            let uvs: Vec<Vec2> = p.floats().chunks_exact(2).map(Vec2::from_slice).collect();
            let (loc, decl) = (p.loc.clone(), p.decl());
            self.warn(&loc, format!("\"{decl}\" is pbrt-v3 syntax; read as \"point2 uv\""));
            check_count(uvs.len(), n, &decl, &loc)?;
            return Ok(Some(uvs));
        }
        Ok(None)
    }

    /// Read the PLY file of a `plymesh`; `None` when it has no triangles (after a warning).
    fn ply_mesh(&mut self, params: &ParamSet, loc: &Location) -> Result<Option<ObjectMesh>, SceneError> {
        let Some((filename, _)) = params.string("filename")? else {
            return Err(SceneError::syntax(
                loc,
                "Shape \"plymesh\" needs a \"string filename\" parameter",
            ));
        };
        let mesh = self.read_ply_file(&filename, loc)?;
        if mesh.skipped_faces > 0 {
            self.warn(
                loc,
                format!(
                    "PLY file \"{filename}\": skipped {} faces that are neither triangles nor quads",
                    mesh.skipped_faces
                ),
            );
        }
        if mesh.indices.is_empty() {
            self.warn(loc, format!("PLY file \"{filename}\" has no triangles; shape ignored"));
            return Ok(None);
        }
        Ok(Some(ObjectMesh {
            positions: mesh.positions,
            indices: mesh.indices,
            normals: mesh.normals,
            uvs: mesh.uvs,
        }))
    }

    fn sphere(&mut self, params: &ParamSet, world_from_object: Transform) -> Result<GeometryDesc, SceneError> {
        let radius = params.float("radius", 1.0)?;
        if radius <= 0.0 {
            let rloc = params.get("radius").map_or(&params.loc, |p| &p.loc);
            return Err(SceneError::invalid(
                rloc,
                format!("sphere radius must be positive, found {radius}"),
            ));
        }
        // pbrt-v4: zmin and zmax are clamped to [-radius, radius] (either order), phimax to
        // [0, 360] degrees.
        let (z0, z1) = (params.float("zmin", -radius)?, params.float("zmax", radius)?);
        let (z_min, z_max) = (z0.min(z1).clamp(-radius, radius), z0.max(z1).clamp(-radius, radius));
        let phi_max = params.float("phimax", 360.0)?.clamp(0.0, 360.0);
        if z_min >= z_max || phi_max <= 0.0 {
            let name = if phi_max <= 0.0 { "phimax" } else { "zmin" };
            let loc = params.get(name).or(params.get("zmax")).map_or(&params.loc, |p| &p.loc);
            return Err(SceneError::invalid(
                loc,
                format!(
                    "sphere cut zmin {z0}, zmax {z1}, phimax {phi_max} leaves nothing of a sphere of radius {radius}"
                ),
            ));
        }
        Ok(GeometryDesc::Sphere {
            radius,
            world_from_object,
            z_min,
            z_max,
            phi_max,
        })
    }
}

/// `Shape "disk"`: `height` (0), `radius` (1), `innerradius` (0), `phimax` (360 degrees).
fn disk(params: &ParamSet, world_from_object: Transform) -> Result<GeometryDesc, SceneError> {
    let at = |name: &str| params.get(name).map_or(&params.loc, |p| &p.loc).clone();
    let height = params.float("height", 0.0)?;
    let radius = params.float("radius", 1.0)?;
    let inner_radius = params.float("innerradius", 0.0)?;
    let phi_max = params.float("phimax", 360.0)?;
    if !(radius > 0.0 && radius.is_finite()) {
        return Err(SceneError::invalid(
            &at("radius"),
            format!("disk radius must be positive, found {radius}"),
        ));
    }
    if !(inner_radius >= 0.0 && inner_radius < radius) {
        return Err(SceneError::invalid(
            &at("innerradius"),
            format!("disk innerradius must be in [0, radius = {radius}), found {inner_radius}"),
        ));
    }
    if !height.is_finite() {
        return Err(SceneError::invalid(&at("height"), "disk height must be finite"));
    }
    // pbrt-v4 clamps phimax to [0, 360].
    let phi_max = phi_max.clamp(0.0, 360.0);
    if phi_max <= 0.0 {
        return Err(SceneError::invalid(
            &at("phimax"),
            "disk phimax must be positive".to_string(),
        ));
    }
    Ok(GeometryDesc::Disk {
        height,
        radius,
        inner_radius,
        phi_max: phi_max.to_radians(),
        world_from_object,
    })
}

/// `Shape "cylinder"`: `radius` (1), `zmin` (-1), `zmax` (1), `phimax` (360 degrees).
/// pbrt-v4 accepts `zmin` and `zmax` in either order and clamps `phimax` to `[0, 360]`.
fn cylinder(params: &ParamSet, world_from_object: Transform) -> Result<GeometryDesc, SceneError> {
    let at = |name: &str| params.get(name).map_or(&params.loc, |p| &p.loc).clone();
    let radius = params.float("radius", 1.0)?;
    let (z0, z1) = (params.float("zmin", -1.0)?, params.float("zmax", 1.0)?);
    let phi_max = params.float("phimax", 360.0)?;
    if !(radius > 0.0 && radius.is_finite()) {
        return Err(SceneError::invalid(
            &at("radius"),
            format!("cylinder radius must be positive, found {radius}"),
        ));
    }
    if !(z0.is_finite() && z1.is_finite()) || z0 == z1 {
        let name = if params.get("zmax").is_some() { "zmax" } else { "zmin" };
        return Err(SceneError::invalid(
            &at(name),
            format!("cylinder zmin and zmax must be finite and differ, found {z0} and {z1}"),
        ));
    }
    let phi_max = phi_max.clamp(0.0, 360.0);
    if phi_max <= 0.0 {
        return Err(SceneError::invalid(&at("phimax"), "cylinder phimax must be positive"));
    }
    Ok(GeometryDesc::Cylinder {
        radius,
        z_min: z0.min(z1),
        z_max: z0.max(z1),
        phi_max: phi_max.to_radians(),
        world_from_object,
    })
}

/// Relative tolerance of the planarity test of bilinear patches: the volume spanned by the
/// patch's edges from one corner, against the cube of its longest edge or diagonal.
const PLANAR_TOLERANCE: f32 = 1e-4;

/// Whether every patch `p00, p10, p01, p11` of a bilinear mesh is planar (up to
/// [`PLANAR_TOLERANCE`]).
fn all_planar(mesh: &ObjectMesh) -> bool {
    let p = &mesh.positions;
    mesh.indices.chunks_exact(4).all(|q| {
        let [p00, p10, p01, p11] = [0, 1, 2, 3].map(|j| p[q[j] as usize]);
        let (e1, e2, e3) = (p10 - p00, p01 - p00, p11 - p00);
        let size = [e1, e2, e3, p11 - p10, p11 - p01, p10 - p01]
            .iter()
            .map(|e| e.length())
            .fold(0.0f32, f32::max);
        let volume = e1.cross(e2).dot(e3).abs();
        volume <= PLANAR_TOLERANCE * size * size * size
    })
}

/// Split each planar bilinear patch `p00, p10, p01, p11` (pbrt-v4's vertex order) into the
/// triangles `p00 p10 p11` and `p00 p11 p01`, whose normals are pbrt-v4's `dpdu x dpdv`.
/// Triangle pairs trace faster than patches (see docs/pbrt-support.md) and keep the
/// renders of planar-patch scenes as they were. Without `uv`, each patch gets its own four
/// vertices with pbrt-v4's default (u, v) at the corners (exact for parallelograms, affine
/// per triangle otherwise).
fn split_planar_patches(mesh: ObjectMesh) -> ObjectMesh {
    let p = &mesh.positions;
    let tri = |q: &[u32]| [q[0], q[1], q[3], q[0], q[3], q[2]];
    if mesh.uvs.is_some() {
        let indices = mesh.indices.chunks_exact(4).flat_map(tri).collect();
        return ObjectMesh { indices, ..mesh };
    }
    let mut out = ObjectMesh {
        positions: Vec::with_capacity(mesh.indices.len()),
        indices: Vec::with_capacity(mesh.indices.len() / 4 * 6),
        normals: mesh.normals.as_ref().map(|_| Vec::with_capacity(mesh.indices.len())),
        uvs: Some(Vec::with_capacity(mesh.indices.len())),
    };
    let corners = [Vec2::ZERO, Vec2::X, Vec2::Y, Vec2::ONE];
    for q in mesh.indices.chunks_exact(4) {
        let base = out.positions.len() as u32;
        for (j, &i) in q.iter().enumerate() {
            out.positions.push(p[i as usize]);
            if let (Some(dst), Some(src)) = (&mut out.normals, &mesh.normals) {
                dst.push(src[i as usize]);
            }
            if let Some(uvs) = &mut out.uvs {
                uvs.push(corners[j]);
            }
        }
        out.indices.extend(tri(&[base, base + 1, base + 2, base + 3]));
    }
    out
}

fn check_count(found: usize, expected: usize, decl: &str, loc: &Location) -> Result<(), SceneError> {
    if found == expected {
        Ok(())
    } else {
        Err(SceneError::invalid(
            loc,
            format!("\"{decl}\" has {found} values but P has {expected} points"),
        ))
    }
}

/// Move an object-space bilinear mesh (with a curved patch) to world space.
fn bilinear_to_world(
    mesh: ObjectMesh,
    world_from_object: &Transform,
    reverse_orientation: bool,
    loc: &Location,
) -> Result<GeometryDesc, SceneError> {
    let m = world_arrays(mesh, world_from_object, reverse_orientation, loc)?;
    Ok(GeometryDesc::BilinearMesh(BilinearMeshDesc {
        positions: m.positions,
        indices: m.indices,
        normals: m.normals,
        uvs: m.uvs,
    }))
}

/// Move an object-space triangle mesh to world space.
fn to_world(
    mesh: ObjectMesh,
    world_from_object: &Transform,
    reverse_orientation: bool,
    loc: &Location,
) -> Result<GeometryDesc, SceneError> {
    let m = world_arrays(mesh, world_from_object, reverse_orientation, loc)?;
    Ok(GeometryDesc::TriangleMesh(TriangleMeshDesc {
        positions: m.positions,
        indices: m.indices,
        normals: m.normals,
        uvs: m.uvs,
        tangents: None,
    }))
}

/// The mesh's positions and normals in world space.
fn world_arrays(
    mesh: ObjectMesh,
    world_from_object: &Transform,
    reverse_orientation: bool,
    loc: &Location,
) -> Result<ObjectMesh, SceneError> {
    let positions: Vec<Vec3> = mesh.positions.iter().map(|&p| world_from_object.point(p)).collect();
    if positions.iter().any(|p| !p.is_finite()) {
        return Err(SceneError::invalid(
            loc,
            "mesh vertices are not finite after transformation to world space",
        ));
    }
    let normals = mesh.normals.map(|normals| {
        let sign = if reverse_orientation { -1.0 } else { 1.0 };
        // A zero normal stays zero: pbrt then falls back to the geometric normal.
        normals
            .iter()
            .map(|&n| (sign * world_from_object.normal(n)).normalize_or_zero())
            .collect()
    });
    Ok(ObjectMesh {
        positions,
        indices: mesh.indices,
        normals,
        uvs: mesh.uvs,
    })
}
