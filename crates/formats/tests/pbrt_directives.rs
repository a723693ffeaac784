//! One test per directive family: transforms, attribute scopes, orientation, materials,
//! lights, options and `Include`, each against hand-computed values.

use mcrender_core::material::DiffuseMaterial;
use std::path::Path;

use mcrender_core::color::Rgb;
use mcrender_core::math::{Mat4, Vec2, Vec3};
use mcrender_core::scene::{
    AreaLightDesc, FilterDesc, GeometryDesc, LightDesc, MaterialDesc, SamplerKind, ShapeDesc, TriangleMeshDesc,
};
use mcrender_formats::pbrt::{load_str, LoadedScene};

fn load(src: &str) -> LoadedScene {
    match load_str(src, "scene.pbrt", Path::new("")) {
        Ok(s) => s,
        Err(e) => panic!("{e}"),
    }
}

/// The error message of a scene that must fail to load.
fn load_err(src: &str) -> String {
    match load_str(src, "scene.pbrt", Path::new("")) {
        Ok(_) => panic!("loaded: {src}"),
        Err(e) => e.to_string(),
    }
}

/// The world-from-object matrix of the only (or first) sphere.
fn sphere_matrix(s: &LoadedScene, i: usize) -> Mat4 {
    match &s.description.shapes[i].geometry {
        GeometryDesc::Sphere { world_from_object, .. } => world_from_object.m,
        other => panic!("not a sphere: {other:?}"),
    }
}

fn mesh(s: &ShapeDesc) -> &TriangleMeshDesc {
    match &s.geometry {
        GeometryDesc::TriangleMesh(m) => m,
        other => panic!("not a mesh: {other:?}"),
    }
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() < 1e-5
}

const TRIANGLE: &str = "Shape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0]";

#[test]
fn translate_scale_rotate_compose_in_order() {
    let s = load("WorldBegin\nTranslate 1 2 3\nShape \"sphere\"\nScale 2 3 4\nShape \"sphere\"\nRotate 90 0 0 1\nShape \"sphere\"");
    assert_eq!(sphere_matrix(&s, 0), Mat4::from_translation(Vec3::new(1.0, 2.0, 3.0)));
    // CTM = T * S: scale first, then translate.
    let ts = sphere_matrix(&s, 1);
    assert_eq!(ts.transform_point3(Vec3::ONE), Vec3::new(3.0, 5.0, 7.0));
    // CTM = T * S * R: (1, 0, 0) -> R -> (0, 1, 0) -> S -> (0, 3, 0) -> T -> (1, 5, 3).
    let tsr = sphere_matrix(&s, 2);
    assert!(close(tsr.transform_point3(Vec3::X), Vec3::new(1.0, 5.0, 3.0)));
}

#[test]
fn transform_replaces_and_concat_transform_multiplies() {
    // The 16 numbers are the matrix's columns (pbrt transposes its row-major reading).
    let s = load(
        "WorldBegin\nTranslate 5 5 5\nTransform [1 0 0 0  0 1 0 0  0 0 1 0  1 2 3 1]\nShape \"sphere\"\n\
         ConcatTransform [2 0 0 0  0 2 0 0  0 0 2 0  0 0 0 1]\nShape \"sphere\"\nIdentity\nShape \"sphere\"",
    );
    assert_eq!(sphere_matrix(&s, 0), Mat4::from_translation(Vec3::new(1.0, 2.0, 3.0)));
    assert_eq!(sphere_matrix(&s, 1).transform_point3(Vec3::X), Vec3::new(3.0, 2.0, 3.0));
    assert_eq!(sphere_matrix(&s, 2), Mat4::IDENTITY);
}

#[test]
fn disk_parameters_and_defaults() {
    let s = load(
        "WorldBegin\nTranslate 0 0 1\nShape \"disk\"\nShape \"disk\" \"float height\" 2 \"float radius\" 3 \
         \"float innerradius\" 1 \"float phimax\" 90",
    );
    let disk = |i: usize| match &s.description.shapes[i].geometry {
        GeometryDesc::Disk {
            height,
            radius,
            inner_radius,
            phi_max,
            world_from_object,
        } => (*height, *radius, *inner_radius, *phi_max, world_from_object.m),
        other => panic!("not a disk: {other:?}"),
    };
    let translate = Mat4::from_translation(Vec3::Z);
    assert_eq!(disk(0), (0.0, 1.0, 0.0, std::f32::consts::TAU, translate));
    assert_eq!(disk(1), (2.0, 3.0, 1.0, std::f32::consts::FRAC_PI_2, translate));
    assert!(!s.description.shapes[0].flip_normals);
}

