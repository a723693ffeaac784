//! Hash-driven permutations used by the stratified and low-discrepancy samplers: random
//! permutations of `0..n` evaluated one element at a time (Kensler 2013), and the hash-based
//! Owen scrambling of base-2 digits (Laine and Karras 2011; Burley 2020).

/// Element `i` of a random permutation of `0..n` chosen by `seed`, without building the
/// permutation (Kensler 2013, "Correlated Multi-Jittered Sampling", as pbrt-v4's
/// `PermutationElement`): a bijective hash on the next power of two, cycle-walked until it
/// lands below `n`. `i` must be below `n`.
#[must_use]
pub fn permutation_element(mut i: u32, n: u32, seed: u32) -> u32 {
    debug_assert!(i < n);
    let p = seed;
    let mut w = n - 1;
    w |= w >> 1;
    w |= w >> 2;
    w |= w >> 4;
    w |= w >> 8;
    w |= w >> 16;
    loop {
        i ^= p;
        i = i.wrapping_mul(0xe170_893d);
        i ^= p >> 16;
        i ^= (i & w) >> 4;
        i ^= p >> 8;
        i = i.wrapping_mul(0x0929_eb3f);
        i ^= p >> 23;
        i ^= (i & w) >> 1;
        i = i.wrapping_mul(1 | p >> 27);
        i = i.wrapping_mul(0x6935_fa69);
        i ^= (i & w) >> 11;
        i = i.wrapping_mul(0x74dc_b303);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0x9e50_1cc3);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0xc860_a3df);
        i &= w;
        i ^= i >> 5;
        if i < n {
            break;
        }
    }
    ((u64::from(i) + u64::from(p)) % u64::from(n)) as u32
}

/// The Laine-Karras permutation (Burley 2020's constants): a bijection on `u32` in which
/// output bit `j` depends only on input bits `0..=j`, each step being "bit `j` XOR a function
/// of the lower bits".
#[inline]
#[must_use]
fn laine_karras_permutation(mut x: u32, seed: u32) -> u32 {
    x = x.wrapping_add(seed);
    x ^= x.wrapping_mul(0x6c50_b47c);
    x ^= x.wrapping_mul(0xb82f_1e52);
    x ^= x.wrapping_mul(0xc7af_e638);
    x ^= x.wrapping_mul(0x8d22_f6e6);
    x
}

/// Hash-based Owen scrambling of the 32 binary digits of `x` read as a fraction, most
/// significant first (Burley 2020, `nested_uniform_scramble`): digit `k` is flipped by a
/// hash of `seed` and the digits before it. A bijection on `u32` that maps every aligned
/// block of `2^m` values onto an aligned block of `2^m` values, so it keeps elementary
/// intervals, and with them the (t, m, s)-net property of a point set.
#[inline]
#[must_use]
pub fn nested_uniform_scramble(x: u32, seed: u32) -> u32 {
    laine_karras_permutation(x.reverse_bits(), seed).reverse_bits()
}

/// [`nested_uniform_scramble`] of the value whose bit reversal is `x_reversed`, for callers
/// that have the reversed digits at hand (the Sobol' sampler builds them directly), so one
/// of the two bit reversals is saved.
#[inline]
#[must_use]
pub fn nested_uniform_scramble_reversed(x_reversed: u32, seed: u32) -> u32 {
    laine_karras_permutation(x_reversed, seed).reverse_bits()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn permutation_element_is_a_permutation() {
        for n in [1u32, 2, 3, 5, 15, 16, 17, 64, 100, 257] {
            for seed in [0u32, 1, 0xdead_beef, 0x1234_5678] {
                let mut seen = vec![false; n as usize];
                for i in 0..n {
                    let j = permutation_element(i, n, seed);
                    assert!(j < n && !seen[j as usize], "n {n} seed {seed}");
                    seen[j as usize] = true;
                }
            }
        }
        // Different seeds give different permutations.
        let a: Vec<u32> = (0..16).map(|i| permutation_element(i, 16, 1)).collect();
        let b: Vec<u32> = (0..16).map(|i| permutation_element(i, 16, 2)).collect();
        assert_ne!(a, b);
    }

    #[test]
    fn owen_scramble_is_a_bijection_that_keeps_aligned_blocks() {
        for seed in [0u32, 7, 0x9e37_79b9] {
            // The top 8 digits of the values k << 24 (k < 256) are all 256 patterns; they
            // must stay so, and each block of 2^m of them must stay an aligned block.
            let mut seen = [false; 256];
            for k in 0..256u32 {
                let s = nested_uniform_scramble(k << 24, seed) >> 24;
                assert!(!seen[s as usize]);
                seen[s as usize] = true;
            }
            for m in 1..8u32 {
                for block in 0..(256 >> m) {
                    let tops: Vec<u32> = (0..1u32 << m)
                        .map(|k| nested_uniform_scramble(((block << m) | k) << 24, seed) >> (24 + m))
                        .collect();
                    assert!(tops.iter().all(|&t| t == tops[0]), "seed {seed} m {m}");
                }
            }
        }
        assert_ne!(nested_uniform_scramble(0, 1), nested_uniform_scramble(0, 2));
    }
}
