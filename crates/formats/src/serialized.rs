//! Mitsuba's `serialized` mesh files: one or more zlib-compressed triangle meshes with a
//! table of their offsets at the end of the file (Mitsuba's `serialized` shape plugin).
//!
//! Layout, all little-endian: each mesh starts with the format tag `0x041C` (u16) and a
//! version (u16, 3 or 4), followed by a zlib stream holding: flags (u32; 0x0001 vertex
//! normals, 0x0002 texture coordinates, 0x0008 vertex colours, 0x0010 face normals wanted,
//! 0x1000 single precision, 0x2000 double precision), in version 4 the mesh's name
//! (UTF-8, NUL-terminated), the vertex count (u64), the triangle count (u64), the positions,
//! normals, texture coordinates and colours as present (3, 3, 2, 3 reals a vertex), then
//! three indices a triangle (u32; u64 when there are more than 2^32 vertices, which is refused). The file
//! ends with the offset of each mesh (u64 in version 4, u32 in version 3) and their number
//! (u32).

use std::io::Read;

use mcrender_core::math::{Vec2, Vec3};
use mcrender_core::scene::TriangleMeshDesc;

use crate::limits::{format_bytes, mesh_bytes};

const FORMAT_TAG: u16 = 0x041C;
const HAS_NORMALS: u32 = 0x0001;
const HAS_UVS: u32 = 0x0002;
const HAS_COLORS: u32 = 0x0008;
const FACE_NORMALS: u32 = 0x0010;
const SINGLE_PRECISION: u32 = 0x1000;
const DOUBLE_PRECISION: u32 = 0x2000;

/// A mesh read from a serialized file.
#[derive(Clone, Debug, PartialEq)]
pub struct SerializedMesh {
    /// The mesh (normals dropped when the file asks for face normals).
    pub mesh: TriangleMeshDesc,
    /// The mesh's name (version 4 files; empty otherwise).
    pub name: String,
}

fn u16_at(bytes: &[u8], at: usize) -> Option<u16> {
    Some(u16::from_le_bytes(bytes.get(at..at + 2)?.try_into().ok()?))
}

fn u32_at(bytes: &[u8], at: usize) -> Option<u32> {
    Some(u32::from_le_bytes(bytes.get(at..at + 4)?.try_into().ok()?))
}

fn u64_at(bytes: &[u8], at: usize) -> Option<u64> {
    Some(u64::from_le_bytes(bytes.get(at..at + 8)?.try_into().ok()?))
}

/// The byte ranges of the meshes in `bytes`, from the table at its end, and the version.
fn mesh_ranges(bytes: &[u8]) -> Result<(u16, Vec<(usize, usize)>), String> {
    let too_short = || format!("{} bytes is too short for a serialized mesh file", bytes.len());
    if u16_at(bytes, 0) != Some(FORMAT_TAG) {
        return Err(format!(
            "expected the serialized format tag 0x041C at the start, found {}",
            u16_at(bytes, 0).map_or_else(|| "the end of the file".to_string(), |t| format!("{t:#06x}"))
        ));
    }
    let version = u16_at(bytes, 2).ok_or_else(too_short)?;
    if !(version == 3 || version == 4) {
        return Err(format!("expected version 3 or 4, found {version}"));
    }
    let count = u32_at(bytes, bytes.len().checked_sub(4).ok_or_else(too_short)?).ok_or_else(too_short)? as usize;
    let entry = if version == 4 { 8 } else { 4 };
    let table = count
        .checked_mul(entry)
        .and_then(|t| bytes.len().checked_sub(4 + t))
        .filter(|_| count > 0)
        .ok_or_else(|| format!("the table at the end lists {count} meshes, which do not fit in the file"))?;
    let mut starts = Vec::with_capacity(count);
    for i in 0..count {
        let at = table + i * entry;
        let offset = if version == 4 {
            u64_at(bytes, at).ok_or_else(too_short)?
        } else {
            u64::from(u32_at(bytes, at).ok_or_else(too_short)?)
        };
        let offset = usize::try_from(offset).unwrap_or(usize::MAX);
        if offset.checked_add(4).is_none_or(|e| e > table) || starts.last().is_some_and(|s| offset <= *s) {
            return Err(format!(
                "mesh {i} starts at byte {offset}, outside the meshes or out of order"
            ));
        }
        starts.push(offset);
    }
    let ends = starts.iter().skip(1).copied().chain([table]);
    Ok((version, starts.iter().copied().zip(ends).collect()))
}

