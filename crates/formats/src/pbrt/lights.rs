//! Lights: `AreaLightSource "diffuse"` (attached to the shapes that follow it) and
//! `LightSource` `"point"`, `"spot"`, `"distant"` and `"infinite"`, with pbrt-v4's
//! parameter names, defaults and normalisations:
//!
//! | light | parameters (default) |
//! |---|---|
//! | `diffuse` (area) | `L` (white), `scale` (1), `twosided` (false), `power` (off: per primitive, see [`AreaLightDesc::power`]) |
//! | `point` | `I` (white), `scale` (1), `power` (off: `I *= power / 4 pi`), `from` (0 0 0) |
//! | `spot` | `I`, `scale`, `from` (0 0 0), `to` (0 0 1), `coneangle` (30), `conedeltaangle` (5), `power` (off: `I *= power / (2 pi ((1 - cos_start) + (cos_start - cos_end) / 2))`) |
//! | `distant` | `L`, `scale`, `from` (0 0 0), `to` (0 0 1), `illuminance` (off: `L *= E`, the illuminance of a surface facing the light for white `L`) |
//! | `infinite` | `L` or `filename`, `scale`, `illuminance` (off; see below) |
//!
//! `infinite` with `filename` reads an image (EXR, PFM, PNG, JPEG or TGA; 8-bit formats are
//! decoded from sRGB) in pbrt-v4's equal-area octahedral layout, which must be square. An
//! mcrender extension, `"string mapping" "equirect"`, reads a latitude-longitude image
//! instead (pbrt-v3's layout: the top row is light-space +z, the columns go round from +x
//! towards +y); `"equalarea"` is the default. The CTM at the `LightSource` turns light
//! space into the world, so `Rotate -90 1 0 0` before it makes the map's +z the world's +y.
//! `illuminance` scales so that the upper hemisphere (light-space z > 0) gives that
//! illuminance, computed as pbrt-v4 does: for `L`, `L *= E / pi`; for an image, with the
//! per-pixel solid angle 2 pi / N that pbrt-v4 uses (half the exact 4 pi / N, so the
//! result is twice as bright as the exact normalisation; we match pbrt's images).
//! `portal` is not supported.
//!
//! pbrt multiplies an `rgb` emission by the colour space's illuminant and divides by that
//! illuminant's luminance; rendering in RGB with sRGB, the two cancel, so the emitted value
//! is simply the given RGB times `scale`.

use glam::{Mat4, Vec3};
use mcrender_core::color::Rgb;
use mcrender_core::math::Transform;
use mcrender_core::sampling::equal_area_square_to_sphere;
use mcrender_core::scene::{
    AreaLightDesc, EnvMapping, ImageInfiniteLightDesc, LightDesc, RgbImageDesc, SpotFalloff, SpotLightDesc,
};

use super::builder::SceneBuilder;
use super::files::ImageUse;
use super::params::{ParamSet, ParamType};
use crate::error::{Location, SceneError};
use crate::image_io::{ColorEncoding, ImageRgb};
use crate::spectra::SpectrumRole;

impl SceneBuilder {
    /// `AreaLightSource "diffuse" ...`: emission for subsequent shapes in this scope.
    pub fn area_light_source(&mut self, kind: &str, params: &mut ParamSet, loc: &Location) -> Result<(), SceneError> {
        self.require_world("AreaLightSource", loc)?;
        if kind != "diffuse" {
            return Err(SceneError::syntax(loc, format!("unknown area light type \"{kind}\"")));
        }
        params.add_inherited(&self.state.attributes.light);
        if let Some(p) = params.get("filename") {
            p.mark_used();
            return Err(SceneError::unsupported(
                &p.loc,
                format!(
                    "parameter \"{}\" of {} (image emission) is not supported yet",
                    p.decl(),
                    params.owner
                ),
            ));
        }
        let radiance = emission(params, "L")?;
        let two_sided = params.bool("twosided", false)?;
        let power = optional_power(params, "power")?;
        self.state.area_light = Some(AreaLightDesc {
            radiance,
            two_sided,
            power,
        });
        self.warn_unused(params);
        Ok(())
    }

