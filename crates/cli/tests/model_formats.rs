//! `mcrender render` on glTF and OBJ files: a small glTF scene renders to its analytic
//! image, an OBJ renders with the default camera and light said on stderr, and malformed
//! files exit with code 2 and a one-line message naming the file and the JSON path.

mod common;

use common::{mcrender, stderr};

/// A 4x4 emissive square at z = 0 (radiance 1), seen from z = 1 by a camera whose
/// 60-degree view it fills: every pixel sees exactly the emitted radiance.
fn emissive_square_gltf() -> String {
    r#"{"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1]}],
  "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0, 0, 1]}],
  "cameras": [{"type": "perspective", "perspective": {"yfov": 1.0472, "aspectRatio": 1.0, "znear": 0.01}}],
  "materials": [{"emissiveFactor": [1, 1, 1], "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1]}}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
  "buffers": [{"byteLength": 60, "uri": "square.bin"}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
  "accessors": [
    {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-2, -2, 0], "max": [2, 2, 0]},
    {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}]}"#
        .to_string()
}

fn square_bin() -> Vec<u8> {
    let mut bin = Vec::new();
    for v in [
        [-2.0f32, -2.0, 0.0],
        [2.0, -2.0, 0.0],
        [2.0, 2.0, 0.0],
        [-2.0, 2.0, 0.0],
    ] {
        bin.extend(v.iter().flat_map(|x| x.to_le_bytes()));
    }
    bin.extend([0u16, 1, 2, 0, 2, 3].iter().flat_map(|x| x.to_le_bytes()));
    bin
}

#[test]
fn a_gltf_scene_renders_to_its_emitted_radiance() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("square.gltf"), emissive_square_gltf()).unwrap();
    std::fs::write(dir.path().join("square.bin"), square_bin()).unwrap();
    let o = mcrender(
        &[
            "render",
            "square.gltf",
            "--spp",
            "4",
            "--resolution",
            "16x16",
            "-o",
            "out.exr",
            "-q",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let img = mcrender_formats::read_image(&dir.path().join("out.exr")).unwrap();
    assert_eq!((img.width, img.height), (16, 16));
    for y in 0..16 {
        for x in 0..16 {
            let p = img.get(x, y);
            assert!(
                (p.r - 1.0).abs() < 1e-4 && (p.g - 1.0).abs() < 1e-4,
                "pixel ({x}, {y}) = {p:?}"
            );
        }
    }
    assert!(!stderr(&o).contains("no camera"), "{}", stderr(&o));
}

#[test]
fn an_obj_renders_with_the_default_camera_and_light_said_on_stderr() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("model.obj"),
        "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n",
    )
    .unwrap();
    let o = mcrender(
        &[
            "render",
            "model.obj",
            "--spp",
            "64",
            "--resolution",
            "8x8",
            "-o",
            "out.exr",
            "--variance-output",
            "var.exr",
            "-q",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("model.obj: no camera; looking at the bounding box from ("),
        "{err}"
    );
    assert!(
        err.contains("model.obj: no light; adding a uniform white environment light"),
        "{err}"
    );
    // The grey square fills the middle of the image under a white sky and sees nothing
    // else: 0.5 reflected, within 4 standard errors (from the variance of the mean).
    let img = mcrender_formats::read_image(&dir.path().join("out.exr")).unwrap();
    let var = mcrender_formats::read_image(&dir.path().join("var.exr")).unwrap();
    let (mut sum, mut v) = (0.0f64, 0.0f64);
    for (x, y) in [(3, 3), (3, 4), (4, 3), (4, 4)] {
        sum += f64::from(img.get(x, y).g) / 4.0;
        v += f64::from(var.get(x, y).g) / 16.0;
    }
    assert!(v > 0.0);
    assert!(
        (sum - 0.5).abs() < 4.0 * v.sqrt(),
        "mean {sum}, standard error {}",
        v.sqrt()
    );
}

#[test]
fn malformed_gltf_exits_2_with_the_json_path() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("square.gltf"),
        emissive_square_gltf().replace("\"count\": 6", "\"count\": 600"),
    )
    .unwrap();
    std::fs::write(dir.path().join("square.bin"), square_bin()).unwrap();
    let o = mcrender(&["render", "square.gltf", "-o", "out.exr", "-q"], dir.path());
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("square.gltf: meshes[0].primitives[0].indices (accessors[1])"),
        "{err}"
    );
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    std::fs::write(dir.path().join("bad.gltf"), "{ not json").unwrap();
    let o = mcrender(&["render", "bad.gltf", "-o", "out.exr", "-q"], dir.path());
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("bad.gltf:1:"), "{}", stderr(&o));
}
