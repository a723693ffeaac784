//! Mitsuba's `mesh_attribute` texture: values stored with one triangle mesh, per vertex
//! (interpolated with the hit's barycentrics, as Mitsuba's `Mesh::eval_attribute`) or per
//! face (constant over each triangle), times a scale. The texture is bound to its mesh's
//! triangle order and vertex indices, so a loader makes one per mesh that uses it; a hit on
//! any other shape reads triangle 0 of whatever [`crate::shape::MeshPoint`] it carries, so
//! only the bound mesh should use it.

use std::sync::Arc;

use super::TextureContext;
use crate::color::Rgb;

/// Where the values of a [`MeshAttributeTexture`] live.
#[derive(Clone, Debug, PartialEq)]
pub enum AttributeRate {
    /// One value per vertex; `indices` are the mesh's, three per triangle.
    Vertex {
        /// The mesh's vertex indices.
        indices: Arc<Vec<u32>>,
    },
    /// One value per triangle.
    Face,
}

/// Values attached to the vertices or triangles of one mesh (a single-channel attribute
/// has the same value in all three channels).
#[derive(Clone, Debug, PartialEq)]
pub struct MeshAttributeTexture {
    /// One value per vertex or per triangle.
    pub values: Arc<Vec<Rgb>>,
    /// Per vertex or per face.
    pub rate: AttributeRate,
    /// Factor applied to the value (Mitsuba's `scale`).
    pub scale: f32,
}

impl MeshAttributeTexture {
    /// The value at `ctx`: the barycentric blend of the triangle's three vertex values, or
    /// the triangle's value; black where the triangle or a vertex is out of range.
    #[must_use]
    pub fn evaluate_rgb(&self, ctx: &TextureContext) -> Rgb {
        let t = ctx.mesh.triangle as usize;
        let value = |i: usize| self.values.get(i).copied().unwrap_or(Rgb::BLACK);
        let v = match &self.rate {
            AttributeRate::Face => value(t),
            AttributeRate::Vertex { indices } => {
                let mut sum = Rgb::BLACK;
                for (k, b) in ctx.mesh.b.iter().enumerate() {
                    if let Some(&i) = indices.get(3 * t + k) {
                        sum += value(i as usize) * *b;
                    }
                }
                sum
            }
        };
        v * self.scale
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shape::MeshPoint;

    fn ctx(triangle: u32, b: [f32; 3]) -> TextureContext {
        TextureContext {
            mesh: MeshPoint { triangle, b },
            ..TextureContext::default()
        }
    }

    #[test]
    fn vertex_values_interpolate_with_the_barycentrics() {
        // Two triangles sharing vertices 1 and 2; the second lists them in another order.
        let t = MeshAttributeTexture {
            values: Arc::new(vec![
                Rgb::new(1.0, 0.0, 0.0),
                Rgb::new(0.0, 1.0, 0.0),
                Rgb::new(0.0, 0.0, 1.0),
                Rgb::splat(2.0),
            ]),
            rate: AttributeRate::Vertex {
                indices: Arc::new(vec![0, 1, 2, 2, 1, 3]),
            },
            scale: 2.0,
        };
        assert_eq!(t.evaluate_rgb(&ctx(0, [1.0, 0.0, 0.0])), Rgb::new(2.0, 0.0, 0.0));
        let mid = t.evaluate_rgb(&ctx(0, [0.5, 0.25, 0.25]));
        assert!((0..3).all(|c| (mid[c] - [1.0, 0.5, 0.5][c]).abs() < 1e-6), "{mid:?}");
        // Triangle 1's first vertex is vertex 2.
        assert_eq!(t.evaluate_rgb(&ctx(1, [1.0, 0.0, 0.0])), Rgb::new(0.0, 0.0, 2.0));
        assert_eq!(t.evaluate_rgb(&ctx(1, [0.0, 0.0, 1.0])), Rgb::splat(4.0));
        // Out of range: black, no panic.
        assert_eq!(t.evaluate_rgb(&ctx(7, [1.0, 0.0, 0.0])), Rgb::BLACK);
    }

    #[test]
    fn face_values_are_constant_per_triangle() {
        let t = MeshAttributeTexture {
            values: Arc::new(vec![Rgb::splat(0.25), Rgb::splat(0.75)]),
            rate: AttributeRate::Face,
            scale: 1.0,
        };
        assert_eq!(t.evaluate_rgb(&ctx(0, [0.2, 0.3, 0.5])), Rgb::splat(0.25));
        assert_eq!(t.evaluate_rgb(&ctx(1, [0.9, 0.1, 0.0])), Rgb::splat(0.75));
        assert_eq!(
            crate::texture::Texture::<f32>::MeshAttribute(Arc::new(t)).evaluate(&ctx(1, [1.0, 0.0, 0.0])),
            0.75
        );
    }
}
