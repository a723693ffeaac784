//! The glTF 2.0 loader through the front door: small files written by the tests (a
//! triangle, a node hierarchy, a camera, lights, textured and emissive materials, GLB and
//! data URIs) and malformed ones, whose errors must name the JSON path.

use mcrender_core::material::{DielectricMaterial, MetallicRoughnessMaterial, NormalMapMaterial};
use std::path::{Path, PathBuf};

use mcrender_core::color::Rgb;
use mcrender_core::math::Vec3;
use mcrender_core::scene::{GeometryDesc, LightDesc, MaterialDesc, TriangleMeshDesc};
use mcrender_core::texture::Texture;
use mcrender_formats::{load, LoadedScene};
use serde_json::{json, Value};

/// One triangle's binary data: positions (36 bytes), normals (36), uvs (24), u16 indices (6 + 2 padding).
fn triangle_bin() -> Vec<u8> {
    let mut b = Vec::new();
    for v in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        b.extend(v.iter().flat_map(|x| x.to_le_bytes()));
    }
    for _ in 0..3 {
        b.extend([0.0f32, 0.0, 1.0].iter().flat_map(|x| x.to_le_bytes()));
    }
    for v in [[0.0f32, 0.0], [1.0, 0.0], [0.0, 1.0]] {
        b.extend(v.iter().flat_map(|x| x.to_le_bytes()));
    }
    b.extend([0u16, 1, 2, 0].iter().flat_map(|x| x.to_le_bytes()));
    b
}

/// A document with one triangle mesh in `uri` (108 bytes), node 0 showing it.
fn triangle_doc(uri: Option<&str>) -> Value {
    let mut buffer = json!({"byteLength": 104});
    if let Some(u) = uri {
        buffer["uri"] = json!(u);
    }
    json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{
            "attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
            "indices": 3
        }]}],
        "buffers": [buffer],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 36},
            {"buffer": 0, "byteOffset": 36, "byteLength": 36},
            {"buffer": 0, "byteOffset": 72, "byteLength": 24},
            {"buffer": 0, "byteOffset": 96, "byteLength": 6}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5123, "count": 3, "type": "SCALAR"}
        ]
    })
}

/// Write `doc` as `scene.gltf` with `tri.bin` beside it.
fn write(dir: &Path, doc: &Value) -> PathBuf {
    std::fs::write(dir.join("tri.bin"), triangle_bin()).unwrap();
    let path = dir.join("scene.gltf");
    std::fs::write(&path, serde_json::to_vec_pretty(doc).unwrap()).unwrap();
    path
}

fn load_doc(doc: &Value) -> LoadedScene {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), doc);
    load(&path).unwrap_or_else(|e| panic!("{e}"))
}

fn load_err(doc: &Value) -> String {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), doc);
    match load(&path) {
        Ok(_) => panic!("loaded a malformed file"),
        Err(e) => e.to_string(),
    }
}

fn mesh(s: &LoadedScene, i: usize) -> &TriangleMeshDesc {
    match &s.description.shapes[i].geometry {
        GeometryDesc::TriangleMesh(m) => m,
        other => panic!("{other:?}"),
    }
}

/// cos 45 degrees, for quarter-turn quaternions.
const H: f64 = std::f64::consts::FRAC_1_SQRT_2;

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-5
}

