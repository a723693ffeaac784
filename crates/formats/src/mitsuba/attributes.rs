//! Mitsuba's mesh attributes: the extra vertex and face properties of a PLY file, grouped
//! as Mitsuba's `ply` plugin groups them, and the `mesh_attribute` texture that reads them.
//!
//! Grouping (Mitsuba's `ply.cpp` documentation): consecutive properties `{prefix}_x, _y,
//! _z, _w`, `_r, _g, _b, _a`, `_0 .. _3` or `_1 .. _4` form one attribute `{prefix}` of up to
//! four channels; bare `r, g, b[, a]` or `red, green, blue[, alpha]` form `color`; the
//! attribute is then named `vertex_{prefix}` or `face_{prefix}`. Any other property stands
//! alone under its own name (`vertex_{name}`), an mcrender choice. The texture renders one-
//! and three-channel attributes (a single channel in all three colour channels).
//!
//! A texture is bound to one mesh's data, but Mitsuba names the attribute and reads it from
//! whichever shape is hit. So a `<bsdf>` built outside any shape with a `mesh_attribute`
//! in it gets a black placeholder and is remembered ([`Builder::attribute_bsdfs`]); each
//! PLY shape using it builds it again with its own attributes in
//! [`Builder::mesh_attributes`].

use std::sync::Arc;

use mcrender_core::color::Rgb;
use mcrender_core::texture::{AttributeRate, MeshAttributeTexture, Texture, TextureValue};

use super::builder::Builder;
use super::props::Props;
use super::xml::Element;
use crate::error::SceneError;
use crate::ply::PlyMesh;

/// One grouped attribute: its name (without the `vertex_`/`face_` part), channels and
/// values (`channels` numbers per vertex or triangle).
#[derive(Clone, Debug, PartialEq)]
pub struct Attribute {
    /// `color`, `weight`, ...
    pub name: String,
    /// 1 to 4.
    pub channels: usize,
    /// `channels` values per element, interleaved.
    pub values: Vec<f32>,
}

/// The attributes of one mesh and its final vertex indices.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshAttributes {
    /// Per-vertex attributes.
    pub vertex: Vec<Attribute>,
    /// Per-triangle attributes.
    pub face: Vec<Attribute>,
    /// The mesh's vertex indices, three per triangle.
    pub indices: Arc<Vec<u32>>,
}

impl MeshAttributes {
    /// The attributes of `ply`; `indices` are set by the caller once the mesh is final.
    #[must_use]
    pub fn of_ply(ply: &PlyMesh) -> Self {
        Self {
            vertex: group(&ply.vertex_attributes),
            face: group(&ply.face_attributes),
            indices: Arc::new(Vec::new()),
        }
    }
}

/// Channel suffixes Mitsuba groups, each in channel order.
const SUFFIXES: [[&str; 4]; 4] = [
    ["x", "y", "z", "w"],
    ["r", "g", "b", "a"],
    ["0", "1", "2", "3"],
    ["1", "2", "3", "4"],
];
/// Bare colour names.
const BARE: [[&str; 4]; 2] = [["r", "g", "b", "a"], ["red", "green", "blue", "alpha"]];

/// Group properties (in file order) into attributes.
#[must_use]
pub fn group(props: &[(String, Vec<f32>)]) -> Vec<Attribute> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < props.len() {
        let (prefix, len) = run_at(props, i);
        let n = props[i].1.len();
        let mut values = Vec::with_capacity(n * len);
        for e in 0..n {
            for p in &props[i..i + len] {
                values.push(p.1[e]);
            }
        }
        out.push(Attribute {
            name: prefix,
            channels: len,
            values,
        });
        i += len;
    }
    out
}

/// The attribute starting at property `i`: its name and how many properties it takes.
fn run_at(props: &[(String, Vec<f32>)], i: usize) -> (String, usize) {
    let name = props[i].0.as_str();
    let longest = |names: &dyn Fn(usize) -> String| {
        (0..4)
            .take_while(|&k| props.get(i + k).is_some_and(|p| p.0 == names(k)))
            .count()
    };
    for bare in BARE {
        if name == bare[0] {
            let len = longest(&|k| bare[k].to_string());
            if len >= 3 {
                return ("color".into(), len);
            }
        }
    }
    if let Some((prefix, suffix)) = name.rsplit_once('_') {
        for set in SUFFIXES {
            if suffix == set[0] {
                let len = longest(&|k| format!("{prefix}_{}", set[k]));
                return (prefix.to_string(), len);
            }
        }
    }
    (name.to_string(), 1)
}

