//! PLY triangle meshes (ASCII and binary, little and big endian), read with the `ply-rs`
//! crate the way pbrt-v4's `plymesh` reads them:
//!
//! * element `vertex`: `x y z`, optional normals `nx ny nz`, optional texture coordinates
//!   `u v` (or `s t`, `texture_u texture_v`, `texture_s texture_t`);
//! * element `face`: a list `vertex_indices` (or `vertex_index`); triangles are kept, quads
//!   are split into the triangles (0, 1, 2) and (0, 2, 3), other polygons are skipped and
//!   counted (pbrt skips them too). pbrt-v4 instead makes each quad a bilinear patch
//!   (p00 p10 p01 p11 = 0 1 3 2): the same surface for planar quads, whose triangles are
//!   exactly our two; a non-planar quad is curved there and two flat triangles here;
//! * other scalar properties of vertices and faces are kept by name, in the header's order
//!   ([`PlyMesh::vertex_attributes`], [`PlyMesh::face_attributes`], a quad's value going to
//!   both its triangles), for Mitsuba's mesh attributes;
//! * any other element is read and ignored.
//!
//! Vertex data must be finite and indices in range; anything else is a [`PlyError`].

use std::io::{BufRead, Cursor};
use std::path::Path;

use glam::{Vec2, Vec3};
use ply_rs::parser::Parser;
use ply_rs::ply::{Property, PropertyAccess};

/// A mesh read from a PLY file, in the file's coordinates.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlyMesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Per-vertex normals, when the file has `nx ny nz`.
    pub normals: Option<Vec<Vec3>>,
    /// Per-vertex texture coordinates, when the file has them.
    pub uvs: Option<Vec<Vec2>>,
    /// Three vertex indices per triangle.
    pub indices: Vec<u32>,
    /// Faces with fewer than 3 or more than 4 vertices, which were skipped.
    pub skipped_faces: usize,
    /// Other scalar vertex properties: name and one value per vertex.
    pub vertex_attributes: Vec<(String, Vec<f32>)>,
    /// Other scalar face properties: name and one value per triangle of [`Self::indices`].
    pub face_attributes: Vec<(String, Vec<f32>)>,
}

/// Why a PLY file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum PlyError {
    /// The file could not be opened or read.
    #[error("{0}")]
    Io(#[from] std::io::Error),
    /// The file is not a valid PLY mesh (shown with control characters escaped and long
    /// quoted input shortened).
    #[error("{}", crate::error::tidy_message(.0))]
    Format(String),
}

/// Read a PLY mesh from a file.
///
/// # Errors
/// [`PlyError::Io`] when the file cannot be read, [`PlyError::Format`] when it is not a
/// valid PLY triangle/quad mesh.
pub fn read_ply(path: &Path) -> Result<PlyMesh, PlyError> {
    read_ply_from(path, &crate::source::DiskFiles)
}

/// [`read_ply`] of the file `path` of `files`.
///
/// # Errors
/// As [`read_ply`].
pub fn read_ply_from(path: &Path, files: &dyn crate::source::FileSource) -> Result<PlyMesh, PlyError> {
    let bytes = files.read(path)?;
    read_ply_bytes(&bytes)
}

