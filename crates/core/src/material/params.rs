//! User parameters to BSDF parameters, shared by several materials: roughness to
//! microfacet alpha, a conductor's index from a reflectance, the coat of a layered
//! material.

use crate::bsdf::{roughness_to_alpha, DielectricBxdf, Microfacet};
use crate::color::Rgb;
use crate::texture::{FloatTexture, RgbTexture, TextureContext};

/// The largest `|g|` a slab keeps: pbrt clamps `g` to [-1, 1], but the Henyey-Greenstein
/// formula is 0/0 at the ends (a Dirac delta), so we stop just short of them.
pub(super) const MAX_ABS_G: f32 = 0.999;

/// The conductor index `(eta, k)` whose normal-incidence reflectance is `r` (pbrt-v4,
/// with `eta = 1`: `((eta-1)^2 + k^2) / ((eta+1)^2 + k^2) = r` gives `k = 2 sqrt(r) /
/// sqrt(1 - r)`), `r` clamped to [0, 0.9999].
pub(super) fn index_from_reflectance(r: Rgb) -> (Rgb, Rgb) {
    let r = r.map(|v| v.clamp(0.0, 0.9999));
    (Rgb::WHITE, r.map(|v| 2.0 * v.sqrt() / (1.0 - v).max(0.0).sqrt()))
}

/// Microfacet alpha from a user roughness, remapped as pbrt does when asked.
pub(super) fn alpha(roughness: f32, remap: bool) -> f32 {
    if remap {
        roughness_to_alpha(roughness)
    } else {
        roughness.max(0.0)
    }
}

/// The dielectric coat of a layered material; an index of 0 means 1, as in pbrt-v4.
pub(super) fn coat(eta: f32, u_roughness: f32, v_roughness: f32, remap: bool) -> DielectricBxdf {
    DielectricBxdf {
        eta: if eta == 0.0 { 1.0 } else { eta },
        distrib: Microfacet::trowbridge_reitz(alpha(u_roughness, remap), alpha(v_roughness, remap)),
    }
}

/// A reflectance-like colour clamped to [0, 1] per channel.
pub(super) fn unit(c: Rgb) -> Rgb {
    c.map(|v| v.clamp(0.0, 1.0))
}

/// The slab between a layered material's coat and base at `ctx`: thickness (kept above 0),
/// albedo in [0, 1] and `g` clamped to [`MAX_ABS_G`].
pub(super) fn slab_at(
    thickness: &FloatTexture,
    albedo: &RgbTexture,
    g: &FloatTexture,
    ctx: &TextureContext,
) -> (f32, Rgb, f32) {
    (
        thickness.evaluate(ctx).max(f32::MIN_POSITIVE),
        unit(albedo.evaluate(ctx)),
        g.evaluate(ctx).clamp(-MAX_ABS_G, MAX_ABS_G),
    )
}

/// Whether the slab's textures are all constants.
pub(super) fn slab_is_constant(thickness: &FloatTexture, albedo: &RgbTexture, g: &FloatTexture) -> bool {
    thickness.is_constant() && albedo.is_constant() && g.is_constant()
}
