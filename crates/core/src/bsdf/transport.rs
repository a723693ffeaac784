//! What a lobe is asked for when it is one layer of a stack (pbrt-v4 `TransportMode` and
//! `BxDFReflTransFlags`): the quantity transported, and which scattering kinds a sampling
//! routine may choose. Only [`super::LayeredBxdf`] uses anything but the defaults
//! (radiance, everything).

/// The quantity carried along a path. Only refraction cares: radiance is scaled by
/// `1 / eta'^2` when it crosses an interface, importance is not (pbrt-v4 section 9.5.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TransportMode {
    /// Radiance, traced from the camera: the BSDF `f(wo, wi)`.
    Radiance,
    /// Importance, traced from the lights: the adjoint BSDF `f*(wo, wi) = f(wi, wo)`.
    Importance,
}

/// The scattering kinds a sampling routine may choose; it samples among those allowed in
/// proportion to their Fresnel weights and its pdf is that of the restricted routine.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReflTrans {
    /// Reflection and transmission.
    All,
    /// Reflection only.
    Reflection,
    /// Transmission only.
    Transmission,
}

impl ReflTrans {
    /// The probabilities of choosing reflection and transmission, given their weights
    /// `r` and `t`: the allowed weights normalised; `None` when nothing allowed has weight.
    #[must_use]
    pub fn probabilities(self, r: f32, t: f32) -> Option<(f32, f32)> {
        let (pr, pt) = match self {
            Self::All => (r, t),
            Self::Reflection => (r, 0.0),
            Self::Transmission => (0.0, t),
        };
        let sum = pr + pt;
        if sum > 0.0 {
            Some((pr / sum, pt / sum))
        } else {
            None
        }
    }
}
