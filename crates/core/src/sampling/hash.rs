//! 64-bit integer hashing, used to derive independent random streams from tuples such as
//! (seed, pixel x, pixel y).

/// 2^64 / golden ratio, the Weyl increment of SplitMix64.
const GOLDEN_GAMMA: u64 = 0x9e37_79b9_7f4a_7c15;

/// A bijective 64-bit finaliser with full avalanche: every input bit flips each output bit
/// with probability about 1/2. This is the SplitMix64 output function (Steele, Lea and
/// Flood 2014, constants from Stafford's "Mix13" variant).
#[inline]
#[must_use]
pub fn mix_bits(mut v: u64) -> u64 {
    v = (v ^ (v >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    v = (v ^ (v >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    v ^ (v >> 31)
}

/// Hash of a sequence of integers. Order matters. The state absorbs each value by
/// `h = mix_bits(h + GOLDEN_GAMMA + v)`; since every step is a bijection in both `h` and
/// `v`, two sequences of the same length that differ in exactly one position never collide.
#[inline]
#[must_use]
pub fn hash_u64s(values: &[u64]) -> u64 {
    let mut h = mix_bits(values.len() as u64);
    for &v in values {
        h = hash_absorb(h, v);
    }
    h
}

/// One step of [`hash_u64s`]: the state `h` absorbs `v`. With it a caller can hash many
/// tuples sharing a prefix at the cost of one step each: `hash_u64s(&[a, b])` is
/// `hash_absorb(hash_absorb(mix_bits(2), a), b)`.
#[inline]
#[must_use]
pub fn hash_absorb(h: u64, v: u64) -> u64 {
    mix_bits(h.wrapping_add(GOLDEN_GAMMA).wrapping_add(v))
}

/// A uniform value in `[0, 1)` hashed from the bit patterns of `values` (pbrt-v4
/// `HashFloat`): the top 24 bits of [`hash_u64s`], so it is exactly representable and below
/// 1. Deterministic: the same floats always give the same value.
#[inline]
#[must_use]
pub fn hash_float(values: &[f32]) -> f32 {
    let mut bits = [0u64; 8];
    let n = values.len().min(bits.len());
    for (b, v) in bits.iter_mut().zip(values) {
        *b = u64::from(v.to_bits());
    }
    (hash_u64s(&bits[..n]) >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    #[test]
    fn mix_bits_avalanches() {
        // Flipping one input bit flips about 32 of the 64 output bits on average.
        let mut total = 0u32;
        let mut trials = 0u32;
        for i in 0..256u64 {
            let v = mix_bits(i.wrapping_mul(0x1234_5678_9abc_def1));
            for bit in 0..64 {
                total += (mix_bits(v) ^ mix_bits(v ^ (1 << bit))).count_ones();
                trials += 1;
            }
        }
        let mean = f64::from(total) / f64::from(trials);
        assert!((mean - 32.0).abs() < 0.5, "{mean}");
    }

    #[test]
    fn hashes_of_nearby_tuples_are_distinct_and_order_dependent() {
        let mut seen = HashSet::new();
        for seed in 0..4u64 {
            for y in 0..64u64 {
                for x in 0..64u64 {
                    assert!(seen.insert(hash_u64s(&[x, y, seed])));
                }
            }
        }
        assert_ne!(hash_u64s(&[1, 2]), hash_u64s(&[2, 1]));
        assert_eq!(hash_u64s(&[5, 9]), hash_absorb(hash_absorb(mix_bits(2), 5), 9));
        assert_ne!(hash_u64s(&[0]), hash_u64s(&[0, 0]));
        assert_ne!(hash_u64s(&[]), hash_u64s(&[0]));
    }

    #[test]
    fn hash_float_is_uniform_in_unit_interval() {
        // Mean 1/2 and a quarter of the values below 1/4 over nearby inputs.
        let n = 100_000;
        let (mut sum, mut low) = (0.0f64, 0u32);
        for i in 0..n {
            let u = hash_float(&[i as f32 * 1e-3, 0.5, -2.0]);
            assert!((0.0..1.0).contains(&u));
            sum += f64::from(u);
            low += u32::from(u < 0.25);
        }
        assert!((sum / f64::from(n) - 0.5).abs() < 0.005);
        assert!((f64::from(low) / f64::from(n) - 0.25).abs() < 0.005);
    }
}
