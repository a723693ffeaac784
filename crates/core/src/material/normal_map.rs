//! Mitsuba 3's `normalmap`: another material with its shading normal replaced by a
//! normal map.

use super::checks::{check_reference, InvalidParameter};
use super::MaterialId;
use crate::math::{Frame, Vec3};
use crate::shape::SurfaceInteraction;
use crate::texture::{RgbTexture, TextureContext};

/// Another material with its shading normal replaced by a normal map (Mitsuba 3's
/// `normalmap`): the map's RGB `c` gives the normal `normalize(2 c - 1)` in the shading
/// frame of the surface (x along the tangent, z the shading normal), and the old tangent
/// projected on the new tangent plane is the new tangent. Applied where rays hit the
/// surface (`Scene::intersect`), so integrators see the perturbed normal (their cosine is
/// taken with it, as Mitsuba's BSDFs take theirs in the perturbed frame).
#[derive(Clone, Debug, PartialEq)]
pub struct NormalMapMaterial {
    /// The material shaded with the new frame (no cycles through normal maps).
    pub material: MaterialId,
    /// Linear RGB in [0, 1] per texel (a `raw` texture).
    pub normal_map: RgbTexture,
}

impl NormalMapMaterial {
    /// Check the parameters of material `index` among `count` materials.
    pub fn validate(&self, index: usize, count: usize) -> Result<(), InvalidParameter> {
        check_reference(index, "normal-maps", self.material, count)
    }

    /// Move the shading frame of `si` to the map's normal; a map pointing below the
    /// geometric surface leaves the frame unchanged.
    pub fn apply(&self, si: &mut SurfaceInteraction) {
        let c = self.normal_map.evaluate(&TextureContext::at_point(si));
        let frame = Frame::from_zx(si.ns, si.dpdu);
        let Some(n_local) = Vec3::new(2.0 * c.r - 1.0, 2.0 * c.g - 1.0, 2.0 * c.b - 1.0).try_normalize() else {
            return;
        };
        // The old tangent projected onto the new tangent plane.
        let s_local = (Vec3::X - n_local * n_local.x)
            .try_normalize()
            .unwrap_or_else(|| Frame::from_z(n_local).x);
        let ns = frame.from_local(n_local).normalize();
        let dpdu = frame.from_local(s_local).normalize();
        // Keep the shading normal on the side of the geometric one.
        if ns.dot(si.n()) * si.ns.dot(si.n()) > 0.0 {
            si.ns = ns;
            si.dpdu = dpdu;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_support::hit;
    use super::super::{DiffuseMaterial, MaterialDesc};
    use super::*;
    use crate::color::Rgb;

    #[test]
    fn normal_maps_move_the_shading_frame_in_its_own_coordinates() {
        let inner = MaterialDesc::Diffuse(DiffuseMaterial {
            reflectance: Rgb::splat(0.5).into(),
        });
        assert_eq!(inner.apply_frame(&mut hit(), &TextureContext::default()), None);
        // A tilted surface, so that local and world coordinates differ.
        let mut si = hit();
        si.ns = Vec3::new(0.0, 0.6, 0.8);
        si.intr.n = si.ns;
        si.dpdu = Vec3::X;
        let map = |c: Rgb| {
            MaterialDesc::NormalMap(NormalMapMaterial {
                material: 3,
                normal_map: c.into(),
            })
        };
        // The identity map leaves the frame as it is.
        let mut s = si;
        assert_eq!(
            map(Rgb::new(0.5, 0.5, 1.0)).apply_frame(&mut s, &TextureContext::default()),
            Some(3)
        );
        assert!((s.ns - si.ns).length() < 1e-6 && (s.dpdu - si.dpdu).length() < 1e-6);
        // Tilt 45 degrees towards the tangent: local normal (1, 0, 1) / sqrt 2.
        let c = 0.5 + 0.5 * std::f32::consts::FRAC_1_SQRT_2;
        let mut s = si;
        assert_eq!(
            map(Rgb::new(c, 0.5, c)).apply_frame(&mut s, &TextureContext::default()),
            Some(3)
        );
        let expected = (Vec3::X + si.ns).normalize();
        assert!((s.ns - expected).length() < 1e-3, "{}", s.ns);
        assert!(s.dpdu.dot(s.ns).abs() < 1e-5 && s.dpdu.dot(Vec3::X) > 0.5, "{}", s.dpdu);
        // A map pointing below the geometric surface is ignored.
        let mut s = si;
        assert_eq!(
            map(Rgb::new(0.5, 0.5, 0.0)).apply_frame(&mut s, &TextureContext::default()),
            Some(3)
        );
        assert_eq!(s.ns, si.ns);
    }
}
