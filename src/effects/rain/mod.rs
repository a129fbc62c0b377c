//! Rain streaks over time (Chang, Yoshida & Mukai; Endo et al.).
//!
//! [`simulate`] runs the rainfalls on the simulation grid and returns, per
//! rainfall, the dirt it deposited, plus the final wall water and dirt that
//! moss grows from. [`stain`] turns deposits into layer coverage.

pub mod droplets;
pub mod sources;
pub mod stain;
pub mod wall;

use rand::Rng as _;
use rayon::prelude::*;
use serde::Serialize;

use crate::error::Result;
use crate::preset::RainParams;
use crate::progress::Progress;
use crate::random::{self, Stream};
use droplets::{Droplet, End};
use sources::Source;
use wall::Wall;

/// What the rain runs on: the wall's luminance and region on the grid.
#[derive(Debug, Clone)]
pub struct RainInput<'a> {
    /// Grid width.
    pub width: usize,
    /// Grid height.
    pub height: usize,
    /// Luminance B in 0..255, row-major.
    pub luma: &'a [f32],
    /// Region mask, row-major.
    pub region: &'a [bool],
    /// Source polylines in grid coordinates.
    pub source_lines: Vec<Vec<(f32, f32)>>,
}

/// Numbers describing one rainfall.
#[derive(Debug, Clone, Default, Serialize)]
pub struct LayerStats {
    /// Droplets that ran.
    pub droplets: u32,
    /// Total droplet steps.
    pub droplet_steps: u64,
    /// Droplets that dried on the wall.
    pub dried: u32,
    /// Droplets that ran off the region.
    pub left_region: u32,
    /// Mean positive deposit over the region.
    pub mean_dirt: f64,
    /// Largest deposit.
    pub max_dirt: f32,
    /// Dirt washed off ledges into the droplets.
    pub dirt_from_ledges: f64,
    /// Dirt that ran off the region.
    pub dirt_lost: f64,
}

/// Where one droplet started and stopped, grid coordinates.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Path {
    /// Start (x, y).
    pub start: (f32, f32),
    /// Last position on the wall.
    pub end: (f32, f32),
    /// Steps taken.
    pub steps: u32,
}

/// One rainfall's result.
#[derive(Debug, Clone)]
pub struct RainLayer {
    /// Dirt this rainfall added, per grid pixel (max(D_end - D_start, 0)).
    pub deposit: Vec<f32>,
    /// Numbers.
    pub stats: LayerStats,
    /// Every droplet's start and end.
    pub paths: Vec<Path>,
}

/// The rain's result.
#[derive(Debug, Clone)]
pub struct RainOutput {
    /// Grid width.
    pub width: usize,
    /// Grid height.
    pub height: usize,
    /// One entry per rainfall, oldest first.
    pub layers: Vec<RainLayer>,
    /// Wall water w after the last rainfall.
    pub water: Vec<f32>,
    /// Wall dirt D after the last rainfall.
    pub dirt: Vec<f32>,
    /// Vertical roughness M_y of the final surface (eq. 1).
    pub roughness_y: Vec<f32>,
}

/// Droplets per rainfall for a region `width` grid pixels wide.
pub fn droplet_count(p: &RainParams, width: usize) -> u32 {
    if p.reference_width == 0 || p.droplets == 0 {
        return p.droplets;
    }
    ((p.droplets as f64 * width as f64 / p.reference_width as f64).round() as u32).max(1)
}