impl Builder {
    /// The `mesh_attribute` texture (`name`, `scale`) for the mesh in
    /// [`Self::mesh_attributes`], or a black placeholder (and a note to build the BSDF
    /// again per shape) outside a shape.
    pub fn mesh_attribute_texture<T: TextureValue>(
        &mut self,
        e: &Element,
        p: &mut Props,
    ) -> Result<Texture<T>, SceneError> {
        let (name, nloc) = p
            .string("name")?
            .ok_or_else(|| SceneError::syntax(&e.loc, "a mesh_attribute needs a \"name\""))?;
        let scale = p.float("scale", 1.0)?;
        let (per_vertex, attr) = if let Some(a) = name.strip_prefix("vertex_") {
            (true, a)
        } else if let Some(a) = name.strip_prefix("face_") {
            (false, a)
        } else {
            return Err(SceneError::invalid(
                &nloc,
                format!("mesh attribute \"{name}\" must start with \"vertex_\" or \"face_\""),
            ));
        };
        let Some(mesh) = &self.mesh_attributes else {
            self.deferred_attribute = true;
            return Ok(Texture::Constant(T::ZERO));
        };
        let list = if per_vertex { &mesh.vertex } else { &mesh.face };
        let Some(a) = list.iter().find(|a| a.name == attr) else {
            let known: Vec<String> = mesh
                .vertex
                .iter()
                .map(|a| format!("vertex_{}", a.name))
                .chain(mesh.face.iter().map(|a| format!("face_{}", a.name)))
                .collect();
            return Err(SceneError::invalid(
                &nloc,
                format!(
                    "the mesh has no attribute \"{name}\" (it has: {})",
                    if known.is_empty() {
                        "none".to_string()
                    } else {
                        known.join(", ")
                    }
                ),
            ));
        };
        let values: Vec<Rgb> = match a.channels {
            1 => a.values.iter().map(|v| Rgb::splat(*v)).collect(),
            3 => a.values.chunks_exact(3).map(|c| Rgb::new(c[0], c[1], c[2])).collect(),
            n => {
                return Err(SceneError::unsupported(
                    &nloc,
                    format!("mesh attribute \"{name}\" with {n} channels (1 or 3 are)"),
                ))
            }
        };
        let rate = if per_vertex {
            AttributeRate::Vertex {
                indices: mesh.indices.clone(),
            }
        } else {
            AttributeRate::Face
        };
        Ok(Texture::MeshAttribute(Arc::new(MeshAttributeTexture {
            values: Arc::new(values),
            rate,
            scale,
        })))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn props(names: &[&str]) -> Vec<(String, Vec<f32>)> {
        names
            .iter()
            .enumerate()
            .map(|(i, n)| (n.to_string(), vec![i as f32, 10.0 + i as f32]))
            .collect()
    }

    #[test]
    fn grouping_follows_mitsubas_names() {
        let g = group(&props(&[
            "color_0", "color_1", "color_2", "weight_0", "r", "g", "b", "alpha", "n_x", "n_y", "quality",
        ]));
        let names: Vec<(&str, usize)> = g.iter().map(|a| (a.name.as_str(), a.channels)).collect();
        assert_eq!(
            names,
            [
                ("color", 3),
                ("weight", 1),
                ("color", 3),
                ("alpha", 1),
                ("n", 2),
                ("quality", 1)
            ]
        );
        // Interleaved per element.
        assert_eq!(g[0].values, [0.0, 1.0, 2.0, 10.0, 11.0, 12.0]);
        let g = group(&props(&["red", "green", "blue", "alpha", "c_1", "c_2", "c_3", "c_4"]));
        let names: Vec<(&str, usize)> = g.iter().map(|a| (a.name.as_str(), a.channels)).collect();
        assert_eq!(names, [("color", 4), ("c", 4)]);
    }
}
