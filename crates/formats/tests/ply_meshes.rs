//! `Shape "plymesh"` with PLY files written here in ASCII, binary little-endian and binary
//! big-endian: vertices, normals, uvs, quads split into triangles, transforms applied.

use std::path::Path;

use mcrender_core::math::{Vec2, Vec3};
use mcrender_core::scene::{GeometryDesc, TriangleMeshDesc};
use mcrender_formats::pbrt::load_str;
use mcrender_formats::ply::read_ply;

/// Vertices of a unit quad at z = 0 (x, y, z, nx, ny, nz, u, v), then a triangle.
const VERTICES: [[f32; 8]; 5] = [
    [0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0],
    [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 0.0],
    [1.0, 1.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
    [0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0],
    [0.5, 0.5, 1.0, 0.0, 1.0, 0.0, 0.5, 0.5],
];
/// One quad and one triangle.
const FACES: [&[i32]; 2] = [&[0, 1, 2, 3], &[0, 1, 4]];

fn header(format: &str) -> String {
    format!(
        "ply\nformat {format} 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n\
         property float nx\nproperty float ny\nproperty float nz\nproperty float u\nproperty float v\n\
         element face 2\nproperty list uchar int vertex_indices\nend_header\n"
    )
}

fn ascii_ply() -> Vec<u8> {
    let mut s = header("ascii");
    for v in VERTICES {
        s += &v.iter().map(|x| x.to_string()).collect::<Vec<_>>().join(" ");
        s += "\n";
    }
    for f in FACES {
        s += &format!(
            "{} {}\n",
            f.len(),
            f.iter().map(|i| i.to_string()).collect::<Vec<_>>().join(" ")
        );
    }
    s.into_bytes()
}

fn binary_ply(big_endian: bool) -> Vec<u8> {
    let format = if big_endian {
        "binary_big_endian"
    } else {
        "binary_little_endian"
    };
    let mut bytes = header(format).into_bytes();
    for v in VERTICES {
        for x in v {
            bytes.extend(if big_endian { x.to_be_bytes() } else { x.to_le_bytes() });
        }
    }
    for f in FACES {
        bytes.push(f.len() as u8);
        for i in f {
            bytes.extend(if big_endian { i.to_be_bytes() } else { i.to_le_bytes() });
        }
    }
    bytes
}

fn load_mesh(ply: &[u8], extra: &str) -> TriangleMeshDesc {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("models")).unwrap();
    std::fs::write(dir.path().join("models/m.ply"), ply).unwrap();
    let src = format!("WorldBegin\n{extra}\nShape \"plymesh\" \"string filename\" \"models/m.ply\"");
    let scene = load_str(&src, "scene.pbrt", dir.path()).unwrap_or_else(|e| panic!("{e}"));
    match &scene.description.shapes[0].geometry {
        GeometryDesc::TriangleMesh(m) => m.clone(),
        other => panic!("{other:?}"),
    }
}

fn check(mesh: &TriangleMeshDesc) {
    assert_eq!(mesh.positions.len(), 5);
    assert_eq!(mesh.positions[2], Vec3::new(1.0, 1.0, 0.0));
    assert_eq!(mesh.indices, vec![0, 1, 2, 0, 2, 3, 0, 1, 4]);
    assert_eq!(mesh.normals.as_ref().unwrap()[4], Vec3::Y);
    assert_eq!(mesh.uvs.as_ref().unwrap()[4], Vec2::splat(0.5));
}

#[test]
fn ascii_ply_loads() {
    check(&load_mesh(&ascii_ply(), ""));
}

#[test]
fn binary_little_endian_ply() {
    check(&load_mesh(&binary_ply(false), ""));
}

#[test]
fn binary_big_endian_ply() {
    check(&load_mesh(&binary_ply(true), ""));
}

#[test]
fn all_encodings_agree() {
    let dir = tempfile::tempdir().unwrap();
    let mut meshes = Vec::new();
    for (name, bytes) in [
        ("a.ply", ascii_ply()),
        ("le.ply", binary_ply(false)),
        ("be.ply", binary_ply(true)),
    ] {
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).unwrap();
        meshes.push(read_ply(&path).unwrap());
    }
    assert_eq!(meshes[0], meshes[1]);
    assert_eq!(meshes[1], meshes[2]);
}

#[test]
fn ply_mesh_is_transformed_and_reverse_orientation_flips_normals() {
    let mesh = load_mesh(&binary_ply(false), "Translate 0 0 2\nScale 3 1 1\nReverseOrientation");
    assert_eq!(mesh.positions[1], Vec3::new(3.0, 0.0, 2.0));
    assert_eq!(mesh.normals.as_ref().unwrap()[0], -Vec3::Z);
}

#[test]
fn ply_without_faces_is_an_error_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("m.ply"), "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n").unwrap();
    let err = load_str(
        "WorldBegin\n  Shape \"plymesh\" \"string filename\" \"m.ply\"",
        "scene.pbrt",
        dir.path(),
    )
    .unwrap_err();
    assert_eq!(
        err.to_string(),
        "scene.pbrt:2:3: cannot read PLY file \"m.ply\": no \"face\" element"
    );
}

#[test]
fn truncated_binary_ply_is_an_error() {
    let bytes = binary_ply(false);
    for cut in [bytes.len() - 1, bytes.len() - 20, 200, 10] {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("m.ply"), &bytes[..cut]).unwrap();
        let err = load_str(
            "WorldBegin\nShape \"plymesh\" \"string filename\" \"m.ply\"",
            "scene.pbrt",
            dir.path(),
        );
        assert!(err.is_err(), "cut at {cut}");
    }
}

#[test]
fn missing_ply_is_relative_to_the_base_dir() {
    let err = load_str(
        "WorldBegin\nShape \"plymesh\" \"string filename\" \"models/foo.ply\"",
        "scene.pbrt",
        Path::new("/nonexistent-dir"),
    )
    .unwrap_err();
    assert_eq!(
        err.to_string(),
        "scene.pbrt:2:1: cannot open PLY file \"models/foo.ply\": No such file or directory"
    );
}

#[test]
fn plymesh_at_the_end_of_an_included_file_falls_back_to_that_files_directory() {
    // pbrt resolves against the top-level file's directory; when the file is not there,
    // mcrender also tries the directory of the file that names it, even when the plymesh is
    // the last directive of an included file.
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("sub")).unwrap();
    std::fs::write(dir.path().join("sub/m.ply"), ascii_ply()).unwrap();
    std::fs::write(
        dir.path().join("sub/geo.pbrt"),
        "Shape \"plymesh\" \"string filename\" \"m.ply\"",
    )
    .unwrap();
    std::fs::write(
        dir.path().join("main.pbrt"),
        "WorldBegin\nInclude \"sub/geo.pbrt\"\nShape \"sphere\"\n",
    )
    .unwrap();
    let scene = mcrender_formats::pbrt::load_file(&dir.path().join("main.pbrt")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.description.shapes.len(), 2);
}
