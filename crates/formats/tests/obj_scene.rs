//! An OBJ file with its MTL as a whole scene through the front door: materials mapped
//! from MTL, emission as area lights, the default camera and light said in the warnings.

use mcrender_core::material::{CoatedDiffuseMaterial, ConductorMaterial, DielectricMaterial, DiffuseMaterial};
use std::path::Path;

use mcrender_core::color::Rgb;
use mcrender_core::scene::{LightDesc, MaterialDesc};
use mcrender_core::texture::Texture;
use mcrender_formats::{load, LoadedScene};

const QUADS: &str = "mtllib scene.mtl
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vn 0 0 1
o matte
usemtl matte
f 1/1/1 2/2/1 3/3/1 4/4/1
o textured
usemtl textured
f 1/1/1 2/2/1 3/3/1
o metal
usemtl metal
f 1/1/1 2/2/1 3/3/1
o plastic
usemtl plastic
f 1/1/1 2/2/1 3/3/1
o glass
usemtl glass
f 1/1/1 2/2/1 3/3/1
";

const MTL: &str = "newmtl matte
Kd 0.2 0.4 0.6
newmtl textured
Kd 1 1 1
map_Kd tex.png
map_Bump bump.png
newmtl metal
Kd 0 0 0
Ks 0.9 0.8 0.7
Ns 98
newmtl plastic
Kd 0.5 0.5 0.5
Ks 0.04 0.04 0.04
Ns 18
newmtl glass
Kd 1 1 1
d 0.1
Ni 1.33
";

fn write_scene(dir: &Path, obj: &str, mtl: &str) -> std::path::PathBuf {
    std::fs::write(dir.join("scene.mtl"), mtl).unwrap();
    let mut img = image::RgbImage::new(2, 1);
    img.put_pixel(0, 0, image::Rgb([255, 0, 0]));
    img.put_pixel(1, 0, image::Rgb([0, 0, 255]));
    img.save(dir.join("tex.png")).unwrap();
    let path = dir.join("model.obj");
    std::fs::write(&path, obj).unwrap();
    path
}

fn load_scene(obj: &str, mtl: &str) -> LoadedScene {
    let dir = tempfile::tempdir().unwrap();
    let path = write_scene(dir.path(), obj, mtl);
    load(&path).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn mtl_materials_map_to_diffuse_texture_conductor_coated_and_dielectric() {
    let s = load_scene(QUADS, MTL);
    let d = &s.description;
    assert_eq!(d.shapes.len(), 5);
    let m = |i: usize| &d.materials[d.shapes[i].material as usize];
    assert_eq!(
        *m(0),
        MaterialDesc::Diffuse(DiffuseMaterial {
            reflectance: Rgb::new(0.2, 0.4, 0.6).into()
        })
    );
    let MaterialDesc::Diffuse(DiffuseMaterial {
        reflectance: Texture::Bitmap(b),
    }) = m(1)
    else {
        panic!("{:?}", m(1))
    };
    assert_eq!((b.width, b.height, b.texels[0]), (2, 1, Rgb::new(1.0, 0.0, 0.0)));
    let alpha = |ns: f32| (2.0 / (ns + 2.0)).sqrt();
    let MaterialDesc::Conductor(ConductorMaterial {
        reflectance: Some(r),
        u_roughness,
        remap_roughness: false,
        ..
    }) = m(2)
    else {
        panic!("{:?}", m(2))
    };
    assert_eq!(r.constant(), Some(Rgb::new(0.9, 0.8, 0.7)));
    assert_eq!(u_roughness.constant(), Some(alpha(98.0)));
    let MaterialDesc::CoatedDiffuse(CoatedDiffuseMaterial {
        reflectance,
        u_roughness,
        eta,
        ..
    }) = m(3)
    else {
        panic!("{:?}", m(3))
    };
    assert_eq!(
        (reflectance.constant(), u_roughness.constant(), *eta),
        (Some(Rgb::splat(0.5)), Some(alpha(18.0)), 1.5)
    );
    let MaterialDesc::Dielectric(DielectricMaterial { eta, .. }) = m(4) else {
        panic!("{:?}", m(4))
    };
    assert_eq!(*eta, 1.33);
    // The quad was triangulated and keeps its attributes.
    let mcrender_core::scene::GeometryDesc::TriangleMesh(q) = &d.shapes[0].geometry else {
        panic!()
    };
    assert_eq!((q.indices.len(), q.normals.is_some(), q.uvs.is_some()), (6, true, true));
    let w = s.warnings.join("\n");
    assert!(w.contains("map_Bump / norm is ignored"), "{w}");
    assert!(
        w.contains("model.obj: no camera; looking at the bounding box from"),
        "{w}"
    );
    assert!(
        w.contains("model.obj: no light; adding a uniform white environment light"),
        "{w}"
    );
    assert!(matches!(d.lights[..], [LightDesc::UniformInfinite { radiance }] if radiance == Rgb::WHITE));
    d.validate().unwrap();
}

#[test]
fn emission_becomes_an_area_light_and_no_environment_is_added() {
    let obj = "mtllib scene.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl lamp\nf 1 2 3\nusemtl matte\nf 1 3 2\n";
    let mtl = "newmtl lamp\nKd 0 0 0\nKe 5 4 3\nnewmtl matte\nKd 0.5 0.5 0.5\n";
    let s = load_scene(obj, mtl);
    let d = &s.description;
    let lit: Vec<_> = d.shapes.iter().filter_map(|s| s.area_light).collect();
    assert_eq!(lit.len(), 1, "{:?}", d.shapes);
    assert_eq!(lit[0].radiance, Rgb::new(5.0, 4.0, 3.0));
    assert!(d.lights.is_empty());
    assert!(!s.warnings.iter().any(|w| w.contains("no light")), "{:?}", s.warnings);
}

#[test]
fn a_file_without_mtl_is_grey_and_bad_files_are_errors() {
    let s = load_scene("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "");
    assert_eq!(
        s.description.materials,
        vec![MaterialDesc::Diffuse(DiffuseMaterial {
            reflectance: Rgb::splat(0.5).into()
        })]
    );
    let dir = tempfile::tempdir().unwrap();
    let e = load(&dir.path().join("gone.obj")).expect_err("missing").to_string();
    assert!(e.contains("gone.obj") && e.contains("cannot open"), "{e}");
    let path = write_scene(dir.path(), "v 0 0 0\nf 1 2 3\n", "");
    let e = load(&path).expect_err("bad index").to_string();
    assert!(e.contains("model.obj"), "{e}");
    let path = write_scene(dir.path(), "v 0 0 0\nv 1 0 0\n", "");
    let e = load(&path).expect_err("no faces").to_string();
    assert!(e.contains("no faces"), "{e}");
    // A texture that is not there.
    let path = write_scene(dir.path(), QUADS, &MTL.replace("tex.png", "nope.png"));
    let e = load(&path).expect_err("missing texture").to_string();
    assert!(e.contains("nope.png"), "{e}");
}
