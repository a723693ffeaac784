//! `KHR_lights_punctual` to mcrender's lights. The extension gives point and spot
//! intensities in candela (lm/sr) and directional illuminance in lux (lm/m^2);
//! mcrender's lights are radiometric (W/sr, W/m^2 per RGB channel). They are converted
//! with the luminous efficacy that defines the candela, 683 lm/W (at 555 nm):
//! `I = colour * intensity / 683`, `E = colour * lux / 683`. A light's `range` (a cut-off
//! for real-time renderers) is ignored with a warning: light falls off by the inverse
//! square law only.

use gltf::khr_lights_punctual::Kind;
use mcrender_core::color::Rgb;
use mcrender_core::math::{Mat4, Transform, Vec3};
use mcrender_core::scene::{LightDesc, SpotFalloff, SpotLightDesc};

/// Lumens per watt: the photometric-to-radiometric conversion (see the module docs).
pub const LUMENS_PER_WATT: f32 = 683.0;

/// The light `l` of a node with world-from-node matrix `m`.
///
/// # Errors
/// `extensions.KHR_lights_punctual.lights[i]: ...` for a non-finite or negative intensity
/// or a singular node transform.
pub fn light(
    l: &gltf::khr_lights_punctual::Light<'_>,
    m: Mat4,
    warnings: &mut Vec<String>,
) -> Result<LightDesc, String> {
    let path = format!("extensions.KHR_lights_punctual.lights[{}]", l.index());
    if !(l.intensity() >= 0.0 && l.intensity().is_finite()) {
        return Err(format!(
            "{path}.intensity: expected a finite value >= 0, found {}",
            l.intensity()
        ));
    }
    if l.range().is_some() {
        warnings.push(format!("{path}.range is ignored (inverse-square falloff only)"));
    }
    let [r, g, b] = l.color();
    let value = Rgb::new(r, g, b).map(|v| v.max(0.0)) * (l.intensity() / LUMENS_PER_WATT);
    let position = m.transform_point3(Vec3::ZERO);
    Ok(match l.kind() {
        Kind::Point => LightDesc::Point {
            position,
            intensity: value,
        },
        Kind::Directional => {
            // The light shines along the node's -z; the description wants the direction
            // towards the light.
            let direction = m
                .transform_vector3(Vec3::Z)
                .try_normalize()
                .ok_or_else(|| format!("{path}: the node's transform is singular"))?;
            LightDesc::Distant {
                direction,
                radiance: value,
            }
        }
        Kind::Spot {
            inner_cone_angle,
            outer_cone_angle,
        } => {
            // mcrender's spot points along light-space +z; glTF's along node -z: turn
            // the node half a turn about x.
            let world_from_light = Transform::new(m * Mat4::from_scale(Vec3::new(1.0, -1.0, -1.0)))
                .ok_or_else(|| format!("{path}: the node's transform is singular"))?;
            let outer = outer_cone_angle.clamp(0.0, std::f32::consts::FRAC_PI_2);
            let inner = inner_cone_angle.clamp(0.0, outer);
            LightDesc::Spot(SpotLightDesc {
                world_from_light,
                intensity: value,
                cos_falloff_start: inner.cos(),
                cos_falloff_end: outer.cos(),
                falloff: SpotFalloff::SmoothCosine,
                projection: None,
            })
        }
    })
}
