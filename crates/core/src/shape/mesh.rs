//! Triangle and bilinear patch meshes in world space, shared by the primitives that index
//! into them.

use crate::math::{Vec2, Vec3, Vec4};

/// Vertex arrays of a mesh, already transformed to world space.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleMesh {
    /// Positions.
    pub positions: Vec<Vec3>,
    /// Three vertex indices per triangle.
    pub indices: Vec<u32>,
    /// Optional unit shading normals per vertex.
    pub normals: Option<Vec<Vec3>>,
    /// Optional texture coordinates per vertex.
    pub uvs: Option<Vec<Vec2>>,
    /// Optional shading tangents per vertex with the bitangent's handedness in `w`
    /// (glTF's `TANGENT`); used only with shading normals.
    pub tangents: Option<Vec<Vec4>>,
    /// Flip the geometric normal when there are no shading normals (pbrt's
    /// `ReverseOrientation` xor "transform swaps handedness").
    pub flip_normals: bool,
}

impl TriangleMesh {
    /// Number of triangles.
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Vertex indices of triangle `i`.
    #[inline]
    #[must_use]
    pub fn vertices(&self, i: u32) -> [usize; 3] {
        let k = 3 * i as usize;
        [
            self.indices[k] as usize,
            self.indices[k + 1] as usize,
            self.indices[k + 2] as usize,
        ]
    }
}

/// Vertex arrays of a bilinear patch mesh (pbrt-v4 `bilinearmesh`), in world space.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BilinearMesh {
    /// Positions.
    pub positions: Vec<Vec3>,
    /// Four vertex indices per patch, in pbrt-v4's order `p00, p10, p01, p11`: the patch
    /// is `p(u, v) = lerp(u, lerp(v, p00, p01), lerp(v, p10, p11))`.
    pub indices: Vec<u32>,
    /// Optional unit shading normals per vertex.
    pub normals: Option<Vec<Vec3>>,
    /// Optional texture coordinates per vertex.
    pub uvs: Option<Vec<Vec2>>,
    /// Flip the geometric normal `dp/du x dp/dv` when there are no shading normals (pbrt's
    /// `ReverseOrientation` xor "transform swaps handedness").
    pub flip_normals: bool,
}

impl BilinearMesh {
    /// Number of patches.
    #[must_use]
    pub fn patch_count(&self) -> usize {
        self.indices.len() / 4
    }

    /// Vertex indices `[i00, i10, i01, i11]` of patch `i`.
    #[inline]
    #[must_use]
    pub fn vertices(&self, i: u32) -> [usize; 4] {
        let k = 4 * i as usize;
        [0, 1, 2, 3].map(|j| self.indices[k + j] as usize)
    }
}