#[test]
fn cylinder_parameters_and_defaults() {
    let s = load(
        "WorldBegin\nTranslate 0 0 1\nShape \"cylinder\"\nReverseOrientation\nShape \"cylinder\" \"float radius\" 2 \
         \"float zmin\" 3 \"float zmax\" 0.5 \"float phimax\" 400\nScale 1 1 -1\nShape \"cylinder\" \"float phimax\" 90",
    );
    let cylinder = |i: usize| match &s.description.shapes[i].geometry {
        GeometryDesc::Cylinder {
            radius,
            z_min,
            z_max,
            phi_max,
            world_from_object,
        } => (*radius, *z_min, *z_max, *phi_max, world_from_object.m),
        other => panic!("not a cylinder: {other:?}"),
    };
    let translate = Mat4::from_translation(Vec3::Z);
    assert_eq!(cylinder(0), (1.0, -1.0, 1.0, std::f32::consts::TAU, translate));
    // zmin > zmax is reordered, phimax clamped to 360, as pbrt-v4 does.
    assert_eq!(cylinder(1), (2.0, 0.5, 3.0, std::f32::consts::TAU, translate));
    assert_eq!(cylinder(2).3, std::f32::consts::FRAC_PI_2);
    // ReverseOrientation flips; a mirroring transform flips back (pbrt-v4's rule).
    let flips: Vec<bool> = s.description.shapes.iter().map(|s| s.flip_normals).collect();
    assert_eq!(flips, [false, true, false]);
}

/// A planar patch becomes two triangles over its four corners, facing pbrt-v4's
/// `dpdu x dpdv`, with the patch's (u, v) at the corners when no `uv` is given.
#[test]
fn sphere_cuts_are_read_and_clamped_as_pbrt_does() {
    let s = load(
        "WorldBegin\nShape \"sphere\" \"float radius\" 2 \"float zmin\" 1.5 \"float zmax\" -5 \"float phimax\" 400",
    );
    let GeometryDesc::Sphere {
        radius,
        z_min,
        z_max,
        phi_max,
        ..
    } = s.description.shapes[0].geometry
    else {
        panic!()
    };
    assert_eq!((radius, z_min, z_max, phi_max), (2.0, -2.0, 1.5, 360.0));
    assert!(s.warnings.iter().all(|w| !w.contains("zmin")), "{:?}", s.warnings);
    assert_eq!(
        load_err("WorldBegin\nShape \"sphere\" \"float zmin\" 0.5 \"float zmax\" 0.5"),
        "scene.pbrt:2:16: sphere cut zmin 0.5, zmax 0.5, phimax 360 leaves nothing of a sphere of radius 1"
    );
}

#[test]
fn planar_bilinear_patches_split_into_triangles() {
    let s = load(
        "WorldBegin\nTranslate 0 0 2\nShape \"bilinearmesh\" \"point3 P\" [0 0 0  2 0 0  0 1 0  2 1 0  4 0 0  4 1 0] \
         \"integer indices\" [0 1 2 3  1 4 3 5]",
    );
    let m = mesh(&s.description.shapes[0]);
    assert_eq!(m.indices.len(), 12);
    assert_eq!(
        m.positions.len(),
        8,
        "each patch gets its own corners for its default uvs"
    );
    let uvs = m.uvs.as_ref().unwrap();
    for t in m.indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|j| m.positions[t[j] as usize]);
        let n = (b - a).cross(c - a);
        assert!(n.z > 0.0 && n.x == 0.0 && n.y == 0.0, "triangle normal {n}");
        for &i in t {
            assert_eq!(m.positions[i as usize].z, 2.0);
        }
    }
    // (u, v) at a vertex: x along the patch's u edge, y along v.
    for (i, p) in m.positions.iter().enumerate().take(4) {
        assert!(close(uvs[i].extend(0.0), Vec3::new(p.x / 2.0, p.y, 0.0)));
    }
    // With uvs given, vertices stay shared.
    let s = load(
        "WorldBegin\nShape \"bilinearmesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0  1 1 0] \
         \"point2 uv\" [0 0 1 0 0 1 1 1]",
    );
    let m = mesh(&s.description.shapes[0]);
    assert_eq!((m.positions.len(), m.indices.clone()), (4, vec![0, 1, 3, 0, 3, 2]));
}

