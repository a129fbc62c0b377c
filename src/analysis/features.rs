//! The photo at analysis resolution and per-pixel statistics: colour,
//! luma, local texture.

use std::borrow::Cow;

use image::DynamicImage;
use rayon::prelude::*;

use crate::photo::Photo;

/// The photo downsampled (area average) so its long side is at most the
/// analysis side, as planes in 0..1 sRGB, with luma and texture.
#[derive(Debug, Clone)]
pub struct Features {
    /// Width.
    pub w: usize,
    /// Height.
    pub h: usize,
    /// Photo pixels per analysis pixel, horizontally.
    pub sx: f32,
    /// Photo pixels per analysis pixel, vertically.
    pub sy: f32,
    /// Red, green, blue planes.
    pub rgb: [Vec<f32>; 3],
    /// Luma (Rec. 601).
    pub luma: Vec<f32>,
    /// Local texture: mean gradient magnitude of luma around each pixel.
    pub texture: Vec<f32>,
}

impl Features {
    /// Downsamples `photo` to at most `side` pixels on its long side.
    pub fn new(photo: &Photo, side: u32) -> Features {
        let (pw, ph) = (photo.width() as usize, photo.height() as usize);
        let long = pw.max(ph).max(1);
        let (w, h) = if long <= side as usize {
            (pw.max(1), ph.max(1))
        } else {
            let s = side as f64 / long as f64;
            (
                ((pw as f64 * s).round() as usize).max(1),
                ((ph as f64 * s).round() as usize).max(1),
            )
        };
        let (raw, ch): (Cow<[u8]>, usize) = match photo.image() {
            DynamicImage::ImageRgb8(i) => (Cow::Borrowed(i.as_raw()), 3),
            DynamicImage::ImageRgba8(i) => (Cow::Borrowed(i.as_raw()), 4),
            other => (Cow::Owned(other.to_rgb8().into_raw()), 3),
        };
        let xspans: Vec<(usize, usize)> = (0..w).map(|ox| span(ox, w, pw)).collect();
        let mut px = vec![[0f32; 3]; w * h];
        px.par_chunks_mut(w).enumerate().for_each(|(oy, row)| {
            let (y0, y1) = span(oy, h, ph);
            // The band's rows summed first (the first row widened, then
            // one long add the compiler vectorises per row), then each
            // output pixel's columns.
            let line = |y: usize| &raw[y * pw * ch..(y + 1) * pw * ch];
            let mut sums: Vec<u32> = line(y0).iter().map(|&v| v as u32).collect();
            for y in y0 + 1..y1 {
                let line = line(y);
                sums.iter_mut().zip(line).for_each(|(s, &v)| *s += v as u32);
            }
            for (o, &(x0, x1)) in row.iter_mut().zip(&xspans) {
                let mut a = [0u32; 3];
                for p in sums[x0 * ch..x1 * ch].chunks_exact(ch) {
                    a[0] += p[0];
                    a[1] += p[1];
                    a[2] += p[2];
                }
                let n = ((x1 - x0) * (y1 - y0)) as f32 * 255.0;
                *o = [a[0] as f32 / n, a[1] as f32 / n, a[2] as f32 / n];
            }
        });
        let plane = |c: usize| px.iter().map(|p| p[c]).collect::<Vec<f32>>();
        let rgb = [plane(0), plane(1), plane(2)];
        let luma: Vec<f32> = px.iter().map(|&p| luma(p)).collect();
        let texture = texture(&luma, w, h, texture_radius(w, h));
        Features {
            w,
            h,
            sx: pw as f32 / w as f32,
            sy: ph as f32 / h as f32,
            rgb,
            luma,
            texture,
        }
    }

    /// Colour of pixel `i`.
    pub fn rgb_at(&self, i: usize) -> [f32; 3] {
        [self.rgb[0][i], self.rgb[1][i], self.rgb[2][i]]
    }
}

/// Rec. 601 luma of an RGB colour (0..1).
pub fn luma([r, g, b]: [f32; 3]) -> f32 {
    0.299 * r + 0.587 * g + 0.114 * b
}

/// How far apart two colours are: the sum of the channels' absolute
/// differences (L1, 0..3).
pub fn l1(a: [f32; 3], b: [f32; 3]) -> f32 {
    (0..3).map(|k| (a[k] - b[k]).abs()).sum::<f32>()
}

/// Local texture of a `w` x `h` luma plane: the mean over a box of radius
/// `r` of its gradient magnitude (central differences, |gx| + |gy|).
pub fn texture(luma: &[f32], w: usize, h: usize, r: usize) -> Vec<f32> {
    let mut grad = vec![0f32; w * h];
    grad.par_chunks_mut(w).enumerate().for_each(|(y, out)| {
        let row = |y: usize| &luma[y * w..(y + 1) * w];
        let (up, here, down) = (row(y.saturating_sub(1)), row(y), row((y + 1).min(h - 1)));
        for (x, g) in out.iter_mut().enumerate() {
            let gx = here[(x + 1).min(w - 1)] - here[x.saturating_sub(1)];
            *g = gx.abs() + (down[x] - up[x]).abs();
        }
    });
    box_mean(&grad, w, h, r)
}

/// Radius of the box the texture is averaged over (a thin line raises the
/// texture this far on each side).
pub fn texture_radius(w: usize, h: usize) -> usize {
    (w.max(h) / 256).max(2)
}

/// The input pixels `[a, b)` that output pixel `o` of `n` covers in `len`.
fn span(o: usize, n: usize, len: usize) -> (usize, usize) {
    let a = o * len / n;
    let b = ((o + 1) * len / n).max(a + 1).min(len);
    (a, b)
}

