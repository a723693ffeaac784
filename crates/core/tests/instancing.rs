//! Object instancing: a two-level BVH must render exactly what the flattened copies render,
//! and share one bottom-level BVH between all instances of an object.

mod common;

use mcrender_core::material::DiffuseMaterial;
use std::sync::Arc;

use common::*;
use mcrender_core::color::Rgb;
use mcrender_core::math::{Mat4, Transform, Vec3};
use mcrender_core::scene::*;

/// A unit box (12 triangles) plus a sphere, in object space; shapes must not emit.
fn object_shapes() -> Vec<ShapeDesc> {
    let p = (0..8)
        .map(|i| Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32) - 0.5)
        .collect::<Vec<_>>();
    #[rustfmt::skip]
    let indices = vec![
        0, 2, 1, 1, 2, 3,  4, 5, 6, 5, 7, 6,  0, 1, 4, 1, 5, 4,
        2, 6, 3, 3, 6, 7,  0, 4, 2, 2, 4, 6,  1, 3, 5, 3, 7, 5,
    ];
    vec![
        ShapeDesc {
            geometry: GeometryDesc::TriangleMesh(TriangleMeshDesc {
                positions: p,
                indices,
                normals: None,
                uvs: None,
                tangents: None,
            }),
            material: 1,
            area_light: None,
            flip_normals: false,
            alpha: None,
        },
        ShapeDesc {
            geometry: GeometryDesc::full_sphere(
                0.3,
                Transform::new(Mat4::from_translation(Vec3::new(0.0, 0.8, 0.0))).unwrap(),
            ),
            material: 2,
            area_light: None,
            flip_normals: false,
            alpha: None,
        },
    ]
}

fn placements() -> Vec<Transform> {
    (0..6)
        .map(|i| {
            let f = i as f32;
            let m = Mat4::from_translation(Vec3::new(-2.5 + f, -0.5 + 0.2 * f, 4.0 + 0.3 * f))
                * Mat4::from_rotation_y(0.5 * f)
                * Mat4::from_rotation_x(0.2 * f)
                * Mat4::from_scale(Vec3::new(0.6 + 0.1 * f, 0.5 + 0.05 * f, 0.7));
            Transform::new(m).unwrap()
        })
        .collect()
}

/// A lit room seen by a perspective camera, without the instanced geometry.
fn base_scene() -> SceneDescription {
    let mut d = empty_scene();
    d.film = FilmDesc { width: 48, height: 32 };
    d.camera.fov_degrees = 60.0;
    d.sampler.samples_per_pixel = 8;
    d.integrator.max_depth = 3;
    d.materials.push(MaterialDesc::Diffuse(DiffuseMaterial {
        reflectance: Rgb::new(0.7, 0.5, 0.3).into(),
    }));
    d.materials.push(MaterialDesc::Diffuse(DiffuseMaterial {
        reflectance: Rgb::new(0.2, 0.6, 0.8).into(),
    }));
    // Floor, and a light above.
    let quad = |y: f32, s: f32, flip: bool| {
        GeometryDesc::TriangleMesh(TriangleMeshDesc {
            positions: vec![
                Vec3::new(-s, y, 0.0),
                Vec3::new(s, y, 0.0),
                Vec3::new(s, y, 10.0),
                Vec3::new(-s, y, 10.0),
            ],
            indices: if flip {
                vec![0, 1, 2, 0, 2, 3]
            } else {
                vec![0, 2, 1, 0, 3, 2]
            },
            normals: None,
            uvs: None,
            tangents: None,
        })
    };
    d.shapes.push(ShapeDesc {
        geometry: quad(-1.0, 6.0, false),
        material: 1,
        area_light: None,
        flip_normals: false,
        alpha: None,
    });
    d.shapes.push(ShapeDesc {
        geometry: quad(3.0, 2.0, true),
        material: 0,
        area_light: Some(AreaLightDesc {
            radiance: Rgb::splat(4.0),
            two_sided: true,
            power: None,
        }),
        flip_normals: false,
        alpha: None,
    });
    d
}

