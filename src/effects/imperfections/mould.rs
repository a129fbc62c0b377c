//! Mould (Becket & Badler): Gaussian clusters of dots around random
//! cluster centres. The cluster density times a dot-sized noise is the
//! field; its threshold at the coverage leaves dots, dense at the centres.

use image::GrayImage;
use rand::Rng as _;
use rayon::prelude::*;

use super::placement::{AREA, Placed};
use super::{Gen, alpha_byte, threshold};
use crate::effects::Context;
use crate::preset::MouldParams;
use crate::random::{Noise, rng};

/// Cluster centres drawn in the placement area: `clusters` per m² of it.
pub fn centres(ctx: &Context, p: &MouldParams, placed: &Placed, seed: u64) -> Vec<(f32, f32)> {
    let m2 = placed.area as f32 / ctx.photo_px(1.0).powi(2);
    let n = (p.clusters * m2).round().max(1.0) as usize;
    let mut r = rng(seed, Gen::Mould.stream(0), 0, 0);
    let (w, h) = (placed.width, placed.height);
    let mut out = Vec::with_capacity(n);
    for _ in 0..n * 50 {
        if out.len() == n || placed.area == 0 {
            break;
        }
        let (x, y) = (r.random_range(0..w), r.random_range(0..h));
        if placed.weight[y * w + x] >= AREA {
            out.push((x as f32 + 0.5, y as f32 + 0.5));
        }
    }
    out
}

/// The mould's alpha.
pub fn draw(ctx: &Context, p: &MouldParams, placed: &Placed, seed: u64) -> GrayImage {
    let (w, h) = (placed.width, placed.height);
    let sigma = ctx.photo_px(p.cluster_size).max(1.0);
    let mut density = vec![0.0f32; w * h];
    for (cx, cy) in centres(ctx, p, placed, seed) {
        let r = 3.0 * sigma;
        let (x0, x1) = ((cx - r).max(0.0) as usize, ((cx + r) as usize + 1).min(w));
        let (y0, y1) = ((cy - r).max(0.0) as usize, ((cy + r) as usize + 1).min(h));
        for y in y0..y1 {
            for x in x0..x1 {
                let d2 = (x as f32 + 0.5 - cx).powi(2) + (y as f32 + 0.5 - cy).powi(2);
                density[y * w + x] += (-d2 / (2.0 * sigma * sigma)).exp();
            }
        }
    }
    let dot = ctx.photo_px(p.dot_size).max(1.0);
    let noise = Noise::new(
        crate::random::key(seed, Gen::Mould.stream(1), 0, 0),
        w as u32,
        h as u32,
        dot * 2.0,
        2,
    );
    // The small constant keeps the noise's order where no cluster reaches.
    let g: Vec<f32> = (0..w * h)
        .into_par_iter()
        .map(|i| {
            let wt = placed.weight[i];
            if wt <= 0.0 {
                return 0.0;
            }
            let n = noise.at((i % w) as f32, (i / w) as f32);
            (density[i].min(1.5) + 0.02) * (0.2 + n) * wt
        })
        .collect();
    let t = threshold(&g, placed, p.coverage);
    GrayImage::from_fn(w as u32, h as u32, |x, y| {
        let i = y as usize * w + x as usize;
        if g[i] > t && placed.weight[i] > 0.0 {
            let s = ((g[i] - t) / t.abs().max(1e-3)).min(1.0);
            image::Luma([alpha_byte(0.55 + 0.45 * s)])
        } else {
            image::Luma([0])
        }
    })
}
