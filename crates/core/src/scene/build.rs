//! Building a [`Scene`] from a [`SceneDescription`]: validation (indices in range, finite
//! numbers, sane sizes) with errors that say what is wrong, then flattening shapes into
//! primitives and building the BVH.

use std::sync::Arc;

use super::{
    EnvMapping, GeometryDesc, Instance, LightDesc, MaterialDesc, ObjectGeometry, Primitive, Scene, SceneDescription,
    ShapeDesc,
};
use crate::accel::WideBvh;
use crate::camera::Camera;
use crate::film::Filter;
use crate::light::{
    DiffuseAreaLight, DistantLight, ImageInfiniteLight, Light, PointLight, PowerLightSampler, SpotLight,
    UniformInfiniteLight,
};
use crate::material::{check_finite, check_non_negative, InvalidParameter, Material};
use crate::math::{Vec2, Vec3, Vec4};
use crate::shape::{BilinearMesh, BilinearPatch, Cylinder, Disk, Shape, Sphere, SphereClip, Triangle, TriangleMesh};
use crate::texture::effective_alpha;

/// Largest image side accepted.
pub const MAX_RESOLUTION: u32 = 32_768;
/// Largest pixel count accepted.
pub const MAX_PIXELS: u64 = 1 << 28;

/// Largest coordinate (in absolute value) a shape may reach in world space. Rendering
/// works in 32-bit floats, where a squared distance overflows to infinity past about
/// 1.8e19; beyond this bound areas, pdfs and ray offsets become infinite or zero and the
/// image black (issue 10: a sphere of radius 1e38 rendered black and exited 0).
pub const MAX_SCENE_COORDINATE: f32 = 1e18;

/// Why a description cannot be rendered.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum BuildError {
    /// A value is out of its valid range or not finite.
    #[error("invalid {what}: {detail}")]
    Invalid {
        /// Which parameter.
        what: String,
        /// What was wrong.
        detail: String,
    },
}

fn invalid(what: impl Into<String>, detail: impl Into<String>) -> BuildError {
    BuildError::Invalid {
        what: what.into(),
        detail: detail.into(),
    }
}

impl From<InvalidParameter> for BuildError {
    fn from(e: InvalidParameter) -> Self {
        Self::Invalid {
            what: e.what,
            detail: e.detail,
        }
    }
}

