//! Mitsuba 3's `normalmap` (and pbrt-v4's `normalmap` parameter): another material with
//! its shading normal replaced by a normal map.

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
    /// Whose rules beyond the frame apply.
    pub style: MapStyle,
}

/// Whose rules a normal or bump map follows beyond moving the shading frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MapStyle {
    /// pbrt-v4's (and glTF's): the frame only.
    #[default]
    Pbrt,
    /// Mitsuba 3.9's, measured through its Python API (its BSDF values for a tilted map,
    /// fitted exactly): where the incoming ray sees the mapped normal from below, the
    /// normal is mirrored about the surface's own (`(x, y, z)` to `(-x, -y, z)` in the
    /// shading frame); and the light side of the BSDF is shadowed by the tilt
    /// ([`crate::bsdf::BumpShadowing`], recorded as `SurfaceInteraction::unmapped_ns`).
    Mitsuba,
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
        // The green channel runs along the bitangent `bitangent_sign * (ns x dpdu)`; the
        // frame's y is `ns x dpdu`.
        let green = si.bitangent_sign * (2.0 * c.g - 1.0);
        let Some(mut n_local) = Vec3::new(2.0 * c.r - 1.0, green, 2.0 * c.b - 1.0).try_normalize() else {
            return;
        };
        if self.style == MapStyle::Mitsuba && frame.from_local(n_local).dot(si.wo) < 0.0 {
            n_local = Vec3::new(-n_local.x, -n_local.y, n_local.z);
        }
        // The old tangent projected onto the new tangent plane.
        let s_local = (Vec3::X - n_local * n_local.x)
            .try_normalize()
            .unwrap_or_else(|| Frame::from_z(n_local).x);
        let ns = frame.from_local(n_local).normalize();
        let dpdu = frame.from_local(s_local).normalize();
        // Keep the shading normal on the side of the geometric one.
        if ns.dot(si.n()) * si.ns.dot(si.n()) > 0.0 {
            if self.style == MapStyle::Mitsuba {
                si.unmapped_ns = Some(si.ns);
            }
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
                style: MapStyle::Pbrt,
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

    /// Mitsuba's style mirrors the mapped normal when the incoming ray sees it from below,
    /// and records the normal before the map for the bump-terminator shadowing; pbrt's
    /// does neither.
    #[test]
    fn mitsuba_maps_face_the_viewer_and_record_the_normal_they_moved() {
        let tilt = Rgb::new(0.8, 0.5, 0.8); // local normal (1, 0, 1) / sqrt 2
        let map = |style| NormalMapMaterial {
            material: 0,
            normal_map: tilt.into(),
            style,
        };
        let h = std::f32::consts::FRAC_1_SQRT_2;
        let mut base = hit();
        base.ns = Vec3::Z;
        base.intr.n = Vec3::Z;
        base.dpdu = Vec3::X;
        for (wo, mirrored) in [(Vec3::new(0.9, 0.0, 0.436), false), (Vec3::new(-0.9, 0.0, 0.436), true)] {
            let mut si = base;
            si.wo = wo.normalize();
            map(MapStyle::Mitsuba).apply(&mut si);
            let x = if mirrored { -h } else { h };
            assert!((si.ns - Vec3::new(x, 0.0, h)).length() < 1e-5, "{wo}: {}", si.ns);
            assert!(si.ns.dot(si.wo) > 0.0);
            assert_eq!(si.unmapped_ns, Some(Vec3::Z));
            let mut si = base;
            si.wo = wo.normalize();
            map(MapStyle::Pbrt).apply(&mut si);
            assert!((si.ns - Vec3::new(h, 0.0, h)).length() < 1e-5, "{wo}: {}", si.ns);
            assert_eq!(si.unmapped_ns, None);
        }
    }

    /// The green channel runs along the bitangent, `bitangent_sign * (ns x dpdu)`: a map
    /// tilted towards +green tilts the normal to +y, or to -y where the mesh's tangents
    /// say the bitangent is mirrored (glTF's `TANGENT.w = -1`).
    #[test]
    fn the_green_channel_follows_the_bitangent_sign() {
        let c = 0.5 + 0.5 * std::f32::consts::FRAC_1_SQRT_2;
        let map = NormalMapMaterial {
            material: 0,
            normal_map: Rgb::new(0.5, c, c).into(),
            style: MapStyle::Pbrt,
        };
        let h = std::f32::consts::FRAC_1_SQRT_2;
        for sign in [1.0, -1.0] {
            let mut si = hit();
            si.bitangent_sign = sign;
            map.apply(&mut si);
            assert!(
                (si.ns - Vec3::new(0.0, sign * h, h)).length() < 1e-5,
                "{sign}: {}",
                si.ns
            );
            assert!((si.dpdu - Vec3::X).length() < 1e-5, "{sign}: {}", si.dpdu);
        }
    }
}
