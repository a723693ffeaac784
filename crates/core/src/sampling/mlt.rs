//! [`MltSampler`]: the primary sample space sampler of Metropolis light transport (Kelemen
//! et al. 2002, "A simple and robust mutation strategy for the Metropolis light transport
//! algorithm"; pbrt-v4 `MLTSampler`).
//!
//! A state is a vector of uniform numbers in [0, 1). Each iteration proposes a new state
//! lazily, one dimension at a time as the path asks for it: a *large step* (probability
//! `large_step_probability`) replaces a value with a fresh uniform one, a *small step*
//! adds a normal perturbation of standard deviation `sigma` and wraps the result into
//! [0, 1). A dimension not touched for `n` iterations receives the `n` small steps it
//! missed at once (their sum is normal with deviation `sigma sqrt(n)`), or a fresh value if
//! a large step was accepted since. Both proposals are symmetric, so the acceptance
//! probability is the ratio of the target function alone. Rejection restores the values
//! the iteration changed.
//!
//! Dimensions are interleaved over `stream_count` streams (camera, light, connection), so
//! that the number of values one part of the path uses does not shift the others.

use super::{Pcg32, SampleSource};
use crate::bytes::{ByteReader, ByteWriter};
use crate::math::Vec2;

/// One dimension of the state.
#[derive(Clone, Copy, Debug, Default)]
struct PrimarySample {
    value: f32,
    /// Iteration of the last change.
    last_modified: u64,
    /// The value and iteration before the current iteration's change (for rejection).
    value_backup: f32,
    modify_backup: u64,
}

/// A Markov chain's state in primary sample space, mutated lazily.
#[derive(Clone, Debug)]
pub struct MltSampler {
    rng: Pcg32,
    sigma: f32,
    large_step_probability: f32,
    stream_count: usize,
    x: Vec<PrimarySample>,
    iteration: u64,
    large_step: bool,
    last_large_step: u64,
    stream: usize,
    sample_index: usize,
}

impl MltSampler {
    /// A state drawn uniformly (iteration 0 is a large step) from the random stream
    /// `(seq_index, seed)`: the same arguments give the same state, which is how a chain
    /// restarts from a bootstrap sample.
    #[must_use]
    pub fn new(seq_index: u64, seed: u64, sigma: f32, large_step_probability: f32, stream_count: usize) -> Self {
        Self {
            rng: Pcg32::new(seq_index, seed),
            sigma,
            large_step_probability,
            stream_count: stream_count.max(1),
            x: Vec::new(),
            iteration: 0,
            large_step: true,
            last_large_step: 0,
            stream: 0,
            sample_index: 0,
        }
    }

    /// Save the chain's whole state (generator, iteration counters, every dimension with
    /// its backup) to `w`, for [`Self::read`]; sigma, the large step probability and the
    /// stream count are settings, not saved.
    pub fn write(&self, w: &mut ByteWriter) {
        self.rng.write(w);
        w.u64(self.iteration);
        w.u8(u8::from(self.large_step));
        w.u64(self.last_large_step);
        w.u64(self.stream as u64);
        w.u64(self.sample_index as u64);
        w.u64(self.x.len() as u64);
        for xi in &self.x {
            w.f32(xi.value);
            w.u64(xi.last_modified);
            w.f32(xi.value_backup);
            w.u64(xi.modify_backup);
        }
    }

    /// The state [`Self::write`] saved, with these settings: it continues exactly as the
    /// saved one would have.
    ///
    /// # Errors
    /// When the bytes run out or do not describe a state (a change after the current
    /// iteration, a stream out of range).
    pub fn read(
        r: &mut ByteReader<'_>,
        sigma: f32,
        large_step_probability: f32,
        stream_count: usize,
    ) -> Result<Self, String> {
        /// Bytes per dimension.
        const DIMENSION_BYTES: u64 = 24;
        let rng = Pcg32::read(r)?;
        let iteration = r.u64()?;
        let large_step = match r.u8()? {
            0 => false,
            1 => true,
            v => return Err(format!("a large-step flag of {v}")),
        };
        let last_large_step = r.u64()?;
        let stream = r.u64()?;
        let sample_index = r.u64()?;
        let n = r.u64()?;
        let stream_count = stream_count.max(1);
        if stream >= stream_count as u64 || sample_index > u64::from(u32::MAX) {
            return Err(format!(
                "stream {stream}, sample {sample_index} of a {stream_count}-stream sampler"
            ));
        }
        if n.checked_mul(DIMENSION_BYTES).is_none_or(|b| b > r.remaining() as u64) {
            return Err(format!("{n} dimensions in {} bytes", r.remaining()));
        }
        let mut x = Vec::with_capacity(n as usize);
        for _ in 0..n {
            x.push(PrimarySample {
                value: r.f32()?,
                last_modified: r.u64()?,
                value_backup: r.f32()?,
                modify_backup: r.u64()?,
            });
        }
        let after = |t: u64| t > iteration;
        if after(last_large_step) || x.iter().any(|xi| after(xi.last_modified) || after(xi.modify_backup)) {
            return Err(format!("a change after the current iteration {iteration}"));
        }
        Ok(Self {
            rng,
            sigma,
            large_step_probability,
            stream_count,
            x,
            iteration,
            large_step,
            last_large_step,
            stream: stream as usize,
            sample_index: sample_index as usize,
        })
    }

    /// Begin a proposal: a large step with probability `large_step_probability`.
    pub fn start_iteration(&mut self) {
        self.iteration += 1;
        self.large_step = self.rng.next_f32() < self.large_step_probability;
    }

    /// Whether the current proposal is a large step.
    #[must_use]
    pub fn is_large_step(&self) -> bool {
        self.large_step
    }

