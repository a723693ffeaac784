//! Wavefront OBJ meshes read with the `tobj` crate: every object and group of the file
//! merged into one triangle mesh (polygons fan-triangulated), with its normals and texture
//! coordinates when every vertex has them. Texture coordinates are kept as written (`v`
//! up, pbrt's convention).

use std::path::Path;

use mcrender_core::math::{Vec2, Vec3};
use mcrender_core::scene::TriangleMeshDesc;

use crate::source::FileSource;

/// What tobj makes of an OBJ file: its models, and its materials (or why they could not be
/// read).
pub type ParsedObj = (Vec<tobj::Model>, Result<Vec<tobj::Material>, tobj::LoadError>);

/// Parse OBJ text with tobj, reading each `mtllib` it names through `mtl` (the bytes of that
/// file, `None` when it cannot be read). The one way into tobj for every loader (the OBJ
/// front door and Mitsuba's `obj` shape): each MTL file passes through [`sanitize_mtl`]
/// first.
///
/// # Errors
/// tobj's, when the OBJ text cannot be parsed.
pub fn parse_obj(
    obj: &[u8],
    options: &tobj::LoadOptions,
    mtl: impl Fn(&Path) -> Option<Vec<u8>>,
) -> Result<ParsedObj, tobj::LoadError> {
    check_face_indices(obj)?;
    tobj::load_obj_buf(&mut std::io::Cursor::new(obj), options, |name| {
        let bytes = mtl(name).ok_or(tobj::LoadError::OpenFileFailed)?;
        tobj::load_mtl_buf(&mut std::io::Cursor::new(sanitize_mtl(&bytes)))
    })
}

/// The lines tobj reads: up to the first one that is not UTF-8, where it stops with an error.
fn obj_lines(obj: &[u8]) -> impl Iterator<Item = &str> {
    obj.split(|b| *b == b'\n').map_while(|l| std::str::from_utf8(l).ok())
}

/// Every index of every `f` and `l` element within range: `1..=n` for the file's `n`
/// positions, texture coordinates or normals, or `-1..=-m` for the `m` defined so far.
/// tobj 4.0.5 turns index 0 and indices below `-m` into huge values and multiplies them
/// unchecked, an overflow panic with overflow checks on and a wrapped index without (found
/// by the `obj` fuzz target: `f 1/1/-11` with one normal).
fn check_face_indices(obj: &[u8]) -> Result<(), tobj::LoadError> {
    const KINDS: [&str; 3] = ["v", "vt", "vn"];
    let mut total = [0i64; 3];
    for line in obj_lines(obj) {
        if let Some(k) = line
            .split_whitespace()
            .next()
            .and_then(|w| KINDS.iter().position(|k| *k == w))
        {
            total[k] += 1;
        }
    }
    let errors = [
        tobj::LoadError::FaceVertexOutOfBounds,
        tobj::LoadError::FaceTexCoordOutOfBounds,
        tobj::LoadError::FaceNormalOutOfBounds,
    ];
    let mut so_far = [0i64; 3];
    for line in obj_lines(obj) {
        let mut words = line.split_whitespace();
        match words.next() {
            Some(w) if KINDS.contains(&w) => {
                so_far[KINDS.iter().position(|k| *k == w).unwrap_or(0)] += 1;
            }
            Some("f" | "l") => {
                for vertex in words {
                    for (k, index) in vertex.split('/').take(3).enumerate() {
                        // Empty (`1//3`) or unparsable parts are tobj's to report.
                        let Ok(i) = index.parse::<i64>() else { continue };
                        let valid = if i < 0 {
                            i.checked_neg().is_some_and(|m| m <= so_far[k])
                        } else {
                            i >= 1 && i <= total[k]
                        };
                        if !valid {
                            return Err(errors[k]);
                        }
                    }
                }
            }
            _ => {}
        }
    }
    Ok(())
}

/// MTL text with colour lines of fewer than three values (`Kd 0.5`, valid MTL for a grey)
/// written out as three: tobj 4.0.5 panics on them (found by the `obj` fuzz target).
fn sanitize_mtl(mtl: &[u8]) -> Vec<u8> {
    let text = String::from_utf8_lossy(mtl);
    let mut out = String::with_capacity(text.len() + 16);
    for line in text.lines() {
        let mut words = line.split_whitespace();
        let key = words.next();
        let rest: Vec<&str> = words.collect();
        match key {
            Some(k @ ("Ka" | "Kd" | "Ks" | "Ke" | "Tf")) if rest.len() < 3 => {
                let v = rest.first().copied().unwrap_or("0");
                out.push_str(&format!("{k} {v} {v} {v}"));
            }
            _ => out.push_str(line),
        }
        out.push('\n');
    }
    out.into_bytes()
}

