//! The Owen-scrambled Sobol' sampler (Burley 2020, "Practical Hash-based Owen Scrambling"),
//! used for pbrt's `sobol`, `zsobol`, `halton`, `pmj02bn` and `paddedsobol`.
//!
//! Each pixel takes its own stretch of the Sobol' sequence: the sample index is shuffled by
//! a hash-based Owen scrambling of its digits, seeded per (pixel, seed), which maps the first
//! `2^m` indices onto an aligned block of `2^m` indices; every dimension of the point is then
//! Owen-scrambled with a seed of its own. Both steps keep the net structure, so for a
//! power-of-two sample count the first two dimensions of a pixel's samples form a
//! (0, m, 2)-net and every dimension is stratified into `spp` intervals.
//!
//! The first [`SOBOL_DIMENSIONS`] dimensions use Joe and Kuo's direction numbers
//! (`new-joe-kuo-6.21201`, 2008), built into generator matrices at compile time. Beyond them
//! each dimension is a one-dimensional Owen-scrambled van der Corput sequence with its own
//! index shuffle ("padding", as Burley recommends): still stratified in 1-D, independent of
//! the other dimensions.

use crate::math::{UVec2, Vec2};
use crate::sampling::{hash_absorb, hash_u64s, mix_bits, nested_uniform_scramble, nested_uniform_scramble_reversed};

/// Number of dimensions with Sobol' generator matrices.
pub const SOBOL_DIMENSIONS: usize = 64;

