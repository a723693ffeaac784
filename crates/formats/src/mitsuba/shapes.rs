//! Shapes: `obj`, `ply`, `sphere`, `rectangle`, `disk`, `cube`, `cylinder`, `shapegroup`
//! and `instance`, each with an optional BSDF (nested or `<ref>`; Mitsuba's default is a
//! diffuse 0.5) and area `emitter`.
//!
//! Texture coordinates are stored as pbrt's (`v` up), which are Mitsuba's with `v`
//! flipped: Mitsuba flips the `v` of OBJ files (`flip_tex_coords`, default true) and
//! puts row 0 of a bitmap at `v = 0`; pbrt keeps OBJ's `v` and puts row 0 at `v = 1`.
//! The `bitmap` texture maps between the two (see `textures`).
//!
//! Normals: Mitsuba's triangles face `(p1 - p0) x (p2 - p0)` whatever the transform's
//! handedness, spheres and cylinders face outwards; `flip_normals` flips them all.

use mcrender_core::math::{Mat4, Transform, Vec2, Vec3};
use mcrender_core::scene::{AreaLightDesc, GeometryDesc, InstanceDesc, ObjectDesc, ShapeDesc, TriangleMeshDesc};

use std::sync::Arc;

use super::attributes::MeshAttributes;
use super::builder::{Builder, Named, Surface};
use super::props::Props;
use super::xml::Element;
use crate::error::{io_error_text, quoted, SceneError};
use crate::ply::PlyError;

