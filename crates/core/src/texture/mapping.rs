//! Texture coordinate generation (pbrt-v4 section 10.2, `TextureMapping2D`): from a
//! [`TextureContext`] to `(s, t)` and its screen-space derivatives.

use std::f32::consts::PI;

use super::TextureContext;
use crate::math::{Transform, Vec2, Vec3};

/// Texture coordinates with their derivatives per pixel step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TexCoord2D {
    /// The coordinates.
    pub st: Vec2,
    /// `ds/dx`.
    pub dsdx: f32,
    /// `ds/dy`.
    pub dsdy: f32,
    /// `dt/dx`.
    pub dtdx: f32,
    /// `dt/dy`.
    pub dtdy: f32,
}

/// How a 2-D texture is laid on a surface (pbrt `"string mapping"`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TextureMapping {
    /// `s = su u + du`, `t = sv v + dv` (pbrt `uv`: `uscale`, `vscale`, `udelta`,
    /// `vdelta`).
    Uv {
        /// `uscale`.
        su: f32,
        /// `vscale`.
        sv: f32,
        /// `udelta`.
        du: f32,
        /// `vdelta`.
        dv: f32,
    },
    /// Angles of the point seen from the texture-space origin: `s = theta / pi`,
    /// `t = phi / 2 pi` (pbrt `spherical`).
    Spherical {
        /// Texture-from-world transform (the inverse of the CTM at the `Texture`).
        texture_from_world: Transform,
    },
    /// Angle around and height along the texture-space z axis:
    /// `s = (pi + atan2(y, x)) / 2 pi`, `t = z` (pbrt `cylindrical`).
    Cylindrical {
        /// Texture-from-world transform.
        texture_from_world: Transform,
    },
    /// Projection onto two texture-space axes: `s = ds + p . vs`, `t = dt + p . vt`
    /// (pbrt `planar`: `v1`, `v2`, `udelta`, `vdelta`).
    Planar {
        /// Texture-from-world transform.
        texture_from_world: Transform,
        /// `v1`.
        vs: Vec3,
        /// `v2`.
        vt: Vec3,
        /// `udelta`.
        ds: f32,
        /// `vdelta`.
        dt: f32,
    },
}

impl Default for TextureMapping {
    fn default() -> Self {
        Self::Uv {
            su: 1.0,
            sv: 1.0,
            du: 0.0,
            dv: 0.0,
        }
    }
}

impl TextureMapping {
    /// Coordinates and their derivatives at `ctx`.
    #[must_use]
    pub fn map(&self, ctx: &TextureContext) -> TexCoord2D {
        match *self {
            Self::Uv { su, sv, du, dv } => TexCoord2D {
                st: Vec2::new(su * ctx.uv.x + du, sv * ctx.uv.y + dv),
                dsdx: su * ctx.dudx,
                dsdy: su * ctx.dudy,
                dtdx: sv * ctx.dvdx,
                dtdy: sv * ctx.dvdy,
            },
            Self::Spherical { texture_from_world } => {
                let pt = texture_from_world.point(ctx.p);
                let (dpdx, dpdy) = (texture_from_world.vector(ctx.dpdx), texture_from_world.vector(ctx.dpdy));
                let x2y2 = pt.x * pt.x + pt.y * pt.y;
                let r_xy = x2y2.sqrt();
                let r2 = x2y2 + pt.z * pt.z;
                // Gradients of theta / pi and phi / 2 pi (pbrt-v4 section 10.2.2; pbrt pairs
                // the phi gradient with s, we pair each with its own coordinate).
                let dsdp = if r_xy > 0.0 {
                    Vec3::new(pt.x * pt.z / r_xy, pt.y * pt.z / r_xy, -r_xy) / (PI * r2)
                } else {
                    Vec3::ZERO
                };
                let dtdp = if x2y2 > 0.0 {
                    Vec3::new(-pt.y, pt.x, 0.0) / (2.0 * PI * x2y2)
                } else {
                    Vec3::ZERO
                };
                let v = pt.normalize_or_zero();
                let theta = v.z.clamp(-1.0, 1.0).acos();
                let phi = v.y.atan2(v.x).rem_euclid(2.0 * PI);
                finite(TexCoord2D {
                    st: Vec2::new(theta / PI, phi / (2.0 * PI)),
                    dsdx: dsdp.dot(dpdx),
                    dsdy: dsdp.dot(dpdy),
                    dtdx: dtdp.dot(dpdx),
                    dtdy: dtdp.dot(dpdy),
                })
            }
            Self::Cylindrical { texture_from_world } => {
                let pt = texture_from_world.point(ctx.p);
                let (dpdx, dpdy) = (texture_from_world.vector(ctx.dpdx), texture_from_world.vector(ctx.dpdy));
                let x2y2 = pt.x * pt.x + pt.y * pt.y;
                let dsdp = if x2y2 > 0.0 {
                    Vec3::new(-pt.y, pt.x, 0.0) / (2.0 * PI * x2y2)
                } else {
                    Vec3::ZERO
                };
                finite(TexCoord2D {
                    st: Vec2::new((PI + pt.y.atan2(pt.x)) / (2.0 * PI), pt.z),
                    dsdx: dsdp.dot(dpdx),
                    dsdy: dsdp.dot(dpdy),
                    dtdx: dpdx.z,
                    dtdy: dpdy.z,
                })
            }
            Self::Planar {
                texture_from_world,
                vs,
                vt,
                ds,
                dt,
            } => {
                let p = texture_from_world.point(ctx.p);
                let (dpdx, dpdy) = (texture_from_world.vector(ctx.dpdx), texture_from_world.vector(ctx.dpdy));
                TexCoord2D {
                    st: Vec2::new(ds + p.dot(vs), dt + p.dot(vt)),
                    dsdx: vs.dot(dpdx),
                    dsdy: vs.dot(dpdy),
                    dtdx: vt.dot(dpdx),
                    dtdy: vt.dot(dpdy),
                }
            }
        }
    }
}

/// Zero derivatives that are not finite.
fn finite(mut c: TexCoord2D) -> TexCoord2D {
    for d in [&mut c.dsdx, &mut c.dsdy, &mut c.dtdx, &mut c.dtdy] {
        if !d.is_finite() {
            *d = 0.0;
        }
    }
    c
}
