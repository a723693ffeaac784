//! What a texture sees of a surface point: position, uv and their screen-space derivatives
//! (pbrt-v4 `TextureEvalContext`), and the least-squares solve that turns the point's
//! screen-space derivatives `dp/dx`, `dp/dy` into `du/dx`, ... (pbrt-v4 section 10.1.1,
//! `SurfaceInteraction::ComputeDifferentials`).

use crate::math::{Vec2, Vec3};
use crate::shape::{MeshPoint, SurfaceInteraction};

/// A point to evaluate textures at, with the footprint of a pixel sample around it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TextureContext {
    /// World-space point.
    pub p: Vec3,
    /// Change of `p` per pixel step in x on the image.
    pub dpdx: Vec3,
    /// Change of `p` per pixel step in y.
    pub dpdy: Vec3,
    /// Surface parameterisation.
    pub uv: Vec2,
    /// `du/dx`.
    pub dudx: f32,
    /// `du/dy`.
    pub dudy: f32,
    /// `dv/dx`.
    pub dvdx: f32,
    /// `dv/dy`.
    pub dvdy: f32,
    /// The triangle and barycentrics on a mesh, for mesh attributes.
    pub mesh: MeshPoint,
}

impl TextureContext {
    /// The context at `si` without a footprint (point lookups).
    #[must_use]
    pub fn at_point(si: &SurfaceInteraction) -> Self {
        Self {
            p: si.p(),
            uv: si.uv,
            mesh: si.mesh,
            ..Self::default()
        }
    }

    /// The context at `si` for a pixel footprint `dpdx`, `dpdy` on the surface: `du/dx`
    /// etc. solve `dp/dx = dp/du du/dx + dp/dv dv/dx` in the least-squares sense through
    /// the normal equations (pbrt-v4 eq. 10.7), clamped to +-1e8 and zeroed when not
    /// finite.
    #[must_use]
    pub fn with_footprint(si: &SurfaceInteraction, dpdx: Vec3, dpdy: Vec3) -> Self {
        let (dpdu, dpdv) = (si.dp_du, si.dp_dv);
        let ata00 = dpdu.dot(dpdu);
        let ata01 = dpdu.dot(dpdv);
        let ata11 = dpdv.dot(dpdv);
        let inv_det = 1.0 / (ata00 * ata11 - ata01 * ata01);
        let inv_det = if inv_det.is_finite() { inv_det } else { 0.0 };
        let solve = |d: Vec3| {
            let (b0, b1) = (dpdu.dot(d), dpdv.dot(d));
            let du = (ata11 * b0 - ata01 * b1) * inv_det;
            let dv = (ata00 * b1 - ata01 * b0) * inv_det;
            let fix = |v: f32| if v.is_finite() { v.clamp(-1e8, 1e8) } else { 0.0 };
            (fix(du), fix(dv))
        };
        let (dudx, dvdx) = solve(dpdx);
        let (dudy, dvdy) = solve(dpdy);
        Self {
            p: si.p(),
            dpdx,
            dpdy,
            uv: si.uv,
            dudx,
            dudy,
            dvdx,
            dvdy,
            mesh: si.mesh,
        }
    }
}