    /// `LightSource "point" | "spot" | "distant" | "infinite" ...`.
    pub fn light_source(&mut self, kind: &str, params: &mut ParamSet, loc: &Location) -> Result<(), SceneError> {
        self.require_world("LightSource", loc)?;
        match kind {
            "point" | "spot" | "distant" | "infinite" => {}
            "goniometric" | "projection" => {
                return Err(SceneError::unsupported(
                    loc,
                    format!("light type \"{kind}\" is not supported yet"),
                ));
            }
            _ => return Err(SceneError::syntax(loc, format!("unknown light type \"{kind}\""))),
        }
        params.add_inherited(&self.state.attributes.light);
        let light = match kind {
            "point" => self.point_light(params, loc)?,
            "spot" => self.spot_light(params, loc)?,
            "distant" => self.distant_light(params, loc)?,
            _ => self.infinite_light(params, loc)?,
        };
        self.world.lights.push(light);
        self.warn_unused(params);
        Ok(())
    }

    fn point_light(&self, params: &ParamSet, loc: &Location) -> Result<LightDesc, SceneError> {
        let mut intensity = emission(params, "I")?;
        // pbrt: "power" sets the total emitted power; a point light emits 4 pi I.
        if let Some(power) = optional_power(params, "power")? {
            intensity *= power / (4.0 * std::f32::consts::PI);
        }
        let from = params.point3("from", Vec3::ZERO)?;
        let position = self.state.ctm.project_point3(from);
        if !position.is_finite() {
            return Err(SceneError::invalid(
                loc,
                "the position of the point light is not finite",
            ));
        }
        Ok(LightDesc::Point { position, intensity })
    }

    fn spot_light(&self, params: &ParamSet, loc: &Location) -> Result<LightDesc, SceneError> {
        let mut intensity = emission(params, "I")?;
        let cone = params.float("coneangle", 30.0)?;
        let delta = params.float("conedeltaangle", 5.0)?;
        if !(0.0..=180.0).contains(&cone) || !(0.0..=cone).contains(&delta) {
            let p = params.get("conedeltaangle").or(params.get("coneangle"));
            return Err(SceneError::invalid(
                p.map_or(loc, |p| &p.loc),
                format!(
                    "{} needs 0 <= \"conedeltaangle\" <= \"coneangle\" <= 180, found {delta} and {cone}",
                    params.owner
                ),
            ));
        }
        let cos_end = cone.to_radians().cos();
        let cos_start = (cone - delta).to_radians().cos();
        if let Some(power) = optional_power(params, "power")? {
            let k = 2.0 * std::f32::consts::PI * ((1.0 - cos_start) + (cos_start - cos_end) / 2.0);
            intensity *= power / k;
        }
        let from = params.point3("from", Vec3::ZERO)?;
        let to = params.point3("to", Vec3::Z)?;
        let dir = direction(params, to - from, loc)?;
        let (x, y) = dir.any_orthonormal_pair();
        let light_to_spot = Mat4::from_translation(from)
            * Mat4::from_cols(x.extend(0.0), y.extend(0.0), dir.extend(0.0), glam::Vec4::W);
        let world_from_light = self.light_transform(self.state.ctm * light_to_spot, params, loc)?;
        Ok(LightDesc::Spot(SpotLightDesc {
            world_from_light,
            intensity,
            cos_falloff_start: cos_start,
            cos_falloff_end: cos_end,
            falloff: SpotFalloff::SmoothCosine,
            projection: None,
        }))
    }

    fn distant_light(&self, params: &ParamSet, loc: &Location) -> Result<LightDesc, SceneError> {
        let mut radiance = emission(params, "L")?;
        let from = params.point3("from", Vec3::ZERO)?;
        let to = params.point3("to", Vec3::Z)?;
        let w = direction(params, from - to, loc)?;
        let world = self.state.ctm.transform_vector3(w).try_normalize().ok_or_else(|| {
            SceneError::invalid(
                loc,
                "the current transformation of the distant light is singular or not finite",
            )
        })?;
        if let Some(e) = optional_power(params, "illuminance")? {
            radiance *= e;
        }
        Ok(LightDesc::Distant {
            direction: world,
            radiance,
        })
    }

