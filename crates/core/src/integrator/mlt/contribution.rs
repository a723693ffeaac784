//! The target function of multiplexed MLT (Hachisuka et al. 2014, "Multiplexed Metropolis
//! light transport"; pbrt-v4 `MLTIntegrator::L`): a point of primary sample space is
//! mapped to one bidirectional path of a fixed depth and one connection strategy `(s, t)`,
//! chosen by the state's first camera-stream value, and its contribution is that
//! strategy's MIS-weighted estimate times the number of strategies (the strategy was
//! picked with probability one over that number).
//!
//! The camera subpath starts at a raster position uniform over the film's sample bounds
//! ([`crate::camera::Camera::sample_bounds`]), so that the strategies with `t >= 2` reach
//! every path a pixel's filter sees, also beyond the image's border. The camera's
//! densities (`pdf_we`, which the connection's MIS weights and throughput use) are those of
//! a position uniform over the pixel bounds, `area(pixel bounds) / area(sample bounds)`
//! times the density actually used; those strategies' contributions are therefore
//! multiplied by the inverse ratio, [`Raster::camera_scale`]. The `t = 1` strategies find
//! their raster position through the lens connection and keep their value.

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

/// Where camera subpaths start: a raster position uniform over the sample bounds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Raster {
    /// Corner of the sample bounds.
    pub min: Vec2,
    /// Size of the sample bounds.
    pub size: Vec2,
    /// `area(sample bounds) / area(pixel bounds)`: the factor of the contributions whose
    /// raster position was drawn here (`t >= 2`).
    pub camera_scale: f32,
}

impl Raster {
    /// The sample bounds of `ctx`'s camera, for a film of `width x height` pixels.
    #[must_use]
    pub fn new(ctx: &Context<'_>, width: u32, height: u32) -> Self {
        let [min, max] = ctx.scene.camera.sample_bounds();
        let size = max - min;
        Self {
            min,
            size,
            camera_scale: size.x * size.y / (width as f32 * height as f32),
        }
    }
}

/// Reusable subpath storage.
#[derive(Default)]
pub struct Buffers {
    camera: Vec<Vertex>,
    light: Vec<Vertex>,
}

/// The contribution of the sampler's current state to paths of `depth` scattering events,
/// the camera subpath starting in `raster`.
pub fn contribution(
    ctx: &Context<'_>,
    sampler: &mut MltSampler,
    depth: usize,
    raster: &Raster,
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
    // A camera subpath of exactly t vertices, through a raster position uniform on the
    // sample bounds.
    let p_raster = raster.min + sampler.get_2d() * raster.size;
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
    let scale = if t >= 2 { raster.camera_scale } else { 1.0 };
    let l = c.l * (strategies as f32 * scale);
    if !l.is_finite() {
        return none;
    }
    PathSample {
        l,
        p_raster: c.p_raster.unwrap_or(p_raster),
    }
}