/// A mesh with a curved patch stays a bilinear mesh, moved to world space (normals by the
/// inverse transpose, negated by `ReverseOrientation`), with its uvs.
#[test]
fn curved_bilinear_patches_load_as_patches() {
    let s = load(
        "WorldBegin\nTranslate 0 0 2\nReverseOrientation\nAreaLightSource \"diffuse\" \"rgb L\" [1 2 3]\n\
         Shape \"bilinearmesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0  1 1 1  2 0 0  2 1 0] \
         \"integer indices\" [0 1 2 3  1 4 3 5] \"normal N\" [0 0 1  0 0 1  0 0 1  0 0 1  0 0 2  0 0 1] \
         \"point2 uv\" [0 0  1 0  0 1  1 1  2 0  2 1]",
    );
    let shape = &s.description.shapes[0];
    let GeometryDesc::BilinearMesh(m) = &shape.geometry else {
        panic!("expected a bilinear mesh, found {:?}", shape.geometry);
    };
    assert_eq!(m.indices, vec![0, 1, 2, 3, 1, 4, 3, 5]);
    assert_eq!(m.positions[3], Vec3::new(1.0, 1.0, 3.0));
    let normals = m.normals.as_ref().unwrap();
    assert!(normals.iter().all(|n| close(*n, -Vec3::Z)), "{normals:?}");
    assert_eq!(m.uvs.as_ref().unwrap()[4], glam::Vec2::new(2.0, 0.0));
    assert!(shape.flip_normals);
    assert!(shape.area_light.is_some());
    // It builds, and the area light has one light per patch.
    let scene = mcrender_core::scene::Scene::build(&s.description).unwrap();
    assert_eq!(scene.lights.len(), 2);
}

/// Shapes inside `ObjectBegin`/`ObjectEnd` keep the CTM of their definition and go to the
/// object; each `ObjectInstance` adds a placement with the CTM at that point. The
/// definition's attribute scope closes with `ObjectEnd`.
#[test]
fn object_instancing_defines_once_and_places_many_times() {
    let s = load(
        "WorldBegin\nObjectBegin \"thing\"\n  Translate 1 0 0\n  Material \"diffuse\" \"rgb reflectance\" [0.1 0.2 0.3]\n  \
         Shape \"sphere\"\n  Shape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0]\nObjectEnd\n\
         Shape \"sphere\"\nObjectInstance \"thing\"\nTranslate 0 5 0\nObjectInstance \"thing\"",
    );
    let d = &s.description;
    assert_eq!(d.shapes.len(), 1);
    assert_eq!(sphere_matrix(&s, 0), Mat4::IDENTITY, "ObjectEnd restores the CTM");
    assert_eq!(d.objects.len(), 1);
    let o = &d.objects[0];
    assert_eq!(o.shapes.len(), 2);
    match &o.shapes[0].geometry {
        GeometryDesc::Sphere { world_from_object, .. } => {
            assert_eq!(world_from_object.m, Mat4::from_translation(Vec3::X));
        }
        other => panic!("not a sphere: {other:?}"),
    }
    assert_eq!(mesh(&o.shapes[1]).positions[0], Vec3::X);
    assert_eq!(
        d.materials[o.shapes[0].material as usize],
        MaterialDesc::Diffuse(DiffuseMaterial {
            reflectance: Rgb::new(0.1, 0.2, 0.3).into()
        })
    );
    assert_ne!(
        d.shapes[0].material, o.shapes[0].material,
        "ObjectEnd restores the material"
    );
    assert_eq!(d.instances.len(), 2);
    assert_eq!(d.instances[0].object, 0);
    assert_eq!(d.instances[0].world_from_instance.m, Mat4::IDENTITY);
    assert_eq!(
        d.instances[1].world_from_instance.m,
        Mat4::from_translation(Vec3::new(0.0, 5.0, 0.0))
    );
}

