//! Named spectra (`"metal-Cu-eta"`, `"glass-BK7"`, ...; pbrt-v4's names, also used for
//! Mitsuba's conductors) reduced to what an RGB renderer uses, once, at load time.
//!
//! Method. The tabulated spectra are those of pbrt-v4 (`src/pbrt/util/spectrum.cpp`;
//! metal indices from measured data, glass indices from refractiveindex.info). They were
//! converted offline, and only the results are stored here:
//! - Metals (`metal-{Ag,Al,Au,Cu}-{eta,k}`): each spectrum `s`, linearly interpolated
//!   (constant beyond its ends), was integrated against the CIE 1931 2-degree colour
//!   matching functions (the multi-lobe Gaussian fit of Wyman, Sloan and Shirley 2013) from
//!   360 to 830 nm in 1 nm steps, the XYZ converted to linear sRGB with the standard matrix,
//!   and each channel divided by the same conversion of the constant spectrum 1. So a
//!   constant index maps to itself, and each channel is a weighted average of the index
//!   over the wavelengths that channel sees. (Evaluating at single wavelengths, R 630,
//!   G 545, B 465 nm, gives values within about 0.1 of these except for Au and Cu, whose
//!   indices change quickly between 550 and 650 nm.)
//! - Glasses (`glass-*`): a dielectric takes one real index, the spectrum's value at
//!   550 nm (linear interpolation), ignoring dispersion.

use mcrender_core::color::Rgb;

/// The RGB of a named metal index spectrum (`metal-Cu-eta`, `metal-Cu-k`, ...), or `None`
/// for other names.
#[must_use]
pub fn metal_rgb(name: &str) -> Option<Rgb> {
    // Computed as described in the module documentation.
    Some(match name {
        "metal-Ag-eta" => Rgb::new(0.128_755, 0.123_146, 0.152_181),
        "metal-Ag-k" => Rgb::new(3.998_709, 3.298_955, 2.360_609),
        "metal-Al-eta" => Rgb::new(1.369_213, 0.932_635, 0.572_798),
        "metal-Al-k" => Rgb::new(7.643_803, 6.620_49, 5.318_793),
        "metal-Au-eta" => Rgb::new(0.121_315, 0.392_612, 1.586_818),
        "metal-Au-k" => Rgb::new(3.296_351, 2.522_392, 1.762_161),
        "metal-Cu-eta" => Rgb::new(0.169_670, 0.970_876, 1.212_831),
        "metal-Cu-k" => Rgb::new(3.236_334, 2.593_74, 2.355_428),
        _ => return None,
    })
}

/// The index of refraction at 550 nm of a named glass spectrum, or `None` for other
/// names.
#[must_use]
pub fn glass_eta(name: &str) -> Option<f32> {
    // Interpolated at 550 nm from pbrt-v4's tables.
    Some(match name {
        "glass-BK7" => 1.518_537,
        "glass-BAF10" => 1.673_051,
        "glass-FK51A" => 1.487_796,
        "glass-LASF9" => 1.855_809,
        "glass-F5" => 1.677_089,
        "glass-F10" => 1.733_574,
        "glass-F11" => 1.791_119,
        _ => return None,
    })
}

/// pbrt-v4 named spectra that exist but have no RGB value here yet.
pub const KNOWN_UNCONVERTED: &[&str] = &[
    "metal-CuZn-eta",
    "metal-CuZn-k",
    "metal-MgO-eta",
    "metal-MgO-k",
    "metal-TiO2-eta",
    "metal-TiO2-k",
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn metals_have_their_colours() {
        // Normal-incidence reflectance ((n-1)^2 + k^2) / ((n+1)^2 + k^2) per channel.
        let r0 = |m: &str| {
            let (n, k) = (
                metal_rgb(&format!("metal-{m}-eta")).unwrap(),
                metal_rgb(&format!("metal-{m}-k")).unwrap(),
            );
            Rgb::from([0, 1, 2].map(|i| ((n[i] - 1.0).powi(2) + k[i] * k[i]) / ((n[i] + 1.0).powi(2) + k[i] * k[i])))
        };
        let (cu, au, ag, al) = (r0("Cu"), r0("Au"), r0("Ag"), r0("Al"));
        assert!(cu.r > cu.g && cu.g > cu.b, "copper {cu:?}");
        assert!(au.r > au.g && au.g > au.b, "gold {au:?}");
        assert!(ag.min_component_for_test() > 0.9, "silver {ag:?}");
        assert!(al.min_component_for_test() > 0.85, "aluminium {al:?}");
        assert!(metal_rgb("metal-Cu").is_none());
    }

    #[test]
    fn glasses_have_plausible_indices() {
        assert!((glass_eta("glass-BK7").unwrap() - 1.5185).abs() < 1e-3);
        assert!(glass_eta("glass-F11").unwrap() > glass_eta("glass-BK7").unwrap());
        assert!(glass_eta("glass-XYZ").is_none());
    }

    trait MinComponent {
        fn min_component_for_test(self) -> f32;
    }
    impl MinComponent for Rgb {
        fn min_component_for_test(self) -> f32 {
            self.r.min(self.g).min(self.b)
        }
    }
}
