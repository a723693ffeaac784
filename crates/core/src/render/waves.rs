//! Splitting a render into waves of doubling sample counts (pbrt-v4 renders this way to
//! write images as it goes): 1, 1, 2, 4, 8, ... samples per pixel, the last wave topping
//! up to the end.

use std::ops::Range;

/// The waves covering `samples`: `[s, s + 1)`, then each wave as long as all before it
/// (so the samples done double), the last one cut at `samples.end`.
pub fn doubling_waves(samples: Range<u32>) -> impl Iterator<Item = Range<u32>> {
    let (first, end) = (samples.start, samples.end);
    let mut done = first;
    std::iter::from_fn(move || {
        if done >= end {
            return None;
        }
        let len = (done - first).max(1);
        let next = done.saturating_add(len).min(end);
        let wave = done..next;
        done = next;
        Some(wave)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn waves_double_and_cover_the_range_once() {
        let w: Vec<_> = doubling_waves(0..11).collect();
        assert_eq!(w, vec![0..1, 1..2, 2..4, 4..8, 8..11]);
        assert_eq!(doubling_waves(5..6).collect::<Vec<_>>(), vec![5..6]);
        assert_eq!(doubling_waves(3..3).count(), 0);
    }
}