    fn infinite_light(&mut self, params: &ParamSet, loc: &Location) -> Result<LightDesc, SceneError> {
        if let Some(p) = params.get("portal") {
            p.mark_used();
            return Err(SceneError::unsupported(
                &p.loc,
                format!("parameter \"{}\" of {} is not supported yet", p.decl(), params.owner),
            ));
        }
        let illuminance = optional_power(params, "illuminance")?;
        let filename = params.string("filename")?;
        let mapping_param = params.string("mapping")?;
        let Some((filename, file_loc)) = filename else {
            if let Some((_, mloc)) = mapping_param {
                return Err(SceneError::invalid(
                    &mloc,
                    format!("\"mapping\" of {} needs a \"filename\"", params.owner),
                ));
            }
            let mut radiance = emission(params, "L")?;
            if let Some(e) = illuminance {
                radiance *= e / std::f32::consts::PI;
            }
            return Ok(LightDesc::UniformInfinite { radiance });
        };
        if let Some(p) = params.get("L") {
            p.mark_used();
            return Err(SceneError::invalid(
                &p.loc,
                format!("{} cannot have both \"L\" and \"filename\"", params.owner),
            ));
        }
        let mapping = match mapping_param.as_ref().map(|(m, l)| (m.as_str(), l)) {
            None | Some(("equalarea", _)) => EnvMapping::EqualArea,
            Some(("equirect", _)) => EnvMapping::Equirect,
            Some((other, mloc)) => {
                return Err(SceneError::invalid(
                    mloc,
                    format!(
                        "unknown \"mapping\" \"{other}\" of {} (expected \"equalarea\" or \"equirect\")",
                        params.owner
                    ),
                ))
            }
        };
        let mut scale = non_negative(params, "scale", 1.0)?;
        let image = self.read_env_image(&filename, &file_loc, mapping)?;
        if let Some(e) = illuminance {
            let k = upper_hemisphere_illuminance(&image, mapping);
            if k > 0.0 {
                scale *= e / k;
            }
        }
        let world_from_light = self.light_transform(self.state.ctm, params, loc)?;
        Ok(LightDesc::ImageInfinite(ImageInfiniteLightDesc {
            image: RgbImageDesc {
                width: image.width,
                height: image.height,
                pixels: image.pixels,
            },
            mapping,
            scale,
            world_from_light,
        }))
    }

    /// Read an environment image and check it suits `mapping`.
    fn read_env_image(&mut self, filename: &str, loc: &Location, mapping: EnvMapping) -> Result<ImageRgb, SceneError> {
        let image = self.read_image_file(filename, loc, ColorEncoding::Srgb, ImageUse::Environment)?;
        if mapping == EnvMapping::EqualArea && image.width != image.height {
            return Err(SceneError::invalid(
                loc,
                format!(
                    "image \"{filename}\" is {}x{}, not square, so it is not an equal-area environment map (for a latitude-longitude map add \"string mapping\" \"equirect\")",
                    image.width, image.height
                ),
            ));
        }
        let mut image = image;
        // pbrt clamps negative values to zero when it looks radiance up.
        for p in &mut image.pixels {
            *p = p.map(|c| c.max(0.0));
        }
        Ok(image)
    }

    /// `m` as a [`Transform`]; an error naming the light when it is singular.
    fn light_transform(&self, m: Mat4, params: &ParamSet, loc: &Location) -> Result<Transform, SceneError> {
        Transform::new(m).ok_or_else(|| {
            SceneError::invalid(
                loc,
                format!(
                    "the current transformation of {} is singular or not finite",
                    params.owner
                ),
            )
        })
    }
}

