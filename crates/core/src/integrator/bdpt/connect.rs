//! Connecting a light subpath prefix of `s` vertices to a camera subpath prefix of `t`
//! vertices (pbrt-v4 `ConnectBDPT`), the contribution of one strategy `(s, t)`:
//! - `s = 0`: the camera subpath itself ends on an emitter;
//! - `t = 1`: the light vertex is joined to a point sampled on the camera lens, and the
//!   result lands on whatever pixel that direction falls in (a splat);
//! - `s = 1`: the camera vertex is joined to a point sampled on a light (next-event
//!   estimation, with the light's own sampling rather than the light subpath's origin);
//! - otherwise the two end vertices are joined by a shadow ray, with the geometry term
//!   `|cos| |cos| / r^2` between them.

use super::mis::{mis_weight, MisMode};
use super::vertex::{Context, Vertex, VertexKind};
use crate::bsdf::TransportMode;
use crate::color::Rgb;
use crate::integrator::TraceStats;
use crate::math::Vec2;
use crate::sampling::SampleSource;
use crate::shape::Interaction;

/// The contribution of one strategy.
#[derive(Clone, Copy, Debug)]
pub struct Connection {
    /// Weighted contribution (MIS weight included).
    pub l: Rgb,
    /// For `t = 1`, the raster position the contribution lands on.
    pub p_raster: Option<Vec2>,
}

/// Connect `light[..s]` with `camera[..t]`; `None` when the strategy contributes nothing.
#[allow(clippy::too_many_arguments)]
pub fn connect(
    ctx: &Context<'_>,
    light: &[Vertex],
    camera: &[Vertex],
    s: usize,
    t: usize,
    mis: MisMode,
    sampler: &mut impl SampleSource,
    stats: &mut TraceStats,
) -> Option<Connection> {
    let scene = ctx.scene;
    // A camera subpath that left the scene can only be completed by s = 0.
    if t > 1 && s != 0 && matches!(camera[t - 1].kind, VertexKind::Light(_)) {
        return None;
    }
    let mut sampled: Option<Vertex> = None;
    let mut p_raster = None;
    let l = if s == 0 {
        // The camera subpath ends on an emitter.
        let pt = &camera[t - 1];
        if !pt.is_light() {
            return None;
        }
        pt.le(scene, &camera[t - 2]) * pt.beta
    } else if t == 1 {
        // Join the light vertex to a point on the lens.
        let qs = &light[s - 1];
        if !qs.is_connectible(scene) {
            return None;
        }
        let cs = scene.camera.sample_wi(qs.p(), sampler.get_2d())?;
        if cs.pdf == 0.0 || cs.we == 0.0 {
            return None;
        }
        let cam = Vertex::camera(Interaction::point(cs.p_lens), Rgb::splat(cs.we / cs.pdf));
        let mut l = qs.beta * qs.f(&cam, TransportMode::Importance) * cam.beta;
        if qs.is_on_surface() {
            l *= cs.wi.dot(qs.ns()).abs();
        }
        if l.is_black() {
            return None;
        }
        stats.shadow_rays += 1;
        if !scene.unoccluded(&qs.intr, &cam.intr) {
            return None;
        }
        p_raster = Some(cs.p_raster);
        sampled = Some(cam);
        l
    } else if s == 1 {
        // Join the camera vertex to a point sampled on a light.
        let pt = &camera[t - 1];
        if !pt.is_connectible(scene) {
            return None;
        }
        let (index, pmf) = scene.light_sampler.sample(sampler.get_1d())?;
        let u = sampler.get_2d();
        let ls = scene.lights[index].sample_li(&pt.intr, u)?;
        if ls.pdf == 0.0 || ls.l.is_black() {
            return None;
        }
        let mut v = Vertex::light(scene, index as u32, ls.p_light, ls.l / (ls.pdf * pmf), 0.0);
        v.pdf_fwd = v.pdf_light_origin(ctx, pt);
        let mut l = pt.beta * pt.f(&v, TransportMode::Radiance) * v.beta;
        if pt.is_on_surface() {
            l *= ls.wi.dot(pt.ns()).abs();
        }
        if l.is_black() {
            return None;
        }
        stats.shadow_rays += 1;
        if !scene.unoccluded(&pt.intr, &ls.p_light) {
            return None;
        }
        sampled = Some(v);
        l
    } else {
        // Join two inner vertices by a shadow ray.
        let (qs, pt) = (&light[s - 1], &camera[t - 1]);
        if !qs.is_connectible(scene) || !pt.is_connectible(scene) {
            return None;
        }
        let l = qs.beta * qs.f(pt, TransportMode::Importance) * pt.f(qs, TransportMode::Radiance) * pt.beta;
        if l.is_black() {
            return None;
        }
        let g = geometry(qs, pt);
        if g == 0.0 {
            return None;
        }
        stats.shadow_rays += 1;
        if !scene.unoccluded(&qs.intr, &pt.intr) {
            return None;
        }
        l * g
    };
    if l.is_black() {
        return None;
    }
    let weight = match mis {
        MisMode::Power => mis_weight(ctx, light, camera, sampled.as_ref(), s, t),
        MisMode::Off => 1.0,
    };
    Some(Connection {
        l: l * weight,
        p_raster,
    })
}

/// `|cos theta_a| |cos theta_b| / r^2` between two vertices, with shading normals at
/// surfaces (visibility tested separately).
fn geometry(a: &Vertex, b: &Vertex) -> f32 {
    let d = a.p() - b.p();
    let d2 = d.length_squared();
    if d2 == 0.0 {
        return 0.0;
    }
    let mut g = 1.0 / d2;
    let w = d * g.sqrt();
    if a.is_on_surface() {
        g *= a.ns().dot(w).abs();
    }
    if b.is_on_surface() {
        g *= b.ns().dot(w).abs();
    }
    g
}