/// Reads the decompressed fields of one mesh.
struct Fields<R: Read> {
    inner: R,
}

impl<R: Read> Fields<R> {
    fn bytes<const N: usize>(&mut self, what: &str) -> Result<[u8; N], String> {
        let mut b = [0u8; N];
        self.inner
            .read_exact(&mut b)
            .map_err(|e| format!("the compressed data ends inside the {what} ({e})"))?;
        Ok(b)
    }

    fn u32(&mut self, what: &str) -> Result<u32, String> {
        Ok(u32::from_le_bytes(self.bytes(what)?))
    }

    fn u64(&mut self, what: &str) -> Result<u64, String> {
        Ok(u64::from_le_bytes(self.bytes(what)?))
    }

    fn real(&mut self, double: bool, what: &str) -> Result<f32, String> {
        Ok(if double {
            f64::from_le_bytes(self.bytes(what)?) as f32
        } else {
            f32::from_le_bytes(self.bytes(what)?)
        })
    }

    fn vec3s(&mut self, n: usize, double: bool, what: &str) -> Result<Vec<Vec3>, String> {
        (0..n)
            .map(|_| {
                Ok(Vec3::new(
                    self.real(double, what)?,
                    self.real(double, what)?,
                    self.real(double, what)?,
                ))
            })
            .collect()
    }
}

/// Mesh `shape_index` of the serialized file `bytes`, refused before its arrays are read
/// when their size (`crate::limits::mesh_bytes`) passes `max_bytes`.
///
/// # Errors
/// A message saying what is malformed (without the file name, which the caller adds).
pub fn read_serialized(bytes: &[u8], shape_index: u32, max_bytes: u64) -> Result<SerializedMesh, String> {
    let (version, ranges) = mesh_ranges(bytes)?;
    let &(start, end) = ranges
        .get(shape_index as usize)
        .ok_or_else(|| format!("shape_index {shape_index}, but the file holds {} meshes", ranges.len()))?;
    if u16_at(bytes, start) != Some(FORMAT_TAG) || u16_at(bytes, start + 2) != Some(version) {
        return Err(format!(
            "mesh {shape_index} does not start with the format tag and version"
        ));
    }
    let mut f = Fields {
        inner: flate2::read::ZlibDecoder::new(&bytes[start + 4..end]),
    };
    let flags = f.u32("flags")?;
    let double = flags & DOUBLE_PRECISION != 0;
    if double && flags & SINGLE_PRECISION != 0 {
        return Err("the flags ask for both single and double precision".to_string());
    }
    let mut name = Vec::new();
    if version == 4 {
        loop {
            match f.bytes::<1>("name")? {
                [0] => break,
                [c] if name.len() < 4096 => name.push(c),
                _ => return Err("the mesh name is not NUL-terminated within 4096 bytes".to_string()),
            }
        }
    }
    let vertices = f.u64("vertex count")?;
    let triangles = f.u64("triangle count")?;
    if vertices > u64::from(u32::MAX) {
        return Err(format!("{vertices} vertices; at most 2^32 - 1 are supported"));
    }
    let need = mesh_bytes(vertices, triangles);
    if need > max_bytes {
        return Err(format!(
            "{vertices} vertices and {triangles} triangles need about {}, past the memory limit of {}",
            format_bytes(need),
            format_bytes(max_bytes)
        ));
    }
    let (n, t) = (vertices as usize, triangles as usize);
    let positions = f.vec3s(n, double, "positions")?;
    let normals = if flags & HAS_NORMALS != 0 {
        Some(f.vec3s(n, double, "normals")?)
    } else {
        None
    };
    let uvs = if flags & HAS_UVS != 0 {
        let uv: Result<Vec<Vec2>, String> = (0..n)
            .map(|_| Ok(Vec2::new(f.real(double, "uvs")?, f.real(double, "uvs")?)))
            .collect();
        Some(uv?)
    } else {
        None
    };
    if flags & HAS_COLORS != 0 {
        // Vertex colours are read past (the mesh_attribute texture does not read them here).
        f.vec3s(n, double, "colours")?;
    }
    let mut indices = Vec::with_capacity(3 * t);
    for _ in 0..3 * t {
        // (u64 indices only with more than 2^32 vertices, refused above.)
        let i = u64::from(f.u32("indices")?);
        if i >= vertices {
            return Err(format!("index {i} is out of range for {vertices} vertices"));
        }
        indices.push(i as u32);
    }
    Ok(SerializedMesh {
        mesh: TriangleMeshDesc {
            positions,
            indices,
            normals: if flags & FACE_NORMALS != 0 { None } else { normals },
            uvs,
            tangents: None,
        },
        name: String::from_utf8_lossy(&name).into_owned(),
    })
}

