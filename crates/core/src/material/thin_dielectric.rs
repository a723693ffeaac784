//! pbrt's `thindielectric` (Mitsuba's `thindielectric`): a thin slab such as a window
//! pane, specular reflection and straight transmission with the interreflections summed.

use super::checks::{check_positive_eta, InvalidParameter};
use crate::bsdf::{Bxdf, ThinDielectricBxdf};

/// A thin dielectric slab (pbrt `thindielectric`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThinDielectricMaterial {
    /// Index of refraction of the slab.
    pub eta: f32,
}

impl ThinDielectricMaterial {
    /// Check the parameters of material `index`.
    pub fn validate(&self, index: usize) -> Result<(), InvalidParameter> {
        check_positive_eta(index, self.eta)
    }

    /// The lobe (no textures).
    #[must_use]
    pub fn bxdf(&self) -> Bxdf {
        Bxdf::ThinDielectric(ThinDielectricBxdf { eta: self.eta })
    }
}
