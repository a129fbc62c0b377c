//! Splotches and stains (Becket & Badler): a midpoint-subdivision fractal
//! thresholded to the coverage. Splotches interpolate from the surface to
//! the dried splotch over `[n, 1]` of the fractal (`n` the threshold: a
//! higher `n` gives sparser splotches) and have fractal wet regions inside;
//! stains are darker near their fractal edge, or a ring with a light inside.

use image::{GrayImage, RgbaImage};
use rayon::prelude::*;

use super::fractal::Fractal;
use super::placement::Placed;
use super::{Gen, alpha_byte, threshold};
use crate::effects::Context;
use crate::effects::rain::wall::NEIGHBOURS;
use crate::preset::BlotchParams;
use crate::stack::{BlendMode, LayerPixels};

/// Share of the field's height over which a splotch fades in at its edge.
const EDGE_FADE: f32 = 0.04;

/// The generator's field times the placement weight, per pixel.
pub fn field(ctx: &Context, p: &BlotchParams, placed: &Placed, seed: u64, which: Gen) -> Vec<f32> {
    let (w, h) = (placed.width, placed.height);
    let size = ctx.photo_px(p.size).max(2.0);
    let f = Fractal::new(seed, which.stream(0), w, h, size, p.roughness);
    (0..w * h)
        .into_par_iter()
        .map(|i| {
            let wt = placed.weight[i];
            if wt > 0.0 {
                f.at((i % w) as f32, (i / w) as f32) * wt
            } else {
                0.0
            }
        })
        .collect()
}

/// The layer's pixels, its blend and its alpha (for the coverage).
pub fn draw(
    ctx: &Context,
    p: &BlotchParams,
    placed: &Placed,
    seed: u64,
    which: Gen,
) -> (LayerPixels, BlendMode, GrayImage) {
    let (w, h) = (placed.width, placed.height);
    let g = field(ctx, p, placed, seed, which);
    let t = threshold(&g, placed, p.coverage);
    let top = g.iter().copied().fold(0.0f32, f32::max);
    // Where a pixel lies in [n, 1]: 0 at the edge, 1 at the field's top.
    let depth = |v: f32| ((v - t) / (top - t).max(1e-6)).clamp(0.0, 1.0);
    let covered = |i: usize| g[i] > t && placed.weight[i] > 0.0;
    if let Gen::Stains = which {
        let alpha = GrayImage::from_fn(w as u32, h as u32, |x, y| {
            let i = y as usize * w + x as usize;
            if !covered(i) {
                return image::Luma([0]);
            }
            let s = depth(g[i]);
            let a = if p.ring {
                0.08 + 0.92 * (-s / 0.06).exp()
            } else {
                // Darker near the edge by `wet`.
                (1.0 - p.wet) * 0.6 + p.wet * (0.35 + 0.65 * (-s / 0.1).exp())
            };
            // [choice] An edge pixel keeps the share of its 8 neighbours
            // that are stained too (a one-pixel soft edge, like the photo's
            // own): a cut at full strength read as a hard, cut-out edge on
            // real photos (blind review 7). The dark rim stays just inside.
            let (x, y) = (x as usize, y as usize);
            let mut inside = 0;
            for (dx, dy) in NEIGHBOURS {
                let (nx, ny) = (x as isize + dx, y as isize + dy);
                let on = nx >= 0 && ny >= 0 && (nx as usize) < w && (ny as usize) < h;
                inside += usize::from(on && covered(ny as usize * w + nx as usize));
            }
            image::Luma([alpha_byte(a * inside as f32 / 8.0)])
        });
        let pixels = LayerPixels::Tint {
            color: p.color,
            alpha: alpha.clone(),
        };
        return (pixels, BlendMode::Multiply, alpha);
    }
    // Splotches: fractal wet and dry regions inside, the wet darker.
    let wet = Fractal::new(
        seed,
        which.stream(1),
        w,
        h,
        ctx.photo_px(p.size * 0.3).max(2.0),
        0.6,
    );
    let wet_level = 1.0 - p.wet;
    let dark = p.color.map(|c| (c as f32 * 0.55) as u8);
    let mut img = RgbaImage::new(w as u32, h as u32);
    img.par_chunks_mut(4 * w).enumerate().for_each(|(y, row)| {
        for (x, px) in row.chunks_exact_mut(4).enumerate() {
            let i = y * w + x;
            if !covered(i) {
                continue;
            }
            let s = depth(g[i]);
            let is_wet = wet.at(x as f32, y as f32) > wet_level;
            let c = if is_wet { dark } else { p.color };
            let a = (s / EDGE_FADE).min(1.0) * if is_wet { 0.95 } else { 0.55 + 0.35 * s };
            px.copy_from_slice(&[c[0], c[1], c[2], alpha_byte(a)]);
        }
    });
    let alpha = GrayImage::from_fn(w as u32, h as u32, |x, y| {
        image::Luma([img.get_pixel(x, y)[3]])
    });
    (LayerPixels::Rgba(img), BlendMode::Normal, alpha)
}
