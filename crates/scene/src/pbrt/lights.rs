//! Lights: `AreaLightSource "diffuse"` (attached to the shapes that follow it) and
//! `LightSource "point"`.
//!
//! pbrt multiplies an `rgb` emission by the colour space's illuminant and divides by that
//! illuminant's luminance; rendering in RGB with sRGB, the two cancel, so the emitted value
//! is simply the given RGB times `scale`.

use glam::Vec3;
use mcrender_core::color::Rgb;
use mcrender_core::scene::{AreaLightDesc, LightDesc};

use super::builder::SceneBuilder;
use super::params::{ParamSet, ParamType};
use crate::error::{Location, SceneError};

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
        self.state.area_light = Some(AreaLightDesc { radiance, two_sided });
        self.warn_unused(params);
        Ok(())
    }

    /// `LightSource "point" ...`; the other pbrt light types are not supported yet.
    pub fn light_source(&mut self, kind: &str, params: &mut ParamSet, loc: &Location) -> Result<(), SceneError> {
        self.require_world("LightSource", loc)?;
        match kind {
            "point" => {}
            "distant" | "infinite" | "spot" | "goniometric" | "projection" => {
                return Err(SceneError::unsupported(
                    loc,
                    format!("light type \"{kind}\" is not supported yet"),
                ));
            }
            _ => return Err(SceneError::syntax(loc, format!("unknown light type \"{kind}\""))),
        }
        params.add_inherited(&self.state.attributes.light);
        let mut intensity = emission(params, "I")?;
        // pbrt: "power" sets the total emitted power; a point light emits 4 pi I.
        let power = params.float("power", -1.0)?;
        if power > 0.0 {
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
        self.lights.push(LightDesc::Point { position, intensity });
        self.warn_unused(params);
        Ok(())
    }
}

/// An emitted colour `name` (default white) times `scale` (default 1); both non-negative.
///
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
        params.rgb(name, Rgb::WHITE)?
    };
    if color.to_array().iter().any(|c| *c < 0.0) {
        let loc = params.get(name).map_or(&params.loc, |p| &p.loc);
        return Err(SceneError::invalid(
            loc,
            format!("emission \"{name}\" of {} must not be negative", params.owner),
        ));
    }
    let scale = params.float("scale", 1.0)?;
    if scale < 0.0 {
        let loc = params.get("scale").map_or(&params.loc, |p| &p.loc);
        return Err(SceneError::invalid(
            loc,
            format!("\"scale\" of {} must not be negative", params.owner),
        ));
    }
    Ok(color * scale)
}
