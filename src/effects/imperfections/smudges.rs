//! Smudges and corrosion (Becket & Badler): "fBm intensity used as an
//! interpolation weight". A midpoint-subdivision fractal times the
//! placement weight is thresholded to the coverage like the splotches; above
//! the threshold its height is the weight `w` in 0..1 that interpolates
//! the wall toward the imperfect look, so both fade in from nothing at
//! their edge instead of starting with a hard boundary.
//!
//! - Smudges (hands, splash-back at the foot of a wall): the wall blurred
//!   and pulled toward a grease colour, with alpha `w` (the paper's direct
//!   interpolation); how far toward the grease is mottled by a finer
//!   fractal, so a smudge is not one flat grey.
//! - Corrosion (stone decay, corroded metal): a discolouration multiplied
//!   into the wall with alpha `discolour x w`, and darker pits where a
//!   fine noise's rank exceeds `1 - pits x w`, so pitting is densest where
//!   the fBm is strongest. A pit smaller than a pixel only darkens it by
//!   its share of the pixel (no black pepper on a small photo).

use image::{GrayImage, RgbaImage};
use rayon::prelude::*;

use super::fractal::Fractal;
use super::placement::Placed;
use super::{Gen, alpha_byte, threshold};
use crate::effects::Context;
use crate::effects::percentile::{Rank, percentile};
use crate::preset::{CorrosionParams, SmudgeParams};
use crate::random::{Noise, key};

/// Quantile of the covered field's heights above the threshold that has
/// full weight.
pub const FULL: f32 = 0.9;

/// The fBm weight of a generator: 0 outside its coverage, rising from just
/// above 0 at the threshold to 1 at the [`FULL`] quantile of the covered
/// heights.
pub struct Weight {
    /// The field (fractal x placement weight), per pixel.
    pub field: Vec<f32>,
    /// The interpolation weight, per pixel (0 = not covered).
    pub weight: Vec<f32>,
}

/// The fractal (stretched `stretch` times wider than tall) times the
/// placement weight, thresholded at `coverage`.
pub fn weight(f: &Fractal, placed: &Placed, coverage: f32, stretch: f32) -> Weight {
    let w = placed.width;
    // Sampling x / s (or y x s) keeps the lattice's coordinates within it.
    let (sx, sy) = (1.0 / stretch.max(1.0), stretch.min(1.0));
    let field: Vec<f32> = (0..w * placed.height)
        .into_par_iter()
        .map(|i| {
            let wt = placed.weight[i];
            if wt > 0.0 {
                f.at((i % w) as f32 * sx, (i / w) as f32 * sy) * wt
            } else {
                0.0
            }
        })
        .collect();
    let t = threshold(&field, placed, coverage);
    // Full weight from the covered heights' FULL quantile up (the top alone
    // would leave most of a smudge faint).
    let heights = field
        .iter()
        .zip(&placed.weight)
        .filter(|(g, wt)| **g > t && **wt > 0.0)
        .map(|(g, _)| g - t);
    let span = percentile(heights, FULL, Rank::Nearest)
        .unwrap_or(1.0)
        .max(1e-6);
    let weight = field
        .par_iter()
        .zip(&placed.weight)
        .map(|(&g, &wt)| {
            if g > t && wt > 0.0 {
                ((g - t) / span).clamp(1e-3, 1.0)
            } else {
                0.0
            }
        })
        .collect();
    Weight { field, weight }
}

/// A generator's fBm over the placement, its coarsest features `size_m`
/// metres across.
fn fractal(
    ctx: &Context,
    which: Gen,
    placed: &Placed,
    size_m: f32,
    roughness: f32,
    seed: u64,
) -> Fractal {
    let px = ctx.photo_px(size_m).max(2.0);
    Fractal::new(
        seed,
        which.stream(0),
        placed.width,
        placed.height,
        px,
        roughness,
    )
}

fn alpha_of(img: &RgbaImage) -> GrayImage {
    GrayImage::from_fn(img.width(), img.height(), |x, y| {
        image::Luma([img.get_pixel(x, y)[3]])
    })
}

