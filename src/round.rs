//! Rounding to a channel value without a libm call: `f32::round` is a
//! library call on baseline x86-64 (no SSE4.1), and the compositor and the
//! layers' surface modulation round every channel of a 12 MP photo, once
//! per time-lapse frame. Each function here equals
//! `v.round().clamp(0.0, MAX) as T` for every `f32`, NaN included (0).

/// `v.round().clamp(0.0, 255.0) as u8`.
#[inline]
pub fn to_u8(v: f32) -> u8 {
    clamped(v, 255.0) as u8
}

/// `v.round().clamp(0.0, 65535.0) as u16`.
#[inline]
pub fn to_u16(v: f32) -> u16 {
    clamped(v, 65535.0) as u16
}

/// `v` rounded half away from zero, clamped to `0..=max` (a whole number
/// below 2^22), NaN to 0.
#[inline]
fn clamped(v: f32, max: f32) -> f32 {
    if v.is_nan() || v < 0.5 {
        return 0.0;
    }
    if v >= max {
        return max;
    }
    // From 0.5 up to 2^22, v + 0.5 rounds across a whole number only where
    // v itself rounds up: truncating it is rounding v (without the
    // unpredictable branch on the fraction).
    (v + 0.5) as u32 as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    fn same(v: f32) {
        assert_eq!(to_u8(v), v.round().clamp(0.0, 255.0) as u8, "{v:?}");
        assert_eq!(to_u16(v), v.round().clamp(0.0, 65535.0) as u16, "{v:?}");
    }

    #[test]
    fn rounds_as_the_library_does() {
        for v in [
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            -0.0,
            f32::MIN_POSITIVE,
            0.5f32.next_down(),
            65534.5,
            65535.5,
            1e9,
            -0.5,
            -1e9,
        ] {
            same(v);
        }
        // Every half and whole number to 2^17 and their neighbours, every
        // float from 0.25 up to 1024, and a sweep.
        for k in 0..(1 << 17) {
            for v in [k as f32, k as f32 + 0.5] {
                [v, v.next_down(), v.next_up(), -v]
                    .into_iter()
                    .for_each(same);
            }
        }
        (0.25f32.to_bits()..1024f32.to_bits())
            .map(f32::from_bits)
            .for_each(same);
        (0..2_000_000).for_each(|i| same(i as f32 * 0.000_137 - 3.0));
    }
}
