//! Bilinear meshes through the scene: validation of the description, and a planar patch
//! traced through the BVH (also inside an instance) where its triangle pair is.

mod common;

use common::empty_scene;
use mcrender_core::math::{Mat4, Ray, Transform, Vec3};
use mcrender_core::sampling::Pcg32;
use mcrender_core::scene::*;

fn patch_shape(m: BilinearMeshDesc) -> ShapeDesc {
    ShapeDesc {
        geometry: GeometryDesc::BilinearMesh(m),
        material: 0,
        area_light: None,
        flip_normals: false,
        alpha: None,
    }
}

fn quad() -> Vec<Vec3> {
    vec![
        Vec3::new(-1.0, -1.0, 2.0),
        Vec3::new(1.5, -1.0, 2.0),
        Vec3::new(-1.0, 1.0, 2.0),
        Vec3::new(0.8, 1.2, 2.0),
    ]
}

#[test]
fn malformed_bilinear_meshes_are_rejected() {
    let cases = [
        (
            BilinearMeshDesc {
                positions: quad(),
                indices: vec![0, 1, 2],
                ..Default::default()
            },
            "3 indices is not a multiple of 4",
        ),
        (
            BilinearMeshDesc {
                positions: quad(),
                indices: vec![0, 1, 2, 4],
                ..Default::default()
            },
            "vertex index 4 out of range (4 vertices)",
        ),
        (
            BilinearMeshDesc {
                positions: quad(),
                indices: vec![0, 1, 2, 3],
                normals: Some(vec![Vec3::Z; 3]),
                ..Default::default()
            },
            "3 normals for 4 vertices",
        ),
        (
            BilinearMeshDesc {
                positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::splat(f32::NAN)],
                indices: vec![0, 1, 2, 3],
                ..Default::default()
            },
            "bilinear mesh (shape 0)",
        ),
    ];
    for (mesh, expected) in cases {
        let mut d = empty_scene();
        d.shapes.push(patch_shape(mesh));
        let err = Scene::build(&d).expect_err("must be rejected").to_string();
        assert!(err.contains(expected), "{err:?} lacks {expected:?}");
    }
}

/// Camera-like rays hit a planar patch in the scene (and in two instances of it) exactly
/// where they hit the patch's triangle pair.
#[test]
fn planar_patch_in_the_scene_matches_triangles() {
    let mesh = BilinearMeshDesc {
        positions: quad(),
        indices: vec![0, 1, 2, 3],
        ..Default::default()
    };
    let tris = TriangleMeshDesc {
        positions: quad(),
        indices: vec![0, 1, 3, 0, 3, 2],
        ..Default::default()
    };
    let mut a = empty_scene();
    a.shapes.push(patch_shape(mesh.clone()));
    let mut b = empty_scene();
    b.shapes.push(ShapeDesc {
        geometry: GeometryDesc::TriangleMesh(tris),
        ..patch_shape(mesh.clone())
    });
    // Instances: the same patch as an object placed twice.
    let mut c = empty_scene();
    c.objects.push(ObjectDesc {
        shapes: vec![patch_shape(mesh)],
    });
    for x in [0.0, 10.0] {
        c.instances.push(InstanceDesc {
            object: 0,
            world_from_instance: Transform::new(Mat4::from_translation(Vec3::new(x, 0.0, 0.0))).unwrap(),
        });
    }
    let [a, b, c] = [a, b, c].map(|d| Scene::build(&d).unwrap());
    let mut rng = Pcg32::new(3, 1);
    let mut hits = 0;
    for _ in 0..5000 {
        let d = Vec3::new(2.0 * rng.next_f32() - 1.0, 2.0 * rng.next_f32() - 1.0, 1.0);
        let ray = Ray::new(Vec3::ZERO, d.normalize());
        let (ha, hb, hc) = (a.intersect(&ray), b.intersect(&ray), c.intersect(&ray));
        assert_eq!(ha.is_some(), hb.is_some(), "{ray:?}");
        assert_eq!(ha.is_some(), hc.is_some(), "{ray:?}");
        if let (Some(ha), Some(hb), Some(hc)) = (ha, hb, hc) {
            assert!((ha.si.t - hb.si.t).abs() < 1e-5 && (ha.si.t - hc.si.t).abs() < 1e-5);
            assert!((ha.si.n() - hb.si.n()).length() < 1e-5, "{} {}", ha.si.n(), hb.si.n());
            hits += 1;
        }
    }
    assert!(hits > 1000, "{hits}");
}