impl SceneDescription {
    /// Check every value the renderer relies on.
    pub fn validate(&self) -> Result<(), BuildError> {
        let (w, h) = (self.film.width, self.film.height);
        if w == 0 || h == 0 || w > MAX_RESOLUTION || h > MAX_RESOLUTION || u64::from(w) * u64::from(h) > MAX_PIXELS {
            return Err(invalid(
                "resolution",
                format!("{w}x{h}; expected 1 to {MAX_RESOLUTION} pixels per side and at most {MAX_PIXELS} pixels"),
            ));
        }
        if self.sampler.samples_per_pixel == 0 {
            return Err(invalid("samples per pixel", "expected at least 1, found 0"));
        }
        let int = &self.integrator;
        if int.light_samples == 0 {
            return Err(invalid("light samples", "expected at least 1, found 0"));
        }
        if let super::RussianRoulette::Threshold { threshold, probability } = int.russian_roulette {
            check_non_negative("Russian roulette threshold", &[threshold])?;
            if !(0.0..1.0).contains(&probability) {
                return Err(invalid(
                    "Russian roulette probability",
                    format!("expected [0, 1), found {probability}"),
                ));
            }
        }
        let c = &self.camera;
        check_finite("camera transform", &c.world_from_camera.m.to_cols_array())?;
        if !(c.fov_degrees > 0.0 && c.fov_degrees < 180.0) {
            return Err(invalid(
                "camera fov",
                format!("expected degrees in (0, 180), found {}", c.fov_degrees),
            ));
        }
        check_non_negative("camera lens radius", &[c.lens_radius])?;
        if c.lens_radius > 0.0 && (c.focal_distance.is_nan() || c.focal_distance <= 0.0) {
            return Err(invalid(
                "camera focal distance",
                format!("expected > 0, found {}", c.focal_distance),
            ));
        }
        match self.filter {
            super::FilterDesc::Box { radius } | super::FilterDesc::Triangle { radius } => {
                check_positive_radius(radius.to_array())?;
            }
            super::FilterDesc::Gaussian { radius, sigma } => {
                check_positive_radius(radius.to_array())?;
                if !(sigma > 0.0 && sigma.is_finite()) {
                    return Err(invalid("filter sigma", format!("expected > 0, found {sigma}")));
                }
            }
            super::FilterDesc::Mitchell { radius, b, c } => {
                check_positive_radius(radius.to_array())?;
                check_finite("Mitchell filter B and C", &[b, c])?;
            }
        }
        let own_driver = matches!(
            self.integrator.kind,
            super::IntegratorKind::Sppm | super::IntegratorKind::Mlt
        );
        if self.reconstruction == crate::film::Reconstruction::FilterSplatting && own_driver {
            return Err(invalid(
                "filter splatting",
                format!(
                    "the {:?} integrator fills the film itself; expected filter sampling",
                    self.integrator.kind
                ),
            ));
        }
        for (i, m) in self.materials.iter().enumerate() {
            m.validate(i, self.materials.len())?;
        }
        check_mix_cycles(&self.materials)?;
        validate_shapes(&self.shapes, self.materials.len())?;
        for (k, o) in self.objects.iter().enumerate() {
            validate_shapes(&o.shapes, self.materials.len())?;
            if o.shapes.iter().any(|s| s.area_light.is_some()) {
                return Err(invalid(
                    format!("object {k}"),
                    "Area lights not supported with object instancing",
                ));
            }
        }
        for (k, inst) in self.instances.iter().enumerate() {
            if inst.object as usize >= self.objects.len() {
                return Err(invalid(
                    format!("instance {k}"),
                    format!("object index {} out of range", inst.object),
                ));
            }
            check_finite("instance transform", &inst.world_from_instance.m.to_cols_array())?;
        }
        for (i, l) in self.lights.iter().enumerate() {
            validate_light(i, l)?;
        }
        Ok(())
    }
}

/// Check the shapes of the scene or of an object.
fn validate_shapes(shapes: &[ShapeDesc], n_materials: usize) -> Result<(), BuildError> {
    for (i, s) in shapes.iter().enumerate() {
        if s.material as usize >= n_materials {
            return Err(invalid(
                format!("shape {i}"),
                format!("material index {} out of range", s.material),
            ));
        }
        if let Some(a) = &s.area_light {
            check_non_negative(&format!("emitted radiance of shape {i}"), &a.radiance.to_array())?;
            if let Some(p) = a.power {
                check_non_negative(&format!("power of the area light of shape {i}"), &[p])?;
            }
        }
        match &s.geometry {
            GeometryDesc::TriangleMesh(m) => {
                let what = format!("triangle mesh (shape {i})");
                check_mesh(
                    &what,
                    3,
                    &m.positions,
                    &m.indices,
                    m.normals.as_deref(),
                    m.uvs.as_deref(),
                )?;
                check_tangents(&what, m.positions.len(), m.tangents.as_deref())?;
            }
            GeometryDesc::BilinearMesh(m) => check_mesh(
                &format!("bilinear mesh (shape {i})"),
                4,
                &m.positions,
                &m.indices,
                m.normals.as_deref(),
                m.uvs.as_deref(),
            )?,
            GeometryDesc::Sphere {
                radius,
                world_from_object,
                z_min,
                z_max,
                phi_max,
            } => {
                if !(*radius > 0.0 && radius.is_finite()) {
                    return Err(invalid(
                        format!("sphere (shape {i})"),
                        format!("expected radius > 0, found {radius}"),
                    ));
                }
                check_finite("sphere zmin, zmax, phimax", &[*z_min, *z_max, *phi_max])?;
                let (lo, hi) = (z_min.min(*z_max).max(-radius), z_min.max(*z_max).min(*radius));
                if lo >= hi || *phi_max <= 0.0 {
                    return Err(invalid(
                        format!("sphere (shape {i})"),
                        format!(
                            "the cut zmin {z_min}, zmax {z_max}, phimax {phi_max} leaves nothing of a sphere of radius {radius}"
                        ),
                    ));
                }
                check_finite("sphere transform", &world_from_object.m.to_cols_array())?;
            }
            GeometryDesc::Disk {
                height,
                radius,
                inner_radius,
                phi_max,
                world_from_object,
            } => {
                let what = format!("disk (shape {i})");
                if !(*radius > 0.0 && radius.is_finite() && height.is_finite()) {
                    return Err(invalid(
                        what,
                        format!("expected a finite height and radius > 0, found {height} and {radius}"),
                    ));
                }
                if !(*inner_radius >= 0.0 && inner_radius < radius) {
                    return Err(invalid(
                        what,
                        format!("expected 0 <= inner radius < radius, found {inner_radius} and {radius}"),
                    ));
                }
                check_phi_max(&what, *phi_max)?;
                check_finite("disk transform", &world_from_object.m.to_cols_array())?;
            }
            GeometryDesc::Cylinder {
                radius,
                z_min,
                z_max,
                phi_max,
                world_from_object,
            } => {
                let what = format!("cylinder (shape {i})");
                if !(*radius > 0.0 && radius.is_finite()) {
                    return Err(invalid(what, format!("expected radius > 0, found {radius}")));
                }
                if !(z_min.is_finite() && z_max.is_finite() && z_min < z_max) {
                    return Err(invalid(
                        what,
                        format!("expected finite zmin < zmax, found {z_min} and {z_max}"),
                    ));
                }
                check_phi_max(&what, *phi_max)?;
                check_finite("cylinder transform", &world_from_object.m.to_cols_array())?;
            }
        }
    }
    Ok(())
}