#[test]
fn a_triangle_loads_with_normals_uvs_default_camera_and_light() {
    let s = load_doc(&triangle_doc(Some("tri.bin")));
    let m = mesh(&s, 0);
    assert_eq!(m.indices, vec![0, 1, 2]);
    assert_eq!(m.positions[1], Vec3::new(1.0, 0.0, 0.0));
    assert_eq!(m.normals.as_ref().unwrap()[2], Vec3::Z);
    // v flipped: glTF's v runs down the image.
    assert_eq!(m.uvs.as_ref().unwrap()[2].y, 0.0);
    assert_eq!(m.uvs.as_ref().unwrap()[0].y, 1.0);
    // The default material of glTF: white, metallic 1, roughness 1.
    let MaterialDesc::MetallicRoughness(MetallicRoughnessMaterial {
        base_color,
        metallic,
        roughness,
    }) = &s.description.materials[0]
    else {
        panic!("{:?}", s.description.materials[0])
    };
    assert_eq!(
        (base_color.constant(), metallic.constant(), roughness.constant()),
        (Some(Rgb::WHITE), Some(1.0), Some(1.0))
    );
    assert!(
        s.warnings
            .iter()
            .any(|w| w.contains("scene.gltf: no camera; looking at the bounding box from")),
        "{:?}",
        s.warnings
    );
    assert!(matches!(s.description.lights[..], [LightDesc::UniformInfinite { .. }]));
    assert!(s.warnings.iter().any(|w| w.contains("no light")), "{:?}", s.warnings);
    s.description.validate().unwrap();
}

#[test]
fn node_transforms_compose_down_the_hierarchy() {
    let mut doc = triangle_doc(Some("tri.bin"));
    doc["scenes"][0]["nodes"] = json!([0]);
    doc["nodes"] = json!([
        {"children": [1], "translation": [1, 0, 0], "scale": [2, 2, 2]},
        {"mesh": 0, "matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,1,0,1],
         "children": [2]},
        {"mesh": 0, "rotation": [0, 0, H, H]}
    ]);
    let s = load_doc(&doc);
    assert_eq!(s.description.shapes.len(), 2);
    // Node 1: p -> (1,0,0) + 2 (p + (0,1,0)).
    let m = mesh(&s, 0);
    assert!(close(m.positions[1], Vec3::new(3.0, 2.0, 0.0)), "{:?}", m.positions);
    // Node 2 under node 1: a quarter turn about z first, (1,0,0) -> (0,1,0).
    let m = mesh(&s, 1);
    assert!(close(m.positions[1], Vec3::new(1.0, 4.0, 0.0)), "{:?}", m.positions);
    assert!(close(m.normals.as_ref().unwrap()[0], Vec3::Z));
}

#[test]
fn a_mirroring_transform_flips_the_normals() {
    let mut doc = triangle_doc(Some("tri.bin"));
    doc["nodes"][0]["scale"] = json!([-1, 1, 1]);
    let s = load_doc(&doc);
    assert!(s.description.shapes[0].flip_normals);
    assert!(!load_doc(&triangle_doc(Some("tri.bin"))).description.shapes[0].flip_normals);
}

#[test]
fn the_first_perspective_camera_is_used_looking_down_its_minus_z() {
    let mut doc = triangle_doc(Some("tri.bin"));
    doc["cameras"] = json!([
        {"type": "perspective", "perspective": {"yfov": 0.8, "aspectRatio": 2.0, "znear": 0.1}},
        {"type": "perspective", "perspective": {"yfov": 0.3, "znear": 0.1}}
    ]);
    doc["scenes"][0]["nodes"] = json!([0, 1, 2]);
    doc["nodes"] = json!([
        {"mesh": 0},
        {"camera": 0, "translation": [0, 0, 5]},
        {"camera": 1}
    ]);
    let s = load_doc(&doc);
    let c = &s.description.camera;
    assert_eq!((s.description.film.width, s.description.film.height), (640, 320));
    assert!((c.fov_degrees - 0.8f32.to_degrees()).abs() < 1e-4, "{}", c.fov_degrees);
    // Camera-space +z (pbrt's forward) is glTF's -z.
    assert!(close(
        c.world_from_camera.point(Vec3::new(0.0, 0.0, 1.0)),
        Vec3::new(0.0, 0.0, 4.0)
    ));
    assert!(close(
        c.world_from_camera.point(Vec3::new(1.0, 1.0, 0.0)),
        Vec3::new(1.0, 1.0, 5.0)
    ));
    assert!(!s.warnings.iter().any(|w| w.contains("no camera")), "{:?}", s.warnings);
    assert!(
        s.warnings
            .iter()
            .any(|w| w.contains("cameras[1]") && w.contains("only the first")),
        "{:?}",
        s.warnings
    );
    // A portrait camera: the field of view spans the (shorter) width.
    doc["cameras"][0]["perspective"]["aspectRatio"] = json!(0.5);
    let s = load_doc(&doc);
    let expect = 2.0 * (0.5f32 * 0.4f32.tan()).atan();
    assert!((s.description.camera.fov_degrees - expect.to_degrees()).abs() < 1e-3);
}