impl Builder {
    /// `<shape>`; `group` collects the shapes of a `shapegroup` instead of the scene.
    pub fn shape(&mut self, el: &Element, group: Option<&mut ObjectDesc>) -> Result<(), SceneError> {
        let kind = el.required("type")?.to_string();
        let mut p = Props::new(el);
        if kind == "shapegroup" {
            let Some(_) = el.attr("id") else {
                return Err(SceneError::syntax(&el.loc, "a shapegroup needs an id"));
            };
            if group.is_some() {
                return Err(SceneError::unsupported(&el.loc, "a shapegroup inside a shapegroup"));
            }
            let mut object = ObjectDesc::default();
            for s in p.nested("shape") {
                if s.tag == "shape" {
                    self.shape(s, Some(&mut object))?;
                } else {
                    return Err(SceneError::unsupported(&s.loc, "<ref> in a shapegroup"));
                }
            }
            self.desc.objects.push(object);
            let idx = (self.desc.objects.len() - 1) as u32;
            self.name(el, Named::ShapeGroup(idx));
            self.finish(&p);
            return Ok(());
        }
        let to_world = p.transform("to_world")?.unwrap_or(Mat4::IDENTITY);
        let transform =
            Transform::new(to_world).ok_or_else(|| SceneError::invalid(&el.loc, "the shape's to_world is singular"))?;
        if kind == "instance" {
            let refs: Vec<_> = p.nested("shape").into_iter().filter(|e| e.tag == "ref").collect();
            let [r] = refs.as_slice() else {
                return Err(SceneError::syntax(
                    &el.loc,
                    "an instance needs one <ref> to a shapegroup",
                ));
            };
            let Named::ShapeGroup(object) = self.lookup(r)? else {
                return Err(SceneError::invalid(
                    &r.loc,
                    "an instance's <ref> must name a shapegroup",
                ));
            };
            let object = *object;
            p.use_refs();
            if group.is_some() {
                return Err(SceneError::unsupported(&el.loc, "an instance inside a shapegroup"));
            }
            self.desc.instances.push(InstanceDesc {
                object,
                world_from_instance: transform,
            });
            self.finish(&p);
            return Ok(());
        }

        // Material: a nested <bsdf> or an unnamed <ref> to one.
        let mut surface = None;
        for b in p.nested("bsdf") {
            let s = if b.tag == "bsdf" {
                self.bsdf(b)?
            } else {
                match self.lookup(b)? {
                    Named::Bsdf(s) => s.clone(),
                    Named::Other(what) if what == "emitter" => continue,
                    _ => return Err(SceneError::invalid(&b.loc, "a shape's <ref> must name a bsdf")),
                }
            };
            if surface.is_some() {
                return Err(SceneError::syntax(&b.loc, "a shape can have only one bsdf"));
            }
            surface = Some(s);
        }
        p.use_refs();
        let Surface {
            mut material,
            mut alpha,
        } = match surface {
            Some(s) => s,
            None => self.default_surface(),
        };
        let mut area_light = None;
        for e in p.nested("emitter") {
            if e.tag != "emitter" {
                continue;
            }
            if e.required("type")? != "area" {
                return Err(SceneError::unsupported(
                    &e.loc,
                    format!("{} inside a shape (only area emitters are)", e.describe()),
                ));
            }
            let mut ep = Props::new(e);
            let radiance = self.emitter_color(&mut ep, "radiance")?;
            self.finish(&ep);
            area_light = Some(AreaLightDesc {
                radiance,
                two_sided: false,
                power: None,
            });
        }
        let flip = p.bool("flip_normals", false)?;
        let mut ply_attributes = None;
        let geometry = match kind.as_str() {
            "obj" | "ply" => {
                let (file, floc) = p
                    .string("filename")?
                    .ok_or_else(|| SceneError::syntax(&el.loc, format!("{} needs a \"filename\"", el.describe())))?;
                let path = self.resolve(&file);
                let mut mesh = if kind == "obj" {
                    let flip_v = p.bool("flip_tex_coords", true)?;
                    let mut m = crate::obj::read_obj_mesh(&path, self.reader.files())
                        .map_err(|e| SceneError::io(&floc, format!("cannot read OBJ {}: {e}", quoted(&file))))?;
                    if !flip_v {
                        flip_uv_v(&mut m);
                    }
                    m
                } else {
                    let ply = crate::ply::read_ply_from(&path, self.reader.files()).map_err(|e| {
                        let why = match e {
                            PlyError::Io(io) => io_error_text(&io),
                            PlyError::Format(msg) => msg,
                        };
                        SceneError::io(&floc, format!("cannot read PLY {}: {why}", quoted(&file)))
                    })?;
                    ply_attributes = Some(MeshAttributes::of_ply(&ply));
                    let mut m = TriangleMeshDesc {
                        positions: ply.positions,
                        indices: ply.indices,
                        normals: ply.normals,
                        uvs: ply.uvs,
                        tangents: None,
                    };
                    flip_uv_v(&mut m);
                    m
                };
                if p.bool("face_normals", false)? {
                    mesh.normals = None;
                }
                GeometryDesc::TriangleMesh(to_world_mesh(mesh, &transform))
            }
            "serialized" => {
                let (file, floc) = p
                    .string("filename")?
                    .ok_or_else(|| SceneError::syntax(&el.loc, format!("{} needs a \"filename\"", el.describe())))?;
                let shape_index = p.int("shape_index", 0)?;
                let shape_index = u32::try_from(shape_index).map_err(|_| {
                    SceneError::syntax(&el.loc, format!("shape_index {shape_index}: expected 0 or more"))
                })?;
                let bytes = self.reader.files().read(&self.resolve(&file)).map_err(|e| {
                    SceneError::io(&floc, format!("cannot read {}: {}", quoted(&file), io_error_text(&e)))
                })?;
                let mut mesh = crate::serialized::read_serialized(&bytes, shape_index, self.limits.max_memory)
                    .map_err(|e| SceneError::io(&floc, format!("cannot read serialized mesh {}: {e}", quoted(&file))))?
                    .mesh;
                // Stored as Mitsuba holds uvs, like its PLY meshes: v flipped to mcrender's.
                flip_uv_v(&mut mesh);
                if p.bool("face_normals", false)? {
                    mesh.normals = None;
                }
                GeometryDesc::TriangleMesh(to_world_mesh(mesh, &transform))
            }
            "rectangle" => GeometryDesc::TriangleMesh(to_world_mesh(rectangle(), &transform)),
            "cube" => GeometryDesc::TriangleMesh(to_world_mesh(cube(), &transform)),
            "sphere" => {
                let center = p.vec3("center")?.unwrap_or(Vec3::ZERO);
                let radius = p.float("radius", 1.0)?;
                if radius <= 0.0 {
                    return Err(SceneError::invalid(
                        &el.loc,
                        format!("sphere radius {radius} must be positive"),
                    ));
                }
                let m = to_world * Mat4::from_translation(center);
                GeometryDesc::full_sphere(radius, Transform::new(m).expect("invertible"))
            }
            "disk" => GeometryDesc::Disk {
                height: 0.0,
                radius: 1.0,
                inner_radius: 0.0,
                phi_max: std::f32::consts::TAU,
                world_from_object: transform,
            },
            "cylinder" => cylinder(el, &mut p, to_world)?,
            _ => {
                return Err(Self::unsupported(
                    el,
                    " (shapes: obj, ply, sphere, rectangle, disk, cube, cylinder, shapegroup, instance)",
                ))
            }
        };
        if let Some(bsdf) = self.attribute_bsdfs.get(&material).cloned() {
            let surface = self.bsdf_with_attributes(el, &bsdf, &geometry, ply_attributes)?;
            material = surface.material;
            alpha = surface.alpha;
        }
        let shape = ShapeDesc {
            geometry,
            material,
            area_light,
            flip_normals: flip,
            alpha,
        };
        match group {
            Some(g) => {
                if shape.area_light.is_some() {
                    return Err(SceneError::unsupported(&el.loc, "an emitter inside a shapegroup"));
                }
                g.shapes.push(shape);
            }
            None => self.desc.shapes.push(shape),
        }
        self.name(el, Named::Other("shape".into()));
        self.finish(&p);
        Ok(())
    }
}