/// Check the arrays of a mesh with `per_face` vertices per face.
fn check_mesh(
    what: &str,
    per_face: usize,
    positions: &[Vec3],
    indices: &[u32],
    normals: Option<&[Vec3]>,
    uvs: Option<&[Vec2]>,
) -> Result<(), BuildError> {
    if !indices.len().is_multiple_of(per_face) {
        return Err(invalid(
            what,
            format!("{} indices is not a multiple of {per_face}", indices.len()),
        ));
    }
    if let Some(bad) = indices.iter().find(|&&k| k as usize >= positions.len()) {
        return Err(invalid(
            what,
            format!("vertex index {bad} out of range ({} vertices)", positions.len()),
        ));
    }
    check_finite(what, &positions.iter().flat_map(|p| p.to_array()).collect::<Vec<_>>())?;
    if let Some(n) = normals {
        if n.len() != positions.len() {
            return Err(invalid(
                what,
                format!("{} normals for {} vertices", n.len(), positions.len()),
            ));
        }
        check_finite(what, &n.iter().flat_map(|p| p.to_array()).collect::<Vec<_>>())?;
    }
    if let Some(uv) = uvs {
        if uv.len() != positions.len() {
            return Err(invalid(
                what,
                format!("{} uvs for {} vertices", uv.len(), positions.len()),
            ));
        }
    }
    Ok(())
}

/// Tangents, if any: one per vertex, finite.
fn check_tangents(what: &str, vertices: usize, tangents: Option<&[Vec4]>) -> Result<(), BuildError> {
    let Some(t) = tangents else {
        return Ok(());
    };
    if t.len() != vertices {
        return Err(invalid(what, format!("{} tangents for {vertices} vertices", t.len())));
    }
    check_finite(what, &t.iter().flat_map(|v| v.to_array()).collect::<Vec<_>>())?;
    Ok(())
}

/// Per-vertex shading normals made unit length (zero stays zero).
fn unit_normals(normals: Option<&[Vec3]>) -> Option<Vec<Vec3>> {
    normals.map(|n| n.iter().map(|v| v.normalize_or_zero()).collect())
}