/// Read a PLY mesh from the bytes of a file.
///
/// # Errors
/// [`PlyError::Format`] when the bytes are not a valid PLY triangle/quad mesh.
pub fn read_ply_bytes(bytes: &[u8]) -> Result<PlyMesh, PlyError> {
    check_header_numbers(bytes)?;
    let mut reader = Cursor::new(bytes);
    let vertex_parser = Parser::<Vertex>::new();
    let face_parser = Parser::<Face>::new();
    let other_parser = Parser::<Ignored>::new();
    let header = vertex_parser
        .read_header(&mut reader)
        .map_err(|e| format_error("invalid header", &e))?;

    let mut vertices: Option<Vec<Vertex>> = None;
    let mut faces: Option<Vec<Face>> = None;
    let mut has = VertexLayout::default();
    let mut extra_names = (Vec::new(), Vec::new());
    for (name, def) in &header.elements {
        match name.as_str() {
            "vertex" => {
                has = VertexLayout::from_names(def.properties.keys().map(String::as_str));
                extra_names.0 = def
                    .properties
                    .values()
                    .filter(|p| is_scalar(p) && !is_vertex_reserved(&p.name))
                    .map(|p| p.name.clone())
                    .collect();
                let read = vertex_parser.read_payload_for_element(&mut reader, def, &header);
                vertices = Some(read.map_err(|e| format_error("cannot read the vertices", &e))?);
            }
            "face" => {
                extra_names.1 = def
                    .properties
                    .values()
                    .filter(|p| is_scalar(p))
                    .map(|p| p.name.clone())
                    .collect();
                let read = face_parser.read_payload_for_element(&mut reader, def, &header);
                faces = Some(read.map_err(|e| format_error("cannot read the faces", &e))?);
            }
            _ => {
                other_parser
                    .read_payload_for_element(&mut reader, def, &header)
                    .map_err(|e| format_error(&format!("cannot read the \"{name}\" elements"), &e))?;
            }
        }
    }
    let vertices = vertices.ok_or_else(|| PlyError::Format("no \"vertex\" element".into()))?;
    let faces = faces.ok_or_else(|| PlyError::Format("no \"face\" element".into()))?;
    if !has.position {
        return Err(PlyError::Format("the vertices have no x, y, z properties".into()));
    }
    build_mesh(&vertices, &faces, &has, &extra_names)
}

/// True for a property holding one number (not a list).
fn is_scalar(p: &ply_rs::ply::PropertyDef) -> bool {
    matches!(p.data_type, ply_rs::ply::PropertyType::Scalar(_))
}

/// Vertex properties with a meaning of their own (position, normal, texture coordinates).
fn is_vertex_reserved(name: &str) -> bool {
    matches!(name, "x" | "y" | "z" | "nx" | "ny" | "nz") || UV_NAMES.iter().any(|(u, v)| name == *u || name == *v)
}

/// The value of the extra property `name` of an element (0 when absent or not a scalar).
fn extra_value(extra: &[(String, f32)], name: &str) -> f32 {
    extra.iter().find(|(n, _)| n == name).map_or(0.0, |(_, v)| *v)
}

fn format_error(what: &str, err: &std::io::Error) -> PlyError {
    PlyError::Format(format!("{what}: {}", ply_rs_message(&err.to_string())))
}

/// One line from a `ply-rs` message, which reads `Line N: what.\n\tString: 'input'\n\tError:
/// <a Debug dump of its parser's state>`: the line and what, the input quoted (shortened),
/// and no dump.
fn ply_rs_message(text: &str) -> String {
    let mut parts = Vec::new();
    for line in text.lines().map(str::trim) {
        if line.starts_with("Error:") {
            // The rest is a Debug dump, possibly over several lines.
            break;
        }
        if let Some(input) = line.strip_prefix("String:") {
            let input = input.trim().trim_matches('\'');
            parts.push(format!("in {}", crate::error::quoted(input.trim())));
        } else if !line.is_empty() && line != "'" {
            let line = line
                .strip_prefix("Line ")
                .map_or_else(|| line.to_string(), |l| format!("line {l}"));
            parts.push(line.trim_end_matches('.').to_string());
        }
    }
    if parts.is_empty() {
        return "malformed file".into();
    }
    parts.join(" ")
}