#[test]
fn look_at_sets_the_camera() {
    let s = load("LookAt 0 1 6.8  0 1 0  0 1 0\nCamera \"perspective\" \"float fov\" 30 \"float lensradius\" 0.1 \"float focaldistance\" 5\nWorldBegin");
    let cam = &s.description.camera;
    let w = cam.world_from_camera;
    assert!(close(w.point(Vec3::ZERO), Vec3::new(0.0, 1.0, 6.8)));
    assert!(close(w.vector(Vec3::Z), -Vec3::Z));
    assert!(close(w.vector(Vec3::Y), Vec3::Y));
    // pbrt's camera space is left-handed: +x is to the right when looking down +z.
    assert!(close(w.vector(Vec3::X), -Vec3::X));
    assert!((w.m * w.m_inv).abs_diff_eq(Mat4::IDENTITY, 1e-5));
    assert_eq!((cam.fov_degrees, cam.lens_radius, cam.focal_distance), (30.0, 0.1, 5.0));
    assert_eq!(cam.screen_window, None);
}

#[test]
fn world_begin_resets_the_ctm() {
    let s = load("Translate 1 0 0\nCamera \"perspective\"\nWorldBegin\nShape \"sphere\"");
    assert_eq!(sphere_matrix(&s, 0), Mat4::IDENTITY);
    assert!(close(
        s.description.camera.world_from_camera.point(Vec3::ZERO),
        Vec3::new(-1.0, 0.0, 0.0)
    ));
}

#[test]
fn attribute_scopes_restore_transform_material_light_and_orientation() {
    let s = load(
        "WorldBegin\nAttributeBegin\n  Translate 1 0 0\n  Material \"diffuse\" \"rgb reflectance\" [0.1 0.2 0.3]\n  \
         AreaLightSource \"diffuse\" \"rgb L\" [1 2 3] \"float scale\" 2 \"bool twosided\" true\n  ReverseOrientation\n  \
         Shape \"sphere\"\nAttributeEnd\nShape \"sphere\"\nTransformBegin\nTranslate 0 1 0\nShape \"sphere\"\nTransformEnd\nShape \"sphere\"",
    );
    let d = &s.description;
    let inner = &d.shapes[0];
    assert_eq!(sphere_matrix(&s, 0), Mat4::from_translation(Vec3::X));
    assert_eq!(
        d.materials[inner.material as usize],
        MaterialDesc::Diffuse(DiffuseMaterial {
            reflectance: Rgb::new(0.1, 0.2, 0.3).into()
        })
    );
    assert_eq!(
        inner.area_light,
        Some(AreaLightDesc {
            radiance: Rgb::new(2.0, 4.0, 6.0),
            two_sided: true,
            power: None
        })
    );
    assert!(inner.flip_normals);
    let outer = &d.shapes[1];
    assert_eq!(sphere_matrix(&s, 1), Mat4::IDENTITY);
    assert_eq!(
        d.materials[outer.material as usize],
        MaterialDesc::Diffuse(DiffuseMaterial {
            reflectance: Rgb::splat(0.5).into()
        })
    );
    assert_eq!(outer.area_light, None);
    assert!(!outer.flip_normals);
    assert_eq!(sphere_matrix(&s, 2), Mat4::from_translation(Vec3::Y));
    assert_eq!(sphere_matrix(&s, 3), Mat4::IDENTITY);
    assert!(s
        .warnings
        .iter()
        .any(|w| w.starts_with("scene.pbrt:10:1: warning: TransformBegin/TransformEnd are deprecated")));
}

#[test]
fn flip_normals_is_reverse_orientation_xor_handedness() {
    let s = load(&format!(
        "WorldBegin\n{TRIANGLE}\nAttributeBegin\nScale -1 1 1\n{TRIANGLE}\nReverseOrientation\n{TRIANGLE}\nAttributeEnd\n\
         ReverseOrientation\n{TRIANGLE}"
    ));
    let flips: Vec<bool> = s.description.shapes.iter().map(|s| s.flip_normals).collect();
    assert_eq!(flips, vec![false, true, false, true]);
}