fn instanced() -> SceneDescription {
    let mut d = base_scene();
    d.objects.push(ObjectDesc {
        shapes: object_shapes(),
    });
    d.instances = placements()
        .into_iter()
        .map(|world_from_instance| InstanceDesc {
            object: 0,
            world_from_instance,
        })
        .collect();
    d
}

/// The same geometry copied into world space.
fn flattened() -> SceneDescription {
    let mut d = base_scene();
    for t in placements() {
        for mut s in object_shapes() {
            s.geometry = match s.geometry {
                GeometryDesc::TriangleMesh(mut m) => {
                    m.positions.iter_mut().for_each(|p| *p = t.point(*p));
                    GeometryDesc::TriangleMesh(m)
                }
                GeometryDesc::Sphere {
                    radius,
                    world_from_object,
                    z_min,
                    z_max,
                    phi_max,
                } => GeometryDesc::Sphere {
                    radius,
                    world_from_object: Transform::new(t.m * world_from_object.m).unwrap(),
                    z_min,
                    z_max,
                    phi_max,
                },
                other => other,
            };
            d.shapes.push(s);
        }
    }
    d
}

#[test]
fn instances_render_like_flattened_copies() {
    let a = render_desc(&instanced());
    let b = render_desc(&flattened());
    let (pa, pb) = (a.film.pixels(), b.film.pixels());
    assert_eq!(pa.len(), pb.len());
    let mut differing = 0;
    let (mut sum_a, mut sum_b) = (0.0f64, 0.0f64);
    for (x, y) in pa.iter().zip(pb) {
        let (x, y) = (x.mean(), y.mean());
        sum_a += f64::from(x.to_array().iter().sum::<f32>());
        sum_b += f64::from(y.to_array().iter().sum::<f32>());
        let diff = (0..3).map(|c| (x[c] - y[c]).abs()).fold(0.0f32, f32::max);
        if diff > 1e-3 * (1.0 + x.to_array().iter().fold(0.0f32, |m, v| m.max(*v))) {
            differing += 1;
        }
    }
    // Hit points differ in the last bits (transformed hits vs transformed vertices), which
    // can flip a rare edge or random decision; nearly every pixel must agree exactly.
    assert!(differing * 100 <= pa.len(), "{differing} of {} pixels differ", pa.len());
    assert!((sum_a - sum_b).abs() <= 1e-3 * sum_b, "{sum_a} vs {sum_b}");
    assert!(sum_b > 0.0);
    // The instances are in view: without them many pixels change.
    let c = render_desc(&base_scene());
    let changed = c
        .film
        .pixels()
        .iter()
        .zip(pb)
        .filter(|(x, y)| {
            (x.mean().to_array().iter().sum::<f32>() - y.mean().to_array().iter().sum::<f32>()).abs() > 1e-2
        })
        .count();
    assert!(changed * 10 > pb.len(), "only {changed} pixels show the instances");
}

#[test]
fn instances_share_one_bottom_level_bvh() {
    let scene = Scene::build(&instanced()).unwrap();
    assert_eq!(scene.instances.len(), 6);
    // The scene's own primitives: the floor and light quads only.
    assert_eq!(scene.primitives.len(), 4);
    for i in &scene.instances {
        assert!(Arc::ptr_eq(&i.object, &scene.instances[0].object));
    }
    // One owner per instance: the geometry exists once.
    assert_eq!(Arc::strong_count(&scene.instances[0].object), 6);
    assert_eq!(scene.instances[0].object.primitives.len(), 13);
}

#[test]
fn area_lights_in_objects_are_rejected() {
    let mut d = instanced();
    d.objects[0].shapes[0].area_light = Some(AreaLightDesc {
        radiance: Rgb::WHITE,
        two_sided: false,
        power: None,
    });
    let err = Scene::build(&d).unwrap_err().to_string();
    assert!(
        err.contains("Area lights not supported with object instancing"),
        "{err}"
    );
    let mut d = instanced();
    d.instances[0].object = 1;
    assert!(Scene::build(&d).is_err());
}