/// Runs `p.layers` rainfalls (Chang sec. 3), reporting progress and stopping
/// when cancelled.
///
/// # Errors
/// [`crate::Error::Cancelled`] when the progress's cancel flag is set.
pub fn simulate(
    input: &RainInput,
    p: &RainParams,
    seed: u64,
    progress: &Progress,
) -> Result<RainOutput> {
    let mut wall = Wall::new(input.width, input.height, input.luma, input.region);
    let mut sources = Vec::new();
    if p.top_edge {
        let edge = sources::top_edge(&wall);
        if !edge.is_empty() {
            sources.push(Source::TopEdge(edge));
        }
    }
    for line in &input.source_lines {
        let padded: Vec<_> = line.iter().map(|&(x, y)| (x + 1.0, y + 1.0)).collect();
        sources.push(Source::line(padded));
    }
    let total_len: f32 = sources.iter().map(Source::length).sum();
    let n = if total_len > 0.0 {
        droplet_count(p, input.width)
    } else {
        0
    };
    let k_d = 1.0 - p.k_s;
    let rounds = p.diffusion_rounds.max(1);
    // Per droplet: (position along the sources, mass), carried between layers.
    let mut starts: Vec<(f32, f32)> = vec![(0.0, 0.0); n as usize];
    let mut layers = Vec::with_capacity(p.layers as usize);
    let mut scratch = Vec::new();
    let mut carry = Vec::new();

    for layer in 0..p.layers {
        let mut layer_rng = random::rng(seed, Stream::RainLayer, layer as u64, 0);
        if layer > 0 {
            // Chang eq. (15): deposited dirt raises the surface for the next rain
            // [choice: eps is a fraction of full scale, and D is what the previous
            // rainfall deposited, so streak channels rise (and later droplets
            // follow them) while the rest of the wall keeps its texture;
            // raising by the total dirt lifts the whole wall to 255 within a
            // few rainfalls and erases the roughness].
            let d_max = wall.deposit_max();
            let raise = 255.0 * p.eps / d_max;
            // Chang eqs. (11-12): drying and wind loss, one xi2 per layer [choice].
            let xi2: f32 = layer_rng.random();
            // One pass over the wall for eq. 15 and eqs. 11-12.
            wall.b
                .par_iter_mut()
                .zip(&mut wall.w)
                .zip(&mut wall.d)
                .zip(&wall.baseline)
                .for_each(|(((b, w), d), base)| {
                    if d_max > 0.0 {
                        *b = (*b + raise * (*d - base).max(0.0)).min(255.0);
                    }
                    *w *= xi2;
                    *d *= xi2;
                });
        }
        // Chang eq. (12): fresh grime I_D0, smooth noise [choice: fBm, not white noise].
        let grime = fill_grime(
            &wall,
            p,
            random::key(seed, Stream::Grime, layer as u64, 0),
            &mut scratch,
        );
        // Chang eqs. (13-14): delta * k_D * D moves into this layer's source term
        // I_D, returned to the wall over the rainfall's diffusion rounds. The
        // baseline is what the dirt would be without droplets: diffused and
        // topped up like D. The layer's deposit is D minus it, so the stain
        // shows what the rain moved, not the smoothing of old grime.
        carry.resize(wall.d.len(), 0.0);
        wall.d
            .par_iter_mut()
            .zip(&mut carry)
            .zip(&mut wall.baseline)
            .enumerate()
            .for_each(|(i, ((d, c), base))| {
                if let Some(grime) = grime {
                    *d += grime[i] * wall.inside[i];
                }
                *c = p.delta * k_d * *d;
                *d -= *c;
                *base = *d;
            });

        let mut stats = LayerStats::default();
        let mut paths = Vec::with_capacity(n as usize);
        let mut round = 0;
        for (k, start) in starts.iter_mut().enumerate() {
            if k % 32 == 0 {
                progress.check()?;
                progress.update(
                    "rain",
                    (layer as f32 + k as f32 / n as f32) / p.layers as f32,
                );
            }
            let mut rng = random::rng(seed, Stream::Droplet, layer as u64, k as u64);
            *start = if layer == 0 {
                (
                    rng.random::<f32>() * total_len,
                    rng.random::<f32>() * p.mass_max,
                )
            } else {
                // Chang eqs. (16-17): normal steps from the previous layer's
                // position and mass (independent draws, Box-Muller's two outputs).
                let (z_pos, z_mass) = random::box_muller(&mut rng);
                (
                    start.0 + p.sigma * z_pos,
                    (start.1 + p.sigma * z_mass).max(0.0),
                )
            };
            start.0 = start.0.rem_euclid(total_len);
            if start.1 >= p.mass_min {
                let (si, u) = sources::pick(&sources, start.0);
                let (x, y) = sources[si].point(u);
                // [choice] Chang makes deposition proportional to droplet mass: a
                // droplet washes dirt off its ledge in proportion to its water,
                // S_0 = ledge_dirt * m / m_max, so small droplets leave faint runs.
                let s0 = p.ledge_dirt * (start.1 / p.mass_max).min(1.0);
                let mut drop = Droplet {
                    x,
                    y,
                    vx: 0.0,
                    vy: 0.0,
                    m: start.1,
                    s: s0,
                };
                stats.dirt_from_ledges += s0 as f64;
                let trace = droplets::run(&mut wall, &mut drop, p, &mut rng);
                stats.droplets += 1;
                stats.droplet_steps += trace.steps as u64;
                stats.dirt_lost += trace.dirt_lost as f64;
                match trace.outcome {
                    End::Dried => stats.dried += 1,
                    End::LeftRegion => stats.left_region += 1,
                    End::StepCap => {}
                }
                paths.push(Path {
                    start: (x - 1.0, y - 1.0),
                    end: (trace.end.0 - 1.0, trace.end.1 - 1.0),
                    steps: trace.steps,
                });
            }
            while (round + 1) * n as usize <= (k + 1) * rounds as usize && round < rounds as usize {
                diffusion_round(&mut wall, p, &carry, rounds);
                round += 1;
            }
        }
        while round < rounds as usize {
            diffusion_round(&mut wall, p, &carry, rounds);
            round += 1;
        }

        let deposit: Vec<f32> = unpad(&wall, |i| (wall.d[i] - wall.baseline[i]).max(0.0));
        let positive: Vec<f32> = deposit.iter().copied().filter(|&d| d > 0.0).collect();
        let area = input.region.iter().filter(|&&r| r).count().max(1);
        stats.mean_dirt = positive.iter().map(|&d| d as f64).sum::<f64>() / area as f64;
        stats.max_dirt = positive.iter().copied().fold(0.0, f32::max);
        layers.push(RainLayer {
            deposit,
            stats,
            paths,
        });
    }
    progress.update("rain", 1.0);
    Ok(RainOutput {
        width: input.width,
        height: input.height,
        layers,
        water: unpad(&wall, |i| wall.w[i]),
        dirt: unpad(&wall, |i| wall.d[i]),
        roughness_y: unpad(&wall, |i| wall.roughness(i).1),
    })
}