/// Mean over a (2r+1)^2 box, clipped at the borders: separable sliding
/// sums in f64 (exact for these values: a flat stretch after a bright one
/// sums to exactly 0, as the classes' tests of "any sky nearby" need). Rows
/// go [`ROWS`] at a time (independent sums keep the core busy; each box's
/// size is divided once per column, not once per pixel), then each
/// band of [`BAND`] rows slides one accumulator the width of the grid down
/// (a loop the compiler vectorises). Blocks and bands are fixed, so the
/// sums are the same at any thread count.
pub fn box_mean(src: &[f32], w: usize, h: usize, r: usize) -> Vec<f32> {
    if w == 0 || h == 0 {
        return Vec::new();
    }
    // 1 / the box's width at each column (clipped at the borders).
    let inv: Vec<f64> = (0..w)
        .map(|x| 1.0 / ((x + r + 1).min(w) - x.saturating_sub(r)) as f64)
        .collect();
    let mut across = vec![0f32; w * h];
    across
        .par_chunks_mut(ROWS * w)
        .zip(src.par_chunks(ROWS * w))
        .for_each(|(out, rows)| {
            let k = rows.len() / w;
            let mut sum = [0f64; ROWS];
            for (j, s) in sum.iter_mut().enumerate().take(k) {
                *s = rows[j * w..j * w + r.min(w)]
                    .iter()
                    .map(|&v| v as f64)
                    .sum();
            }
            for (x, &inv) in inv.iter().enumerate() {
                for (j, s) in sum.iter_mut().enumerate().take(k) {
                    if x + r < w {
                        *s += rows[j * w + x + r] as f64;
                    }
                    if x > r {
                        *s -= rows[j * w + x - r - 1] as f64;
                    }
                    out[j * w + x] = (*s * inv) as f32;
                }
            }
        });
    let mut out = vec![0f32; w * h];
    out.par_chunks_mut(BAND * w)
        .enumerate()
        .for_each(|(b, out)| {
            let y0 = b * BAND;
            let row = |y: usize| &across[y * w..(y + 1) * w];
            // The window of the band's first row, less its bottom row,
            // plus the row that row will drop.
            let mut acc = vec![0f64; w];
            for y in y0.saturating_sub(r + 1)..(y0 + r).min(h) {
                acc.iter_mut()
                    .zip(row(y))
                    .for_each(|(a, &v)| *a += v as f64);
            }
            for (y, o) in (y0..).zip(out.chunks_exact_mut(w)) {
                if y + r < h {
                    acc.iter_mut()
                        .zip(row(y + r))
                        .for_each(|(a, &v)| *a += v as f64);
                }
                if y > r {
                    acc.iter_mut()
                        .zip(row(y - r - 1))
                        .for_each(|(a, &v)| *a -= v as f64);
                }
                let inv = 1.0 / ((y + r + 1).min(h) - y.saturating_sub(r)) as f64;
                o.iter_mut()
                    .zip(&acc)
                    .for_each(|(o, &a)| *o = (a * inv) as f32);
            }
        });
    out
}

/// Rows per band of [`box_mean`]'s vertical pass.
const BAND: usize = 32;

/// Rows [`box_mean`]'s horizontal pass sums side by side (8 rather than 4:
/// each running sum waits on its own add and subtract, so twice as many
/// chains keep the adder busy; the sums are the same).
const ROWS: usize = 8;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_mean_of_a_constant_is_the_constant_and_spreads_a_spike() {
        let c = box_mean(&[2.0; 30], 6, 5, 2);
        assert!(c.iter().all(|v| (v - 2.0).abs() < 1e-6));
        let mut spike = vec![0.0; 25];
        spike[12] = 9.0;
        let m = box_mean(&spike, 5, 5, 1);
        assert!((m[12] - 1.0).abs() < 1e-6 && m[0] == 0.0);
    }

    #[test]
    fn box_mean_matches_the_direct_sum_across_blocks_and_bands() {
        // Boxes much smaller than the grid, about as wide, and wider; rows
        // not a multiple of the blocks, more rows than a band.
        for (w, h, r) in [(150, 23, 4), (9, 7, 4), (5, 30, 2), (4, 3, 6), (31, 75, 3)] {
            check_box_mean(w, h, r);
        }
    }

    fn check_box_mean(w: usize, h: usize, r: usize) {
        let src: Vec<f32> = (0..w * h).map(|i| ((i * 7919) % 101) as f32).collect();
        let m = box_mean(&src, w, h, r);
        for (y, x) in (0..h).flat_map(|y| (0..w).map(move |x| (y, x))) {
            let (mut sum, mut n) = (0.0, 0.0);
            for yy in y.saturating_sub(r)..(y + r + 1).min(h) {
                for xx in x.saturating_sub(r)..(x + r + 1).min(w) {
                    sum += src[yy * w + xx];
                    n += 1.0;
                }
            }
            assert!(
                (m[y * w + x] - sum / n).abs() < 1e-3,
                "{w}x{h} r {r}: {x},{y}"
            );
        }
    }

    #[test]
    fn downsampling_averages_areas() {
        let img = image::RgbImage::from_fn(40, 20, |x, _| {
            image::Rgb(if x < 20 { [255, 0, 0] } else { [0, 0, 255] })
        });
        let f = Features::new(&Photo::new(DynamicImage::ImageRgb8(img)), 10);
        assert_eq!((f.w, f.h), (10, 5));
        assert!((f.rgb[0][0] - 1.0).abs() < 1e-6 && f.rgb[2][9] > 0.99);
    }
}