/// Mitsuba's `cylinder`: radius `radius` (1) around the segment from `p0` (origin) to `p1`
/// (`+z`), open, placed by `to_world`. Mitsuba builds its frame as
/// `to_world * translate(p0) * to_frame(Frame(d / |d|)) * scale(r, r, |d|)` with
/// `uv = (phi / 2 pi, h / |d|)` for the height `h` along `d`; `Frame` completes `d` by
/// Duff et al.'s orthonormal basis (JCGT 2017), as glam's `any_orthonormal_pair` does, so
/// the azimuth (`u`) starts where Mitsuba's does. Our cylinder keeps the radius out of the
/// transform and runs `z` from `-|d|` to 0 through a mirror `z -> -z`, so that pbrt's
/// `v = (z - z_min) / (z_max - z_min)` is `1 - h / |d|`: Mitsuba's `v` flipped, the
/// convention of every Mitsuba shape here (see the module doc). The normal stays outwards
/// through the mirror (it is transformed as a normal). A non-uniform `to_world` gives the
/// exact elliptic cylinder, where Mitsuba warns and keeps one radius.
fn cylinder(el: &Element, p: &mut Props, to_world: Mat4) -> Result<GeometryDesc, SceneError> {
    let radius = p.float("radius", 1.0)?;
    let loc_of = |p: &mut Props, name: &str| p.get(name).map_or(el.loc.clone(), |e| e.loc.clone());
    if !(radius > 0.0 && radius.is_finite()) {
        return Err(SceneError::invalid(
            &loc_of(p, "radius"),
            format!("cylinder radius {radius} must be positive"),
        ));
    }
    let p0 = p.vec3("p0")?.unwrap_or(Vec3::ZERO);
    let p1 = p.vec3("p1")?.unwrap_or(Vec3::Z);
    let d = p1 - p0;
    let length = d.length();
    if !(length > 0.0 && length.is_finite()) {
        let name = if p.has("p1") { "p1" } else { "p0" };
        return Err(SceneError::invalid(
            &loc_of(p, name),
            format!("cylinder p0 {p0} and p1 {p1} must be distinct finite points"),
        ));
    }
    // `+ 0.0` turns a -0 into +0: Mitsuba's sign(-0) is +1, glam's signum(-0) is -1.
    let axis = d / length + Vec3::ZERO;
    let (s, t) = axis.any_orthonormal_pair();
    let frame = Mat4::from_cols(s.extend(0.0), t.extend(0.0), axis.extend(0.0), glam::Vec4::W);
    let m = to_world * Mat4::from_translation(p0) * frame * Mat4::from_scale(Vec3::new(1.0, 1.0, -1.0));
    let world_from_object =
        Transform::new(m).ok_or_else(|| SceneError::invalid(&el.loc, "the cylinder's to_world is singular"))?;
    Ok(GeometryDesc::Cylinder {
        radius,
        z_min: -length,
        z_max: 0.0,
        phi_max: std::f32::consts::TAU,
        world_from_object,
    })
}

