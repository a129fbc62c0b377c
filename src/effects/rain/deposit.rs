//! The colour of the rain's deposit, per pixel, from the wall it lies on.
//!
//! [choice, beyond Chang, who multiplies one dirt colour onto the wall:]
//! run-off dirt on a facade is a deposit, not a tint (`how-facades-age.md`;
//! blind review 21, tell 4: "a transparent grey layer, the grain shows
//! through unchanged, no colour shift"). Where it is thick it hides the
//! wall's grain (it fills the pores), it takes its hue from the wall it
//! lies on (soot on limestone reads grey-black, on brick brown-black, on
//! render yellow-grey-brown) and it is duller than the wall. So with
//! `stain.wall_hue > 0` each rain layer paints (normal blend) the colour of
//! this map, at its own coverage: the local wall's mean colour (over
//! [`LOCAL_M`]), desaturated toward the dirt's own hue (`stain.color`) by
//! `1 - wall_hue`, and as much darker than the wall as `stain.color` is
//! darker than white. Over a wall pixel of the local mean the layer
//! darkens as the multiply of `stain.color` did; over the grain it pulls
//! every pixel toward the same colour, so the grain's contrast falls by
//! the coverage.

use image::{GrayImage, RgbImage};
use rayon::prelude::*;

use crate::effects::Context;
use crate::field::RowMajor;

/// The window the wall's local colour is averaged over, metres (half its
/// side) [choice: 0.3 m, a few bricks and a joint or two, so a brick band
/// and the stone course beside it keep their own hues while the grain,
/// the single brick and the joint, does not print into the deposit; at
/// 0.1 m the darker bricks showed through a thick deposit as a pattern].
pub const LOCAL_M: f32 = 0.3;

/// Rec. 601 luma of an sRGB colour in 0..255.
fn luma(c: [f32; 3]) -> f32 {
    0.299 * c[0] + 0.587 * c[1] + 0.114 * c[2]
}

/// The deposit's colour for a wall whose local mean colour is `wall`
/// (0..255): `dirt`'s darkness relative to white, with `wall_hue` of the
/// wall's own chroma and the rest of the dirt's.
pub fn deposit_color(wall: [f32; 3], dirt: [u8; 3], wall_hue: f32) -> [f32; 3] {
    let dirt = dirt.map(f32::from);
    let dirt_luma = luma(dirt).max(1.0);
    let darkness = dirt_luma / 255.0;
    let wall_luma = luma(wall);
    let w = wall_hue.clamp(0.0, 1.0);
    [0, 1, 2].map(|i| {
        let hue = w * wall[i] + (1.0 - w) * wall_luma * dirt[i] / dirt_luma;
        (darkness * hue).clamp(0.0, 255.0)
    })
}

/// The deposit colour map at the photo's size: [`deposit_color`] of the
/// wall's local mean colour, which is sampled at the grid's cells and
/// averaged over the region within [`LOCAL_M`], then upsampled.
pub fn colors(ctx: &Context, dirt: [u8; 3], wall_hue: f32) -> RgbImage {
    let grid = ctx.grid;
    let (gw, gh) = (grid.width, grid.height);
    let (pw, ph) = (ctx.photo.width(), ctx.photo.height());
    let samples: Vec<[f32; 3]> = (0..gw * gh)
        .into_par_iter()
        .map(|i| {
            let (x, y) = grid.to_photo((i % gw) as f32 + 0.5, (i / gw) as f32 + 0.5);
            let x = (x.max(0.0) as u32).min(pw.saturating_sub(1));
            let y = (y.max(0.0) as u32).min(ph.saturating_sub(1));
            ctx.photo.rgb_at(x, y)
        })
        .collect();
    let radius = ctx.grid_px(LOCAL_M).round().max(1.0) as usize;
    let region = ctx.region;
    // The wall's mean colour, for cells outside the region (the upsample
    // blends them into the wall's edge).
    let inside = region.data().iter().filter(|r| **r).count().max(1) as f32;
    let mean = [0, 1, 2].map(|c| {
        samples
            .iter()
            .zip(region.data())
            .filter(|(_, r)| **r)
            .map(|(v, _)| v[c])
            .sum::<f32>()
            / inside
    });
    // The mean over the region's cells in the window: masked sums over
    // the region's share (as `box_mean`, at a quarter of its cost here).
    let ones: Vec<f32> = region
        .data()
        .iter()
        .map(|r| f32::from(u8::from(*r)))
        .collect();
    let share = box_blur(&ones, gw, gh, radius);
    let local = [0, 1, 2].map(|c| {
        let v: Vec<f32> = samples.iter().zip(&ones).map(|(s, r)| s[c] * r).collect();
        let sum = box_blur(&v, gw, gh, radius);
        sum.iter()
            .zip(&share)
            .map(|(s, n)| s / n.max(1e-6))
            .collect::<Vec<f32>>()
    });
    let colours: Vec<[f32; 3]> = (0..gw * gh)
        .map(|i| {
            let wall = match region.data()[i] {
                true => local.each_ref().map(|l| l[i]),
                false => mean,
            };
            deposit_color(wall, dirt, wall_hue)
        })
        .collect();
    let planes: Vec<GrayImage> = vec![0, 1, 2]
        .into_par_iter()
        .map(|k| {
            let v = colours.iter().map(|c| c[k] / 255.0).collect();
            grid.upsample(&RowMajor::new(gw, gh, v), None, pw, ph)
        })
        .collect();
    let mut rgb = RgbImage::new(pw, ph);
    rgb.par_chunks_mut(3)
        .zip(planes[0].as_raw().par_iter())
        .zip(planes[1].as_raw().par_iter())
        .zip(planes[2].as_raw().par_iter())
        .for_each(|(((o, r), g), b)| o.copy_from_slice(&[*r, *g, *b]));
    rgb
}

