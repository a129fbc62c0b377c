//! Rust (Becket & Badler): a rule-guided aggregation, a generalised
//! diffusion-limited aggregation on the simulation grid. Each iteration a
//! cell at the metal (the placement's railings, sills or edges) rusts with
//! a small chance, any other cell with a very small one, and a neighbour
//! of rust with a high one; fixings start rusted. The number of iterations
//! is the severity. Where rust forms, water carries dissolved iron down:
//! a short smear below it ([choice]: a run of fixed length, not a γ-ton
//! flow; the `gammaton` effect's `rust-runs` preset has the full one).

use image::{GrayImage, RgbaImage};
use rand::Rng as _;
use rayon::prelude::*;

use super::placement::{AREA, Placed};
use super::{Coverage, Gen, Made, alpha_byte, layer, measured, threshold};
use crate::effects::Context;
use crate::effects::rain::wall::NEIGHBOURS;
use crate::effects::region::Region;
use crate::error::Result;
use crate::field::RowMajor;
use crate::preset::{Placement, RustParams};
use crate::progress::Progress;
use crate::random::{Noise, key, rng};
use crate::stack::{BlendMode, LayerPixels};

/// The aggregation's inputs on the grid.
pub struct Ground<'a> {
    /// Where rust may form, 0..1 (the placement weight).
    pub allowed: &'a RowMajor<f32>,
    /// The metal: cells that rust with `p_edge`.
    pub sources: &'a RowMajor<bool>,
    /// Cells rusted from the start (fixings).
    pub seeds: &'a [(usize, usize)],
}

/// The iteration each cell rusted in (`f32::INFINITY` = never; 0 = a seed).
pub struct Aggregate {
    /// Per cell.
    pub age: RowMajor<f32>,
    /// Iterations run.
    pub iterations: u32,
    /// Rusted cells.
    pub rusted: usize,
}

/// Runs the aggregation for `p.iterations`, and on until at least
/// `min_rusted` cells rusted (up to four times as long plus 400).
pub fn aggregate(g: &Ground, p: &RustParams, min_rusted: usize, seed: u64) -> Aggregate {
    let (w, h) = (g.allowed.width(), g.allowed.height());
    let mut age = RowMajor::filled(w, h, f32::INFINITY);
    let mut rusted = 0;
    for &(x, y) in g.seeds {
        if x < w && y < h && age.get(x, y).is_infinite() {
            age.data_mut()[y * w + x] = 0.0;
            rusted += 1;
        }
    }
    let cap = p.iterations.saturating_mul(4).saturating_add(400);
    let mut it = 0;
    while it < p.iterations || (rusted < min_rusted && it < cap) {
        it += 1;
        let prev = age.clone();
        let was = |x: isize, y: isize| -> bool {
            x >= 0
                && y >= 0
                && (x as usize) < w
                && (y as usize) < h
                && prev.get(x as usize, y as usize).is_finite()
        };
        let stream = Gen::Rust.stream(0);
        let new: usize = age
            .data_mut()
            .par_chunks_mut(w)
            .enumerate()
            .map(|(y, row)| {
                let mut n = 0;
                for (x, a) in row.iter_mut().enumerate() {
                    let allowed = g.allowed.get(x, y);
                    if a.is_finite() || allowed <= 0.0 {
                        continue;
                    }
                    let (xi, yi) = (x as isize, y as isize);
                    let k = NEIGHBOURS
                        .iter()
                        .filter(|(dx, dy)| was(xi + dx, yi + dy))
                        .count();
                    let mut chance = p.p_interior + 1.0 - (1.0 - p.p_neighbour).powi(k as i32);
                    if g.sources.get(x, y) {
                        chance += p.p_edge;
                    }
                    let u = (key(seed, stream, it as u64, (y * w + x) as u64) >> 40) as f32
                        / (1u64 << 24) as f32;
                    if u < chance * allowed {
                        *a = it as f32;
                        n += 1;
                    }
                }
                n
            })
            .sum();
        rusted += new;
    }
    Aggregate {
        age,
        iterations: it,
        rusted,
    }
}