/// The shapes a description stands for (one per triangle or patch of a mesh).
fn shape_geometry(s: &ShapeDesc) -> Vec<Shape> {
    match &s.geometry {
        GeometryDesc::TriangleMesh(m) => {
            let mesh = Arc::new(TriangleMesh {
                positions: m.positions.clone(),
                indices: m.indices.clone(),
                normals: unit_normals(m.normals.as_deref()),
                uvs: m.uvs.clone(),
                tangents: m.tangents.clone(),
                flip_normals: s.flip_normals,
            });
            (0..mesh.triangle_count() as u32)
                .map(|index| Shape::Triangle(Triangle::new(mesh.clone(), index)))
                .filter(|t| t.area() > 0.0)
                .collect()
        }
        GeometryDesc::BilinearMesh(m) => {
            let mesh = Arc::new(BilinearMesh {
                positions: m.positions.clone(),
                indices: m.indices.clone(),
                normals: unit_normals(m.normals.as_deref()),
                uvs: m.uvs.clone(),
                flip_normals: s.flip_normals,
            });
            (0..mesh.patch_count() as u32)
                .map(|index| Shape::Bilinear(BilinearPatch::new(mesh.clone(), index)))
                .filter(|p| p.area() > 0.0)
                .collect()
        }
        GeometryDesc::Sphere {
            radius,
            world_from_object,
            z_min,
            z_max,
            phi_max,
        } => {
            let clip = SphereClip {
                z_min: *z_min,
                z_max: *z_max,
                phi_max: phi_max.to_radians(),
            };
            vec![Shape::Sphere(Sphere::partial(
                *radius,
                clip,
                *world_from_object,
                s.flip_normals,
            ))]
        }
        GeometryDesc::Disk {
            height,
            radius,
            inner_radius,
            phi_max,
            world_from_object,
        } => vec![Shape::Disk(Disk::new(
            *height,
            *radius,
            *inner_radius,
            *phi_max,
            *world_from_object,
            s.flip_normals,
        ))],
        GeometryDesc::Cylinder {
            radius,
            z_min,
            z_max,
            phi_max,
            world_from_object,
        } => vec![Shape::Cylinder(Cylinder::new(
            *radius,
            *z_min,
            *z_max,
            *phi_max,
            *world_from_object,
            s.flip_normals,
        ))],
    }
}

fn validate_light(i: usize, l: &LightDesc) -> Result<(), BuildError> {
    match l {
        LightDesc::Point { position, intensity } => {
            check_finite(&format!("position of light {i}"), &position.to_array())?;
            check_non_negative(&format!("intensity of light {i}"), &intensity.to_array())?;
        }
        LightDesc::Spot(s) => {
            check_finite(
                &format!("transform of light {i}"),
                &s.world_from_light.m.to_cols_array(),
            )?;
            check_non_negative(&format!("intensity of light {i}"), &s.intensity.to_array())?;
            let (start, end) = (s.cos_falloff_start, s.cos_falloff_end);
            if !((-1.0..=1.0).contains(&start) && (-1.0..=1.0).contains(&end) && end <= start) {
                return Err(invalid(
                    format!("cone of light {i}"),
                    format!("expected -1 <= cos_falloff_end <= cos_falloff_start <= 1, found {end} and {start}"),
                ));
            }
            if s.projection.is_some() && end <= 0.0 {
                return Err(invalid(
                    format!("cone of light {i}"),
                    format!(
                        "a projected image needs a cone narrower than 90 degrees (cos_falloff_end > 0), found {end}"
                    ),
                ));
            }
        }
        LightDesc::Distant { direction, radiance } => {
            check_finite(&format!("direction of light {i}"), &direction.to_array())?;
            if (direction.length() - 1.0).abs() > 1e-3 {
                return Err(invalid(
                    format!("direction of light {i}"),
                    format!("expected a unit vector, found {direction}"),
                ));
            }
            check_non_negative(&format!("radiance of light {i}"), &radiance.to_array())?;
        }
        LightDesc::UniformInfinite { radiance } => {
            check_non_negative(&format!("radiance of light {i}"), &radiance.to_array())?;
        }
        LightDesc::ImageInfinite(e) => {
            let what = format!("environment image of light {i}");
            let (w, h) = (e.image.width, e.image.height);
            if w == 0 || h == 0 || u64::from(w) * u64::from(h) > MAX_PIXELS {
                return Err(invalid(what, format!("{w}x{h}; expected 1 to {MAX_PIXELS} pixels")));
            }
            if e.image.pixels.len() as u64 != u64::from(w) * u64::from(h) {
                return Err(invalid(
                    what,
                    format!("{} pixels do not make a {w}x{h} image", e.image.pixels.len()),
                ));
            }
            if e.mapping == EnvMapping::EqualArea && w != h {
                return Err(invalid(
                    what,
                    format!("{w}x{h} is not square, as the equal-area mapping needs"),
                ));
            }
            if let Some(p) = e
                .image
                .pixels
                .iter()
                .find(|p| !p.is_finite() || p.to_array().iter().any(|c| *c < 0.0))
            {
                return Err(invalid(
                    what,
                    format!("expected finite non-negative pixels, found {p:?}"),
                ));
            }
            check_non_negative(&format!("scale of light {i}"), &[e.scale])?;
            check_finite(
                &format!("transform of light {i}"),
                &e.world_from_light.m.to_cols_array(),
            )?;
        }
    }
    Ok(())
}