    /// Keep the proposal as the chain's new state.
    pub fn accept(&mut self) {
        if self.large_step {
            self.last_large_step = self.iteration;
        }
    }

    /// Discard the proposal: the dimensions it changed return to their previous values.
    pub fn reject(&mut self) {
        for xi in &mut self.x {
            if xi.last_modified == self.iteration {
                xi.value = xi.value_backup;
                xi.last_modified = xi.modify_backup;
            }
        }
        self.iteration -= 1;
    }

    /// Start drawing from stream `index` (from its first dimension).
    pub fn start_stream(&mut self, index: usize) {
        debug_assert!(index < self.stream_count);
        self.stream = index;
        self.sample_index = 0;
    }

    /// Bring dimension `i` up to the current iteration.
    fn ensure_ready(&mut self, i: usize) {
        if i >= self.x.len() {
            // A dimension never used so far: any uniform value is a draw from the state's
            // (uniform) distribution, so it starts fresh as of the last large step.
            let fresh = self.x.len()..=i;
            for _ in fresh {
                let value = self.rng.next_f32();
                self.x.push(PrimarySample {
                    value,
                    last_modified: self.last_large_step,
                    value_backup: value,
                    modify_backup: self.last_large_step,
                });
            }
        }
        let (iteration, large_step, last_large_step) = (self.iteration, self.large_step, self.last_large_step);
        let xi = &mut self.x[i];
        if xi.last_modified == iteration {
            return;
        }
        // A large step was accepted after this dimension's last change: it got a fresh value
        // then.
        if xi.last_modified < last_large_step {
            xi.value = self.rng.next_f32();
            xi.last_modified = last_large_step;
        }
        xi.value_backup = xi.value;
        xi.modify_backup = xi.last_modified;
        if large_step {
            xi.value = self.rng.next_f32();
        } else {
            // The small steps this dimension missed, at once: their sum is normal with
            // deviation sigma sqrt(n).
            let n = (iteration - xi.last_modified) as f32;
            let z = standard_normal(&mut self.rng);
            xi.value = wrap(xi.value + self.sigma * n.sqrt() * z);
        }
        xi.last_modified = iteration;
    }
}

impl SampleSource for MltSampler {
    fn get_1d(&mut self) -> f32 {
        let i = self.stream + self.stream_count * self.sample_index;
        self.sample_index += 1;
        self.ensure_ready(i);
        self.x[i].value
    }

    fn get_2d(&mut self) -> Vec2 {
        let a = self.get_1d();
        Vec2::new(a, self.get_1d())
    }
}

/// `v` wrapped into [0, 1).
#[inline]
fn wrap(v: f32) -> f32 {
    let w = v - v.floor();
    // `v - floor(v)` rounds to 1 for tiny negative `v`.
    if w >= 1.0 {
        0.0
    } else {
        w
    }
}

/// A standard normal deviate (Box-Muller transform; the second deviate is discarded).
fn standard_normal(rng: &mut Pcg32) -> f32 {
    let u1 = 1.0 - rng.next_f32(); // in (0, 1]
    let u2 = rng.next_f32();
    (-2.0 * u1.ln()).sqrt() * (2.0 * std::f32::consts::PI * u2).cos()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejection_restores_the_state() {
        let mut s = MltSampler::new(3, 7, 0.01, 0.3, 3);
        s.start_stream(1);
        let before: Vec<f32> = (0..6).map(|_| s.get_1d()).collect();
        for _ in 0..20 {
            s.start_iteration();
            s.start_stream(1);
            let proposed: Vec<f32> = (0..6).map(|_| s.get_1d()).collect();
            assert_ne!(proposed, before);
            s.reject();
        }
        // After the rejections the state is the one before them.
        let values: Vec<f32> = s.x.iter().skip(1).step_by(3).map(|x| x.value).collect();
        assert_eq!(values, before);
    }

    #[test]
    fn the_same_stream_gives_the_same_state() {
        let draw = || {
            let mut s = MltSampler::new(11, 5, 0.01, 0.3, 3);
            s.start_stream(0);
            (0..8).map(|_| s.get_1d()).collect::<Vec<_>>()
        };
        assert_eq!(draw(), draw());
    }

    #[test]
    fn a_saved_state_continues_exactly_and_bad_states_are_refused() {
        let mut s = MltSampler::new(4, 9, 0.05, 0.3, 3);
        let draw = |s: &mut MltSampler, k: usize| {
            let mut v = Vec::new();
            for i in 0..k {
                s.start_iteration();
                s.start_stream(i % 3);
                v.extend((0..5).map(|_| s.get_1d()));
                if i % 2 == 0 {
                    s.accept();
                } else {
                    s.reject();
                }
            }
            v
        };
        draw(&mut s, 11); // ends on stream 1
        let mut w = ByteWriter::new();
        s.write(&mut w);
        let bytes = w.into_bytes();
        let mut r = ByteReader::new(&bytes);
        let mut back = MltSampler::read(&mut r, 0.05, 0.3, 3).unwrap();
        r.finish().unwrap();
        assert_eq!(draw(&mut back, 20), draw(&mut s, 20));
        // Cut short, or a stream the sampler does not have.
        assert!(MltSampler::read(&mut ByteReader::new(&bytes[..bytes.len() - 1]), 0.05, 0.3, 3).is_err());
        assert!(MltSampler::read(&mut ByteReader::new(&bytes), 0.05, 0.3, 1).is_err());
    }

    #[test]
    fn wrap_stays_in_the_unit_interval() {
        for v in [-1e-9_f32, -0.25, 0.0, 0.999_999_94, 1.0, 2.5, -3.75] {
            let w = wrap(v);
            assert!((0.0..1.0).contains(&w), "{v} -> {w}");
        }
    }
}