/// `v -> 1 - v` for every texture coordinate.
fn flip_uv_v(m: &mut TriangleMeshDesc) {
    if let Some(uvs) = &mut m.uvs {
        for uv in uvs {
            uv.y = 1.0 - uv.y;
        }
    }
}

/// An object-space mesh moved to world space.
fn to_world_mesh(mut m: TriangleMeshDesc, t: &Transform) -> TriangleMeshDesc {
    for p in &mut m.positions {
        *p = t.point(*p);
    }
    if let Some(ns) = &mut m.normals {
        for n in ns {
            *n = t.normal(*n).normalize_or_zero();
        }
    }
    m
}

/// Mitsuba's `rectangle`: `[-1, 1]^2` in the plane `z = 0`, facing +z, Mitsuba
/// `uv = ((x + 1) / 2, (y + 1) / 2)`.
fn rectangle() -> TriangleMeshDesc {
    let positions = vec![
        Vec3::new(-1.0, -1.0, 0.0),
        Vec3::new(1.0, -1.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(-1.0, 1.0, 0.0),
    ];
    let uvs = positions
        .iter()
        .map(|p| Vec2::new((p.x + 1.0) / 2.0, 1.0 - (p.y + 1.0) / 2.0))
        .collect();
    TriangleMeshDesc {
        positions,
        indices: vec![0, 1, 2, 0, 2, 3],
        normals: Some(vec![Vec3::Z; 4]),
        uvs: Some(uvs),
        tangents: None,
    }
}

/// Mitsuba's `cube`: `[-1, 1]^3`, faces outwards, flat normals.
fn cube() -> TriangleMeshDesc {
    let mut m = TriangleMeshDesc::default();
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let n = Vec3::from_array(std::array::from_fn(|i| if i == axis { sign } else { 0.0 }));
            let (u, v) = (n.any_orthonormal_pair().0, n.any_orthonormal_pair().1);
            let base = m.positions.len() as u32;
            for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                m.positions.push(n + u * a + v * b);
            }
            // Wind counter-clockwise seen from outside: (u x v) must point along n.
            if u.cross(v).dot(n) > 0.0 {
                m.indices.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
            } else {
                m.indices.extend([base, base + 2, base + 1, base, base + 3, base + 2]);
            }
        }
    }
    m
}

impl Builder {
    /// The `<bsdf>` `bsdf`, which reads mesh attributes, built again for the shape `el`
    /// with the attributes of its PLY file and its final vertex indices. The BSDF's `id`
    /// keeps naming the first build, and its warnings are not repeated.
    fn bsdf_with_attributes(
        &mut self,
        el: &Element,
        bsdf: &Element,
        geometry: &GeometryDesc,
        attributes: Option<MeshAttributes>,
    ) -> Result<Surface, SceneError> {
        let (GeometryDesc::TriangleMesh(mesh), Some(mut attributes)) = (geometry, attributes) else {
            return Err(SceneError::unsupported(
                &el.loc,
                format!(
                    "{} with a mesh_attribute texture (only PLY meshes have attributes)",
                    el.describe()
                ),
            ));
        };
        attributes.indices = Arc::new(mesh.indices.clone());
        let id = bsdf.attr("id").map(str::to_string);
        let named = id.as_ref().and_then(|id| self.named.get(id).cloned());
        let warnings = self.warnings.len();
        self.mesh_attributes = Some(attributes);
        let surface = self.bsdf(bsdf);
        self.mesh_attributes = None;
        self.warnings.truncate(warnings);
        if let (Some(id), Some(named)) = (id, named) {
            self.named.insert(id, named);
        }
        surface
    }
}