/// A serialized file holding `meshes` (version 4, single precision): the writer the tests
/// and the fuzz seeds use.
#[must_use]
pub fn write_serialized(meshes: &[(&str, &TriangleMeshDesc)]) -> Vec<u8> {
    use std::io::Write;
    let mut out = Vec::new();
    let mut offsets = Vec::new();
    for (name, m) in meshes {
        offsets.push(out.len() as u64);
        out.extend_from_slice(&FORMAT_TAG.to_le_bytes());
        out.extend_from_slice(&4u16.to_le_bytes());
        let mut body = Vec::new();
        let flags = SINGLE_PRECISION
            | if m.normals.is_some() { HAS_NORMALS } else { 0 }
            | if m.uvs.is_some() { HAS_UVS } else { 0 };
        body.extend_from_slice(&flags.to_le_bytes());
        body.extend_from_slice(name.as_bytes());
        body.push(0);
        body.extend_from_slice(&(m.positions.len() as u64).to_le_bytes());
        body.extend_from_slice(&(m.indices.len() as u64 / 3).to_le_bytes());
        let reals = m
            .positions
            .iter()
            .flat_map(|p| p.to_array())
            .chain(m.normals.iter().flatten().flat_map(|n| n.to_array()))
            .chain(m.uvs.iter().flatten().flat_map(|uv| uv.to_array()));
        for r in reals {
            body.extend_from_slice(&r.to_le_bytes());
        }
        for i in &m.indices {
            body.extend_from_slice(&i.to_le_bytes());
        }
        let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
        z.write_all(&body).expect("writing to memory");
        out.extend_from_slice(&z.finish().expect("writing to memory"));
    }
    for o in &offsets {
        out.extend_from_slice(&o.to_le_bytes());
    }
    out.extend_from_slice(&(meshes.len() as u32).to_le_bytes());
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad(z: f32) -> TriangleMeshDesc {
        TriangleMeshDesc {
            positions: vec![
                Vec3::new(0.0, 0.0, z),
                Vec3::new(1.0, 0.0, z),
                Vec3::new(1.0, 1.0, z),
                Vec3::new(0.0, 1.0, z),
            ],
            indices: vec![0, 1, 2, 0, 2, 3],
            normals: Some(vec![Vec3::Z; 4]),
            uvs: Some(vec![Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y]),
            tangents: None,
        }
    }

    #[test]
    fn meshes_round_trip_by_index() {
        let (a, mut b) = (quad(0.0), quad(2.0));
        b.normals = None;
        let file = write_serialized(&[("a", &a), ("second", &b)]);
        let m = read_serialized(&file, 1, u64::MAX).unwrap();
        assert_eq!((m.name.as_str(), &m.mesh), ("second", &b));
        assert_eq!(read_serialized(&file, 0, u64::MAX).unwrap().mesh, a);
        let e = read_serialized(&file, 2, u64::MAX).unwrap_err();
        assert!(e.contains("shape_index 2, but the file holds 2 meshes"), "{e}");
    }

    #[test]
    fn malformed_files_are_errors() {
        let file = write_serialized(&[("a", &quad(0.0))]);
        let limit = read_serialized(&file, 0, 10).unwrap_err();
        assert!(limit.contains("past the memory limit"), "{limit}");
        assert!(read_serialized(&[], 0, u64::MAX).unwrap_err().contains("format tag"));
        assert!(read_serialized(&file[..20], 0, u64::MAX).is_err());
        // A count in the table larger than the file.
        let mut bad = file.clone();
        let n = bad.len();
        bad[n - 4..].copy_from_slice(&1000u32.to_le_bytes());
        assert!(read_serialized(&bad, 0, u64::MAX).unwrap_err().contains("do not fit"));
        // Every truncation and every single-byte change is an error or a mesh, never a panic.
        for cut in 0..file.len() {
            let _ = read_serialized(&file[..cut], 0, 1 << 20);
        }
        for at in 0..file.len() {
            let mut f = file.clone();
            f[at] ^= 0x5a;
            let _ = read_serialized(&f, 0, 1 << 20);
        }
    }
}