/// Error when a `Mix` material contains itself, directly or through other mixes (a
/// depth-first search over the mix graph).
fn check_mix_cycles(materials: &[MaterialDesc]) -> Result<(), BuildError> {
    // 0: not visited, 1: on the current path, 2: done.
    let mut state = vec![0u8; materials.len()];
    for root in 0..materials.len() {
        if state[root] != 0 {
            continue;
        }
        // Stack of (material, next child to visit).
        let mut stack = vec![(root, 0usize)];
        state[root] = 1;
        while let Some(&mut (m, ref mut next)) = stack.last_mut() {
            let children = materials[m].children();
            if let Some(&c) = children.get(*next) {
                *next += 1;
                let c = c as usize;
                match state[c] {
                    0 => {
                        state[c] = 1;
                        stack.push((c, 0));
                    }
                    1 => {
                        return Err(invalid(
                            format!("material {c}"),
                            "a mix or normal-map material contains itself (directly or through others)",
                        ))
                    }
                    _ => {}
                }
            } else {
                state[m] = 2;
                stack.pop();
            }
        }
    }
    Ok(())
}

/// The largest absolute coordinate of `b`.
fn farthest(b: &crate::math::Bounds3) -> f32 {
    b.min.abs().max(b.max.abs()).max_element()
}

/// Whether `b` lies within [`MAX_SCENE_COORDINATE`] of the origin on every axis.
fn within_scene_limit(b: &crate::math::Bounds3) -> bool {
    // Empty bounds (min above max) hold nothing and pass.
    b.min.cmpgt(b.max).any() || farthest(b) <= MAX_SCENE_COORDINATE
}

/// A partial quadric's sweep: `0 < phi_max <= 2 pi` (radians, with rounding slack).
fn check_phi_max(what: &str, phi_max: f32) -> Result<(), BuildError> {
    if phi_max > 0.0 && phi_max <= 2.0 * std::f32::consts::PI + 1e-6 {
        Ok(())
    } else {
        Err(invalid(what, format!("expected 0 < phi_max <= 2 pi, found {phi_max}")))
    }
}

fn check_positive_radius(r: [f32; 2]) -> Result<(), BuildError> {
    if r.iter().all(|v| *v > 0.0 && v.is_finite()) {
        Ok(())
    } else {
        Err(invalid("filter radius", format!("expected > 0, found {r:?}")))
    }
}