/// Chang eq. (12)'s fresh grime for this rainfall, in storage order, or
/// `None` when there is none.
fn fill_grime<'a>(
    wall: &Wall,
    p: &RainParams,
    key: u64,
    scratch: &'a mut Vec<f32>,
) -> Option<&'a [f32]> {
    if p.initial_dirt <= 0.0 {
        return None;
    }
    // Filled in storage order (column-major), i.e. the noise is transposed.
    let noise = random::Noise::new(
        key,
        wall.rows as u32,
        wall.cols as u32,
        p.initial_dirt_scale,
        2,
    );
    scratch.resize(wall.d.len(), 0.0);
    noise.fill(wall.rows, p.initial_dirt, scratch);
    Some(scratch)
}

/// Eqs. (9-10) diffusion, then in one pass I_sun evaporation and this
/// round's share of the carried-over dirt (eq. 13's source term) to the dirt
/// and its baseline.
fn diffusion_round(wall: &mut Wall, p: &RainParams, carry: &[f32], rounds: u32) {
    let evaporation = if p.diffusion_rounds > 0 {
        wall.diffuse(p.tau, p.dirt_coupling, p.diffusion_iterations);
        p.i_sun
    } else {
        0.0
    };
    let share = 1.0 / rounds as f32;
    wall.w
        .par_iter_mut()
        .zip(&mut wall.d)
        .zip(&mut wall.baseline)
        .zip(carry)
        .for_each(|(((w, d), base), c)| {
            if evaporation > 0.0 {
                *w = (*w - evaporation).max(0.0);
            }
            *d += c * share;
            *base += c * share;
        });
}

/// Copies the unpadded interior of a padded (column-major) wall field into
/// a row-major grid, tile by tile so reads and writes both stay in cache.
fn unpad(wall: &Wall, f: impl Fn(usize) -> f32 + Sync) -> Vec<f32> {
    const TILE: usize = 32;
    let (w, h) = (wall.cols - 2, wall.rows - 2);
    let mut out = vec![0.0; w * h];
    out.par_chunks_mut(w * TILE)
        .enumerate()
        .for_each(|(band, rows)| {
            let y0 = band * TILE;
            let band_h = rows.len() / w;
            for x0 in (0..w).step_by(TILE) {
                for x in x0..(x0 + TILE).min(w) {
                    for dy in 0..band_h {
                        rows[dy * w + x] = f(wall.idx(x + 1, y0 + dy + 1));
                    }
                }
            }
        });
    out
}

#[cfg(test)]
mod tests;
