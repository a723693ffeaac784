//! Buffers and accessors of a glTF file, read with every range checked: the `gltf`
//! crate's own readers assume valid offsets and may panic (or wrap around) on hostile
//! input, so mcrender decodes the accessors it needs itself. Errors name the JSON path of
//! what was read (`meshes[0].primitives[1].indices`).

use std::path::Path;

use gltf::accessor::{DataType, Dimensions};

/// The bytes of every buffer, by index.
pub struct Buffers(pub Vec<gltf::buffer::Data>);

impl Buffers {
    /// Read every buffer of `doc` (`.bin` files beside the scene, data URIs, or the GLB's
    /// binary chunk `blob`).
    ///
    /// # Errors
    /// `buffers[i]: ...` when a buffer cannot be read or is shorter than its `byteLength`.
    pub fn load(doc: &gltf::Document, dir: &Path, mut blob: Option<Vec<u8>>) -> Result<Self, String> {
        let mut out = Vec::new();
        for b in doc.buffers() {
            let path = format!("buffers[{}]", b.index());
            let data = gltf::buffer::Data::from_source_and_blob(b.source(), Some(dir), &mut blob).map_err(|e| {
                let what = match b.source() {
                    gltf::buffer::Source::Uri(u) if !u.starts_with("data:") => {
                        format!(
                            "cannot read \"{}\": {}",
                            crate::error::escape_control(u),
                            error_text(&e)
                        )
                    }
                    _ => format!("cannot read the buffer: {}", error_text(&e)),
                };
                format!("{path}.uri: {what}")
            })?;
            if data.len() < b.length() {
                return Err(format!(
                    "{path}.byteLength: {} bytes expected, the data has {}",
                    b.length(),
                    data.len()
                ));
            }
            out.push(data);
        }
        Ok(Self(out))
    }

    /// The bytes of buffer view `view`, checked against its buffer.
    ///
    /// # Errors
    /// `bufferViews[i]: ...` when the view reaches past the end of its buffer.
    pub fn view<'s>(&'s self, view: &gltf::buffer::View<'_>) -> Result<&'s [u8], String> {
        let data = &self.0[view.buffer().index()].0;
        view.offset()
            .checked_add(view.length())
            .and_then(|end| data.get(view.offset()..end))
            .ok_or_else(|| {
                format!(
                    "bufferViews[{}]: bytes {}..+{} are outside buffer {} ({} bytes)",
                    view.index(),
                    view.offset(),
                    view.length(),
                    view.buffer().index(),
                    data.len()
                )
            })
    }
}

/// The text of a `gltf` error, without Rust's ` (os error N)`.
pub fn error_text(e: &gltf::Error) -> String {
    match e {
        gltf::Error::Io(io) => crate::error::io_error_text(io),
        other => other.to_string(),
    }
}

fn components(d: Dimensions) -> usize {
    match d {
        Dimensions::Scalar => 1,
        Dimensions::Vec2 => 2,
        Dimensions::Vec3 => 3,
        Dimensions::Vec4 | Dimensions::Mat2 => 4,
        Dimensions::Mat3 => 9,
        Dimensions::Mat4 => 16,
    }
}

fn size_of(t: DataType) -> usize {
    match t {
        DataType::I8 | DataType::U8 => 1,
        DataType::I16 | DataType::U16 => 2,
        DataType::U32 | DataType::F32 => 4,
    }
}

/// Read accessor `a` as `n` components per element, converted to `f64` (normalised
/// integers mapped to [0, 1] or [-1, 1] as the spec defines; plain integers as they are).
/// `path` is where the accessor is used, for errors.
///
/// # Errors
/// When the accessor has another number of components, is sparse or has no buffer view,
/// or reaches outside its buffer view.
pub fn read(buffers: &Buffers, a: &gltf::Accessor<'_>, n: usize, path: &str) -> Result<Vec<f64>, String> {
    let what = format!("{path} (accessors[{}])", a.index());
    if a.sparse().is_some() {
        return Err(format!("{what}: sparse accessors are not supported"));
    }
    if components(a.dimensions()) != n {
        return Err(format!(
            "{what}: expected {n} components per element, found {:?}",
            a.dimensions()
        ));
    }
    let Some(view) = a.view() else {
        return Err(format!("{what}: an accessor without bufferView is not supported"));
    };
    let bytes = buffers.view(&view)?;
    let size = size_of(a.data_type());
    let element = size * n;
    let stride = view.stride().unwrap_or(element);
    if stride < element {
        return Err(format!(
            "{what}: byteStride {stride} is smaller than an element ({element} bytes)"
        ));
    }
    let count = a.count();
    if count == 0 {
        return Ok(Vec::new());
    }
    let end = (count - 1)
        .checked_mul(stride)
        .and_then(|v| v.checked_add(a.offset()))
        .and_then(|v| v.checked_add(element));
    if end.is_none_or(|e| e > bytes.len()) {
        return Err(format!(
            "{what}: {count} elements from byte {} reach past the end of bufferViews[{}] ({} bytes)",
            a.offset(),
            view.index(),
            bytes.len()
        ));
    }
    let mut out = Vec::with_capacity(count * n);
    for i in 0..count {
        let base = a.offset() + i * stride;
        for c in 0..n {
            let o = base + c * size;
            let b = &bytes[o..o + size];
            let v = match a.data_type() {
                DataType::F32 => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
                DataType::U32 => f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
                DataType::U16 => {
                    let v = f64::from(u16::from_le_bytes([b[0], b[1]]));
                    if a.normalized() {
                        v / 65535.0
                    } else {
                        v
                    }
                }
                DataType::I16 => {
                    let v = f64::from(i16::from_le_bytes([b[0], b[1]]));
                    if a.normalized() {
                        (v / 32767.0).max(-1.0)
                    } else {
                        v
                    }
                }
                DataType::U8 => {
                    let v = f64::from(b[0]);
                    if a.normalized() {
                        v / 255.0
                    } else {
                        v
                    }
                }
                DataType::I8 => {
                    let v = f64::from(b[0] as i8);
                    if a.normalized() {
                        (v / 127.0).max(-1.0)
                    } else {
                        v
                    }
                }
            };
            out.push(v);
        }
    }
    Ok(out)
}

/// Read accessor `a` as vertex indices below `vertices`.
///
/// # Errors
/// As [`read`], and when an index is not an unsigned integer below `vertices`.
pub fn read_indices(
    buffers: &Buffers,
    a: &gltf::Accessor<'_>,
    vertices: usize,
    path: &str,
) -> Result<Vec<u32>, String> {
    if !matches!(a.data_type(), DataType::U8 | DataType::U16 | DataType::U32) || a.normalized() {
        return Err(format!(
            "{path} (accessors[{}]): indices must be unsigned bytes, shorts or ints",
            a.index()
        ));
    }
    let values = read(buffers, a, 1, path)?;
    values
        .iter()
        .map(|&v| {
            if v < vertices as f64 {
                Ok(v as u32)
            } else {
                Err(format!(
                    "{path} (accessors[{}]): index {v} is out of range ({vertices} vertices)",
                    a.index()
                ))
            }
        })
        .collect()
}