#[test]
fn mesh_is_moved_to_world_space_with_normals_and_uvs() {
    let s = load(
        "WorldBegin\nTranslate 0 0 5\nScale 2 1 1\nReverseOrientation\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0]\n\
         \"integer indices\" [0 1 2 2 1 3] \"normal N\" [1 0 1 1 0 1 1 0 1 0 0 0] \"point2 uv\" [0 0 1 0 0 1 1 1]",
    );
    let m = mesh(&s.description.shapes[0]);
    assert_eq!(m.positions[3], Vec3::new(2.0, 1.0, 5.0));
    assert_eq!(m.indices, vec![0, 1, 2, 2, 1, 3]);
    // Normals go by the inverse transpose: (1, 0, 1) -> (0.5, 0, 1), normalised, then
    // negated by ReverseOrientation (as pbrt does). A zero normal stays zero.
    let n = m.normals.as_ref().unwrap();
    assert!(close(n[0], -Vec3::new(0.5, 0.0, 1.0).normalize()));
    assert_eq!(n[3], Vec3::ZERO);
    assert_eq!(m.uvs.as_ref().unwrap()[3], Vec2::ONE);
}

#[test]
fn three_vertices_need_no_indices_and_legacy_uv_warns() {
    let s = load("WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"float uv\" [0 0 1 0 0 1]");
    let m = mesh(&s.description.shapes[0]);
    assert_eq!(m.indices, vec![0, 1, 2]);
    assert_eq!(m.uvs.as_ref().unwrap()[1], Vec2::X);
    assert!(
        s.warnings.iter().any(|w| w.contains("\"float uv\" is pbrt-v3 syntax")),
        "{:?}",
        s.warnings
    );
}

#[test]
fn named_materials_are_resolved_and_deduplicated() {
    let s = load(
        "WorldBegin\nNamedMaterial \"later\"\nShape \"sphere\"\n\
         MakeNamedMaterial \"later\" \"string type\" \"diffuse\" \"rgb reflectance\" [0.2 0.2 0.2]\n\
         MakeNamedMaterial \"same\" \"string type\" [\"diffuse\"] \"rgb reflectance\" [0.2 0.2 0.2]\n\
         NamedMaterial \"same\"\nShape \"sphere\"\nMaterial \"diffuse\"\nShape \"sphere\"\nShape \"sphere\"",
    );
    let d = &s.description;
    assert_eq!(d.materials.len(), 2);
    assert_eq!(d.shapes[0].material, d.shapes[1].material);
    assert_eq!(d.shapes[2].material, d.shapes[3].material);
    assert_ne!(d.shapes[0].material, d.shapes[2].material);
    assert_eq!(
        d.materials[d.shapes[2].material as usize],
        MaterialDesc::Diffuse(DiffuseMaterial {
            reflectance: Rgb::splat(0.5).into()
        })
    );
}

#[test]
fn point_light_is_transformed_and_scaled() {
    let s = load(
        "WorldBegin\nTranslate 0 2 0\nLightSource \"point\" \"rgb I\" [1 2 3] \"float scale\" 2 \"point3 from\" [1 0 0]\n\
         LightSource \"point\" \"float power\" 100\n\
         LightSource \"point\" \"spectrum I\" \"stdillum-D65\" \"float scale\" 3",
    );
    let lights = &s.description.lights;
    assert_eq!(
        lights[0],
        LightDesc::Point {
            position: Vec3::new(1.0, 2.0, 0.0),
            intensity: Rgb::new(2.0, 4.0, 6.0)
        }
    );
    let LightDesc::Point { intensity, .. } = lights[1] else {
        panic!("{:?}", lights[1])
    };
    assert!((intensity.r - 100.0 / (4.0 * std::f32::consts::PI)).abs() < 1e-4);
    let LightDesc::Point { intensity, .. } = lights[2] else {
        panic!("{:?}", lights[2])
    };
    assert_eq!(intensity, Rgb::splat(3.0));
}

