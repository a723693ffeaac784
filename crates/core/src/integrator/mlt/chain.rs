//! One Markov chain of MLT ([`Chain`]): its primary sample space state, the path that state
//! maps to, and the generator of its acceptance decisions. A chain advances one mutation
//! at a time and is a consistent state after any of them, so it can stop anywhere (a
//! cancelled render, a checkpoint) and continue later, saved with [`Chain::write`], to the
//! same splats as a chain never stopped.

use std::sync::atomic::{AtomicBool, Ordering};

use super::contribution::{contribution, Buffers, PathSample, Raster};
use super::MltSettings;
use crate::bytes::{ByteReader, ByteWriter};
use crate::color::Rgb;
use crate::film::Splat;
use crate::integrator::bdpt::vertex::Context;
use crate::integrator::TraceStats;
use crate::math::Vec2;
use crate::sampling::{hash_u64s, MltSampler, Pcg32};

use super::contribution::STREAM_COUNT;

/// Mutations between two looks at the cancel flag.
const CANCEL_CHECK: u64 = 256;

/// A running chain.
#[derive(Clone, Debug)]
pub(super) struct Chain {
    /// The bootstrap state it started from (its depth is `start mod (maxdepth + 1)`).
    start: u64,
    /// Depth of its paths.
    depth: usize,
    /// Acceptance decisions.
    rng: Pcg32,
    sampler: MltSampler,
    /// The path of the current state and its luminance.
    current: PathSample,
    y_current: f32,
    /// Mutations made.
    pub done: u64,
    /// Proposals accepted.
    pub accepted: u64,
}

/// The generator of chain `index`'s decisions: its first draw picks the start.
fn chain_rng(index: u64, settings: &MltSettings) -> Pcg32 {
    Pcg32::new(index, hash_u64s(&[settings.seed, 0x6d6c_7400]))
}

/// The primary sample space state of bootstrap sample `index`.
pub(super) fn bootstrap_sampler(index: u64, settings: &MltSettings) -> MltSampler {
    MltSampler::new(
        index,
        settings.seed,
        settings.sigma,
        settings.large_step_probability,
        STREAM_COUNT,
    )
}

/// The bootstrap state chain `index` starts from: state `i` with probability `Y_i / sum Y`,
/// `cdf` being the running sums of the bootstrap luminances (not all zero).
pub(super) fn choose_start(index: u64, cdf: &[f64], settings: &MltSettings) -> u64 {
    let total = *cdf.last().expect("a non-empty bootstrap");
    let u = f64::from(chain_rng(index, settings).next_f32()) * total;
    cdf.partition_point(|&c| c <= u).min(cdf.len() - 1) as u64
}

impl Chain {
    /// Chain `index` at bootstrap state `start` (as [`choose_start`] chose it).
    pub fn begin(
        ctx: &Context<'_>,
        index: u64,
        start: u64,
        settings: &MltSettings,
        raster: &Raster,
        buffers: &mut Buffers,
        trace: &mut TraceStats,
    ) -> Self {
        let mut rng = chain_rng(index, settings);
        // The draw that chose the start.
        rng.next_f32();
        let depth = (start % (u64::from(settings.max_depth) + 1)) as usize;
        let mut sampler = bootstrap_sampler(start, settings);
        let current = contribution(ctx, &mut sampler, depth, raster, buffers, trace);
        Self {
            start,
            depth,
            rng,
            sampler,
            current,
            y_current: current.l.luminance().max(0.0),
            done: 0,
            accepted: 0,
        }
    }

    /// Make up to `n` mutations, pushing their splats (not yet scaled by `b`) onto `splats`;
    /// stops early, after a whole mutation, when `cancel` is set.
    #[allow(clippy::too_many_arguments)]
    pub fn run(
        &mut self,
        ctx: &Context<'_>,
        n: u64,
        raster: &Raster,
        buffers: &mut Buffers,
        splats: &mut Vec<Splat>,
        trace: &mut TraceStats,
        cancel: &AtomicBool,
    ) {
        for j in 0..n {
            if j % CANCEL_CHECK == 0 && j > 0 && cancel.load(Ordering::Relaxed) {
                return;
            }
            self.mutate(ctx, raster, buffers, splats, trace);
        }
    }

    /// One Metropolis-Hastings step with symmetric proposals; both states are splatted with
    /// the probability of the chain being there next (expected values, Veach 1997 11.5).
    fn mutate(
        &mut self,
        ctx: &Context<'_>,
        raster: &Raster,
        buffers: &mut Buffers,
        splats: &mut Vec<Splat>,
        trace: &mut TraceStats,
    ) {
        self.sampler.start_iteration();
        let proposed = contribution(ctx, &mut self.sampler, self.depth, raster, buffers, trace);
        let y_proposed = proposed.l.luminance().max(0.0);
        let accept = if self.y_current > 0.0 {
            (y_proposed / self.y_current).min(1.0)
        } else {
            1.0
        };
        if accept > 0.0 && y_proposed > 0.0 {
            splats.push(Splat {
                p_film: proposed.p_raster,
                l: proposed.l * (accept / y_proposed),
            });
        }
        if accept < 1.0 && self.y_current > 0.0 {
            splats.push(Splat {
                p_film: self.current.p_raster,
                l: self.current.l * ((1.0 - accept) / self.y_current),
            });
        }
        if self.rng.next_f32() < accept {
            self.current = proposed;
            self.y_current = y_proposed;
            self.sampler.accept();
            self.accepted += 1;
        } else {
            self.sampler.reject();
        }
        self.done += 1;
    }

    /// Save the chain to `w`, for [`Self::read`].
    pub fn write(&self, w: &mut ByteWriter) {
        w.u64(self.start);
        w.u64(self.done);
        w.u64(self.accepted);
        self.rng.write(w);
        let PathSample { l, p_raster } = self.current;
        for v in [l.r, l.g, l.b, p_raster.x, p_raster.y, self.y_current] {
            w.f32(v);
        }
        self.sampler.write(w);
    }

    /// The chain [`Self::write`] saved, under `settings`, with a bootstrap of
    /// `n_bootstrap` states.
    ///
    /// # Errors
    /// When the bytes run out or do not describe a chain of these settings.
    pub fn read(r: &mut ByteReader<'_>, settings: &MltSettings, n_bootstrap: u64) -> Result<Self, String> {
        let (start, done, accepted) = (r.u64()?, r.u64()?, r.u64()?);
        if start >= n_bootstrap || accepted > done {
            return Err(format!(
                "a chain from bootstrap state {start} of {n_bootstrap}, {accepted} of {done} accepted"
            ));
        }
        let rng = Pcg32::read(r)?;
        let mut v = [0.0f32; 6];
        for x in &mut v {
            *x = r.f32()?;
        }
        let sampler = MltSampler::read(r, settings.sigma, settings.large_step_probability, STREAM_COUNT)?;
        Ok(Self {
            start,
            depth: (start % (u64::from(settings.max_depth) + 1)) as usize,
            rng,
            sampler,
            current: PathSample {
                l: Rgb::new(v[0], v[1], v[2]),
                p_raster: Vec2::new(v[3], v[4]),
            },
            y_current: v[5],
            done,
            accepted,
        })
    }
}
