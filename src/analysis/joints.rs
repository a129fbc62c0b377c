//! The photo's colours with paving joints taken out ([`unjoint`]): the
//! ground fill steps from colour to colour and would stop at each joint of
//! a pavement laid in slabs or setts.

use rayon::prelude::*;

use super::features::Features;

/// The colour of each pixel, with thin lines (paving joints, up to 2
/// analysis pixels wide) removed from row `from` down: a 5-tap median along
/// rows, then along columns. Above `from` the photo's own colour.
pub(super) fn unjoint(f: &Features, from: usize) -> Vec<[f32; 3]> {
    let (w, h) = (f.w, f.h);
    let mut out: Vec<[f32; 3]> = (0..w * h).map(|i| f.rgb_at(i)).collect();
    let from = from.min(h);
    // Row medians from two rows above `from`, for the column medians below it.
    let y0 = from.saturating_sub(2);
    for c in 0..3 {
        let p = &f.rgb[c];
        let mut rows = vec![0f32; (h - y0) * w];
        rows.par_chunks_mut(w).enumerate().for_each(|(k, row)| {
            let line = &p[(y0 + k) * w..(y0 + k + 1) * w];
            let tap = |x: usize| {
                median5(std::array::from_fn(|d| {
                    line[(x + d).saturating_sub(2).min(w - 1)]
                }))
            };
            // Inside the row the five taps are a window; at the ends, clamped.
            for (o, v) in row.iter_mut().skip(2).zip(line.windows(5)) {
                *o = median5([v[0], v[1], v[2], v[3], v[4]]);
            }
            for x in (0..2.min(w)).chain(w.saturating_sub(2).max(2)..w) {
                row[x] = tap(x);
            }
        });
        out[from * w..]
            .par_chunks_mut(w)
            .enumerate()
            .for_each(|(k, row)| {
                let y = from + k;
                let tap = |d: usize| {
                    let r = (y + d).saturating_sub(2).min(h - 1) - y0;
                    &rows[r * w..(r + 1) * w]
                };
                let taps = (tap(0).iter().zip(tap(1)), tap(2).iter().zip(tap(3)));
                let taps = taps.0.zip(taps.1).zip(tap(4));
                for (o, (((&a, &b), (&m, &d)), &e)) in row.iter_mut().zip(taps) {
                    o[c] = median5([a, b, m, d, e]);
                }
            });
    }
    out
}

/// Median of five by min and max (colours in 0..1, no NaN): the smaller of
/// the two pairs' minima and the larger of their maxima are not the median;
/// it is the median of the three left.
fn median5(v: [f32; 5]) -> f32 {
    let (lo, hi) = (
        v[0].min(v[1]).max(v[2].min(v[3])),
        v[0].max(v[1]).min(v[2].max(v[3])),
    );
    let (x, y) = (lo.min(hi), lo.max(hi));
    x.max(y.min(v[4]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median5_is_the_middle_of_the_sorted_five() {
        let mut seed = 7u32;
        for _ in 0..2000 {
            let v: [f32; 5] = std::array::from_fn(|_| {
                seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                (seed >> 24) as f32 / 16.0
            });
            let mut s = v;
            s.sort_by(f32::total_cmp);
            assert_eq!(median5(v), s[2], "{v:?}");
        }
    }
}
