//! Fixtures shared by the materials' unit tests.

use super::MaterialDesc;
use crate::bsdf::Bxdf;
use crate::math::{Vec2, Vec3};
use crate::shape::{Interaction, SurfaceInteraction};
use crate::texture::{ScaleTexture, Texture, TextureContext, TextureValue};

/// A hit at the origin on the plane z = 0, seen from above.
pub fn hit() -> SurfaceInteraction {
    SurfaceInteraction {
        intr: Interaction {
            p: Vec3::ZERO,
            p_error: Vec3::ZERO,
            n: Vec3::Z,
        },
        ns: Vec3::Z,
        dpdu: Vec3::X,
        dp_du: Vec3::X,
        dp_dv: Vec3::Y,
        uv: Vec2::splat(0.5),
        wo: Vec3::Z,
        t: 1.0,
        mesh: crate::shape::MeshPoint::default(),
        unmapped_ns: None,
        bitangent_sign: 1.0,
    }
}

/// The lobe `m` gives at [`hit`].
pub fn bxdf(m: &MaterialDesc) -> Bxdf {
    let si = hit();
    *m.bsdf(&si, &TextureContext::at_point(&si)).unwrap().bxdf()
}

/// A texture that is not a constant (so `is_textured` sees it) evaluating to `v * s`.
pub fn scaled<T: TextureValue>(v: T, s: f32) -> Texture<T> {
    Texture::Scale(std::sync::Arc::new(ScaleTexture {
        tex: v.into(),
        scale: s.into(),
    }))
}