/// Guard `ply-rs` against headers it handles badly: it parses header numbers with `unwrap`
/// (so digit runs must be short), and it would read an element without properties forever
/// (so those must be empty). Every property of every entry takes at least one byte, so
/// `count * properties` may not exceed the file size either.
fn check_header_numbers(bytes: &[u8]) -> Result<(), PlyError> {
    let mut reader = Cursor::new(bytes);
    let mut line = Vec::new();
    // (name, count, number of properties) of the element being declared.
    let mut element: Option<(String, u64, u64)> = None;
    let check_element = |e: &Option<(String, u64, u64)>| match e {
        Some((name, count, 0)) if *count > 0 => Err(PlyError::Format(format!(
            "element \"{name}\" has {count} entries but no properties"
        ))),
        Some((name, count, properties)) if count.saturating_mul(*properties) > bytes.len() as u64 => {
            Err(PlyError::Format(format!(
                "element \"{name}\" claims {count} entries, more than the file can hold"
            )))
        }
        _ => Ok(()),
    };
    loop {
        line.clear();
        let n = reader.read_until(b'\n', &mut line).map_err(PlyError::Io)?;
        if n == 0 {
            return Ok(()); // no end_header: ply-rs reports that
        }
        let mut run = 0;
        for &b in &line {
            run = if b.is_ascii_digit() { run + 1 } else { 0 };
            if run > 18 {
                return Err(PlyError::Format("a number in the header is too large".into()));
            }
        }
        let text = String::from_utf8_lossy(&line);
        let words: Vec<&str> = text.split_whitespace().collect();
        match words.first().copied() {
            Some("element") => {
                check_element(&element)?;
                let name = words.get(1).copied().unwrap_or("").to_string();
                let count = words.get(2).and_then(|c| c.parse::<u64>().ok()).unwrap_or(0);
                element = Some((name, count, 0));
            }
            Some("property") => {
                if let Some(e) = &mut element {
                    e.2 += 1;
                }
            }
            Some("end_header") => return check_element(&element),
            _ => {}
        }
    }
}

/// Which optional vertex properties the file declares.
#[derive(Clone, Copy, Debug, Default)]
struct VertexLayout {
    position: bool,
    normal: bool,
    uv: Option<usize>,
}

/// Names of the texture-coordinate pairs pbrt accepts, in its order of preference.
const UV_NAMES: [(&str, &str); 4] = [
    ("u", "v"),
    ("s", "t"),
    ("texture_u", "texture_v"),
    ("texture_s", "texture_t"),
];

impl VertexLayout {
    fn from_names<'a>(names: impl Iterator<Item = &'a str> + Clone) -> Self {
        let has = |n: &str| names.clone().any(|m| m == n);
        Self {
            position: has("x") && has("y") && has("z"),
            normal: has("nx") && has("ny") && has("nz"),
            uv: UV_NAMES.iter().position(|(u, v)| has(u) && has(v)),
        }
    }
}

/// One vertex: position, normal and the four candidate uv pairs.
#[derive(Clone, Debug, Default)]
struct Vertex {
    p: [f64; 3],
    n: [f64; 3],
    uv: [[f64; 2]; 4],
    /// Other scalar properties.
    extra: Vec<(String, f32)>,
}

fn scalar(p: &Property) -> Option<f64> {
    Some(match *p {
        Property::Char(v) => f64::from(v),
        Property::UChar(v) => f64::from(v),
        Property::Short(v) => f64::from(v),
        Property::UShort(v) => f64::from(v),
        Property::Int(v) => f64::from(v),
        Property::UInt(v) => f64::from(v),
        Property::Float(v) => f64::from(v),
        Property::Double(v) => v,
        _ => return None,
    })
}

impl PropertyAccess for Vertex {
    fn new() -> Self {
        Self::default()
    }

    fn set_property(&mut self, name: String, property: Property) {
        let Some(v) = scalar(&property) else { return };
        match name.as_str() {
            "x" => self.p[0] = v,
            "y" => self.p[1] = v,
            "z" => self.p[2] = v,
            "nx" => self.n[0] = v,
            "ny" => self.n[1] = v,
            "nz" => self.n[2] = v,
            other => {
                let mut uv = false;
                for (i, (u, w)) in UV_NAMES.iter().enumerate() {
                    if other == *u {
                        self.uv[i][0] = v;
                        uv = true;
                    } else if other == *w {
                        self.uv[i][1] = v;
                        uv = true;
                    }
                }
                if !uv {
                    self.extra.push((name, v as f32));
                }
            }
        }
    }
}

/// One face: its vertex indices (`None` when the list holds a non-integer type).
#[derive(Clone, Debug, Default)]
struct Face {
    indices: Option<Vec<i64>>,
    /// Other scalar properties.
    extra: Vec<(String, f32)>,
}