impl Scene {
    /// Validate the description and build the scene.
    pub fn build(desc: &SceneDescription) -> Result<Self, BuildError> {
        desc.validate()?;
        let materials: Vec<Material> = desc.materials.iter().map(Material::from_desc).collect();
        let has_interfaces = materials.iter().any(|m| matches!(m, Material::Interface));
        let has_normal_maps = materials.iter().any(|m| m.frame_inner().is_some());
        let mut primitives = Vec::new();
        let mut lights = Vec::new();
        // Which description shape each primitive comes from (for messages).
        let mut primitive_shape = Vec::new();
        for (shape_index, s) in desc.shapes.iter().enumerate() {
            let shapes = shape_geometry(s);
            primitive_shape.resize(primitive_shape.len() + shapes.len(), shape_index);
            let alpha = effective_alpha(s.alpha.as_ref());
            for shape in shapes {
                let light = s.area_light.filter(|a| !a.radiance.is_black()).map(|a| {
                    let sides = if a.two_sided { 2.0 } else { 1.0 };
                    // pbrt-v4's `power`: per primitive (one light per triangle), by its area.
                    let radiance = match a.power {
                        Some(p) => a.radiance * (p / (std::f32::consts::PI * sides * shape.area())),
                        None => a.radiance,
                    };
                    lights.push(Light::DiffuseArea(DiffuseAreaLight {
                        shape: shape.clone(),
                        radiance,
                        two_sided: a.two_sided,
                        alpha: alpha.clone(),
                    }));
                    (lights.len() - 1) as u32
                });
                primitives.push(Primitive {
                    shape,
                    material: s.material,
                    light,
                    alpha: alpha.clone(),
                });
            }
        }
        for l in &desc.lights {
            lights.push(match l {
                &LightDesc::Point { position, intensity } => Light::Point(PointLight { position, intensity }),
                LightDesc::Spot(s) => Light::Spot(SpotLight {
                    world_from_light: s.world_from_light,
                    intensity: s.intensity,
                    cos_falloff_start: s.cos_falloff_start,
                    cos_falloff_end: s.cos_falloff_end,
                    falloff: s.falloff,
                    projection: s.projection.clone(),
                }),
                &LightDesc::Distant { direction, radiance } => Light::Distant(DistantLight {
                    direction: direction.normalize(),
                    radiance,
                    scene_radius: 0.0,
                    scene_center: Vec3::ZERO,
                }),
                &LightDesc::UniformInfinite { radiance } => Light::UniformInfinite(UniformInfiniteLight {
                    radiance,
                    scene_radius: 0.0,
                    scene_center: Vec3::ZERO,
                }),
                LightDesc::ImageInfinite(e) => Light::ImageInfinite(ImageInfiniteLight::new(
                    e.image.width,
                    e.image.height,
                    &e.image.pixels,
                    e.scale,
                    e.mapping,
                    &e.world_from_light,
                )),
            });
        }
        let objects: Vec<Arc<ObjectGeometry>> = desc
            .objects
            .iter()
            .map(|o| {
                let primitives = o
                    .shapes
                    .iter()
                    .flat_map(|s| {
                        shape_geometry(s).into_iter().map(|shape| Primitive {
                            shape,
                            material: s.material,
                            light: None,
                            alpha: effective_alpha(s.alpha.as_ref()),
                        })
                    })
                    .collect();
                Arc::new(ObjectGeometry::new(primitives, &materials))
            })
            .collect();
        let instances: Vec<Instance> = desc
            .instances
            .iter()
            .map(|i| Instance::new(objects[i.object as usize].clone(), i.world_from_instance))
            .filter(|i| !i.object.primitives.is_empty())
            .collect();
        let bounds: Vec<_> = primitives
            .iter()
            .map(|p: &Primitive| p.shape.bounds())
            .chain(instances.iter().map(Instance::bounds))
            .collect();
        let first_instance = primitives.len();
        if let Some(i) = bounds.iter().position(|b| !within_scene_limit(b)) {
            let which = if i < first_instance {
                format!("shape {}", primitive_shape[i])
            } else {
                format!("object instance {}", i - first_instance)
            };
            return Err(invalid(
                "scene size",
                format!(
                    "{which} reaches {:e} in world space, past the limit of {MAX_SCENE_COORDINATE:e} (32-bit floats lose distances beyond it; scale the scene down)",
                    farthest(&bounds[i])
                ),
            ));
        }
        let filter = Filter::new(&desc.filter);
        let mut bvh = WideBvh::build(&bounds);
        let primitives = bvh.reorder_by_leaves(primitives);
        bvh.attach_triangles(|i| primitives.get(i as usize).and_then(|p| p.plain_triangle(&materials)));
        // Distant and infinite lights need the scene's size before their power is known.
        let scene_bounds = bounds.iter().fold(crate::math::Bounds3::EMPTY, |a, b| a.union(*b));
        lights.iter_mut().for_each(|l| l.preprocess(&scene_bounds));
        let infinite_lights = (0..lights.len() as u32)
            .filter(|&i| lights[i as usize].is_infinite())
            .collect();
        Ok(Self {
            primitives,
            materials,
            light_sampler: PowerLightSampler::with_selection(&lights, desc.integrator.light_selection),
            lights,
            infinite_lights,
            camera: Camera::new(&desc.camera, &desc.film, filter.radius()),
            filter,
            film: desc.film,
            reconstruction: desc.reconstruction,
            sampler: desc.sampler,
            integrator: desc.integrator,
            instances,
            has_interfaces,
            has_normal_maps,
            bvh,
        })
    }
}