#[test]
fn options_are_read() {
    let s = load(
        "Film \"rgb\" \"integer xresolution\" 320 \"integer yresolution\" 200 \"string filename\" \"out.exr\" \"float iso\" 100\n\
         PixelFilter \"gaussian\" \"float xradius\" 2 \"float yradius\" 3 \"float sigma\" 0.7\n\
         Sampler \"independent\" \"integer pixelsamples\" 7 \"integer seed\" 42\nIntegrator \"volpath\" \"integer maxdepth\" 3\n\
         Camera \"perspective\" \"float screenwindow\" [-1 1 -0.5 0.5]\nWorldBegin",
    );
    let d = &s.description;
    assert_eq!((d.film.width, d.film.height), (320, 200));
    assert_eq!(s.output_filename.as_deref(), Some("out.exr"));
    assert_eq!(
        d.filter,
        FilterDesc::Gaussian {
            radius: Vec2::new(2.0, 3.0),
            sigma: 0.7
        }
    );
    assert_eq!((d.sampler.samples_per_pixel, d.sampler.seed), (7, 42));
    assert_eq!(d.integrator.max_depth, 3);
    assert_eq!(d.camera.screen_window, Some([-1.0, 1.0, -0.5, 0.5]));
    let warnings = s.warnings.join("\n");
    assert!(
        warnings.contains(
            "scene.pbrt:1:92: warning: parameter \"float iso\" of Film \"rgb\" is not supported and was ignored"
        ),
        "{warnings}"
    );
    assert!(
        warnings.contains("integrator \"volpath\" renders as \"path\""),
        "{warnings}"
    );
    assert!(warnings.contains("the scene has no lights"), "{warnings}");
}

#[test]
fn defaults_match_pbrt() {
    let s = load("WorldBegin\nShape \"sphere\"");
    let d = &s.description;
    assert_eq!((d.film.width, d.film.height), (1280, 720));
    assert_eq!(d.integrator.max_depth, 5);
    assert_eq!(d.sampler.samples_per_pixel, 16);
    assert_eq!(d.camera.fov_degrees, 90.0);
    assert_eq!(d.camera.world_from_camera.m, Mat4::IDENTITY);
    let GeometryDesc::Sphere { radius, .. } = d.shapes[0].geometry else {
        panic!()
    };
    assert_eq!(radius, 1.0);
}

#[test]
fn filter_defaults_and_fallbacks() {
    let radius = |src: &str| load(&format!("{src}\nWorldBegin")).description.filter;
    assert_eq!(
        radius("PixelFilter \"box\""),
        FilterDesc::Box {
            radius: Vec2::splat(0.5)
        }
    );
    assert_eq!(
        radius("PixelFilter \"triangle\""),
        FilterDesc::Triangle {
            radius: Vec2::splat(2.0)
        }
    );
    assert_eq!(
        radius("PixelFilter \"gaussian\""),
        FilterDesc::Gaussian {
            radius: Vec2::splat(1.5),
            sigma: 0.5
        }
    );
    let s = load("PixelFilter \"mitchell\" \"float B\" 0.3\nWorldBegin");
    assert_eq!(
        s.description.filter,
        FilterDesc::Mitchell {
            radius: Vec2::splat(2.0),
            b: 0.3,
            c: 1.0 / 3.0
        }
    );
    assert!(!s.warnings.iter().any(|w| w.contains("filter")), "{:?}", s.warnings);
    let s = load("PixelFilter \"lanczos\"\nWorldBegin");
    assert_eq!(
        s.description.filter,
        FilterDesc::Gaussian {
            radius: Vec2::splat(1.5),
            sigma: 0.5
        }
    );
    assert!(s.warnings[0].contains("pixel filter \"lanczos\" is not implemented yet; using \"gaussian\""));
}