impl PropertyAccess for Face {
    fn new() -> Self {
        Self::default()
    }

    fn set_property(&mut self, name: String, property: Property) {
        if name != "vertex_indices" && name != "vertex_index" {
            if let Some(v) = scalar(&property) {
                self.extra.push((name, v as f32));
            }
            return;
        }
        self.indices = match property {
            Property::ListChar(v) => Some(v.into_iter().map(i64::from).collect()),
            Property::ListUChar(v) => Some(v.into_iter().map(i64::from).collect()),
            Property::ListShort(v) => Some(v.into_iter().map(i64::from).collect()),
            Property::ListUShort(v) => Some(v.into_iter().map(i64::from).collect()),
            Property::ListInt(v) => Some(v.into_iter().map(i64::from).collect()),
            Property::ListUInt(v) => Some(v.into_iter().map(i64::from).collect()),
            _ => None,
        };
    }
}

/// An element we do not use.
struct Ignored;

impl PropertyAccess for Ignored {
    fn new() -> Self {
        Self
    }
}

fn finite_vec3(v: [f64; 3], what: &str, i: usize) -> Result<Vec3, PlyError> {
    let f = Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32);
    if f.is_finite() {
        Ok(f)
    } else {
        Err(PlyError::Format(format!("the {what} of vertex {i} is not finite")))
    }
}

