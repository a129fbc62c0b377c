//! The wall as a soft matte: the hard labels through a guided filter on the
//! photo's luma (He, Sun and Tang, "Guided image filtering", 2010, eqs.
//! (7)-(8)), so the matte's edges follow the photo's. The filter runs as
//! the fast guided filter (He and Sun, "Fast guided filter", 2015, Alg. 2):
//! its coefficients `a` and `b` are smooth, so they are found on a grid
//! subsampled by [`SUBSAMPLE`] and upsampled bilinearly, while the output
//! `q = a I + b` uses the guide `I` at full resolution.

use image::GrayImage;
use rayon::prelude::*;

use super::features::{Features, box_mean};
use super::wall::Class;

/// The fast guided filter's subsampling ratio `s` ([`halve`]): a quarter
/// of the box means' work. Measured on LabelMeFacade train (100 photos): the
/// same wall IoU and spill as the full-resolution filter to three digits.
const SUBSAMPLE: usize = 2;

/// Regularisation `epsilon` of eq. (7): edges in luma weaker than about
/// its square root (0.06) are smoothed over.
const EPS: f32 = 0.004;

/// The wall as a soft matte (0..1) at analysis resolution.
pub fn refine(f: &Features, class: &[Class]) -> Vec<f32> {
    let (w, h) = (f.w, f.h);
    let p: Vec<f32> = class
        .iter()
        .map(|&c| (c == Class::Wall) as u8 as f32)
        .collect();
    if p.iter().all(|&v| v == 1.0) || p.iter().all(|&v| v == 0.0) {
        return p;
    }
    // Alg. 2, steps 1-2: subsample the guide and the input; the radius
    // shrinks with them (rounded up, so the window is never smaller).
    let r = (w.max(h) / 300).max(2).div_ceil(SUBSAMPLE);
    let (sw, sh) = (w.div_ceil(SUBSAMPLE), h.div_ceil(SUBSAMPLE));
    let i = halve(&f.luma, w, h);
    let p = halve(&p, w, h);
    // Steps 3-5: eqs. (7)-(8) on the coarse grid.
    let mean_i = box_mean(&i, sw, sh, r);
    let mean_p = box_mean(&p, sw, sh, r);
    let ip: Vec<f32> = i.iter().zip(&p).map(|(a, b)| a * b).collect();
    let ii: Vec<f32> = i.iter().map(|a| a * a).collect();
    let corr_ip = box_mean(&ip, sw, sh, r);
    let corr_ii = box_mean(&ii, sw, sh, r);
    let (a, b): (Vec<f32>, Vec<f32>) = (0..sw * sh)
        .map(|k| {
            let var = corr_ii[k] - mean_i[k] * mean_i[k];
            let cov = corr_ip[k] - mean_i[k] * mean_p[k];
            let a = cov / (var + EPS); // eq. (7)
            (a, mean_p[k] - a * mean_i[k]) // eq. (8)
        })
        .unzip();
    let ma = box_mean(&a, sw, sh, r);
    let mb = box_mean(&b, sw, sh, r);
    // Step 6: upsample the mean coefficients; q = a I + b at full size.
    let xs = taps(w, SUBSAMPLE as f32, sw);
    let mut q = vec![0f32; w * h];
    q.par_chunks_mut(w)
        .zip(f.luma.par_chunks(w))
        .enumerate()
        .for_each(|(y, (q, luma))| {
            let (y0, y1, ty) = tap((y as f32 + 0.5) / SUBSAMPLE as f32 - 0.5, sh);
            let row = |m: &[f32]| -> Vec<f32> {
                let (r0, r1) = (&m[y0 * sw..(y0 + 1) * sw], &m[y1 * sw..(y1 + 1) * sw]);
                r0.iter().zip(r1).map(|(u, v)| u + (v - u) * ty).collect()
            };
            let (ra, rb) = (row(&ma), row(&mb));
            for ((q, &l), &(x0, x1, tx)) in q.iter_mut().zip(luma).zip(&xs) {
                let a = ra[x0] + (ra[x1] - ra[x0]) * tx;
                let b = rb[x0] + (rb[x1] - rb[x0]) * tx;
                *q = (a * l + b).clamp(0.0, 1.0);
            }
        });
    q
}

/// `v` (`w` x `h`) averaged over 2 x 2 blocks ([`SUBSAMPLE`]; the blocks
/// on the right and bottom edges may be cut short).
fn halve(v: &[f32], w: usize, h: usize) -> Vec<f32> {
    let (sw, sh) = (w.div_ceil(2), h.div_ceil(2));
    let mut out = vec![0f32; sw * sh];
    out.par_chunks_mut(sw).enumerate().for_each(|(y, out)| {
        let top = &v[2 * y * w..(2 * y + 1) * w];
        let (pair, rows): (Vec<f32>, f32) = match v.get((2 * y + 1) * w..(2 * y + 2) * w) {
            Some(bottom) => (top.iter().zip(bottom).map(|(a, b)| a + b).collect(), 2.0),
            None => (top.to_vec(), 1.0),
        };
        for (o, block) in out.iter_mut().zip(pair.chunks(2)) {
            *o = block.iter().sum::<f32>() / (rows * block.len() as f32);
        }
    });
    out
}

