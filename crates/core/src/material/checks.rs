//! Validation of material parameters before a scene is built: the numbers a BSDF relies on
//! (finite, non-negative, a positive index of refraction). Only constant textures are
//! checked here; image textures are checked where they are decoded, and the others combine
//! those.

use crate::texture::{FloatTexture, RgbTexture};

/// A parameter that fails validation: which one, and what was wrong with it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct InvalidParameter {
    /// Which parameter, e.g. "reflectance of material 3".
    pub what: String,
    /// What was wrong, e.g. "expected non-negative values, found -1".
    pub detail: String,
}

/// An [`InvalidParameter`] from its two parts.
pub fn invalid(what: impl Into<String>, detail: impl Into<String>) -> InvalidParameter {
    InvalidParameter {
        what: what.into(),
        detail: detail.into(),
    }
}

/// Every value finite.
pub fn check_finite(what: &str, vals: &[f32]) -> Result<(), InvalidParameter> {
    match vals.iter().find(|v| !v.is_finite()) {
        Some(v) => Err(invalid(what, format!("expected finite numbers, found {v}"))),
        None => Ok(()),
    }
}

/// Every value finite and at least 0.
pub fn check_non_negative(what: &str, vals: &[f32]) -> Result<(), InvalidParameter> {
    check_finite(what, vals)?;
    match vals.iter().find(|v| **v < 0.0) {
        Some(v) => Err(invalid(what, format!("expected non-negative values, found {v}"))),
        None => Ok(()),
    }
}

/// The channels of a constant texture (nothing for other textures).
#[must_use]
pub fn rgb_constant(t: &RgbTexture) -> Vec<f32> {
    t.constant().map(|c| c.to_array().to_vec()).unwrap_or_default()
}

/// The values of the constant textures among `ts`.
#[must_use]
pub fn float_constants(ts: &[&FloatTexture]) -> Vec<f32> {
    ts.iter().filter_map(|t| t.constant()).collect()
}

/// A constant RGB parameter of material `index` non-negative.
pub(super) fn check_rgb(index: usize, name: &str, t: &RgbTexture) -> Result<(), InvalidParameter> {
    check_non_negative(&format!("{name} of material {index}"), &rgb_constant(t))
}

/// The constant roughnesses of material `index` non-negative.
pub(super) fn check_roughness(index: usize, ts: &[&FloatTexture]) -> Result<(), InvalidParameter> {
    check_non_negative(&format!("roughness of material {index}"), &float_constants(ts))
}

/// An index of refraction finite and above 0.
pub(super) fn check_positive_eta(index: usize, eta: f32) -> Result<(), InvalidParameter> {
    if eta > 0.0 && eta.is_finite() {
        Ok(())
    } else {
        Err(invalid(
            format!("index of refraction of material {index}"),
            format!("expected a finite value > 0, found {eta}"),
        ))
    }
}

/// The slab of a layered material: thickness and albedo finite and non-negative, `g`
/// finite (clamped when the BSDF is built, as pbrt does).
pub(super) fn check_slab(
    index: usize,
    thickness: &FloatTexture,
    albedo: &RgbTexture,
    g: &FloatTexture,
) -> Result<(), InvalidParameter> {
    check_non_negative(
        &format!("thickness of material {index}"),
        &float_constants(&[thickness]),
    )?;
    check_rgb(index, "albedo", albedo)?;
    check_finite(&format!("g of material {index}"), &float_constants(&[g]))
}

/// A material index referred to by material `index` within the `count` materials.
pub(super) fn check_reference(index: usize, verb: &str, target: u32, count: usize) -> Result<(), InvalidParameter> {
    if (target as usize) < count {
        Ok(())
    } else {
        Err(invalid(
            format!("material {index}"),
            format!("{verb} material index {target}, out of range"),
        ))
    }
}