fn build_mesh(
    vertices: &[Vertex],
    faces: &[Face],
    has: &VertexLayout,
    extra_names: &(Vec<String>, Vec<String>),
) -> Result<PlyMesh, PlyError> {
    let positions = vertices
        .iter()
        .enumerate()
        .map(|(i, v)| finite_vec3(v.p, "position", i))
        .collect::<Result<Vec<_>, _>>()?;
    let normals = if has.normal {
        Some(
            vertices
                .iter()
                .enumerate()
                .map(|(i, v)| finite_vec3(v.n, "normal", i))
                .collect::<Result<Vec<_>, _>>()?,
        )
    } else {
        None
    };
    let uvs = match has.uv {
        Some(k) => Some(
            vertices
                .iter()
                .enumerate()
                .map(|(i, v)| {
                    let uv = Vec2::new(v.uv[k][0] as f32, v.uv[k][1] as f32);
                    if uv.is_finite() {
                        Ok(uv)
                    } else {
                        Err(PlyError::Format(format!(
                            "the texture coordinates of vertex {i} are not finite"
                        )))
                    }
                })
                .collect::<Result<Vec<_>, _>>()?,
        ),
        None => None,
    };

    let n = positions.len();
    let index = |i: i64| -> Result<u32, PlyError> {
        if (0..n as i64).contains(&i) {
            Ok(i as u32)
        } else {
            Err(PlyError::Format(format!(
                "vertex index {i} is out of range (the file has {n} vertices)"
            )))
        }
    };
    let mut indices = Vec::with_capacity(faces.len() * 3);
    let mut skipped_faces = 0;
    let mut face_attributes: Vec<(String, Vec<f32>)> = extra_names.1.iter().map(|n| (n.clone(), Vec::new())).collect();
    for (f, face) in faces.iter().enumerate() {
        let Some(ix) = &face.indices else {
            return Err(PlyError::Format(format!(
                "face {f} has no integer \"vertex_indices\" (or \"vertex_index\") list"
            )));
        };
        let triangles = match ix[..] {
            [a, b, c] => {
                indices.extend([index(a)?, index(b)?, index(c)?]);
                1
            }
            [a, b, c, d] => {
                let (a, b, c, d) = (index(a)?, index(b)?, index(c)?, index(d)?);
                indices.extend([a, b, c, a, c, d]);
                2
            }
            _ => {
                skipped_faces += 1;
                0
            }
        };
        for (name, values) in &mut face_attributes {
            let v = extra_value(&face.extra, name);
            values.extend(std::iter::repeat_n(v, triangles));
        }
    }
    let vertex_attributes = extra_names
        .0
        .iter()
        .map(|name| {
            (
                name.clone(),
                vertices.iter().map(|v| extra_value(&v.extra, name)).collect(),
            )
        })
        .collect();
    Ok(PlyMesh {
        positions,
        normals,
        uvs,
        indices,
        skipped_faces,
        vertex_attributes,
        face_attributes,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const ASCII_QUAD: &str = "ply\nformat ascii 1.0\ncomment test\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty float u\nproperty float v\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0 0 0\n1 0 0 1 0\n1 1 0 1 1\n0 1 0 0 1\n4 0 1 2 3\n5 0 1 2 3 0\n";

    /// Extra scalar properties are kept by name and in order; a quad's face value goes to
    /// both of its triangles; lists other than the indices are not attributes.
    #[test]
    fn extra_properties_become_attributes() {
        let src = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
                   property float color_0\nproperty uchar q\nelement face 2\nproperty list uchar int vertex_indices\n\
                   property float weight\nproperty list uchar int other\nend_header\n\
                   0 0 0 0.5 1\n1 0 0 0.25 2\n1 1 0 0.125 3\n0 1 0 1 4\n4 0 1 2 3 0.75 0\n3 0 1 2 0.5 1 7\n";
        let m = read_ply_bytes(src.as_bytes()).unwrap();
        assert_eq!(m.indices.len(), 9);
        assert_eq!(
            m.vertex_attributes,
            [
                ("color_0".to_string(), vec![0.5, 0.25, 0.125, 1.0]),
                ("q".to_string(), vec![1.0, 2.0, 3.0, 4.0])
            ]
        );
        assert_eq!(m.face_attributes, [("weight".to_string(), vec![0.75, 0.75, 0.5])]);
        // Files without extras have none.
        let plain = read_ply_bytes(ASCII_QUAD.as_bytes()).unwrap();
        assert!(plain.vertex_attributes.is_empty() && plain.face_attributes.is_empty());
    }

    #[test]
    fn ply_rs_debug_dumps_are_not_shown() {
        let src = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty foo y\nend_header\n";
        let err = read_ply_bytes(src.as_bytes()).unwrap_err().to_string();
        assert!(!err.contains("ParseError") && !err.contains('{'), "{err}");
        assert!(err.contains("line 5") && err.contains("\"property foo y\""), "{err}");
        let src = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\nzz\n";
        let err = read_ply_bytes(src.as_bytes()).unwrap_err().to_string();
        assert!(!err.contains("Custom") && !err.contains("kind:"), "{err}");
        assert!(!err.chars().any(char::is_control), "{err}");
    }

    #[test]
    fn ascii_quads_are_split_and_big_polygons_skipped() {
        let m = read_ply_bytes(ASCII_QUAD.as_bytes()).unwrap();
        assert_eq!(m.positions.len(), 4);
        assert_eq!(m.positions[2], Vec3::new(1.0, 1.0, 0.0));
        assert_eq!(m.indices, vec![0, 1, 2, 0, 2, 3]);
        assert_eq!(m.uvs.as_ref().unwrap()[1], Vec2::new(1.0, 0.0));
        assert!(m.normals.is_none());
        assert_eq!(m.skipped_faces, 1);
    }

    #[test]
    fn out_of_range_index_is_an_error() {
        let src = ASCII_QUAD.replace("4 0 1 2 3\n", "4 0 1 2 9\n");
        let err = read_ply_bytes(src.as_bytes()).unwrap_err();
        assert_eq!(
            err.to_string(),
            "vertex index 9 is out of range (the file has 4 vertices)"
        );
    }

    #[test]
    fn garbage_is_an_error_not_a_panic() {
        for src in [
            &b""[..],
            b"ply\n",
            b"ply\nformat ascii 1.0\nelement vertex 99999999999999999999999999\nend_header\n",
            b"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nend_header\n1\n",
            b"\xff\xfe\x00garbage",
            b"ply\nformat ascii 1.0\nelement vertex 4000000000\nend_header\n",
            b"ply\nformat binary_little_endian 1.0\nelement vertex 1000\nproperty float x\nend_header\n",
        ] {
            assert!(read_ply_bytes(src).is_err());
        }
    }
}