/// Read `path` of `files` as one triangle mesh in the file's coordinates (its materials
/// are read, as tobj does, and ignored).
///
/// # Errors
/// A message (not naming the file: the caller does) when it cannot be read or parsed, has
/// no triangles, or has non-finite coordinates.
pub fn read_obj_mesh(path: &Path, files: &dyn FileSource) -> Result<TriangleMeshDesc, String> {
    let options = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ..tobj::LoadOptions::default()
    };
    let obj = files.read(path).map_err(|e| crate::error::io_error_text(&e))?;
    let dir = path.parent().unwrap_or_else(|| Path::new(""));
    let (models, _materials) =
        parse_obj(&obj, &options, |mtl| files.read(&dir.join(mtl)).ok()).map_err(|e| e.to_string())?;
    let meshes: Vec<&tobj::Mesh> = models.iter().map(|m| &m.mesh).collect();
    mesh_of(&meshes)
}

/// The meshes `parts` merged into one, with normals and uvs kept only when every
/// vertex has valid ones.
///
/// # Errors
/// As [`read_obj_mesh`].
pub fn mesh_of(parts: &[&tobj::Mesh]) -> Result<TriangleMeshDesc, String> {
    let mut mesh = TriangleMeshDesc::default();
    let (mut normals, mut uvs) = (Vec::new(), Vec::new());
    let (mut all_normals, mut all_uvs) = (true, true);
    for m in parts {
        let base = mesh.positions.len() as u32;
        let n = m.positions.len() / 3;
        mesh.positions
            .extend(m.positions.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])));
        if m.normals.len() == 3 * n {
            normals.extend(m.normals.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])));
        } else {
            all_normals = false;
        }
        if m.texcoords.len() == 2 * n {
            uvs.extend(m.texcoords.chunks_exact(2).map(|c| Vec2::new(c[0], c[1])));
        } else {
            all_uvs = false;
        }
        for &i in &m.indices {
            if i as usize >= n {
                return Err(format!("vertex index {i} out of range"));
            }
            mesh.indices.push(base + i);
        }
    }
    if mesh.indices.is_empty() {
        return Err("the file has no faces".into());
    }
    if mesh.positions.iter().any(|p| !p.is_finite()) {
        return Err("non-finite vertex position".into());
    }
    if all_normals && normals.iter().all(|n| n.is_finite() && n.length_squared() > 0.0) {
        mesh.normals = Some(normals);
    }
    if all_uvs && uvs.iter().all(|uv| uv.is_finite()) {
        mesh.uvs = Some(uvs);
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_quad_becomes_two_triangles_with_its_attributes() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("quad.obj");
        std::fs::write(
            &path,
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n\
             f 1/1/1 2/2/1 3/3/1 4/4/1\n",
        )
        .unwrap();
        let m = read_obj_mesh(&path, &crate::source::DiskFiles).unwrap();
        assert_eq!(m.indices.len(), 6);
        assert_eq!(m.positions.len(), 4);
        assert_eq!(m.normals.as_ref().unwrap()[0], Vec3::Z);
        assert_eq!(m.uvs.as_ref().unwrap()[2], Vec2::new(1.0, 1.0));
    }

    #[test]
    fn a_missing_file_or_a_bad_index_is_an_error() {
        assert!(read_obj_mesh(Path::new("/definitely/not/here.obj"), &crate::source::DiskFiles).is_err());
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bad.obj");
        std::fs::write(&path, "v 0 0 0\nf 1 2 3\n").unwrap();
        assert!(read_obj_mesh(&path, &crate::source::DiskFiles).is_err());
    }

    /// Found by the `obj` fuzz target (session 6): `f 1/1/-11` with one normal made tobj
    /// compute a huge normal index and multiply it unchecked (a panic with overflow checks).
    #[test]
    fn regression_out_of_range_face_indices_are_errors_before_tobj() {
        let options = tobj::LoadOptions {
            single_index: true,
            triangulate: true,
            ..tobj::LoadOptions::default()
        };
        let head = "v 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvn 0 0 1\n";
        let parse = |faces: &str| parse_obj(format!("{head}{faces}").as_bytes(), &options, |_| None).map(|_| ());
        assert!(parse("f 1/1/1 2/1/1 3/1/1\n").is_ok());
        assert!(parse("f -3/-1/-1 -2/-1/-1 -1/-1/-1\n").is_ok());
        for bad in [
            "f 1/1/-11 2/1/1 3/1/1\n",
            "f 1/1/1 2/1/1 3/1/2\n",
            "f 0 2 3\n",
            "f -4 2 3\n",
            "f 1/2 2/1 3/1\n",
            "f 1 2 9223372036854775807\n",
            "f 1 2 -9223372036854775808\n",
            "l 1 5\n",
        ] {
            // Checked here, not left to tobj (which, without overflow checks, often wraps
            // into an error of its own, and sometimes into an in-range index).
            assert!(check_face_indices(format!("{head}{bad}").as_bytes()).is_err(), "{bad}");
            assert!(parse(bad).is_err(), "{bad}");
        }
    }
}
