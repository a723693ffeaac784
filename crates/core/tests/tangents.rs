//! Mesh tangents (glTF's `TANGENT`) through the scene: validated with the mesh, and a
//! normal map on a mesh with them reads its green channel along `w (n x t)`.

mod common;

use common::empty_scene;
use mcrender_core::color::Rgb;
use mcrender_core::material::{MapStyle, NormalMapMaterial};
use mcrender_core::math::{Ray, Vec2, Vec3, Vec4};
use mcrender_core::scene::*;

/// A unit square at z = 0 facing +z with normals and uvs, tangents `t` at every vertex,
/// shaded by material `material`.
fn square(t: Option<Vec<Vec4>>, material: u32) -> ShapeDesc {
    ShapeDesc {
        geometry: GeometryDesc::TriangleMesh(TriangleMeshDesc {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
            indices: vec![0, 1, 2, 0, 2, 3],
            normals: Some(vec![Vec3::Z; 4]),
            uvs: Some(vec![Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y]),
            tangents: t,
        }),
        material,
        area_light: None,
        flip_normals: false,
        alpha: None,
    }
}

#[test]
fn tangent_counts_and_values_are_checked() {
    for (t, expected) in [
        (vec![Vec4::X; 3], "3 tangents for 4 vertices"),
        (vec![Vec4::splat(f32::NAN); 4], "triangle mesh (shape 0)"),
    ] {
        let mut d = empty_scene();
        d.shapes.push(square(Some(t), 0));
        let err = Scene::build(&d).expect_err("must be rejected").to_string();
        assert!(err.contains(expected), "{err:?} lacks {expected:?}");
    }
}

#[test]
fn a_normal_map_tilts_along_the_mesh_tangent_frame() {
    // The map tilts 45 degrees towards +green (the bitangent).
    let c = 0.5 + 0.5 * std::f32::consts::FRAC_1_SQRT_2;
    let h = std::f32::consts::FRAC_1_SQRT_2;
    let shading_normal = |t: Option<Vec<Vec4>>| {
        let mut d = empty_scene();
        d.materials.push(MaterialDesc::NormalMap(NormalMapMaterial {
            material: 0,
            normal_map: Rgb::new(0.5, c, c).into(),
            style: MapStyle::Pbrt,
        }));
        d.shapes.push(square(t, 1));
        let scene = Scene::build(&d).unwrap();
        let ray = Ray::new(Vec3::new(0.3, 0.6, 1.0), -Vec3::Z);
        scene.intersect(&ray).expect("the ray hits the square").si
    };
    // Without tangents: tangent dp/du = +x, bitangent n x t = +y.
    let si = shading_normal(None);
    assert!((si.ns - Vec3::new(0.0, h, h)).length() < 1e-5, "{}", si.ns);
    // Tangent +y: bitangent n x t = -x, or +x when w = -1.
    for (w, x) in [(1.0, -h), (-1.0, h)] {
        let si = shading_normal(Some(vec![Vec4::new(0.0, 1.0, 0.0, w); 4]));
        assert!((si.ns - Vec3::new(x, 0.0, h)).length() < 1e-5, "w = {w}: {}", si.ns);
        assert!(si.dpdu.dot(Vec3::Y) > 0.99, "w = {w}: {}", si.dpdu);
    }
}