/// Joe and Kuo's `new-joe-kuo-6.21201` parameters for Sobol' dimensions 2 to 64 (their
/// numbering; dimension 1 is van der Corput): degree `s` of the primitive polynomial, its
/// inner coefficients `a` as bits, and the initial direction integers `m_1..m_s`.
#[rustfmt::skip]
const JOE_KUO: [(u32, u32, [u32; 9]); SOBOL_DIMENSIONS - 1] = [
    (1, 0, [1, 0, 0, 0, 0, 0, 0, 0, 0]), // dim 2
    (2, 1, [1, 3, 0, 0, 0, 0, 0, 0, 0]), // dim 3
    (3, 1, [1, 3, 1, 0, 0, 0, 0, 0, 0]), // dim 4
    (3, 2, [1, 1, 1, 0, 0, 0, 0, 0, 0]), // dim 5
    (4, 1, [1, 1, 3, 3, 0, 0, 0, 0, 0]), // dim 6
    (4, 4, [1, 3, 5, 13, 0, 0, 0, 0, 0]), // dim 7
    (5, 2, [1, 1, 5, 5, 17, 0, 0, 0, 0]), // dim 8
    (5, 4, [1, 1, 5, 5, 5, 0, 0, 0, 0]), // dim 9
    (5, 7, [1, 1, 7, 11, 19, 0, 0, 0, 0]), // dim 10
    (5, 11, [1, 1, 5, 1, 1, 0, 0, 0, 0]), // dim 11
    (5, 13, [1, 1, 1, 3, 11, 0, 0, 0, 0]), // dim 12
    (5, 14, [1, 3, 5, 5, 31, 0, 0, 0, 0]), // dim 13
    (6, 1, [1, 3, 3, 9, 7, 49, 0, 0, 0]), // dim 14
    (6, 13, [1, 1, 1, 15, 21, 21, 0, 0, 0]), // dim 15
    (6, 16, [1, 3, 1, 13, 27, 49, 0, 0, 0]), // dim 16
    (6, 19, [1, 1, 1, 15, 7, 5, 0, 0, 0]), // dim 17
    (6, 22, [1, 3, 1, 15, 13, 25, 0, 0, 0]), // dim 18
    (6, 25, [1, 1, 5, 5, 19, 61, 0, 0, 0]), // dim 19
    (7, 1, [1, 3, 7, 11, 23, 15, 103, 0, 0]), // dim 20
    (7, 4, [1, 3, 7, 13, 13, 15, 69, 0, 0]), // dim 21
    (7, 7, [1, 1, 3, 13, 7, 35, 63, 0, 0]), // dim 22
    (7, 8, [1, 3, 5, 9, 1, 25, 53, 0, 0]), // dim 23
    (7, 14, [1, 3, 1, 13, 9, 35, 107, 0, 0]), // dim 24
    (7, 19, [1, 3, 1, 5, 27, 61, 31, 0, 0]), // dim 25
    (7, 21, [1, 1, 5, 11, 19, 41, 61, 0, 0]), // dim 26
    (7, 28, [1, 3, 5, 3, 3, 13, 69, 0, 0]), // dim 27
    (7, 31, [1, 1, 7, 13, 1, 19, 1, 0, 0]), // dim 28
    (7, 32, [1, 3, 7, 5, 13, 19, 59, 0, 0]), // dim 29
    (7, 37, [1, 1, 3, 9, 25, 29, 41, 0, 0]), // dim 30
    (7, 41, [1, 3, 5, 13, 23, 1, 55, 0, 0]), // dim 31
    (7, 42, [1, 3, 7, 3, 13, 59, 17, 0, 0]), // dim 32
    (7, 50, [1, 3, 1, 3, 5, 53, 69, 0, 0]), // dim 33
    (7, 55, [1, 1, 5, 5, 23, 33, 13, 0, 0]), // dim 34
    (7, 56, [1, 1, 7, 7, 1, 61, 123, 0, 0]), // dim 35
    (7, 59, [1, 1, 7, 9, 13, 61, 49, 0, 0]), // dim 36
    (7, 62, [1, 3, 3, 5, 3, 55, 33, 0, 0]), // dim 37
    (8, 14, [1, 3, 1, 15, 31, 13, 49, 245, 0]), // dim 38
    (8, 21, [1, 3, 5, 15, 31, 59, 63, 97, 0]), // dim 39
    (8, 22, [1, 3, 1, 11, 11, 11, 77, 249, 0]), // dim 40
    (8, 38, [1, 3, 1, 11, 27, 43, 71, 9, 0]), // dim 41
    (8, 47, [1, 1, 7, 15, 21, 11, 81, 45, 0]), // dim 42
    (8, 49, [1, 3, 7, 3, 25, 31, 65, 79, 0]), // dim 43
    (8, 50, [1, 3, 1, 1, 19, 11, 3, 205, 0]), // dim 44
    (8, 52, [1, 1, 5, 9, 19, 21, 29, 157, 0]), // dim 45
    (8, 56, [1, 3, 7, 11, 1, 33, 89, 185, 0]), // dim 46
    (8, 67, [1, 3, 3, 3, 15, 9, 79, 71, 0]), // dim 47
    (8, 70, [1, 3, 7, 11, 15, 39, 119, 27, 0]), // dim 48
    (8, 84, [1, 1, 3, 1, 11, 31, 97, 225, 0]), // dim 49
    (8, 97, [1, 1, 1, 3, 23, 43, 57, 177, 0]), // dim 50
    (8, 103, [1, 3, 7, 7, 17, 17, 37, 71, 0]), // dim 51
    (8, 115, [1, 3, 1, 5, 27, 63, 123, 213, 0]), // dim 52
    (8, 122, [1, 1, 3, 5, 11, 43, 53, 133, 0]), // dim 53
    (9, 8, [1, 3, 5, 5, 29, 17, 47, 173, 479]), // dim 54
    (9, 13, [1, 3, 3, 11, 3, 1, 109, 9, 69]), // dim 55
    (9, 16, [1, 1, 1, 5, 17, 39, 23, 5, 343]), // dim 56
    (9, 22, [1, 3, 1, 5, 25, 15, 31, 103, 499]), // dim 57
    (9, 25, [1, 1, 1, 11, 11, 17, 63, 105, 183]), // dim 58
    (9, 44, [1, 1, 5, 11, 9, 29, 97, 231, 363]), // dim 59
    (9, 47, [1, 1, 5, 15, 19, 45, 41, 7, 383]), // dim 60
    (9, 52, [1, 3, 7, 7, 31, 19, 83, 137, 221]), // dim 61
    (9, 55, [1, 1, 1, 3, 23, 15, 111, 223, 83]), // dim 62
    (9, 59, [1, 1, 5, 13, 31, 15, 55, 25, 161]), // dim 63
    (9, 62, [1, 1, 3, 13, 25, 47, 39, 87, 257]), // dim 64
];

/// Generator matrices, one per dimension: column `j` (the image of index bit `j`) as a
/// 32-bit fraction, most significant digit first. The sampler reads [`SOBOL_NIBBLES`]; these
/// are the reference the tests check the tables against.
#[cfg(test)]
static SOBOL_MATRICES: [[u32; 32]; SOBOL_DIMENSIONS] = sobol_matrices();

/// Builds the generator matrices from [`JOE_KUO`] by the Sobol' recurrence
/// `v_i = v_{i-s} ^ (v_{i-s} >> s) ^ XOR_k a_k v_{i-k}` (Bratley and Fox 1988).
const fn sobol_matrices() -> [[u32; 32]; SOBOL_DIMENSIONS] {
    let mut out = [[0u32; 32]; SOBOL_DIMENSIONS];
    let mut j = 0;
    while j < 32 {
        out[0][j] = 1 << (31 - j);
        j += 1;
    }
    let mut d = 1;
    while d < SOBOL_DIMENSIONS {
        let (s, a, m) = JOE_KUO[d - 1];
        let s = s as usize;
        let mut v = [0u32; 32];
        let mut i = 0;
        while i < 32 {
            if i < s {
                v[i] = m[i] << (31 - i);
            } else {
                v[i] = v[i - s] ^ (v[i - s] >> s);
                let mut k = 1;
                while k < s {
                    if (a >> (s - 1 - k)) & 1 == 1 {
                        v[i] ^= v[i - k];
                    }
                    k += 1;
                }
            }
            i += 1;
        }
        out[d] = v;
        d += 1;
    }
    out
}