#[test]
fn punctual_lights_are_converted_from_photometric_units() {
    let mut doc = triangle_doc(Some("tri.bin"));
    doc["extensionsUsed"] = json!(["KHR_lights_punctual"]);
    doc["extensions"] = json!({"KHR_lights_punctual": {"lights": [
        {"type": "point", "color": [1.0, 0.5, 0.0], "intensity": 683.0},
        {"type": "spot", "intensity": 1366.0,
         "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}},
        {"type": "directional", "intensity": 68.3}
    ]}});
    doc["scenes"][0]["nodes"] = json!([0, 1, 2, 3]);
    doc["nodes"] = json!([
        {"mesh": 0},
        {"translation": [0, 3, 0], "extensions": {"KHR_lights_punctual": {"light": 0}}},
        {"translation": [0, 0, 2], "extensions": {"KHR_lights_punctual": {"light": 1}}},
        // A quarter turn about x: -z (the light's direction) becomes -y... pointing down.
        {"rotation": [-H, 0, 0, H], "extensions": {"KHR_lights_punctual": {"light": 2}}}
    ]);
    let s = load_doc(&doc);
    let lights = &s.description.lights;
    assert_eq!(lights.len(), 3, "{lights:?}");
    let LightDesc::Point { position, intensity } = &lights[0] else {
        panic!()
    };
    assert!(close(*position, Vec3::new(0.0, 3.0, 0.0)));
    assert_eq!(*intensity, Rgb::new(1.0, 0.5, 0.0));
    let LightDesc::Spot(spot) = &lights[1] else { panic!() };
    assert_eq!(spot.intensity, Rgb::splat(2.0));
    assert!((spot.cos_falloff_start - 0.2f32.cos()).abs() < 1e-6);
    assert!((spot.cos_falloff_end - 0.5f32.cos()).abs() < 1e-6);
    // The spot at z = 2 points along glTF -z, at the triangle.
    let tip = spot.world_from_light.point(Vec3::new(0.0, 0.0, 1.0));
    assert!(close(tip, Vec3::new(0.0, 0.0, 1.0)), "{tip}");
    let LightDesc::Distant { direction, radiance } = &lights[2] else {
        panic!()
    };
    assert!((radiance.r - 0.1).abs() < 1e-6);
    // Shining down, so the direction towards the light is up.
    assert!(close(*direction, Vec3::Y), "{direction}");
    assert!(!s.warnings.iter().any(|w| w.contains("no light")), "{:?}", s.warnings);
}

/// A 2x1 PNG: red, then green.
fn write_png(dir: &Path, name: &str, texels: &[[u8; 3]]) {
    let mut img = image::RgbImage::new(texels.len() as u32, 1);
    for (i, t) in texels.iter().enumerate() {
        img.put_pixel(i as u32, 0, image::Rgb(*t));
    }
    img.save(dir.join(name)).unwrap();
}

#[test]
fn textures_factors_emission_and_transmission_become_materials() {
    let dir = tempfile::tempdir().unwrap();
    write_png(dir.path(), "base.png", &[[255, 0, 0], [0, 255, 0]]);
    write_png(dir.path(), "mr.png", &[[0, 255, 128], [0, 0, 255]]);
    let mut doc = triangle_doc(Some("tri.bin"));
    doc["extensionsUsed"] = json!([
        "KHR_materials_emissive_strength",
        "KHR_materials_transmission",
        "KHR_materials_ior",
        "KHR_texture_transform",
        "EXT_made_up"
    ]);
    doc["images"] = json!([{"uri": "base.png"}, {"uri": "mr.png"}]);
    doc["samplers"] = json!([{"wrapS": 33071}]);
    doc["textures"] = json!([{"source": 0, "sampler": 0}, {"source": 1}]);
    doc["materials"] = json!([
        {"pbrMetallicRoughness": {
            "baseColorFactor": [0.5, 1.0, 1.0, 1.0],
            "baseColorTexture": {"index": 0,
                "extensions": {"KHR_texture_transform": {"offset": [0.25, 0.0], "scale": [2.0, 1.0], "rotation": 0.5}}},
            "metallicFactor": 0.5, "roughnessFactor": 1.0,
            "metallicRoughnessTexture": {"index": 1}},
         "normalTexture": {"index": 1, "scale": 0.5}},
        {"emissiveFactor": [1.0, 0.5, 0.25],
         "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4.0}}},
        {"pbrMetallicRoughness": {"roughnessFactor": 0.5},
         "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                        "KHR_materials_ior": {"ior": 1.33}}}
    ]);
    let prim = doc["meshes"][0]["primitives"][0].clone();
    let mut prims = Vec::new();
    for m in 0..3 {
        let mut p = prim.clone();
        p["material"] = json!(m);
        prims.push(p);
    }
    doc["meshes"][0]["primitives"] = json!(prims);
    let path = write(dir.path(), &doc);
    let s = load(&path).unwrap_or_else(|e| panic!("{e}"));
    let d = &s.description;
    assert_eq!(d.shapes.len(), 3);
    // The normal texture wraps the material: texels linear, x and y of 2 c - 1 times
    // the scale 0.5 (mr.png's first texel is (0, 255, 128)).
    let MaterialDesc::NormalMap(NormalMapMaterial {
        material, normal_map, ..
    }) = &d.materials[d.shapes[0].material as usize]
    else {
        panic!("{:?}", d.materials)
    };
    let Texture::Bitmap(n) = normal_map else {
        panic!("{normal_map:?}")
    };
    assert_eq!(n.texels[0], Rgb::new(0.25, 0.75, 128.0 / 255.0));
    assert_eq!(n.texels[1], Rgb::new(0.25, 0.25, 1.0));
    let MaterialDesc::MetallicRoughness(MetallicRoughnessMaterial {
        base_color,
        metallic,
        roughness,
    }) = &d.materials[*material as usize]
    else {
        panic!()
    };
    let Texture::Bitmap(b) = base_color else {
        panic!("{base_color:?}")
    };
    // sRGB 255 is linear 1, times the factor.
    assert_eq!((b.width, b.height), (2, 1));
    assert_eq!(b.texels[0], Rgb::new(0.5, 0.0, 0.0));
    assert_eq!(b.texels[1], Rgb::new(0.0, 1.0, 0.0));
    assert_eq!(b.wrap, mcrender_core::texture::BitmapWrap::Clamp);
    assert_eq!(
        b.mapping,
        mcrender_core::texture::TextureMapping::Uv {
            su: 2.0,
            sv: 1.0,
            du: 0.25,
            dv: 0.0
        }
    );
    // Metalness from blue (linear, times 0.5), roughness from green.
    let (Texture::Bitmap(m), Texture::Bitmap(r)) = (metallic, roughness) else {
        panic!()
    };
    assert!((m.texels[0].r - 0.5 * 128.0 / 255.0).abs() < 1e-6 && m.texels[1].r == 0.5);
    assert!(r.texels[0].r == 1.0 && r.texels[1].r == 0.0);
    assert!(d.shapes[0].area_light.is_none());
    // Emission times strength, one-sided (not doubleSided).
    let light = d.shapes[1].area_light.expect("emissive");
    assert_eq!(light.radiance, Rgb::new(4.0, 2.0, 1.0));
    assert!(!light.two_sided);
    // Transmission 1 with an index: a dielectric, alpha = roughness^2.
    assert_eq!(
        d.materials[d.shapes[2].material as usize],
        MaterialDesc::Dielectric(DielectricMaterial {
            eta: 1.33,
            u_roughness: 0.25.into(),
            v_roughness: 0.25.into(),
            remap_roughness: false,
            microfacet: Default::default(),
        })
    );
    let w = s.warnings.join("\n");
    assert!(w.contains("EXT_made_up is not supported"), "{w}");
    assert!(w.contains("KHR_texture_transform.rotation 0.5 is ignored"), "{w}");
    // The emissive triangle lights the scene: no environment light added.
    assert!(d.lights.is_empty(), "{:?}", d.lights);
    d.validate().unwrap();
}

/// Standard base64 (RFC 4648) with padding, for data URIs.
fn base64(bytes: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for c in bytes.chunks(3) {
        let n =
            (u32::from(c[0]) << 16) | (u32::from(*c.get(1).unwrap_or(&0)) << 8) | u32::from(*c.get(2).unwrap_or(&0));
        for i in 0..4 {
            if i <= c.len() {
                out.push(A[(n >> (18 - 6 * i) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[test]
fn embedded_data_uri_buffers_and_glb_load_the_same_triangle() {
    let reference = load_doc(&triangle_doc(Some("tri.bin")));
    let uri = format!("data:application/octet-stream;base64,{}", base64(&triangle_bin()));
    let s = load_doc(&triangle_doc(Some(&uri)));
    assert_eq!(mesh(&s, 0), mesh(&reference, 0));

    // GLB: header, JSON chunk (padded with spaces), BIN chunk.
    let mut json = serde_json::to_vec(&triangle_doc(None)).unwrap();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let bin = triangle_bin();
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut glb = Vec::new();
    glb.extend(b"glTF");
    glb.extend(2u32.to_le_bytes());
    glb.extend((total as u32).to_le_bytes());
    glb.extend((json.len() as u32).to_le_bytes());
    glb.extend(b"JSON");
    glb.extend(&json);
    glb.extend((bin.len() as u32).to_le_bytes());
    glb.extend(b"BIN\0");
    glb.extend(&bin);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("tri.glb");
    std::fs::write(&path, &glb).unwrap();
    let s = load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(mesh(&s, 0), mesh(&reference, 0));
}

/// The triangle with a `TANGENT` accessor (`count` of them, each `t`) after its data, in
/// `tri-t.bin`.
fn with_tangents(dir: &Path, t: [f32; 4], count: usize) -> PathBuf {
    let mut doc = triangle_doc(Some("tri-t.bin"));
    let mut bin = triangle_bin();
    let offset = bin.len();
    for _ in 0..count {
        bin.extend(t.iter().flat_map(|x| x.to_le_bytes()));
    }
    std::fs::write(dir.join("tri-t.bin"), &bin).unwrap();
    doc["buffers"][0]["byteLength"] = json!(bin.len());
    doc["bufferViews"]
        .as_array_mut()
        .unwrap()
        .push(json!({"buffer": 0, "byteOffset": offset, "byteLength": 16 * count}));
    doc["accessors"]
        .as_array_mut()
        .unwrap()
        .push(json!({"bufferView": 4, "componentType": 5126, "count": count, "type": "VEC4"}));
    doc["meshes"][0]["primitives"][0]["attributes"]["TANGENT"] = json!(4);
    let path = dir.join("scene.gltf");
    std::fs::write(&path, serde_json::to_vec_pretty(&doc).unwrap()).unwrap();
    path
}

#[test]
fn tangents_are_read_moved_to_world_and_mirrored_with_the_node() {
    let dir = tempfile::tempdir().unwrap();
    // Not along dp/du (+x here), bitangent mirrored.
    let h = std::f32::consts::FRAC_1_SQRT_2;
    let path = with_tangents(dir.path(), [h, h, 0.0, -1.0], 3);
    let s = load(&path).unwrap_or_else(|e| panic!("{e}"));
    let t = mesh(&s, 0).tangents.as_ref().expect("tangents read");
    assert_eq!(t.len(), 3);
    assert!(close(t[0].truncate(), Vec3::new(h, h, 0.0)) && t[0].w == -1.0, "{t:?}");
    assert!(!s.warnings.iter().any(|w| w.contains("TANGENT")), "{:?}", s.warnings);
    s.description.validate().unwrap();

    // A mirroring node moves the tangent as a vector and turns the handedness around.
    let mut doc: Value = serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
    doc["nodes"][0]["scale"] = json!([-1, 1, 1]);
    std::fs::write(&path, serde_json::to_vec_pretty(&doc).unwrap()).unwrap();
    let s = load(&path).unwrap_or_else(|e| panic!("{e}"));
    let t = mesh(&s, 0).tangents.as_ref().expect("tangents read");
    assert!(close(t[1].truncate(), Vec3::new(-h, h, 0.0)) && t[1].w == 1.0, "{t:?}");

    // Without normals, tangents are ignored (the spec).
    doc["nodes"][0]["scale"] = json!([1, 1, 1]);
    doc["meshes"][0]["primitives"][0]["attributes"]
        .as_object_mut()
        .unwrap()
        .remove("NORMAL");
    std::fs::write(&path, serde_json::to_vec_pretty(&doc).unwrap()).unwrap();
    let s = load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(mesh(&s, 0).tangents, None);
}

#[test]
fn a_tangent_count_other_than_the_vertex_count_is_an_error_naming_the_accessor() {
    let dir = tempfile::tempdir().unwrap();
    let e = load(&with_tangents(dir.path(), [1.0, 0.0, 0.0, 1.0], 2))
        .expect_err("two tangents for three vertices")
        .to_string();
    assert!(
        e.contains("scene.gltf")
            && e.contains("meshes[0].primitives[0].attributes.TANGENT: 2 tangents for 3 positions"),
        "{e}"
    );
    let e = load(&with_tangents(dir.path(), [f32::NAN, 0.0, 0.0, 1.0], 3))
        .expect_err("a NaN tangent")
        .to_string();
    assert!(e.contains("attributes.TANGENT: non-finite tangent"), "{e}");
}

#[test]
fn malformed_files_name_the_file_and_the_json_path() {
    // Bad JSON: file:line:col.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.gltf");
    std::fs::write(&path, "{\n  \"asset\": {\"version\": \"2.0\"},\n  oops\n}").unwrap();
    let e = load(&path).expect_err("bad JSON").to_string();
    assert!(e.starts_with(&format!("{}:3:", path.display())), "{e}");

    // A buffer file that does not exist.
    let e = load_err(&triangle_doc(Some("missing.bin")));
    assert!(
        e.contains("scene.gltf: buffers[0].uri: cannot read \"missing.bin\""),
        "{e}"
    );
    // A buffer shorter than its byteLength.
    let mut doc = triangle_doc(Some("tri.bin"));
    doc["buffers"][0]["byteLength"] = json!(4000);
    assert!(load_err(&doc).contains("buffers[0].byteLength"), "{}", load_err(&doc));
    // An accessor reaching past its view.
    let mut doc = triangle_doc(Some("tri.bin"));
    doc["accessors"][3]["count"] = json!(300);
    let e = load_err(&doc);
    assert!(e.contains("meshes[0].primitives[0].indices (accessors[3])"), "{e}");
    // A view outside its buffer.
    let mut doc = triangle_doc(Some("tri.bin"));
    doc["bufferViews"][0]["byteOffset"] = json!(100);
    let e = load_err(&doc);
    assert!(e.contains("bufferViews[0]"), "{e}");
    // An index past the last vertex.
    let mut doc = triangle_doc(Some("tri.bin"));
    doc["accessors"][3]["componentType"] = json!(5121);
    doc["accessors"][3]["count"] = json!(6);
    doc["accessors"][0]["count"] = json!(1);
    let e = load_err(&doc);
    assert!(
        e.contains("meshes[0].primitives[0].indices") && e.contains("out of range"),
        "{e}"
    );
    // A reference to an accessor that does not exist (the crate's validation).
    let mut doc = triangle_doc(Some("tri.bin"));
    doc["meshes"][0]["primitives"][0]["indices"] = json!(17);
    let e = load_err(&doc);
    assert!(e.contains("meshes[0].primitives[0].indices"), "{e}");
    // A POSITION accessor that does not exist (gltf-json's validation would panic on it).
    let mut doc = triangle_doc(Some("tri.bin"));
    doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(9);
    let e = load_err(&doc);
    assert!(
        e.contains("meshes[0].primitives[0].attributes.POSITION: accessor 9 does not exist"),
        "{e}"
    );
    // A cycle in the node hierarchy.
    let mut doc = triangle_doc(Some("tri.bin"));
    doc["nodes"] = json!([{"mesh": 0, "children": [1]}, {"children": [0]}]);
    let e = load_err(&doc);
    assert!(e.contains("nodes["), "{e}");
    // Not a GLB at all.
    let path = dir.path().join("x.glb");
    std::fs::write(&path, b"glTF\x02\0\0\0\x10\0\0\0garbage!").unwrap();
    assert!(load(&path).is_err());
}

#[test]
fn the_fuzz_seeds_are_valid_scenes() {
    // The seeds should exercise the whole loader, not stop at the first error.
    let seeds = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/seeds/gltf");
    for name in ["scene.gltf", "scene.glb"] {
        let s = load(&seeds.join(name)).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(s.description.shapes.len(), 4, "{name}");
        assert!(matches!(s.description.lights[..], [LightDesc::Spot(_)]), "{name}");
        mcrender_core::scene::Scene::build(&s.description).unwrap();
    }
}

/// The CRC-32 of PNG chunks (ISO 3309, reflected polynomial 0xedb88320).
fn crc32(bytes: &[u8]) -> u32 {
    let mut c = !0u32;
    for &b in bytes {
        c ^= u32::from(b);
        for _ in 0..8 {
            c = if c & 1 == 1 { 0xedb8_8320 ^ (c >> 1) } else { c >> 1 };
        }
    }
    !c
}

/// The start of a PNG of `n` x `n` RGB pixels: its header and a two-byte image data chunk,
/// enough to read the size from, far too little to decode.
fn png_header(n: u32) -> Vec<u8> {
    let mut out = b"\x89PNG\r\n\x1a\n".to_vec();
    let mut chunk = |kind: &[u8], data: &[u8]| {
        out.extend((data.len() as u32).to_be_bytes());
        let body = [kind, data].concat();
        out.extend(&body);
        out.extend(crc32(&body).to_be_bytes());
    };
    let ihdr = [&n.to_be_bytes()[..], &n.to_be_bytes(), &[8, 2, 0, 0, 0]].concat();
    chunk(b"IHDR", &ihdr);
    chunk(b"IDAT", &[0x78, 0x9c]);
    out
}

/// Regression: glTF images were decoded without a look at the memory limit and reported as
/// 0 bytes to the command line's memory check. A 16384x16384 base colour texture is now
/// refused from its header (the file holds only that: decoding would fail otherwise), with
/// the figure and the limit; a small one is counted.
#[test]
fn gltf_texture_16384_is_refused_before_decoding_and_textures_are_counted() {
    use mcrender_formats::limits::{image_texture_bytes, LoadLimits};
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("big.png"), png_header(16384)).unwrap();
    write_png(dir.path(), "small.png", &[[255, 0, 0], [0, 255, 0]]);
    let mut doc = triangle_doc(Some("tri.bin"));
    doc["images"] = json!([{"uri": "big.png"}]);
    doc["textures"] = json!([{"source": 0}]);
    doc["materials"] = json!([{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]);
    doc["meshes"][0]["primitives"][0]["material"] = json!(0);
    let path = write(dir.path(), &doc);
    let options = mcrender_formats::LoadOptions {
        limits: LoadLimits { max_memory: 1 << 30 },
        ..mcrender_formats::LoadOptions::default()
    };
    let err = mcrender_formats::load_with(&path, &options).unwrap_err().to_string();
    assert!(
        err.contains("images[0], 16384x16384") && err.contains("memory limit of 1.0 GiB"),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1, "{err}");
    // Without the limit it is read, and fails as the truncated file it is.
    let err = load(&path).unwrap_err().to_string();
    assert!(err.contains("cannot read the image"), "{err}");

    doc["images"] = json!([{"uri": "small.png"}]);
    let path = write(dir.path(), &doc);
    let loaded = mcrender_formats::load_with(&path, &options).unwrap();
    assert_eq!(loaded.image_bytes, image_texture_bytes(2, 1));
}

/// The alpha test of the first shape, evaluated as a constant.
fn constant_alpha(s: &LoadedScene, shape: usize) -> Option<f32> {
    s.description.shapes[shape]
        .alpha
        .as_ref()
        .map(|a| a.constant().expect("a constant alpha"))
}

#[test]
fn alpha_modes_become_alpha_tests() {
    let dir = tempfile::tempdir().unwrap();
    let mut doc = triangle_doc(Some("tri.bin"));
    doc["materials"] = json!([
        {"alphaMode": "MASK", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.3]}},
        {"alphaMode": "MASK", "alphaCutoff": 0.25, "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.3]}},
        {"alphaMode": "BLEND", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.25]}},
        {"pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.25]}},
        {"alphaMode": "MASK", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}
    ]);
    // A 2x1 RGBA texture: alpha 1 then 0.
    let mut img = image::RgbaImage::new(2, 1);
    img.put_pixel(0, 0, image::Rgba([255, 255, 255, 255]));
    img.put_pixel(1, 0, image::Rgba([255, 255, 255, 0]));
    img.save(dir.path().join("rgba.png")).unwrap();
    doc["images"] = json!([{"uri": "rgba.png"}]);
    doc["textures"] = json!([{"source": 0}]);
    let prim = doc["meshes"][0]["primitives"][0].clone();
    let prims: Vec<Value> = (0..5)
        .map(|m| {
            let mut p = prim.clone();
            p["material"] = json!(m);
            p
        })
        .collect();
    doc["meshes"][0]["primitives"] = json!(prims);
    let s = load(&write(dir.path(), &doc)).unwrap_or_else(|e| panic!("{e}"));
    // MASK below the default cutoff 0.5: never present; above a cutoff of 0.25: no test.
    assert!(constant_alpha(&s, 0).unwrap() <= 0.0);
    assert_eq!(constant_alpha(&s, 1), None);
    // BLEND: coverage; OPAQUE ignores the factor's alpha.
    assert_eq!(constant_alpha(&s, 2), Some(0.25));
    assert_eq!(constant_alpha(&s, 3), None);
    // A MASK texture: present where the texel's alpha is 1 (>= 1), absent at 0 (<= 0).
    let Some(Texture::Bitmap(b)) = &s.description.shapes[4].alpha else {
        panic!("{:?}", s.description.shapes[4].alpha)
    };
    assert!(b.texels[0].r >= 1.0 && b.texels[1].r <= 0.0, "{:?}", b.texels);
    assert!(s
        .warnings
        .join("\n")
        .contains("materials[2].alphaMode BLEND is rendered as coverage"));
    s.description.validate().unwrap();
}