#[test]
fn samplers_map_to_their_kinds_without_warnings() {
    let s = load("Sampler \"stratified\" \"integer xsamples\" 3 \"integer ysamples\" 5\nOption \"seed\" 9\nWorldBegin");
    assert_eq!(s.description.sampler.samples_per_pixel, 15);
    assert_eq!(s.description.sampler.seed, 9);
    assert_eq!(
        s.description.sampler.kind,
        SamplerKind::Stratified {
            x_samples: 3,
            y_samples: 5,
            jitter: true
        }
    );
    assert!(s.warnings.iter().all(|w| !w.contains("sampler")), "{:?}", s.warnings);
    let s = load("Sampler \"stratified\" \"bool jitter\" false\nWorldBegin");
    assert_eq!(s.description.sampler.samples_per_pixel, 16);
    assert_eq!(
        s.description.sampler.kind,
        SamplerKind::Stratified {
            x_samples: 4,
            y_samples: 4,
            jitter: false
        }
    );
    for name in ["sobol", "zsobol", "halton", "pmj02bn", "paddedsobol"] {
        let s = load(&format!(
            "Sampler \"{name}\" \"integer pixelsamples\" 32 \"string randomization\" \"owen\"\nWorldBegin"
        ));
        assert_eq!(s.description.sampler.kind, SamplerKind::OwenSobol, "{name}");
        assert_eq!(s.description.sampler.samples_per_pixel, 32);
        assert!(
            s.warnings.iter().all(|w| !w.contains("sampler")),
            "{name}: {:?}",
            s.warnings
        );
    }
    let s = load("Sampler \"independent\"\nWorldBegin");
    assert_eq!(s.description.sampler.kind, SamplerKind::Independent);
    assert!(s.warnings.iter().all(|w| !w.contains("sampler")));
}

#[test]
fn sampler_errors_name_the_problem() {
    let e = load_err("Sampler \"sobol\" \"string randomization\" \"scrambled\"\nWorldBegin");
    assert!(e.contains("expected a randomization"), "{e}");
    let e = load_err("Sampler \"stratified\" \"integer xsamples\" 0\nWorldBegin");
    assert!(e.contains("xsamples and ysamples must be at least 1"), "{e}");
    let e = load_err("Sampler \"zsobol\" \"integer pixelsamples\" 0\nWorldBegin");
    assert!(e.contains("must be at least 1"), "{e}");
    let e = load_err("Sampler \"magic\"\nWorldBegin");
    assert!(e.contains("unknown sampler \"magic\""), "{e}");
}

#[test]
fn attribute_directive_sets_shape_defaults() {
    let s = load("WorldBegin\nAttributeBegin\nAttribute \"shape\" \"float radius\" 0.25\nShape \"sphere\"\nAttributeEnd\nShape \"sphere\"");
    let radii: Vec<f32> = s
        .description
        .shapes
        .iter()
        .map(|s| match s.geometry {
            GeometryDesc::Sphere { radius, .. } => radius,
            _ => 0.0,
        })
        .collect();
    assert_eq!(radii, vec![0.25, 1.0]);
}

#[test]
fn coordinate_systems() {
    let s = load(
        "LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\nTranslate 1 0 0\nCoordinateSystem \"moved\"\n\
         Identity\nCoordSysTransform \"camera\"\nShape \"sphere\"\nCoordSysTransform \"moved\"\nShape \"sphere\"",
    );
    assert!(close(
        sphere_matrix(&s, 0).transform_point3(Vec3::ZERO),
        Vec3::new(0.0, 0.0, -5.0)
    ));
    assert_eq!(sphere_matrix(&s, 1), Mat4::from_translation(Vec3::X));
}

#[test]
fn unused_parameters_warn_with_their_location() {
    let s = load("WorldBegin\nShape \"sphere\" \"float radius\" 2\n  \"float foo\" 1 \"float zmax\" 0.5");
    assert!(
        s.warnings.contains(
            &"scene.pbrt:3:3: warning: parameter \"float foo\" of Shape \"sphere\" is not supported and was ignored"
                .to_string()
        ),
        "{:?}",
        s.warnings
    );
    // zmax is read (a cut sphere), so it is not warned about.
    assert!(s.warnings.iter().all(|w| !w.contains("zmax")), "{:?}", s.warnings);
}

