//! Whole scenes: the repository's Cornell box copy (`scenes/cornell-box`), and (when
//! `MCRENDER_SCENES` names the directory holding `cornell-box/`, `coffee/`, `veach-mis/`)
//! the shared test scenes.

#[path = "common/shared_scenes.rs"]
mod shared_scenes;

use mcrender_core::material::{CoatedDiffuseMaterial, ConductorMaterial, DiffuseMaterial};
use std::path::{Path, PathBuf};

use mcrender_core::color::Rgb;
use mcrender_core::math::Vec3;
use mcrender_core::scene::{FilterDesc, GeometryDesc, MaterialDesc, SamplerKind, SceneDescription};
use mcrender_formats::pbrt::{load_file, LoadedScene};
use mcrender_formats::SceneErrorKind;
use shared_scenes::shared_scenes_dir;

fn cornell_copy() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell-box/scene-v4.pbrt")
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() < 1e-5
}

fn check_cornell(loaded: &LoadedScene) {
    let d: &SceneDescription = &loaded.description;
    assert_eq!(d.shapes.len(), 8);
    assert!(d
        .shapes
        .iter()
        .all(|s| matches!(s.geometry, GeometryDesc::TriangleMesh(_))));
    assert!(d.shapes.iter().all(|s| !s.flip_normals));
    assert!(d.lights.is_empty());

    let lights: Vec<_> = d.shapes.iter().filter_map(|s| s.area_light.map(|l| (s, l))).collect();
    assert_eq!(lights.len(), 1);
    let (light_shape, light) = lights[0];
    assert_eq!(light.radiance, Rgb::new(17.0, 12.0, 4.0));
    assert!(!light.two_sided);
    assert_eq!(
        d.materials[light_shape.material as usize],
        MaterialDesc::Diffuse(DiffuseMaterial {
            reflectance: Rgb::BLACK.into()
        })
    );
    let GeometryDesc::TriangleMesh(mesh) = &light_shape.geometry else {
        unreachable!()
    };
    assert!(mesh.positions.iter().all(|p| (p.y - 1.98).abs() < 1e-6));
    assert!(mesh
        .normals
        .as_ref()
        .unwrap()
        .iter()
        .all(|n| close(*n, Vec3::new(0.0, -1.0, 0.0))));

    // Left wall, right wall, the shared grey, and the light's black.
    assert_eq!(d.materials.len(), 4);
    assert!(d.materials.contains(&MaterialDesc::Diffuse(DiffuseMaterial {
        reflectance: Rgb::new(0.63, 0.065, 0.05).into()
    })));
    let total_triangles: usize = d
        .shapes
        .iter()
        .map(|s| match &s.geometry {
            GeometryDesc::TriangleMesh(m) => m.indices.len() / 3,
            GeometryDesc::Sphere { .. }
            | GeometryDesc::Disk { .. }
            | GeometryDesc::Cylinder { .. }
            | GeometryDesc::BilinearMesh(_) => 0,
        })
        .sum();
    assert_eq!(total_triangles, 5 * 2 + 2 * 12 + 2);

    assert_eq!((d.film.width, d.film.height), (1024, 1024));
    assert_eq!(d.integrator.max_depth, 65);
    assert_eq!(
        d.filter,
        FilterDesc::Triangle {
            radius: mcrender_core::math::Vec2::ONE
        }
    );
    assert_eq!(d.sampler.samples_per_pixel, 64);
    assert_eq!(loaded.output_filename.as_deref(), Some("cornell-box.png"));

    // Camera at (0, 1, 6.8) looking down -z, camera +x = world +x: the red wall (x = -1) is
    // on the left of the image.
    let cam = &d.camera;
    assert_eq!(cam.fov_degrees, 19.5);
    assert!(close(cam.world_from_camera.point(Vec3::ZERO), Vec3::new(0.0, 1.0, 6.8)));
    assert!(close(cam.world_from_camera.vector(Vec3::Z), -Vec3::Z));
    assert!(close(cam.world_from_camera.vector(Vec3::X), Vec3::X));
    assert!(close(cam.world_from_camera.vector(Vec3::Y), Vec3::Y));

    // `Sampler "sobol"` maps to the Owen-scrambled Sobol' sampler, without a warning.
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    assert_eq!(d.sampler.kind, SamplerKind::OwenSobol);
}

#[test]
fn cornell_box_copy_loads_as_expected() {
    check_cornell(&load_file(&cornell_copy()).unwrap());
}

#[test]
fn shared_cornell_box_matches_the_copy() {
    let Some(dir) = shared_scenes_dir("shared_cornell_box_matches_the_copy") else {
        return;
    };
    let shared = load_file(&dir.join("cornell-box/scene-v4.pbrt")).unwrap();
    check_cornell(&shared);
    let copy = load_file(&cornell_copy()).unwrap();
    assert_eq!(shared.description.shapes, copy.description.shapes);
}

#[test]
fn coffee_loads_with_its_coated_plastics() {
    let Some(dir) = shared_scenes_dir("coffee_loads_with_its_coated_plastics") else {
        return;
    };
    let loaded = load_file(&dir.join("coffee/scene-v4.pbrt")).unwrap();
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let m = &loaded.description.materials;
    let orange = MaterialDesc::CoatedDiffuse(CoatedDiffuseMaterial {
        reflectance: Rgb::new(1.0, 0.378676, 0.013473).into(),
        u_roughness: 0.001.into(),
        v_roughness: 0.001.into(),
        remap_roughness: false,
        thickness: 0.01.into(),
        eta: 1.5,
        albedo: Rgb::BLACK.into(),
        g: 0.0.into(),
        max_depth: 10,
        n_samples: 1,
    });
    assert!(m.contains(&orange), "{m:?}");
    let coated = m.iter().filter(|d| matches!(d, MaterialDesc::CoatedDiffuse(_))).count();
    assert_eq!(coated, 3, "orange and black plastic, floor: {m:?}");
    assert!(m.iter().any(|d| matches!(d, MaterialDesc::Conductor(_))));
    assert!(m.iter().any(|d| matches!(d, MaterialDesc::Dielectric(_))));
}