/// Point `index` of the unscrambled Sobol' sequence in dimension `dim` (below
/// [`SOBOL_DIMENSIONS`]), as a 32-bit fraction, bit by bit (the tests' reference).
#[cfg(test)]
#[inline]
#[must_use]
pub fn sobol_u32(mut index: u32, dim: usize) -> u32 {
    let matrix = &SOBOL_MATRICES[dim];
    let mut x = 0;
    // Visit only the set bits of the index (scrambled indices use all 32 bits).
    while index != 0 {
        x ^= matrix[index.trailing_zeros() as usize];
        index &= index - 1;
    }
    x
}

/// The generator matrices with bit-reversed columns, tabulated by nibble:
/// `SOBOL_NIBBLES[dim][k][v]` is the XOR of the reversed columns `4k + b` for the bits `b`
/// set in `v`. Eight lookups then give a point's reversed digits for any index, with no
/// data-dependent loop (the bit-by-bit loop of [`sobol_u32`], about 16 rounds for a
/// scrambled index and a mispredicted exit, was most of the sampler's time); 32 KiB.
static SOBOL_NIBBLES: [[[u32; 16]; 8]; SOBOL_DIMENSIONS] = sobol_nibbles();

const fn sobol_nibbles() -> [[[u32; 16]; 8]; SOBOL_DIMENSIONS] {
    let matrices = sobol_matrices();
    let mut out = [[[0u32; 16]; 8]; SOBOL_DIMENSIONS];
    let mut d = 0;
    while d < SOBOL_DIMENSIONS {
        let mut k = 0;
        while k < 8 {
            let mut v = 0;
            while v < 16 {
                let mut b = 0;
                while b < 4 {
                    if (v >> b) & 1 == 1 {
                        out[d][k][v] ^= matrices[d][4 * k + b].reverse_bits();
                    }
                    b += 1;
                }
                v += 1;
            }
            k += 1;
        }
        d += 1;
    }
    out
}

/// [`sobol_u32`]`(index, dim).reverse_bits()`, by table ([`SOBOL_NIBBLES`]).
#[inline]
#[must_use]
pub fn sobol_u32_reversed(index: u32, dim: usize) -> u32 {
    high_digits_reversed(index, dim) ^ low_digits_reversed(index, dim)
}

/// The share of index bits 0..8 in [`sobol_u32_reversed`]`(index, dim)` (the XOR of the
/// two low nibbles' table entries).
#[inline]
fn low_digits_reversed(index: u32, dim: usize) -> u32 {
    let table = &SOBOL_NIBBLES[dim];
    table[0][index as usize & 15] ^ table[1][(index >> 4) as usize & 15]
}

/// The share of index bits 8 and up in [`sobol_u32_reversed`]`(index, dim)` (the XOR of the
/// six high nibbles' table entries): the same for every index of an aligned block of 256.
#[inline]
fn high_digits_reversed(index: u32, dim: usize) -> u32 {
    let table = &SOBOL_NIBBLES[dim];
    let mut x = 0;
    for (k, nibbles) in table.iter().enumerate().skip(2) {
        x ^= nibbles[(index >> (4 * k)) as usize & 15];
    }
    x
}

