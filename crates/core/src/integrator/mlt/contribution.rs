//! The target function of multiplexed MLT (Hachisuka et al. 2014, "Multiplexed Metropolis
//! light transport"; pbrt-v4 `MLTIntegrator::L`): a point of primary sample space is
//! mapped to one bidirectional path of a fixed depth and one connection strategy `(s, t)`,
//! chosen by the state's first camera-stream value, and its contribution is that
//! strategy's MIS-weighted estimate times the number of strategies (the strategy was
//! picked with probability one over that number).

use crate::color::Rgb;
use crate::integrator::bdpt::connect::connect;
use crate::integrator::bdpt::mis::MisMode;
use crate::integrator::bdpt::subpath::{camera_subpath, light_subpath};
use crate::integrator::bdpt::vertex::{Context, Vertex};
use crate::integrator::TraceStats;
use crate::math::Vec2;
use crate::sampling::{MltSampler, SampleSource};

/// The sample streams: camera subpath, light subpath, connection.
pub const CAMERA_STREAM: usize = 0;
/// See [`CAMERA_STREAM`].
pub const LIGHT_STREAM: usize = 1;
/// See [`CAMERA_STREAM`].
pub const CONNECTION_STREAM: usize = 2;
/// Number of streams.
pub const STREAM_COUNT: usize = 3;

/// A path's contribution and the raster position it lands on.
#[derive(Clone, Copy, Debug)]
pub struct PathSample {
    /// Contribution (zero when the state maps to no path).
    pub l: Rgb,
    /// Raster position.
    pub p_raster: Vec2,
}

/// Reusable subpath storage.
#[derive(Default)]
pub struct Buffers {
    camera: Vec<Vertex>,
    light: Vec<Vertex>,
}

/// The contribution of the sampler's current state to paths of `depth` scattering events
/// on a film of `resolution` pixels.
pub fn contribution(
    ctx: &Context<'_>,
    sampler: &mut MltSampler,
    depth: usize,
    resolution: Vec2,
    buffers: &mut Buffers,
    stats: &mut TraceStats,
) -> PathSample {
    sampler.start_stream(CAMERA_STREAM);
    // Choose the strategy: depth 0 is only the camera path hitting a light.
    let (s, t, strategies) = if depth == 0 {
        (0, 2, 1)
    } else {
        let n = depth + 2;
        let s = ((sampler.get_1d() * n as f32) as usize).min(n - 1);
        (s, n - s, n)
    };
    // A camera subpath of exactly t vertices, through a raster position uniform on the film.
    let p_raster = sampler.get_2d() * resolution;
    let none = PathSample {
        l: Rgb::BLACK,
        p_raster,
    };
    let ray = ctx.scene.camera.generate_ray(p_raster, sampler.get_2d());
    camera_subpath(ctx, ray, sampler, t, &mut buffers.camera, stats);
    if buffers.camera.len() != t {
        return none;
    }
    // A light subpath of exactly s vertices.
    sampler.start_stream(LIGHT_STREAM);
    light_subpath(ctx, sampler, s, &mut buffers.light, stats);
    if buffers.light.len() != s {
        return none;
    }
    // Connect them.
    sampler.start_stream(CONNECTION_STREAM);
    let Some(c) = connect(
        ctx,
        &buffers.light,
        &buffers.camera,
        s,
        t,
        MisMode::Power,
        sampler,
        stats,
    ) else {
        return none;
    };
    let l = c.l * strategies as f32;
    if !l.is_finite() {
        return none;
    }
    PathSample {
        l,
        p_raster: c.p_raster.unwrap_or(p_raster),
    }
}
