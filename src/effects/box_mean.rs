//! The mean of a grid map over the region within a square window, by
//! separable running sums: the moss's local wetness (Chang eq. 18's
//! neighbourhood) and the γ-ton texture synthesis read it.

use rayon::prelude::*;

use crate::field::RowMajor;

/// Columns a task of the column pass sums at once.
const BLOCK: usize = 64;

/// Mean of `values` over the region cells within `radius` (a square
/// window), per grid cell; 0 outside the region.
pub fn box_mean(values: &RowMajor<f32>, region: &RowMajor<bool>, radius: usize) -> RowMajor<f32> {
    let (w, h) = (values.width(), values.height());
    let (values, region) = (values.data(), region.data());
    let masked: Vec<f32> = values
        .iter()
        .zip(region)
        .map(|(v, r)| if *r { *v } else { 0.0 })
        .collect();
    let ones: Vec<f32> = region.iter().map(|r| f32::from(u8::from(*r))).collect();
    let sum = down_columns(&along_rows(&masked, w, radius), w, h, radius);
    let count = down_columns(&along_rows(&ones, w, radius), w, h, radius);
    let mean = sum
        .iter()
        .zip(&count)
        .zip(region)
        .map(|((s, c), r)| if *r && *c > 0.0 { s / c } else { 0.0 })
        .collect();
    RowMajor::new(w, h, mean)
}

/// The running sum over `radius` either side, each row on its own, rows
/// in parallel.
fn along_rows(src: &[f32], w: usize, radius: usize) -> Vec<f32> {
    let mut out = vec![0.0; src.len()];
    out.par_chunks_mut(w.max(1))
        .zip(src.par_chunks(w.max(1)))
        .for_each(|(out, row)| {
            let mut sum = [0.0f64];
            running(
                &mut sum,
                row.len(),
                radius,
                |i| &row[i..i + 1],
                |i, s| out[i] = s[0] as f32,
            );
        });
    out
}

/// The running sum over `radius` above and below, for blocks of columns in
/// parallel, each block walking down the rows; each column adds and takes
/// in the same order as [`along_rows`] does along a row.
fn down_columns(src: &[f32], w: usize, h: usize, radius: usize) -> Vec<f32> {
    let blocks: Vec<(usize, Vec<f32>)> = (0..w)
        .step_by(BLOCK)
        .collect::<Vec<_>>()
        .into_par_iter()
        .map(|c0| {
            let bw = BLOCK.min(w - c0);
            let mut sum = vec![0.0f64; bw];
            let mut col = vec![0.0f32; bw * h];
            running(
                &mut sum,
                h,
                radius,
                |i| &src[i * w + c0..i * w + c0 + bw],
                |i, s| {
                    for (o, s) in col[i * bw..(i + 1) * bw].iter_mut().zip(s) {
                        *o = *s as f32;
                    }
                },
            );
            (c0, col)
        })
        .collect();
    let mut out = vec![0.0; w * h];
    for (c0, col) in blocks {
        let bw = col.len() / h.max(1);
        for (y, part) in col.chunks_exact(bw.max(1)).enumerate() {
            out[y * w + c0..y * w + c0 + bw].copy_from_slice(part);
        }
    }
    out
}

/// The window sums along a line of `len` cells, several lines at once
/// (`sum` holds one per line; `at(i)` gives cell `i` of each): the first
/// `radius` cells, then per cell the one entering the window added and the
/// one leaving it taken away, and `put(i, sum)`.
fn running<'a>(
    sum: &mut [f64],
    len: usize,
    radius: usize,
    at: impl Fn(usize) -> &'a [f32],
    mut put: impl FnMut(usize, &[f64]),
) {
    let add = |sum: &mut [f64], cells: &[f32], sign: f64| {
        for (s, v) in sum.iter_mut().zip(cells) {
            *s += sign * *v as f64;
        }
    };
    for i in 0..radius.min(len) {
        add(sum, at(i), 1.0);
    }
    for i in 0..len {
        if i + radius < len {
            add(sum, at(i + radius), 1.0);
        }
        if i > radius {
            add(sum, at(i - radius - 1), -1.0);
        }
        put(i, sum);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_mean_matches_a_plain_window_average() {
        // Narrower than a column block, and across three blocks.
        for (w, h, r) in [(9, 7, 2), (150, 6, 3)] {
            window_average(w, h, r);
        }
    }

    fn window_average(w: usize, h: usize, r: usize) {
        let values = RowMajor::from_fn(w, h, |x, y| ((y * w + x) * 37 % 11) as f32);
        let region = RowMajor::from_fn(w, h, |x, y| !(y * w + x).is_multiple_of(5));
        let got = box_mean(&values, &region, r);
        let (got, values, region) = (got.data(), values.data(), region.data());
        for y in 0..h {
            for x in 0..w {
                let (mut s, mut n) = (0.0, 0.0);
                for yy in y.saturating_sub(r)..(y + r + 1).min(h) {
                    for xx in x.saturating_sub(r)..(x + r + 1).min(w) {
                        if region[yy * w + xx] {
                            s += values[yy * w + xx];
                            n += 1.0;
                        }
                    }
                }
                let want = if region[y * w + x] { s / n } else { 0.0 };
                assert!((got[y * w + x] - want).abs() < 1e-4, "({x}, {y})");
            }
        }
    }
}
