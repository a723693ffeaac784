//! The PCG32 random number generator (O'Neill 2014, "PCG: A family of simple fast
//! space-efficient statistically good algorithms for random number generation"): a 64-bit
//! linear congruential state with the XSH-RR output permutation giving 32-bit numbers, and
//! 2^63 selectable streams.

use crate::bytes::{ByteReader, ByteWriter};

/// LCG multiplier of PCG32.
const MULT: u64 = 0x5851_f42d_4c95_7f2d;
/// Default state of the reference implementation (`PCG32_INITIALIZER`).
const DEFAULT_STATE: u64 = 0x853c_49e6_748f_ea9b;
/// Default increment (stream) of the reference implementation.
const DEFAULT_INC: u64 = 0xda3e_39cb_94b9_5bdb;
/// 2^-24: spacing of the `f32` values returned by [`Pcg32::next_f32`].
const INV_2_POW_24: f32 = 1.0 / 16_777_216.0;

/// A PCG-XSH-RR 64/32 generator: 64 bits of state, 32-bit outputs, period 2^64 in each of
/// 2^63 streams.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Pcg32 {
    state: u64,
    /// Stream selector; always odd.
    inc: u64,
}

impl Default for Pcg32 {
    /// The reference implementation's default generator (`PCG32_INITIALIZER`).
    fn default() -> Self {
        Self {
            state: DEFAULT_STATE,
            inc: DEFAULT_INC,
        }
    }
}

impl Pcg32 {
    /// The generator of stream `seq_index` started from `seed`; the same as
    /// `pcg32_srandom_r(rng, seed, seq_index)` of the reference implementation.
    #[must_use]
    pub fn new(seq_index: u64, seed: u64) -> Self {
        let mut rng = Self { state: 0, inc: 1 };
        rng.set_sequence(seq_index, seed);
        rng
    }

    /// Restarts the generator on stream `seq_index` from `seed` (reference seeding: step
    /// once from zero, add the seed, step again).
    pub fn set_sequence(&mut self, seq_index: u64, seed: u64) {
        self.state = 0;
        self.inc = (seq_index << 1) | 1;
        self.step();
        self.state = self.state.wrapping_add(seed);
        self.step();
    }

    /// Save the generator (state and stream) to `w`, for [`Self::read`].
    pub fn write(&self, w: &mut ByteWriter) {
        w.u64(self.state);
        w.u64(self.inc);
    }

    /// The generator [`Self::write`] saved.
    ///
    /// # Errors
    /// When the bytes run out or the stream selector is even (no generator has one).
    pub fn read(r: &mut ByteReader<'_>) -> Result<Self, String> {
        let (state, inc) = (r.u64()?, r.u64()?);
        if inc & 1 == 0 {
            return Err("a random generator with an even stream selector".into());
        }
        Ok(Self { state, inc })
    }

    /// One LCG step: `state = state * MULT + inc (mod 2^64)`.
    #[inline]
    fn step(&mut self) {
        self.state = self.state.wrapping_mul(MULT).wrapping_add(self.inc);
    }

    /// The next uniformly distributed 32-bit integer.
    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.step();
        // XSH-RR: xorshift the high bits down, then rotate by the top 5 bits.
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        let rot = (old >> 59) as u32;
        xorshifted.rotate_right(rot)
    }

    /// The next uniformly distributed float in [0, 1): the 24 high bits of
    /// [`next_u32`](Self::next_u32) times 2^-24, so every value is exact and 1 never occurs.
    #[inline]
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * INV_2_POW_24
    }

    /// Moves the generator `delta` steps forwards (backwards if negative) in O(log |delta|),
    /// by composing the affine LCG step with itself (Brown 1994, "Random number generation
    /// with arbitrary strides").
    pub fn advance(&mut self, delta: i64) {
        // A negative delta is the same as 2^64 - |delta| steps forwards: the period is 2^64.
        let mut delta = delta as u64;
        let (mut cur_mult, mut cur_plus) = (MULT, self.inc);
        let (mut acc_mult, mut acc_plus) = (1u64, 0u64);
        while delta > 0 {
            if delta & 1 == 1 {
                acc_mult = acc_mult.wrapping_mul(cur_mult);
                acc_plus = acc_plus.wrapping_mul(cur_mult).wrapping_add(cur_plus);
            }
            // Square the step: x -> m x + p applied twice is x -> m^2 x + (m + 1) p.
            cur_plus = cur_mult.wrapping_add(1).wrapping_mul(cur_plus);
            cur_mult = cur_mult.wrapping_mul(cur_mult);
            delta >>= 1;
        }
        self.state = acc_mult.wrapping_mul(self.state).wrapping_add(acc_plus);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_reference_pcg32_demo() {
        // pcg32-demo with seed 42, sequence 54 (pcg32_srandom_r(&rng, 42u, 54u)).
        let mut rng = Pcg32::new(54, 42);
        let expected = [
            0xa15c_02b7,
            0x7b47_f409,
            0xba1d_3330,
            0x83d2_f293,
            0xbfa4_784b,
            0xcbed_606e,
        ];
        for e in expected {
            assert_eq!(rng.next_u32(), e);
        }
    }

    #[test]
    fn set_sequence_restarts_the_stream() {
        let mut a = Pcg32::new(7, 11);
        let first: Vec<u32> = (0..8).map(|_| a.next_u32()).collect();
        a.set_sequence(7, 11);
        let again: Vec<u32> = (0..8).map(|_| a.next_u32()).collect();
        assert_eq!(first, again);
        let mut b = Pcg32::new(8, 11);
        assert_ne!(first[0], b.next_u32());
    }

    #[test]
    fn advance_matches_stepping_and_goes_back() {
        let mut a = Pcg32::new(3, 1234);
        let mut b = a.clone();
        for _ in 0..1000 {
            a.next_u32();
        }
        b.advance(1000);
        assert_eq!(a, b);
        b.advance(-1000);
        let mut c = Pcg32::new(3, 1234);
        assert_eq!(b.next_u32(), c.next_u32());
        b.advance(0);
        c.advance(0);
        assert_eq!(b, c);
    }

    #[test]
    fn floats_are_in_unit_interval_and_can_reach_the_top_value() {
        let mut rng = Pcg32::default();
        let mut max = 0.0f32;
        for _ in 0..100_000 {
            let x = rng.next_f32();
            assert!((0.0..1.0).contains(&x));
            max = max.max(x);
        }
        assert!(max > 0.999);
        // The largest representable output is 1 - 2^-24 < 1.
        assert!(((1u32 << 24) - 1) as f32 * INV_2_POW_24 < 1.0);
    }

    #[test]
    fn bits_are_balanced() {
        // Each of the 32 output bits is set about half the time (binomial sd ~ 0.0016 for
        // 100k draws; 0.01 is > 6 sd).
        let mut rng = Pcg32::new(0, 0);
        let n = 100_000;
        let mut counts = [0u32; 32];
        for _ in 0..n {
            let x = rng.next_u32();
            for (bit, c) in counts.iter_mut().enumerate() {
                *c += (x >> bit) & 1;
            }
        }
        for c in counts {
            assert!((f64::from(c) / f64::from(n) - 0.5).abs() < 0.01, "{c}");
        }
    }
}