/// The matte at the photo's size (bilinear).
pub fn upsample(small: &[f32], f: &Features, pw: u32, ph: u32) -> GrayImage {
    let (w, h) = (f.w, f.h);
    let xs = taps(pw as usize, f.sx, w);
    // Each analysis row widened to the photo's width once, in 0..255;
    // then each photo row is a blend of two wide rows (a loop the compiler
    // vectorises, no lookups per photo pixel).
    let wide: Vec<Vec<f32>> = small
        .par_chunks(w)
        .map(|row| {
            xs.iter()
                .map(|&(x0, x1, tx)| (row[x0] + (row[x1] - row[x0]) * tx) * 255.0)
                .collect()
        })
        .collect();
    let mut out = vec![0u8; pw as usize * ph as usize];
    out.par_chunks_mut(pw as usize)
        .enumerate()
        .for_each(|(y, row)| {
            let (y0, y1, ty) = tap((y as f32 + 0.5) / f.sy - 0.5, h);
            for (o, (&a, &b)) in row.iter_mut().zip(wide[y0].iter().zip(&wide[y1])) {
                // Rounded by adding 1.5 * 2^23: the float's low mantissa
                // bits are then the nearest integer (0..=255 here, as the
                // matte is in 0..1). Bit operations vectorise; a float to
                // u8 cast saturates one pixel at a time.
                *o = (a + (b - a) * ty + ROUND).to_bits() as u8;
            }
        });
    GrayImage::from_raw(pw, ph, out).expect("buffer has the photo's size")
}

/// Added to a float in 0..2^22 to round it to an integer in the low
/// mantissa bits.
const ROUND: f32 = 12_582_912.0;

/// For each of `n` output pixels, its two neighbours in an input `len`
/// long that is `scale` times smaller, and the weight of the second.
fn taps(n: usize, scale: f32, len: usize) -> Vec<(usize, usize, f32)> {
    (0..n)
        .map(|x| tap((x as f32 + 0.5) / scale - 0.5, len))
        .collect()
}

/// The two neighbours of continuous coordinate `c` in `0..n` and the weight of the second.
fn tap(c: f32, n: usize) -> (usize, usize, f32) {
    let c = c.clamp(0.0, (n - 1) as f32);
    let a = c.floor() as usize;
    (a, (a + 1).min(n - 1), c - a as f32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::photo::Photo;

    /// A photo whose left part (x < `edge`) is dark, the rest pale, with
    /// the classes split at `split`.
    fn split_scene(edge: u32, split: usize) -> (Features, Vec<Class>) {
        let (w, h) = (120u32, 80u32);
        let img = image::RgbImage::from_fn(w, h, |x, _| {
            image::Rgb(if x < edge {
                [40, 40, 45]
            } else {
                [200, 190, 170]
            })
        });
        let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 120);
        let class = (0..f.w * f.h)
            .map(|i| {
                if i % f.w < split {
                    Class::Sky
                } else {
                    Class::Wall
                }
            })
            .collect();
        (f, class)
    }

    #[test]
    fn the_matte_is_sharp_where_the_photo_has_an_edge() {
        // The same step in the labels as below, on the photo's edge: the
        // matte steps within a pixel or two instead of ramping.
        let (f, class) = split_scene(60, 60);
        let m = refine(&f, &class);
        let row = &m[40 * f.w..41 * f.w];
        assert!(row[..59].iter().all(|&v| v < 0.1), "{:?}", &row[55..65]);
        assert!(row[61..].iter().all(|&v| v > 0.9), "{:?}", &row[55..65]);
    }

    #[test]
    fn with_no_edge_in_the_photo_the_matte_is_soft() {
        // A flat photo gives the guide nothing to snap to: the step in
        // the labels comes out as a ramp, not a staircase.
        let (f, class) = split_scene(0, 60);
        let m = refine(&f, &class);
        let row = &m[40 * f.w..41 * f.w];
        let between = row[55..65].iter().filter(|&&v| v > 0.1 && v < 0.9).count();
        assert!(between >= 3, "a ramp across the step: {:?}", &row[55..65]);
        assert!(row.windows(2).all(|p| p[1] >= p[0] - 1e-6), "monotone");
    }

    #[test]
    fn the_upsampled_matte_has_the_photos_size_and_rounds() {
        let (f, class) = split_scene(60, 60);
        let m = upsample(&refine(&f, &class), &f, 240, 160);
        assert_eq!(m.dimensions(), (240, 160));
        assert_eq!(m.get_pixel(10, 80)[0], 0);
        assert_eq!(m.get_pixel(230, 80)[0], 255);
    }
}