/// The rust and its run-down as layers.
pub fn stage(
    ctx: &Context,
    p: &RustParams,
    placed: &Placed,
    seed: u64,
    progress: &Progress,
) -> Result<Made> {
    let grid = ctx.grid;
    let (gw, gh) = (grid.width, grid.height);
    let (w, h) = (placed.width, placed.height);
    let at = |gx: usize, gy: usize| -> usize {
        let (x, y) = grid.to_photo(gx as f32 + 0.5, gy as f32 + 0.5);
        (y as usize).min(h - 1) * w + (x as usize).min(w - 1)
    };
    let allowed = RowMajor::from_fn(gw, gh, |x, y| {
        if ctx.region.get(x, y) {
            placed.weight[at(x, y)]
        } else {
            0.0
        }
    });
    let near = 1.5 * grid.scale;
    let feature = matches!(
        p.placement,
        Placement::Railings | Placement::Sills | Placement::Edges | Placement::Point
    );
    let sources = RowMajor::from_fn(gw, gh, |x, y| {
        if allowed.get(x, y) <= 0.0 {
            return false;
        }
        if feature {
            return placed.distance[at(x, y)] <= near;
        }
        // Otherwise the region's own edges are the metal.
        [(-1isize, 0isize), (1, 0), (0, -1), (0, 1)]
            .iter()
            .any(|(dx, dy)| {
                let (xx, yy) = (x as isize + dx, y as isize + dy);
                xx < 0
                    || yy < 0
                    || xx as usize >= gw
                    || yy as usize >= gh
                    || !ctx.region.get(xx as usize, yy as usize)
            })
    });
    let mut r = rng(seed, Gen::Rust.stream(1), 0, 0);
    let mut seeds = Vec::new();
    for _ in 0..p.fixings as usize * 50 {
        if seeds.len() == p.fixings as usize {
            break;
        }
        let (x, y) = (r.random_range(0..gw), r.random_range(0..gh));
        if allowed.get(x, y) >= AREA {
            seeds.push((x, y));
        }
    }
    let area_cells = allowed.data().iter().filter(|&&a| a >= AREA).count();
    let min = (p.coverage as f64 * area_cells as f64 * 1.1).ceil() as usize;
    let ground = Ground {
        allowed: &allowed,
        sources: &sources,
        seeds: &seeds,
    };
    let agg = aggregate(&ground, p, min, seed);
    progress.check()?;
    let total = agg.iterations as f32 + 1.0;
    let value = RowMajor::from_fn(gw, gh, |x, y| {
        let a = agg.age.get(x, y);
        if a.is_finite() {
            0.3 + 0.7 * (total - a) / total
        } else {
            0.0
        }
    });
    let noise = Noise::new(
        key(seed, Gen::Rust.stream(2), 0, 0),
        w as u32,
        h as u32,
        ctx.photo_px(0.02).max(1.5),
        2,
    );
    let g: Vec<f32> = (0..w * h)
        .into_par_iter()
        .map(|i| {
            let wt = placed.weight[i];
            if wt <= 0.0 {
                return 0.0;
            }
            let (x, y) = ((i % w) as f32 + 0.5, (i / w) as f32 + 0.5);
            (bilinear(&value, grid.to_grid(x, y)) + 0.04 * noise.at(x, y)) * wt
        })
        .collect();
    let t = threshold(&g, placed, p.coverage);
    let top = g.iter().copied().fold(0.0f32, f32::max);
    let dark = p.color.map(|c| (c as f32 * 0.45) as u8);
    let mut img = RgbaImage::new(w as u32, h as u32);
    img.par_chunks_mut(4 * w).enumerate().for_each(|(y, row)| {
        for (x, px) in row.chunks_exact_mut(4).enumerate() {
            let i = y * w + x;
            if g[i] > t && placed.weight[i] > 0.0 {
                let s = ((g[i] - t) / (top - t).max(1e-6)).clamp(0.0, 1.0);
                let c: [u8; 3] = std::array::from_fn(|k| {
                    (p.color[k] as f32 + (dark[k] as f32 - p.color[k] as f32) * s) as u8
                });
                px.copy_from_slice(&[c[0], c[1], c[2], alpha_byte(0.75 + 0.25 * s)]);
            }
        }
    });
    let alpha = GrayImage::from_fn(w as u32, h as u32, |x, y| {
        image::Luma([img.get_pixel(x, y)[3]])
    });
    let coverage = Coverage {
        name: "rust".into(),
        placement: placed.used.clone(),
        area: placed.area,
        target: p.coverage,
        coverage: measured(&alpha, placed),
    };
    let mut layers = vec![layer(
        "rust",
        BlendMode::Normal,
        p.opacity,
        LayerPixels::Rgba(img),
    )];
    if p.run > 0.0 {
        let runs = run_down(&alpha, ctx.wall, ctx.photo_px(p.run), &noise);
        layers.insert(
            0,
            layer(
                "rust runs",
                BlendMode::Normal,
                p.run_opacity,
                LayerPixels::Tint {
                    color: dark,
                    alpha: runs,
                },
            ),
        );
    }
    Ok(Made { layers, coverage })
}

/// A smear below the rust, fading over `length` pixels, uneven from
/// column to column; zero under the rust itself and off the wall.
fn run_down(rust: &GrayImage, wall: &Region, length: f32, noise: &Noise) -> GrayImage {
    let (w, h) = (rust.width() as usize, rust.height() as usize);
    let mut out = GrayImage::new(w as u32, h as u32);
    let fade = 1.0 / length.max(1.0);
    for x in 0..w {
        let streak = 0.4 + 0.6 * noise.at(x as f32 * 7.0, 0.0);
        let mut carried = 0.0f32;
        for y in 0..h {
            let a = rust.get_pixel(x as u32, y as u32)[0] as f32 / 255.0;
            carried = (carried - fade).max(a);
            if a == 0.0 && carried > 0.0 && wall.contains(x as f32 + 0.5, y as f32 + 0.5) {
                out.put_pixel(
                    x as u32,
                    y as u32,
                    image::Luma([(carried * streak * 255.0) as u8]),
                );
            }
        }
    }
    out
}

fn bilinear(v: &RowMajor<f32>, (x, y): (f32, f32)) -> f32 {
    let (w, h) = (v.width(), v.height());
    let gx = (x - 0.5).clamp(0.0, (w - 1) as f32);
    let gy = (y - 0.5).clamp(0.0, (h - 1) as f32);
    let (ix, iy) = (gx as usize, gy as usize);
    let (jx, jy) = ((ix + 1).min(w - 1), (iy + 1).min(h - 1));
    let (tx, ty) = (gx - ix as f32, gy - iy as f32);
    let top = v.get(ix, iy) + (v.get(jx, iy) - v.get(ix, iy)) * tx;
    let bottom = v.get(ix, jy) + (v.get(jx, jy) - v.get(ix, jy)) * tx;
    top + (bottom - top) * ty
}