/// A 32-bit fraction as a float in [0, 1): its 24 high bits, so the result is exact.
#[inline]
fn to_unit(x: u32) -> f32 {
    (x >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// Owen-scrambled Sobol' points with a per-pixel shuffle of the sequence.
#[derive(Clone, Debug)]
pub struct OwenSobolSampler {
    samples_per_pixel: u32,
    seed: u64,
    /// Hash of (pixel, seed): seeds the index shuffle and every dimension's scrambling.
    pixel_hash: u64,
    /// The state of `hash_u64s(&[pixel_hash, dim])` after absorbing `pixel_hash`, so each
    /// dimension's hash costs one mixing step (the same values, computed once per sample).
    dim_hash_state: u64,
    sample_index: u32,
    /// The pixel's sample index after the shuffle: the Sobol' point used.
    sobol_index: u32,
    dimension: u32,
    /// [`high_digits_reversed`] of `sobol_index` per dimension, valid where `high_valid` has
    /// the dimension's bit. The shuffle maps a pixel's first `2^m` sample indices onto one
    /// aligned block of `2^m`, so every sample of a pixel (up to 256 of them) shares these:
    /// each dimension's six high table lookups are made once per pixel instead of once per
    /// sample (they were about 4% of a Sobol' render's instructions).
    high: [u32; SOBOL_DIMENSIONS],
    high_valid: u64,
    /// Each table dimension's scrambling hash (`hash_u64s(&[pixel_hash, dim])`), valid where
    /// `hash_valid` has the dimension's bit. It depends on the pixel alone, so a pixel's
    /// consecutive samples share it: one mixing step per dimension and pixel instead of
    /// one per value (the hash was a fifth of the sampler's instructions).
    dim_hash: [u64; SOBOL_DIMENSIONS],
    hash_valid: u64,
}

// `high_valid` and `hash_valid` have one bit per table dimension.
const _: () = assert!(SOBOL_DIMENSIONS <= u64::BITS as usize);

impl OwenSobolSampler {
    /// A sampler taking `samples_per_pixel` samples in each pixel (powers of two keep the
    /// net properties exactly).
    #[must_use]
    pub fn new(samples_per_pixel: u32, seed: u64) -> Self {
        Self {
            samples_per_pixel,
            seed,
            pixel_hash: 0,
            dim_hash_state: 0,
            sample_index: 0,
            sobol_index: 0,
            dimension: 0,
            high: [0; SOBOL_DIMENSIONS],
            high_valid: 0,
            dim_hash: [0; SOBOL_DIMENSIONS],
            hash_valid: 0,
        }
    }

    /// Number of samples taken in each pixel.
    #[inline]
    #[must_use]
    pub fn samples_per_pixel(&self) -> u32 {
        self.samples_per_pixel
    }

    /// Restarts at sample `sample_index` of `pixel`.
    #[inline]
    pub fn start_pixel_sample(&mut self, pixel: UVec2, sample_index: u32) {
        let pixel_hash = hash_u64s(&[u64::from(pixel.x), u64::from(pixel.y), self.seed]);
        let sobol_index = nested_uniform_scramble(sample_index, pixel_hash as u32);
        // The cached digits are bits 8.. of the index, whatever the pixel.
        if sobol_index >> 8 != self.sobol_index >> 8 {
            self.high_valid = 0;
        }
        if pixel_hash != self.pixel_hash {
            self.hash_valid = 0;
        }
        self.pixel_hash = pixel_hash;
        self.dim_hash_state = hash_absorb(mix_bits(2), pixel_hash);
        self.sample_index = sample_index;
        self.sobol_index = sobol_index;
        self.dimension = 0;
    }

    /// Dimension `dim` of the current sample.
    #[inline(always)]
    fn sample(&mut self, dim: u32) -> f32 {
        // The point's digits bit-reversed, as the scrambling wants them.
        let (x_reversed, dim_hash) = if (dim as usize) < SOBOL_DIMENSIONS {
            let d = dim as usize;
            if self.hash_valid & 1 << d == 0 {
                self.dim_hash[d] = hash_absorb(self.dim_hash_state, u64::from(dim));
                self.hash_valid |= 1 << d;
            }
            let dim_hash = self.dim_hash[d];
            debug_assert_eq!(dim_hash, hash_u64s(&[self.pixel_hash, u64::from(dim)]));
            if self.high_valid & 1 << d == 0 {
                self.high[d] = high_digits_reversed(self.sobol_index, d);
                self.high_valid |= 1 << d;
            }
            let x = self.high[d] ^ low_digits_reversed(self.sobol_index, d);
            debug_assert_eq!(x, sobol_u32_reversed(self.sobol_index, d));
            (x, dim_hash)
        } else {
            // Padding: a van der Corput point (the reversed digits of the index) with an
            // index shuffle of its own.
            let dim_hash = hash_absorb(self.dim_hash_state, u64::from(dim));
            (
                nested_uniform_scramble(self.sample_index, (dim_hash >> 32) as u32),
                dim_hash,
            )
        };
        to_unit(nested_uniform_scramble_reversed(x_reversed, dim_hash as u32))
    }

    /// The next value in [0, 1).
    #[inline]
    pub fn get_1d(&mut self) -> f32 {
        let dim = self.dimension;
        self.dimension += 1;
        self.sample(dim)
    }

    /// The next two values in [0, 1)^2.
    #[inline]
    pub fn get_2d(&mut self) -> Vec2 {
        let dim = self.dimension;
        self.dimension += 2;
        Vec2::new(self.sample(dim), self.sample(dim + 1))
    }

    /// Position inside the pixel; the same as [`get_2d`](Self::get_2d), and so the first two
    /// dimensions (the best stratified pair) when drawn first.
    #[inline]
    pub fn get_pixel_2d(&mut self) -> Vec2 {
        self.get_2d()
    }
}
