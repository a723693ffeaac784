//! Spectra to RGB, shared by the loaders: [`sampled`] converts spectra given in a scene
//! file (wavelength-value pairs, blackbodies) by the role they play, [`named`] holds the
//! named metal and glass spectra, converted offline.

pub mod named;
pub mod sampled;

pub use named::{glass_eta, metal_rgb, KNOWN_UNCONVERTED};
pub use sampled::{blackbody, blackbody_rgb, sampled_spectrum, spectrum_pairs, spectrum_to_rgb, SpectrumRole};
pub(crate) use sampled::{cie_xyz, xyz_to_linear_srgb};
