//! The one percentile the effects share (and the analysis's newer medians:
//! at q = 0.5 with [`Rank::Nearest`] it is the value of rank `n / 2`, the
//! upper median of an even count): a value of the data itself (no
//! interpolation), found by selection rather than a full sort.

/// Which value a fractional rank `(n - 1) q` picks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rank {
    /// The nearest rank, `round((n - 1) q)` (the stain's D_max).
    Nearest,
    /// The rank below, `floor((n - 1) q)` (moss's D_max and vigour scale).
    Below,
}

/// The `q`-quantile (`q` clamped to 0..=1) of `values`: the value of rank
/// `rank((n - 1) q)` in ascending order (`f32::total_cmp`); `None` when
/// there are none.
///
/// ```
/// use grime::effects::percentile::{Rank, percentile};
/// let v = [4.0, 1.0, 3.0, 2.0];
/// assert_eq!(percentile(v, 0.5, Rank::Nearest), Some(3.0)); // rank 1.5 -> 2
/// assert_eq!(percentile(v, 0.5, Rank::Below), Some(2.0)); // rank 1.5 -> 1
/// assert_eq!(percentile([0.0f32; 0], 0.5, Rank::Below), None);
/// ```
pub fn percentile(values: impl IntoIterator<Item = f32>, q: f32, rank: Rank) -> Option<f32> {
    let mut v: Vec<f32> = values.into_iter().collect();
    if v.is_empty() {
        return None;
    }
    let r = (v.len() - 1) as f32 * q.clamp(0.0, 1.0);
    // Truncation is floor: r is never negative.
    let k = match rank {
        Rank::Nearest => r.round(),
        Rank::Below => r,
    } as usize;
    Some(*v.select_nth_unstable_by(k, f32::total_cmp).1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #[test]
        fn matches_a_sorted_copy(
            v in proptest::collection::vec(-1e3f32..1e3, 1..200), q in -0.5f32..1.5,
        ) {
            let mut sorted = v.clone();
            sorted.sort_by(f32::total_cmp);
            let r = (v.len() - 1) as f32 * q.clamp(0.0, 1.0);
            let near = percentile(v.iter().copied(), q, Rank::Nearest).unwrap();
            let below = percentile(v.iter().copied(), q, Rank::Below).unwrap();
            prop_assert_eq!(near, sorted[r.round() as usize]);
            prop_assert_eq!(below, sorted[r.floor() as usize]);
            prop_assert!(below <= near);
        }
    }

    #[test]
    fn ends_are_the_extremes() {
        let v = [5.0, -2.0, 9.0, 0.5];
        for rank in [Rank::Nearest, Rank::Below] {
            assert_eq!(percentile(v, 0.0, rank), Some(-2.0));
            assert_eq!(percentile(v, 1.0, rank), Some(9.0));
        }
    }
}
