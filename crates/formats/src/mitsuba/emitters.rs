//! Emitters that are not attached to shapes: `point` (`intensity`, `position` or
//! `to_world`), `spot` (`intensity`, `cutoff_angle`, `beam_width`, `texture`, `to_world`:
//! [`SpotFalloff::LinearAngle`], Mitsuba's linear ramp in angle, and the projected texture),
//! `directional` (`irradiance`, `direction` or `to_world`'s +z), `constant` (`radiance`) and
//! `envmap` (`filename`, `scale`, `to_world`). Area emitters belong to shapes (`shapes`).
//!
//! Mitsuba's envmap is a latitude-longitude image with +y up: a direction `d` (in the
//! emitter's space) reads `u = atan2(d.x, -d.z) / 2 pi`, `v = acos(d.y) / pi`. mcrender's
//! [`EnvMapping::Equirect`] reads `phi = 2 pi u` from +x towards +y and `theta = pi v`
//! from +z, so its light space maps to Mitsuba's by `(x, y, z) -> (y, z, -x)`. The image is
//! interpolated bilinearly as Mitsuba does ([`EnvMapping::EquirectBilinear`]: columns
//! centred at `(x + 0.5) / width`, rows from pole to pole at `y / (height - 1)`).

use mcrender_core::color::Rgb;
use mcrender_core::math::{Mat4, Transform, Vec3, Vec4};
use mcrender_core::scene::{EnvMapping, ImageInfiniteLightDesc, LightDesc, RgbImageDesc, SpotFalloff, SpotLightDesc};

use super::builder::{Builder, Named};
use super::images::ImageUse;
use super::props::Props;
use super::xml::Element;
use crate::error::SceneError;
use crate::image_io::ColorEncoding;

impl Builder {
    /// A top-level `<emitter>`.
    pub fn emitter(&mut self, el: &Element) -> Result<(), SceneError> {
        let kind = el.required("type")?;
        let mut p = Props::new(el);
        let to_world = p.transform("to_world")?;
        let light = match kind {
            "point" => {
                let intensity = self.emitter_color(&mut p, "intensity")?;
                let position = match p.vec3("position")? {
                    Some(pos) => pos,
                    None => to_world.unwrap_or(Mat4::IDENTITY).transform_point3(Vec3::ZERO),
                };
                LightDesc::Point { position, intensity }
            }
            "directional" => {
                let irradiance = self.emitter_color(&mut p, "irradiance")?;
                let d = match p.vec3("direction")? {
                    Some(d) => d,
                    None => to_world.unwrap_or(Mat4::IDENTITY).transform_vector3(Vec3::Z),
                };
                let Some(d) = d.try_normalize() else {
                    return Err(SceneError::invalid(
                        &el.loc,
                        "a directional emitter needs a non-zero direction",
                    ));
                };
                LightDesc::Distant {
                    direction: -d,
                    radiance: irradiance,
                }
            }
            "constant" => LightDesc::UniformInfinite {
                radiance: self.emitter_color(&mut p, "radiance")?,
            },
            "envmap" => {
                let (file, floc) = p
                    .string("filename")?
                    .ok_or_else(|| SceneError::syntax(&el.loc, "an envmap needs a \"filename\""))?;
                let img = self.read_image_counted(
                    &file,
                    "environment map",
                    ColorEncoding::Srgb,
                    ImageUse::Environment,
                    &floc,
                )?;
                let scale = p.float("scale", 1.0)?;
                // mcrender's equirect light space -> Mitsuba's envmap space (module docs).
                let to_mitsuba = Mat4::from_cols(Vec4::new(0.0, 0.0, -1.0, 0.0), Vec4::X, Vec4::Y, Vec4::W);
                let m = to_world.unwrap_or(Mat4::IDENTITY) * to_mitsuba;
                LightDesc::ImageInfinite(ImageInfiniteLightDesc {
                    image: RgbImageDesc {
                        width: img.width,
                        height: img.height,
                        pixels: img.pixels,
                    },
                    mapping: EnvMapping::EquirectBilinear,
                    scale,
                    world_from_light: Transform::new(m)
                        .ok_or_else(|| SceneError::invalid(&el.loc, "the envmap's to_world is singular"))?,
                })
            }
            "area" => {
                return Err(SceneError::syntax(
                    &el.loc,
                    "an area emitter must be nested in the <shape> that emits",
                ))
            }
            "spot" => {
                let intensity = self.emitter_color(&mut p, "intensity")?;
                let cutoff = p.float("cutoff_angle", 20.0)?;
                let beam = p.float("beam_width", cutoff * 0.75)?;
                if !(0.0 <= beam && beam <= cutoff && cutoff < 90.0) {
                    return Err(SceneError::invalid(
                        &el.loc,
                        format!("a spot needs 0 <= beam_width <= cutoff_angle < 90 degrees, found {beam} and {cutoff}"),
                    ));
                }
                let projection = match p.get("texture") {
                    None => None,
                    Some(_) => Some(self.rgb_param(&mut p, "texture", Rgb::splat(1.0), false)?),
                };
                let world_from_light = Transform::new(to_world.unwrap_or(Mat4::IDENTITY))
                    .ok_or_else(|| SceneError::invalid(&el.loc, "the spot's to_world is singular"))?;
                LightDesc::Spot(SpotLightDesc {
                    world_from_light,
                    intensity,
                    cos_falloff_start: beam.to_radians().cos(),
                    cos_falloff_end: cutoff.to_radians().cos(),
                    falloff: SpotFalloff::LinearAngle,
                    projection,
                })
            }
            _ => {
                return Err(Self::unsupported(
                    el,
                    " (emitters: area, point, spot, directional, constant, envmap)",
                ))
            }
        };
        self.desc.lights.push(light);
        self.name(el, Named::Other("emitter".into()));
        self.finish(&p);
        Ok(())
    }
}