/// The smudges' layer (normal blend) and its alpha.
pub fn smudges(
    ctx: &Context,
    p: &SmudgeParams,
    placed: &Placed,
    seed: u64,
) -> (RgbaImage, GrayImage) {
    let (w, h) = (placed.width, placed.height);
    let f = fractal(ctx, Gen::Smudges, placed, p.size, p.roughness, seed);
    let wt = weight(&f, placed, p.coverage, p.stretch);
    let photo = ctx.photo.image().to_rgb8();
    let r = ctx.photo_px(p.blur).round() as usize;
    let blurred = if r == 0 {
        photo
    } else {
        crate::effects::weathering::smoothed(&photo, r)
    };
    let mottle = Fractal::new(
        seed,
        Gen::Smudges.stream(1),
        w,
        h,
        ctx.photo_px(p.size * 0.15).max(2.0),
        0.6,
    );
    let img = layer(w, h, &wt.weight, |i, v| {
        let (x, y) = (i % w, i / w);
        let c = blurred.get_pixel(x as u32, y as u32).0;
        let k = p.darken * (0.5 + mottle.at(x as f32, y as f32));
        let px = std::array::from_fn(|j| {
            (c[j] as f32 + (p.color[j] as f32 - c[j] as f32) * k.min(1.0)).round() as u8
        });
        (px, v)
    });
    let alpha = alpha_of(&img);
    (img, alpha)
}

/// A `w` x `h` RGBA layer from a per-pixel rule on the pixel's index and
/// weight (only where the weight is above 0).
fn layer(
    w: usize,
    h: usize,
    weight: &[f32],
    rule: impl Fn(usize, f32) -> ([u8; 3], f32) + Sync,
) -> RgbaImage {
    let mut img = RgbaImage::new(w as u32, h as u32);
    img.par_chunks_mut(4 * w).enumerate().for_each(|(y, row)| {
        for (x, px) in row.chunks_exact_mut(4).enumerate() {
            let v = weight[y * w + x];
            if v > 0.0 {
                let (c, a) = rule(y * w + x, v);
                px.copy_from_slice(&[c[0], c[1], c[2], alpha_byte(a)]);
            }
        }
    });
    img
}

/// Alpha of a pit at least [`PIT_PX`] pixels across.
pub const PIT_ALPHA: f32 = 0.7;

/// Pits this many pixels across or more are drawn at full alpha; smaller
/// ones darken their pixel by their share of it.
pub const PIT_PX: f32 = 2.0;

/// The alpha of a pit `px` pixels across.
pub fn pit_alpha(px: f32) -> f32 {
    PIT_ALPHA * (px / PIT_PX).clamp(0.0, 1.0).powi(2)
}

/// Which covered pixels of `weight` are pits: a noise `pit_size` across,
/// ranked over the covered pixels, above `1 - pits x w`.
pub fn pits(ctx: &Context, p: &CorrosionParams, weight: &[f32], w: usize, seed: u64) -> Vec<bool> {
    let h = weight.len() / w.max(1);
    let noise = Noise::new(
        key(seed, Gen::Corrosion.stream(1), 0, 0),
        w as u32,
        h as u32,
        ctx.photo_px(p.pit_size).max(1.0),
        2,
    );
    let n: Vec<f32> = (0..w * h)
        .into_par_iter()
        .map(|i| {
            if weight[i] > 0.0 {
                noise.at((i % w) as f32, (i / w) as f32)
            } else {
                f32::NAN
            }
        })
        .collect();
    // The noise's distribution over the covered pixels (a sample of it).
    let mut sample: Vec<f32> = n.iter().copied().filter(|v| !v.is_nan()).collect();
    let step = (sample.len() / 4096).max(1);
    sample = sample.into_iter().step_by(step).collect();
    sample.sort_by(f32::total_cmp);
    let rank = |v: f32| sample.partition_point(|&s| s < v) as f32 / sample.len().max(1) as f32;
    n.par_iter()
        .zip(weight)
        .map(|(&v, &wt)| wt > 0.0 && rank(v) > 1.0 - p.pits * wt)
        .collect()
}

/// The corrosion's layer (multiplied into the wall, so the wall's own
/// texture stays) and its alpha.
pub fn corrosion(
    ctx: &Context,
    p: &CorrosionParams,
    placed: &Placed,
    seed: u64,
) -> (RgbaImage, GrayImage) {
    let (w, h) = (placed.width, placed.height);
    let f = fractal(ctx, Gen::Corrosion, placed, p.size, p.roughness, seed);
    let wt = weight(&f, placed, p.coverage, 1.0);
    let pitted = pits(ctx, p, &wt.weight, w, seed);
    // A pit: the colour darkened by the pit's share of its pixel.
    let pit_a = pit_alpha(ctx.photo_px(p.pit_size));
    let dark = 1.0 - 0.45 * pit_a / PIT_ALPHA;
    let pit = p.color.map(|c| (c as f32 * dark) as u8);
    let img = layer(w, h, &wt.weight, |i, v| {
        let a = p.discolour * v;
        if pitted[i] {
            (pit, a.max(pit_a))
        } else {
            (p.color, a)
        }
    });
    let alpha = alpha_of(&img);
    (img, alpha)
}
