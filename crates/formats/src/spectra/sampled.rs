//! Spectra given in the scene file (`"spectrum x" [ λ0 v0 λ1 v1 ... ]`, `"blackbody x" [ T ]`)
//! reduced to linear sRGB once, at load, by the role the parameter plays (pbrt-v4's
//! `SpectrumType`):
//!
//! - **Illuminant** (emission `L`, `I`): pbrt-v4 divides a light's spectrum by its luminance
//!   (`scale /= SpectrumToPhotometric(L)`), so what is left is a colour of luminance 1: the
//!   spectrum's CIE XYZ divided by its Y, converted to linear sRGB. A blackbody is used this
//!   way (its normalisation by the peak cancels).
//! - **Albedo** (reflectances) and **unbounded** (indices of refraction): each channel is
//!   the spectrum's average weighted by what that channel sees, the linear sRGB of the
//!   spectrum's XYZ divided, channel by channel, by that of the constant spectrum 1. A
//!   constant spectrum maps to itself. Albedos are then clamped to [0, 1] as pbrt clamps
//!   them. This is the method used for the named metal spectra in [`super::named`].
//!
//! XYZ integrals run from 360 to 830 nm in 1 nm steps, against the CIE 1931 2-degree colour
//! matching functions in the multi-lobe Gaussian fit of Wyman, Sloan and Shirley (2013,
//! "Simple Analytic Approximations to the CIE XYZ Color Matching Functions", eq. 2-4).
//! Sampled spectra are interpolated linearly and held constant beyond their ends.

use mcrender_core::color::Rgb;

/// How a spectrum parameter is used, which decides its conversion (module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpectrumRole {
    /// Emitted radiance or intensity: normalised to luminance 1.
    Illuminant,
    /// A reflectance or transmittance: a weighted average per channel, clamped to [0, 1].
    Albedo,
    /// Any other quantity (indices of refraction): a weighted average per channel.
    Unbounded,
}

/// The `(wavelength, value)` pairs of a `spectrum` parameter's numbers `[l0 v0 l1 v1 ...]`
/// (parsing has checked that they come in pairs).
#[must_use]
pub fn spectrum_pairs(values: &[f32]) -> Vec<(f32, f32)> {
    values.chunks_exact(2).map(|c| (c[0], c[1])).collect()
}

/// A piecewise-linear spectrum from `(wavelength nm, value)` pairs.
///
/// # Errors
/// A message when there are no pairs, the wavelengths do not increase, or a value is not
/// finite.
pub fn sampled_spectrum(pairs: &[(f32, f32)]) -> Result<impl Fn(f64) -> f64 + '_, String> {
    if pairs.is_empty() {
        return Err("a sampled spectrum needs at least one (wavelength, value) pair".into());
    }
    if pairs.iter().any(|(l, v)| !l.is_finite() || !v.is_finite()) {
        return Err("spectrum wavelengths and values must be finite".into());
    }
    if pairs.windows(2).any(|w| w[1].0 <= w[0].0) {
        return Err("spectrum wavelengths must increase".into());
    }
    Ok(move |lambda: f64| {
        let i = pairs.partition_point(|(l, _)| f64::from(*l) <= lambda);
        if i == 0 {
            return f64::from(pairs[0].1);
        }
        if i == pairs.len() {
            return f64::from(pairs[i - 1].1);
        }
        let ((l0, v0), (l1, v1)) = (pairs[i - 1], pairs[i]);
        let t = (lambda - f64::from(l0)) / f64::from(l1 - l0);
        f64::from(v0) + t * f64::from(v1 - v0)
    })
}

/// Planck's law: spectral radiance of a blackbody at `kelvin` for `lambda_nm`, in
/// W / (sr m^2 m) (only its shape matters here).
#[must_use]
pub fn blackbody(lambda_nm: f64, kelvin: f64) -> f64 {
    const C: f64 = 299_792_458.0;
    const H: f64 = 6.626_070_15e-34;
    const KB: f64 = 1.380_649e-23;
    let l = lambda_nm * 1e-9;
    2.0 * H * C * C / (l.powi(5) * ((H * C / (l * KB * kelvin)).exp() - 1.0))
}

/// The linear sRGB of a spectrum used in `role`.
#[must_use]
pub fn spectrum_to_rgb(s: impl Fn(f64) -> f64, role: SpectrumRole) -> Rgb {
    let xyz = integrate_xyz(s);
    match role {
        SpectrumRole::Illuminant => {
            if xyz[1] <= 0.0 {
                return Rgb::BLACK;
            }
            let rgb = xyz_to_linear_srgb(xyz.map(|c| c / xyz[1]));
            Rgb::new(rgb[0] as f32, rgb[1] as f32, rgb[2] as f32)
        }
        SpectrumRole::Albedo | SpectrumRole::Unbounded => {
            let rgb = xyz_to_linear_srgb(xyz);
            let one = xyz_to_linear_srgb(integrate_xyz(|_| 1.0));
            let c: [f32; 3] = std::array::from_fn(|i| (rgb[i] / one[i]) as f32);
            let c = Rgb::from(c);
            if role == SpectrumRole::Albedo {
                c.map(|v| v.clamp(0.0, 1.0))
            } else {
                c
            }
        }
    }
}

/// The colour of a blackbody at `kelvin` as an illuminant (luminance 1).
///
/// # Errors
/// A message when the temperature is not positive and finite.
pub fn blackbody_rgb(kelvin: f32) -> Result<Rgb, String> {
    if !(kelvin.is_finite() && kelvin > 0.0) {
        return Err(format!(
            "a blackbody temperature must be positive (Kelvin), got {kelvin}"
        ));
    }
    Ok(spectrum_to_rgb(
        |l| blackbody(l, f64::from(kelvin)),
        SpectrumRole::Illuminant,
    ))
}