/// `v` normalised; an error when `from` and `to` coincide.
fn direction(params: &ParamSet, v: Vec3, loc: &Location) -> Result<Vec3, SceneError> {
    v.try_normalize().ok_or_else(|| {
        let loc = params.get("to").or(params.get("from")).map_or(loc, |p| &p.loc);
        SceneError::invalid(
            loc,
            format!("\"from\" and \"to\" of {} must be different points", params.owner),
        )
    })
}

/// The illuminance of the light-space upper hemisphere (z > 0) of an environment image,
/// `sum Y(pixel) cos(theta) d omega`, with pbrt-v4's per-pixel solid angle `2 pi / N` for the
/// equal-area layout (see the module documentation) and, consistently, half the exact
/// solid angle for the latitude-longitude one.
fn upper_hemisphere_illuminance(image: &ImageRgb, mapping: EnvMapping) -> f32 {
    use std::f64::consts::PI;
    let (w, h) = (image.width as usize, image.height as usize);
    let mut sum = 0.0f64;
    for y in 0..h {
        for x in 0..w {
            let (u, v) = ((x as f64 + 0.5) / w as f64, (y as f64 + 0.5) / h as f64);
            let (cos_theta, solid_angle) = match mapping {
                EnvMapping::EqualArea => {
                    let d = equal_area_square_to_sphere(glam::Vec2::new(u as f32, v as f32));
                    (f64::from(d.z), 2.0 * PI / (w * h) as f64)
                }
                EnvMapping::Equirect | EnvMapping::EquirectBilinear => {
                    let (t0, t1) = (PI * y as f64 / h as f64, PI * (y + 1) as f64 / h as f64);
                    ((PI * v).cos(), 0.5 * 2.0 * PI / w as f64 * (t0.cos() - t1.cos()))
                }
            };
            if cos_theta > 0.0 {
                sum += f64::from(image.pixels[y * w + x].luminance()) * cos_theta * solid_angle;
            }
        }
    }
    sum as f32
}

/// A positive `float` parameter that switches a normalisation on; pbrt ignores values
/// <= 0 (its default is -1), so do we.
fn optional_power(params: &ParamSet, name: &str) -> Result<Option<f32>, SceneError> {
    let v = params.float(name, -1.0)?;
    Ok((v > 0.0).then_some(v))
}

/// A non-negative `float` parameter.
fn non_negative(params: &ParamSet, name: &str, default: f32) -> Result<f32, SceneError> {
    let v = params.float(name, default)?;
    if v < 0.0 {
        let loc = params.get(name).map_or(&params.loc, |p| &p.loc);
        return Err(SceneError::invalid(
            loc,
            format!("\"{name}\" of {} must not be negative", params.owner),
        ));
    }
    Ok(v)
}

/// An emitted colour `name` (default white) times `scale` (default 1); both non-negative.
///
/// Spectra as (wavelength, value) pairs and `blackbody` temperatures become the RGB of
/// luminance 1 that pbrt-v4's normalisation leaves (see [`crate::spectra`]).
/// `"spectrum L" "stdillum-D65"` is accepted too: pbrt normalises an emission spectrum by its
/// luminance, and the sRGB white point is D65, so it is exactly RGB white.
fn emission(params: &ParamSet, name: &str) -> Result<Rgb, SceneError> {
    let d65 = params
        .get(name)
        .is_some_and(|p| p.ty == ParamType::Spectrum && p.strings() == ["stdillum-D65"]);
    let color = if d65 {
        params.lookup(name, &[ParamType::Spectrum])?;
        Rgb::WHITE
    } else {
        params.color(name, Rgb::WHITE, SpectrumRole::Illuminant)?
    };
    if color.to_array().iter().any(|c| *c < 0.0) {
        let loc = params.get(name).map_or(&params.loc, |p| &p.loc);
        return Err(SceneError::invalid(
            loc,
            format!("emission \"{name}\" of {} must not be negative", params.owner),
        ));
    }
    Ok(color * non_negative(params, "scale", 1.0)?)
}
