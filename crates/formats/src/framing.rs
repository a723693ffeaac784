//! Defaults for formats that describe models rather than whole scenes (OBJ, glTF without
//! a camera or lights): a camera that frames the bounding box, a uniform environment light,
//! and the film, sampler and integrator settings such a scene renders with.

use mcrender_core::color::Rgb;
use mcrender_core::math::{Transform, Vec3};
use mcrender_core::scene::{
    CameraDesc, FilmDesc, FilterDesc, GeometryDesc, IntegratorDesc, LightDesc, Reconstruction, SamplerDesc,
    SceneDescription,
};

/// Field of view of the default camera (degrees, along the shorter image axis).
pub const DEFAULT_FOV_DEGREES: f32 = 40.0;

/// Direction from the bounding box's centre towards the default camera (y is up, as in
/// OBJ and glTF): in front, a little to the right and above.
const VIEW_DIRECTION: Vec3 = Vec3::new(0.35, 0.45, 1.0);

/// An empty scene with the settings of model formats: 640x480, 64 spp, path tracing to depth 8.
#[must_use]
pub fn model_scene() -> SceneDescription {
    SceneDescription {
        camera: CameraDesc::default(),
        film: FilmDesc {
            width: 640,
            height: 480,
        },
        filter: FilterDesc::default(),
        reconstruction: Reconstruction::default(),
        sampler: SamplerDesc {
            samples_per_pixel: 64,
            ..SamplerDesc::default()
        },
        integrator: IntegratorDesc {
            max_depth: 8,
            ..IntegratorDesc::default()
        },
        materials: Vec::new(),
        shapes: Vec::new(),
        lights: Vec::new(),
        objects: Vec::new(),
        instances: Vec::new(),
    }
}

/// The world-space bounding box `(min, max)` of the scene's triangle meshes, `None` when
/// it has none.
#[must_use]
pub fn mesh_bounds(desc: &SceneDescription) -> Option<(Vec3, Vec3)> {
    let mut points = desc.shapes.iter().filter_map(|s| match &s.geometry {
        GeometryDesc::TriangleMesh(m) => Some(m.positions.iter()),
        _ => None,
    });
    let first = points.next()?;
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for p in first.chain(points.flatten()) {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    (lo.cmple(hi).all()).then_some((lo, hi))
}

/// A pinhole camera that sees the whole bounding sphere of `(lo, hi)` from
/// [`VIEW_DIRECTION`], with the eye point it sits at.
#[must_use]
pub fn framing_camera(lo: Vec3, hi: Vec3) -> (CameraDesc, Vec3) {
    let (eye, camera_from_world) = framing_view(lo, hi)
        // Bounds too large for f32 arithmetic (the core refuses such scenes when it
        // validates them, naming the coordinate): frame the unit box instead.
        .or_else(|| framing_view(Vec3::splat(-1.0), Vec3::splat(1.0)))
        .expect("the unit box can be framed");
    let world_from_camera = Transform::new(camera_from_world.inverse()).expect("a look-at matrix is invertible");
    (
        CameraDesc {
            world_from_camera,
            fov_degrees: DEFAULT_FOV_DEGREES,
            ..CameraDesc::default()
        },
        eye,
    )
}

/// The eye point and camera-from-world matrix looking at the bounding sphere of `(lo,
/// hi)`; `None` when that sphere is too large for the arithmetic to stay finite.
fn framing_view(lo: Vec3, hi: Vec3) -> Option<(Vec3, glam::Mat4)> {
    let centre = 0.5 * (lo + hi);
    let radius = (0.5 * (hi - lo)).length().max(1e-3);
    // The bounding sphere fits inside the cone of half-angle fov/2 at this distance.
    let distance = 1.05 * radius / (0.5 * DEFAULT_FOV_DEGREES).to_radians().sin();
    let eye = centre + distance * VIEW_DIRECTION.normalize();
    if !(eye.is_finite() && centre.is_finite()) {
        return None;
    }
    crate::transform::look_at(eye, centre, Vec3::Y).ok().map(|m| (eye, m))
}

/// Give `desc` a framing camera when `has_camera` is false and a uniform white environment
/// light when it has no emitter, saying so in `warnings` as `file: no camera; ...`.
pub fn add_defaults(desc: &mut SceneDescription, file: &str, has_camera: bool, warnings: &mut Vec<String>) {
    if !has_camera {
        let (lo, hi) = mesh_bounds(desc).unwrap_or((Vec3::splat(-1.0), Vec3::splat(1.0)));
        let (camera, eye) = framing_camera(lo, hi);
        desc.camera = camera;
        warnings.push(format!(
            "{file}: no camera; looking at the bounding box from ({:.3}, {:.3}, {:.3}) with a {DEFAULT_FOV_DEGREES} degree field of view",
            eye.x, eye.y, eye.z
        ));
    }
    let emits = !desc.lights.is_empty() || desc.shapes.iter().any(|s| s.area_light.is_some());
    if !emits {
        desc.lights.push(LightDesc::UniformInfinite { radiance: Rgb::WHITE });
        warnings.push(format!(
            "{file}: no light; adding a uniform white environment light (radiance 1)"
        ));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_framing_camera_sees_every_corner_of_the_box() {
        let (lo, hi) = (Vec3::new(-1.0, 0.0, -2.0), Vec3::new(3.0, 1.0, 0.5));
        let (camera, eye) = framing_camera(lo, hi);
        let camera_from_world = camera.world_from_camera.inverse();
        let half = (0.5 * camera.fov_degrees).to_radians().tan();
        for i in 0..8 {
            let corner = Vec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            );
            let c = camera_from_world.point(corner);
            assert!(c.z > 0.0, "corner {corner} behind the camera at {eye}");
            assert!(
                c.x.abs() / c.z <= half && c.y.abs() / c.z <= half,
                "corner {corner} at {c}"
            );
        }
    }

    /// Found by the `obj` fuzz target (session 6): a vertex at 6.7e23 made the bounding
    /// sphere's radius infinite, and the look-at `expect` panicked.
    #[test]
    fn regression_huge_bounds_frame_the_unit_box_instead_of_panicking() {
        for hi in [Vec3::new(6.7e23, 1.0, 0.0), Vec3::splat(f32::MAX)] {
            let (camera, eye) = framing_camera(Vec3::splat(-1.0), hi);
            assert!(eye.is_finite(), "{eye}");
            assert_eq!(camera, framing_camera(Vec3::splat(-1.0), Vec3::splat(1.0)).0);
        }
    }
}