/// One lobe of the Wyman-Sloan-Shirley fit: a Gaussian with different widths either side.
fn lobe(lambda: f64, mu: f64, sigma_below: f64, sigma_above: f64) -> f64 {
    let s = if lambda < mu { sigma_below } else { sigma_above };
    let t = (lambda - mu) / s;
    (-0.5 * t * t).exp()
}

/// CIE 1931 colour matching functions at `lambda` nm (Wyman et al. 2013, multi-lobe fit).
pub(crate) fn cie_xyz(lambda: f64) -> [f64; 3] {
    [
        1.056 * lobe(lambda, 599.8, 37.9, 31.0) + 0.362 * lobe(lambda, 442.0, 16.0, 26.7)
            - 0.065 * lobe(lambda, 501.1, 20.4, 26.2),
        0.821 * lobe(lambda, 568.8, 46.9, 40.5) + 0.286 * lobe(lambda, 530.9, 16.3, 31.1),
        1.217 * lobe(lambda, 437.0, 11.8, 36.0) + 0.681 * lobe(lambda, 459.0, 26.0, 13.8),
    ]
}

/// XYZ of a spectrum, 360..=830 nm in 1 nm steps (the common scale cancels in every use).
fn integrate_xyz(s: impl Fn(f64) -> f64) -> [f64; 3] {
    let mut xyz = [0.0; 3];
    for l in 360..=830 {
        let l = f64::from(l);
        let (v, m) = (s(l), cie_xyz(l));
        for c in 0..3 {
            xyz[c] += v * m[c];
        }
    }
    xyz
}

/// CIE XYZ to linear sRGB (IEC 61966-2-1, D65 white).
pub(crate) fn xyz_to_linear_srgb([x, y, z]: [f64; 3]) -> [f64; 3] {
    [
        3.240_454_2 * x - 1.537_138_5 * y - 0.498_531_4 * z,
        -0.969_266 * x + 1.876_010_8 * y + 0.041_556 * z,
        0.055_643_4 * x - 0.204_025_9 * y + 1.057_225_2 * z,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn luminance(c: Rgb) -> f32 {
        0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b
    }

    #[test]
    fn blackbodies_have_luminance_one_and_their_colours() {
        let warm = blackbody_rgb(2700.0).unwrap();
        let white = blackbody_rgb(6500.0).unwrap();
        let cold = blackbody_rgb(12000.0).unwrap();
        for c in [warm, white, cold] {
            assert!((luminance(c) - 1.0).abs() < 0.01, "{c:?}");
        }
        assert!(warm.r > warm.g && warm.g > warm.b, "2700 K is orange: {warm:?}");
        assert!(cold.b > cold.g && cold.g > cold.r, "12000 K is blue: {cold:?}");
        // 6500 K lies near the sRGB white point (D65, correlated temperature 6504 K, just
        // off the Planckian locus).
        for ch in 0..3 {
            assert!((white[ch] - 1.0).abs() < 0.1, "{white:?}");
        }
        assert!(blackbody_rgb(0.0).is_err() && blackbody_rgb(f32::NAN).is_err());
    }

    #[test]
    fn planck_peaks_where_wien_says() {
        // Wien's displacement law: peak at 2.898e6 nm K / T.
        let t = 5000.0;
        let peak = (300..3000).max_by(|a, b| blackbody(f64::from(*a), t).total_cmp(&blackbody(f64::from(*b), t)));
        assert!((f64::from(peak.unwrap()) - 2.897_772e6 / t).abs() <= 1.0, "{peak:?}");
    }

    #[test]
    fn constant_spectra_map_to_themselves() {
        let s = [(400.0, 0.25), (700.0, 0.25)];
        for role in [SpectrumRole::Albedo, SpectrumRole::Unbounded] {
            let c = spectrum_to_rgb(sampled_spectrum(&s).unwrap(), role);
            for ch in 0..3 {
                assert!((c[ch] - 0.25).abs() < 1e-5, "{role:?} {c:?}");
            }
        }
        // The equal-energy illuminant E is close to, but not exactly, the D65 white.
        let e = spectrum_to_rgb(sampled_spectrum(&s).unwrap(), SpectrumRole::Illuminant);
        assert!((luminance(e) - 1.0).abs() < 1e-3 && e.r > e.b, "{e:?}");
    }

    #[test]
    fn a_red_reflectance_is_red_and_clamped() {
        let red = [(400.0, 0.0), (580.0, 0.0), (600.0, 1.5), (800.0, 1.5)];
        let c = spectrum_to_rgb(sampled_spectrum(&red).unwrap(), SpectrumRole::Albedo);
        assert!(c.r == 1.0 && c.g < 0.2 && c.b < 0.05, "{c:?}");
        let u = spectrum_to_rgb(sampled_spectrum(&red).unwrap(), SpectrumRole::Unbounded);
        assert!(u.r > 1.0, "unbounded values are not clamped: {u:?}");
    }

    #[test]
    fn interpolation_is_linear_and_constant_beyond_the_ends() {
        let s = [(400.0, 1.0), (500.0, 3.0)];
        let f = sampled_spectrum(&s).unwrap();
        assert_eq!(
            (f(300.0), f(400.0), f(450.0), f(500.0), f(900.0)),
            (1.0, 1.0, 2.0, 3.0, 3.0)
        );
        assert!(sampled_spectrum(&[]).is_err());
        assert!(sampled_spectrum(&[(500.0, 1.0), (400.0, 1.0)]).is_err());
        assert!(sampled_spectrum(&[(500.0, f32::NAN)]).is_err());
    }
}
