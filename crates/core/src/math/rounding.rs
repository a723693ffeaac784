//! Rounding an `f32` to an integer without a library call: on x86-64 CPUs without SSE4.1
//! (the portable baseline this crate is built for) `f32::floor` and `f32::ceil` call libm,
//! which costs more than the arithmetic around them in the film's inner loops.

/// `v.floor()` as an `i64`, saturating at the type's bounds (NaN gives 0).
#[inline]
#[must_use]
pub fn floor_to_i64(v: f32) -> i64 {
    // Truncation rounds toward zero (saturating); one less for a negative non-integer.
    let t = v as i64;
    if (t as f32) > v {
        t.saturating_sub(1)
    } else {
        t
    }
}

/// `v.ceil()` as an `i64`, saturating at the type's bounds (NaN gives 0).
#[inline]
#[must_use]
pub fn ceil_to_i64(v: f32) -> i64 {
    // One more than the truncation for a positive non-integer.
    let t = v as i64;
    if (t as f32) < v {
        t.saturating_add(1)
    } else {
        t
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn agrees_with_the_library_wherever_an_i64_holds_the_result() {
        let mut values = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            2.999_999_8,
            -2.999_999_8,
            1e-30,
            -1e-30,
        ];
        values.extend([8_388_607.5, -8_388_607.5, 16_777_217.0, 1e18, -1e18, f32::MIN_POSITIVE]);
        // Every 1/8 and a spread of magnitudes, both signs.
        values.extend((-400..400).map(|i| i as f32 / 8.0));
        values.extend((0..200).map(|i| 1.23f32 * 1.17f32.powi(i) * if i % 2 == 0 { 1.0 } else { -1.0 }));
        for v in values.into_iter().filter(|v| v.abs() < 9e18) {
            assert_eq!(floor_to_i64(v), v.floor() as i64, "floor {v}");
            assert_eq!(ceil_to_i64(v), v.ceil() as i64, "ceil {v}");
        }
    }

    #[test]
    fn saturates_and_maps_nan_to_zero() {
        assert_eq!(floor_to_i64(f32::INFINITY), i64::MAX);
        assert_eq!(floor_to_i64(f32::NEG_INFINITY), i64::MIN);
        assert_eq!(ceil_to_i64(f32::INFINITY), i64::MAX);
        assert_eq!(ceil_to_i64(f32::NEG_INFINITY), i64::MIN);
        assert_eq!(floor_to_i64(f32::NAN), 0);
        assert_eq!(ceil_to_i64(f32::NAN), 0);
    }
}