#[test]
fn include_is_relative_to_the_scene_directory_and_errors_name_the_included_file() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("sub")).unwrap();
    std::fs::write(
        dir.path().join("sub/shapes.pbrt"),
        "Translate 0 0 1\nShape \"sphere\"\nInclude \"sub/more.pbrt\"\n",
    )
    .unwrap();
    std::fs::write(
        dir.path().join("sub/more.pbrt"),
        "Shape \"sphere\" \"float radius\" 3\n",
    )
    .unwrap();
    std::fs::write(
        dir.path().join("main.pbrt"),
        "WorldBegin\nAttributeBegin\nInclude \"sub/shapes.pbrt\"\nAttributeEnd\nShape \"sphere\"\n",
    )
    .unwrap();
    let s = mcrender_formats::pbrt::load_file(&dir.path().join("main.pbrt")).unwrap();
    assert_eq!(s.description.shapes.len(), 3);
    assert_eq!(sphere_matrix(&s, 0), Mat4::from_translation(Vec3::Z));
    assert_eq!(sphere_matrix(&s, 2), Mat4::IDENTITY);

    std::fs::write(dir.path().join("sub/more.pbrt"), "\n  Shape \"cube\"\n").unwrap();
    let err = mcrender_formats::pbrt::load_file(&dir.path().join("main.pbrt")).unwrap_err();
    let included = dir.path().join("sub/more.pbrt");
    assert_eq!(
        err.to_string(),
        format!("{}:2:3: unknown shape \"cube\"", included.display())
    );

    // load_str resolves includes against its base directory.
    let s = load_str("WorldBegin\nImport \"sub/shapes.pbrt\"", "inline", &dir.path().join("")).unwrap_err();
    assert!(s.to_string().contains("unknown shape \"cube\""));
}

#[test]
fn include_falls_back_to_the_including_file_directory() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("sub")).unwrap();
    std::fs::write(dir.path().join("sub/a.pbrt"), "Include \"b.pbrt\"\n").unwrap();
    std::fs::write(dir.path().join("sub/b.pbrt"), "Shape \"sphere\"\n").unwrap();
    std::fs::write(dir.path().join("main.pbrt"), "WorldBegin\nInclude \"sub/a.pbrt\"\n").unwrap();
    let s = mcrender_formats::pbrt::load_file(&dir.path().join("main.pbrt")).unwrap();
    assert_eq!(s.description.shapes.len(), 1);
}

#[test]
fn recursive_include_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("a.pbrt"), "Include \"a.pbrt\"\n").unwrap();
    let err = mcrender_formats::pbrt::load_file(&dir.path().join("a.pbrt")).unwrap_err();
    assert!(err.to_string().contains("nested too deeply"), "{err}");
}

#[test]
fn bdpt_is_read_with_its_parameters_and_no_fallback_warning() {
    let s = load(
        "Integrator \"bdpt\" \"integer maxdepth\" 7 \"bool regularize\" true \"bool visualizeweights\" true\n\
         WorldBegin\nLightSource \"point\" \"rgb I\" [1 1 1]",
    );
    let i = &s.description.integrator;
    assert_eq!(i.kind, mcrender_core::scene::IntegratorKind::Bdpt);
    assert_eq!(i.max_depth, 7);
    assert!(i.bdpt.regularize && i.bdpt.visualize_weights && !i.bdpt.visualize_strategies);
    assert!(i.bdpt.mis && i.bdpt.strategy.is_none());
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    // Another integrator's parameters are not bdpt's.
    let s = load("Integrator \"path\" \"bool regularize\" true\nWorldBegin\nLightSource \"point\" \"rgb I\" [1 1 1]");
    assert!(!s.description.integrator.bdpt.regularize);
    assert!(s.warnings.iter().any(|w| w.contains("regularize")), "{:?}", s.warnings);
}

#[test]
fn russian_roulette_rules_are_read() {
    let with = |params: &str| format!("Integrator \"path\" {params}\nWorldBegin\n");
    let rr = |params: &str| load(&with(params)).description.integrator.russian_roulette;
    use mcrender_core::scene::RussianRoulette;
    assert_eq!(rr(""), RussianRoulette::Throughput);
    assert_eq!(rr("\"string russianroulette\" \"off\""), RussianRoulette::Off);
    assert_eq!(
        rr("\"string russianroulette\" \"mitsuba\""),
        RussianRoulette::Delayed { start_depth: 5 }
    );
    assert_eq!(
        rr("\"string russianroulette\" \"mitsuba\" \"integer rrdepth\" [ 2 ]"),
        RussianRoulette::Delayed { start_depth: 2 }
    );
    let err = load_err(&with(
        "\"string russianroulette\" \"mitsuba\" \"integer rrdepth\" [ -1 ]",
    ));
    assert!(err.contains("rrdepth"), "{err}");
    let err = load_err(&with("\"string russianroulette\" \"sometimes\""));
    assert!(err.contains("\"mitsuba\""), "{err}");
}
