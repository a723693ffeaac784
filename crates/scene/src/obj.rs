//! Wavefront OBJ meshes read with the `tobj` crate: every object and group of the file
//! merged into one triangle mesh (polygons fan-triangulated), with its normals and texture
//! coordinates when every vertex has them. Texture coordinates are kept as written (`v`
//! up, pbrt's convention).

use std::path::Path;

use mcrender_core::math::{Vec2, Vec3};
use mcrender_core::scene::TriangleMeshDesc;

/// Read `path` as one triangle mesh in the file's coordinates.
///
/// # Errors
/// A message (not naming the file: the caller does) when it cannot be read or parsed, has
/// no triangles, or has non-finite coordinates.
pub fn read_obj_mesh(path: &Path) -> Result<TriangleMeshDesc, String> {
    let options = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ..tobj::LoadOptions::default()
    };
    let (models, _materials) = tobj::load_obj(path, &options).map_err(|e| e.to_string())?;
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
        let m = read_obj_mesh(&path).unwrap();
        assert_eq!(m.indices.len(), 6);
        assert_eq!(m.positions.len(), 4);
        assert_eq!(m.normals.as_ref().unwrap()[0], Vec3::Z);
        assert_eq!(m.uvs.as_ref().unwrap()[2], Vec2::new(1.0, 1.0));
    }

    #[test]
    fn a_missing_file_or_a_bad_index_is_an_error() {
        assert!(read_obj_mesh(Path::new("/definitely/not/here.obj")).is_err());
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bad.obj");
        std::fs::write(&path, "v 0 0 0\nf 1 2 3\n").unwrap();
        assert!(read_obj_mesh(&path).is_err());
    }
}
