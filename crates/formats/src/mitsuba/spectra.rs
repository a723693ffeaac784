//! Mitsuba's named indices of refraction and its `spectrum` values reduced to RGB as its
//! RGB variants do.
//!
//! * `<spectrum value="0.5"/>` is the constant 0.5; `value="400:0, 500:8, ..."` is a
//!   piecewise-linear spectrum that is zero outside its wavelengths. Emission spectra become
//!   `XYZ = int s(l) xyz(l) dl / int y(l) dl` (so the constant 1 has Y = 1), converted to
//!   linear sRGB; other spectra (reflectances) become the per-channel weighted average of
//!   `s` (a constant maps to itself), clamped to [0, 1].
//! * Named IORs are the values of Mitsuba's documentation table.

use mcrender_core::color::Rgb;

use crate::spectra::{cie_xyz, xyz_to_linear_srgb};

/// Mitsuba's named indices of refraction.
#[must_use]
pub fn named_ior(name: &str) -> Option<f32> {
    Some(match name {
        "vacuum" => 1.0,
        "helium" => 1.000_036,
        "hydrogen" => 1.000_132,
        "air" => 1.000_277,
        "carbon dioxide" => 1.000_449,
        "water" => 1.333,
        "acetone" => 1.36,
        "ethanol" => 1.361,
        "carbon tetrachloride" => 1.461,
        "glycerol" => 1.4729,
        "benzene" => 1.501,
        "silicone oil" => 1.520_45,
        "bromine" => 1.661,
        "water ice" => 1.31,
        "fused quartz" => 1.458,
        "pyrex" => 1.47,
        "acrylic glass" => 1.49,
        "polypropylene" => 1.49,
        "bk7" => 1.5046,
        "sodium chloride" => 1.544,
        "amber" => 1.55,
        "pet" => 1.575,
        "diamond" => 2.419,
        _ => return None,
    })
}

/// The pbrt name of the spectra of a Mitsuba conductor `material`, when mcrender has them.
#[must_use]
pub fn conductor_spectra(name: &str) -> Option<(Rgb, Rgb)> {
    use crate::spectra::metal_rgb;
    let pbrt = match name {
        "Ag" | "Al" | "Au" | "Cu" => name,
        _ => return None,
    };
    Some((
        metal_rgb(&format!("metal-{pbrt}-eta"))?,
        metal_rgb(&format!("metal-{pbrt}-k"))?,
    ))
}

/// RGB of a piecewise-linear spectrum (zero outside its wavelengths), as an emitter's
/// (`emission`) or as a reflectance.
#[must_use]
pub fn pairs_to_rgb(pairs: &[(f32, f32)], emission: bool) -> Rgb {
    if !emission && pairs.windows(2).all(|w| w[0].1 == w[1].1) {
        return Rgb::splat(pairs[0].1.clamp(0.0, 1.0));
    }
    let s = |l: f64| -> f64 {
        let i = pairs.partition_point(|(w, _)| f64::from(*w) <= l);
        if i == 0 || i == pairs.len() {
            return if (l - f64::from(pairs[pairs.len() - 1].0)).abs() < 1e-9 {
                f64::from(pairs[pairs.len() - 1].1)
            } else {
                0.0
            };
        }
        let ((l0, v0), (l1, v1)) = (pairs[i - 1], pairs[i]);
        let t = (l - f64::from(l0)) / f64::from(l1 - l0);
        f64::from(v0) + t * f64::from(v1 - v0)
    };
    let integrate = |f: &dyn Fn(f64) -> f64| {
        let mut xyz = [0.0f64; 3];
        // 0.1 nm steps, midpoint rule.
        for k in 0..4700 {
            let l = 360.05 + 0.1 * f64::from(k);
            let c = cie_xyz(l);
            let v = f(l);
            for (a, b) in xyz.iter_mut().zip(c) {
                *a += v * b * 0.1;
            }
        }
        xyz
    };
    let xyz = integrate(&s);
    if emission {
        let y_integral = integrate(&|_| 1.0)[1];
        let rgb = xyz_to_linear_srgb(xyz.map(|c| c / y_integral));
        Rgb::new(rgb[0] as f32, rgb[1] as f32, rgb[2] as f32)
    } else {
        let rgb = xyz_to_linear_srgb(xyz);
        let one = xyz_to_linear_srgb(integrate(&|_| 1.0));
        Rgb::new(
            (rgb[0] / one[0]).clamp(0.0, 1.0) as f32,
            (rgb[1] / one[1]).clamp(0.0, 1.0) as f32,
            (rgb[2] / one[2]).clamp(0.0, 1.0) as f32,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_constant_reflectance_stays_constant() {
        let c = pairs_to_rgb(&[(400.0, 0.78), (500.0, 0.78), (700.0, 0.78)], false);
        assert_eq!(c, Rgb::splat(0.78));
    }

    #[test]
    fn a_flat_emission_over_the_visible_range_is_near_white_of_luminance_one() {
        let c = pairs_to_rgb(&[(360.0, 1.0), (830.0, 1.0)], true);
        let y = 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
        assert!((y - 1.0).abs() < 0.01, "{c:?}");
        // A reddish ramp is redder than it is blue.
        let r = pairs_to_rgb(&[(400.0, 0.0), (500.0, 8.0), (600.0, 15.6), (700.0, 18.4)], true);
        assert!(r.r > r.b && r.r > 0.0, "{r:?}");
    }

    #[test]
    fn named_iors() {
        assert_eq!(named_ior("bk7"), Some(1.5046));
        assert_eq!(named_ior("diamond"), Some(2.419));
        assert_eq!(named_ior("unobtainium"), None);
    }
}