/// Rows a task of [`box_blur`] slides its window down.
const STRIP: usize = 64;

/// The mean of `values` (`w` x `h`, row-major) over the square window
/// `radius` either side, clipped at the borders: a running sum along each
/// row, then a window of row sums slid down strips of rows (the photo-size
/// maps of [`super::soak`], where [`crate::effects::box_mean::box_mean`]'s region
/// counts are not needed).
pub(super) fn box_blur(values: &[f32], w: usize, h: usize, radius: usize) -> Vec<f32> {
    let mut rows = vec![0.0f32; w * h];
    rows.par_chunks_mut(w.max(1))
        .zip(values.par_chunks(w.max(1)))
        .for_each(|(out, row)| {
            let mut sum: f32 = row[..radius.min(w)].iter().sum();
            for (x, o) in out.iter_mut().enumerate() {
                if x + radius < w {
                    sum += row[x + radius];
                }
                if x > radius {
                    sum -= row[x - radius - 1];
                }
                let n = (x + radius).min(w - 1) + 1 - x.saturating_sub(radius);
                *o = sum / n as f32;
            }
        });
    let mut out = vec![0.0f32; w * h];
    out.par_chunks_mut((STRIP * w).max(1))
        .enumerate()
        .for_each(|(strip, out)| {
            let y0 = strip * STRIP;
            let mut sum = vec![0.0f32; w];
            // The window above row y0, with the row its first step drops.
            let top = if y0 > radius { y0 - radius - 1 } else { 0 };
            for y in top..(y0 + radius).min(h) {
                sum.iter_mut()
                    .zip(&rows[y * w..][..w])
                    .for_each(|(s, v)| *s += v);
            }
            for (dy, out) in out.chunks_mut(w).enumerate() {
                let y = y0 + dy;
                if y + radius < h {
                    let add = &rows[(y + radius) * w..][..w];
                    sum.iter_mut().zip(add).for_each(|(s, v)| *s += v);
                }
                if y > radius {
                    let sub = &rows[(y - radius - 1) * w..][..w];
                    sum.iter_mut().zip(sub).for_each(|(s, v)| *s -= v);
                }
                let n = ((y + radius).min(h - 1) + 1 - y.saturating_sub(radius)) as f32;
                out.iter_mut().zip(&sum).for_each(|(o, s)| *o = s / n);
            }
        });
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_blur_matches_a_plain_window_mean() {
        let (w, h, r) = (23, 150, 3);
        let v: Vec<f32> = (0..w * h).map(|i| ((i * 37) % 29) as f32).collect();
        let got = box_blur(&v, w, h, r);
        for y in 0..h {
            for x in 0..w {
                let (mut s, mut n) = (0.0, 0.0);
                for yy in y.saturating_sub(r)..(y + r + 1).min(h) {
                    for xx in x.saturating_sub(r)..(x + r + 1).min(w) {
                        s += v[yy * w + xx];
                        n += 1.0;
                    }
                }
                let want = s / n;
                assert!((got[y * w + x] - want).abs() < 1e-3, "({x}, {y})");
            }
        }
    }

    /// The deposit on red brick is redder than on grey stone, darker than
    /// either wall, and duller (less chroma) than the brick.
    #[test]
    fn the_deposit_takes_the_walls_hue_darker_and_duller() {
        let dirt = [86, 76, 62];
        let brick = [150.0, 80.0, 60.0];
        let stone = [170.0, 168.0, 165.0];
        let on_brick = deposit_color(brick, dirt, 0.6);
        let on_stone = deposit_color(stone, dirt, 0.6);
        let redness = |c: [f32; 3]| c[0] / (c[1] + c[2]);
        assert!(redness(on_brick) > redness(on_stone) + 0.2);
        assert!(luma(on_brick) < 0.5 * luma(brick));
        assert!(luma(on_stone) < 0.5 * luma(stone));
        let chroma = |c: [f32; 3]| (c[0] - c[2]) / luma(c);
        assert!(chroma(on_brick) < chroma(brick));
        // With no wall hue, the dirt's own hue at the wall's lightness.
        let plain = deposit_color(brick, dirt, 0.0);
        assert!((redness(plain) - redness(dirt.map(f32::from))).abs() < 1e-3);
    }
}