#[test]
fn veach_mis_loads_with_its_conductor_plates() {
    let Some(dir) = shared_scenes_dir("veach_mis_loads_with_its_conductor_plates") else {
        return;
    };
    let scene = load_file(&dir.join("veach-mis/scene-v4.pbrt")).unwrap_or_else(|e| panic!("{e}"));
    let d = &scene.description;
    let plates: Vec<f32> = d
        .materials
        .iter()
        .filter_map(|m| match m.clone() {
            MaterialDesc::Conductor(ConductorMaterial {
                eta,
                k,
                reflectance: None,
                u_roughness,
                v_roughness,
                remap_roughness: false,
                ..
            }) => {
                assert_eq!(eta, Rgb::new(0.200438, 0.924033, 1.102212).into());
                assert_eq!(k, Rgb::new(3.912949, 2.452848, 2.142188).into());
                assert_eq!(u_roughness, v_roughness);
                u_roughness.constant()
            }
            _ => None,
        })
        .collect();
    assert_eq!(plates, [0.01, 0.05, 0.1, 0.25]);
    assert!(
        scene.warnings.iter().all(|w| !w.contains("conductor")),
        "{:?}",
        scene.warnings
    );
}

#[test]
fn missing_scene_file_is_an_io_error() {
    let err = load_file(Path::new("no/such/scene.pbrt")).unwrap_err();
    assert_eq!(err.kind, SceneErrorKind::Io);
    assert_eq!(
        err.to_string(),
        "no/such/scene.pbrt: cannot open scene file: No such file or directory"
    );
}

#[test]
fn coffee_geometry_loads_once_its_materials_are_diffuse() {
    // Exercises plymesh on real binary PLY files: swap the unsupported material types for
    // "diffuse" (their other parameters then only cause warnings).
    let Some(dir) = shared_scenes_dir("coffee_geometry_loads_once_its_materials_are_diffuse") else {
        return;
    };
    let coffee = dir.join("coffee");
    let mut src = std::fs::read_to_string(coffee.join("scene-v4.pbrt")).unwrap();
    for kind in ["coateddiffuse", "dielectric", "conductor"] {
        src = src.replace(
            &format!("\"string type\" [ \"{kind}\" ]"),
            "\"string type\" [ \"diffuse\" ]",
        );
    }
    let scene =
        mcrender_formats::pbrt::load_str(&src, "coffee-diffuse.pbrt", &coffee).unwrap_or_else(|e| panic!("{e}"));
    let d = &scene.description;
    let plymeshes = src.matches("Shape \"plymesh\"").count();
    let trianglemeshes = src.matches("Shape \"trianglemesh\"").count();
    assert_eq!(d.shapes.len(), plymeshes + trianglemeshes);
    assert_eq!(d.shapes.iter().filter(|s| s.area_light.is_some()).count(), 3);
    assert_eq!((d.film.width, d.film.height), (800, 1000));
    for shape in &d.shapes {
        let GeometryDesc::TriangleMesh(m) = &shape.geometry else {
            panic!("coffee has only meshes")
        };
        assert!(!m.indices.is_empty());
        assert!(m.indices.iter().all(|&i| (i as usize) < m.positions.len()));
        if let Some(n) = &m.normals {
            assert_eq!(n.len(), m.positions.len());
        }
        if let Some(uv) = &m.uvs {
            assert_eq!(uv.len(), m.positions.len());
        }
    }
    // The Metal material's spectral eta and k are reported as ignored.
    assert!(scene
        .warnings
        .iter()
        .any(|w| w.contains("parameter \"spectrum eta\" of MakeNamedMaterial \"Metal\"")));
}

#[test]
fn veach_mis_geometry_loads_once_its_materials_are_diffuse() {
    let Some(dir) = shared_scenes_dir("veach_mis_geometry_loads_once_its_materials_are_diffuse") else {
        return;
    };
    let veach = dir.join("veach-mis");
    let src = std::fs::read_to_string(veach.join("scene-v4.pbrt"))
        .unwrap()
        .replace("\"string type\" [ \"conductor\" ]", "\"string type\" [ \"diffuse\" ]");
    let scene = mcrender_formats::pbrt::load_str(&src, "veach.pbrt", &veach).unwrap_or_else(|e| panic!("{e}"));
    let d = &scene.description;
    assert_eq!(d.shapes.len(), 9);
    let spheres: Vec<_> = d
        .shapes
        .iter()
        .filter_map(|s| match s.geometry {
            GeometryDesc::Sphere {
                radius,
                world_from_object,
                ..
            } => Some((radius, world_from_object, s.area_light)),
            _ => None,
        })
        .collect();
    assert_eq!(spheres.len(), 3);
    let (radius, world_from_object, light) = spheres[2];
    assert_eq!(radius, 0.05);
    assert!(close(world_from_object.point(Vec3::ZERO), Vec3::new(0.0, 6.5, 2.7)));
    assert_eq!(light.unwrap().radiance, Rgb::splat(3039.6353));
    assert_eq!((d.film.width, d.film.height, d.integrator.max_depth), (1280, 720, 3));
}
