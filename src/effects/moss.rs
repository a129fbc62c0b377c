//! Moss (Caloplaca lichen) where the wall stays wet and dirty (Chang,
//! Yoshida & Mukai sec. 4), grown over the years.
//!
//! **Where.** A pixel p is colonised with probability (Chang eq. 18)
//! `f(p) = 1/2 (w/a + D/D_max) M_y(p) gamma`, clamped to [0, 1] (the paper's
//! Table 1 sets gamma = 1.5 although its text asks for gamma <= 1). `w` and
//! `D` are the wall water and dirt the rain left; without rain,
//! `1/2 (w/a + D/D_max)` is replaced by a humidity that falls from
//! `humidity` at the top of the wall to half of it at the bottom [choice: the
//! top of a wall takes the rain, so it is the wet part in photos].
//!
//! [choice] M_y (eq. 1) is computed from the photo's luminance, not from the
//! rain's final surface: eq. 15 raises that surface by the deposited dirt
//! after every rainfall and, over a dozen rainfalls, saturates it at 255 on
//! most of the wall, where M_y becomes 0.
//!
//! [choice] D_max is a high percentile (`stain.percentile`) of the final wall
//! dirt, so one hot pixel does not flatten D/D_max everywhere else.
//!
//! **How it grows** (beyond the paper, whose authors find their moss too
//! scattered). Time runs in years; each year, in this order:
//! 1. every existing colony seeds a neighbour with chance `spread` x its
//!    vigour, at a normal distance of `spread_distance` baselines; the
//!    neighbour takes with chance vigour(q)^2. A spot's vigour is
//!    F(q) / F_ref in [0, 1], where F is f averaged over half a baseline
//!    around q and F_ref its 99th percentile over the wall [choice: spores
//!    land near their parent, and lichen only grows and spreads while it is
//!    wet; relative to the wall's best spots so clusters form where eq. 18
//!    is highest on any photo; the local mean keeps noise in M_y from
//!    letting colonies spread over dry wall];
//! 2. `seed_rate` candidate pixels per baseline^2 of wall are drawn
//!    uniformly; each is colonised iff f(p) >= xi5 (eq. 18's test).
//!
//! A cell of half a baseline holds at most one colony [choice: otherwise
//! spreading grows without bound; with it, wet areas fill up into dense
//! patches over the years]. A colony grows to full size in `maturity` years
//! of full vigour (slower where vigour is lower): its arms go from 1 to 6
//! and its radius from 35 % to 100 % of its size, a log-normal multiple
//! (sigma `size_spread`) of the baseline.
//!
//! **What it looks like.** Chang's point-based fractal: a mountain-shaped
//! generator `(0,0) (1/3,0) (1/2,peak) (2/3,0) (1,0)` replaces every segment
//! of a baseline, `iterations` times, and only the vertices are drawn, as
//! dots. The baseline is `moss.colony_m` through the scene's scale (or,
//! when set, Chang's `moss.baseline` fraction of the region's width). Each
//! arm of a colony is such a baseline from its centre outward [choice: arms
//! at even angles make the round rosettes of real colonies]. Every
//! replacement flips to a random side and scales its peak by U(0.5, 1.5)
//! [choice: a fixed generator repeats visibly]. Each dot's R, G and B are
//! jittered by up to `color_jitter`. The layer is normal-blended; its alpha
//! is the dots' coverage, times the region mask's weight.
//!
//! Everything is seeded per year, per colony: the result does not depend on
//! the number of threads.

use image::RgbaImage;
use rand::Rng as _;
use rayon::prelude::*;
use serde::Serialize;

use crate::effects::box_mean::box_mean;
use crate::effects::percentile::{Rank, percentile};
use crate::effects::region::Region;
use crate::effects::roughness;
use crate::error::Result;
use crate::field::{Field, Order, RowMajor};
use crate::grid::Grid;
use crate::preset::MossParams;
use crate::progress::Progress;
use crate::random::{self, Rng, Stream};

/// The rain's wall state, on the simulation grid.
#[derive(Debug, Clone, Copy)]
pub struct Wet<'a> {
    /// Wall water w.
    pub water: &'a RowMajor<f32>,
    /// Saturation a.
    pub saturation: f32,
    /// Wall dirt D.
    pub dirt: &'a RowMajor<f32>,
    /// D_max.
    pub d_max: f32,
}

/// What moss grows from, on the simulation grid.
#[derive(Debug, Clone, Copy)]
pub struct MossInput<'a> {
    /// Photo luminance B in 0..255 on the grid.
    pub luma: &'a RowMajor<f32>,
    /// Region on the grid.
    pub region: &'a RowMajor<bool>,
    /// The rain's water and dirt, on the grid; `None` = use `humidity`.
    pub wet: Option<Wet<'a>>,
    /// Where the wall stays wet (splash zone, ledge tops, joints,
    /// shelter; see [`super::habitat`]), 0..1 on the grid, multiplying
    /// eq. 18; `None` = everywhere alike (Chang's own).
    pub habitat: Option<&'a RowMajor<f32>>,
    /// Fractal baseline, photo pixels: a colony's typical radius.
    pub baseline: f32,
}

impl MossInput<'_> {
    /// Grid width and height.
    fn size(&self) -> (usize, usize) {
        (self.luma.width(), self.luma.height())
    }
}

/// One colony.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Colony {
    /// Centre, photo pixels.
    pub x: f32,
    /// Centre, photo pixels.
    pub y: f32,
    /// Year it took hold (1-based).
    pub born: u32,
    /// Size as a multiple of the baseline.
    pub size: f32,
    /// Direction of its first arm, radians.
    pub angle: f32,
    /// How well its spot suits moss, 0..1: scales its growth and spreading.
    pub vigour: f32,
    /// Whether a neighbour seeded it (rather than eq. 18 on its own).
    pub from_neighbour: bool,
}

/// Moss numbers for the report.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct MossStats {
    /// Years grown.
    pub years: u32,
    /// Colonies on the wall.
    pub colonies: usize,
    /// Of which seeded by a neighbour.
    pub from_neighbours: usize,
    /// Dots drawn.
    pub dots: usize,
    /// Baseline length, photo pixels.
    pub baseline_px: f32,
    /// Mean alpha over the wall, 0..1.
    pub coverage: f64,
}

/// Chang eq. (18): the probability that moss takes at a pixel with water
/// ratio `w_a` = w/a, dirt ratio `d` = D/D_max and vertical roughness `m_y`.
///
/// ```
/// use grime::effects::moss::seed_probability;
/// assert_eq!(seed_probability(1.0, 1.0, 0.5, 1.0), 0.5);
/// assert_eq!(seed_probability(1.0, 1.0, 1.0, 1.5), 1.0); // clamped
/// ```
pub fn seed_probability(w_a: f32, d: f32, m_y: f32, gamma: f32) -> f32 {
    (0.5 * (w_a + d) * m_y * gamma).clamp(0.0, 1.0)
}

/// The wetness term 1/2 (w/a + D/D_max) per grid pixel, each ratio clamped
/// to [0, 1]; or the humidity profile without rain. 0 outside the region.
pub fn wetness(input: &MossInput, humidity: f32) -> RowMajor<f32> {
    let (w, h) = input.size();
    let region = input.region.data();
    let values = (0..w * h)
        .into_par_iter()
        .map(|i| {
            if !region[i] {
                return 0.0;
            }
            match input.wet {
                Some(wet) => {
                    let (water, dirt) = (wet.water.data()[i], wet.dirt.data()[i]);
                    let wa = (water / wet.saturation.max(f32::MIN_POSITIVE)).clamp(0.0, 1.0);
                    let d = (dirt / wet.d_max.max(f32::MIN_POSITIVE)).clamp(0.0, 1.0);
                    0.5 * (wa + d)
                }
                None => humidity * (1.0 - 0.5 * (i / w) as f32 / h.max(1) as f32),
            }
        })
        .collect();
    RowMajor::new(w, h, values)
}

/// f(p) of eq. 18 on the grid: 2 x wetness x M_y x gamma, clamped.
pub fn probability(input: &MossInput, p: &MossParams) -> RowMajor<f32> {
    let (w, h) = input.size();
    let wet = wetness(input, p.humidity);
    let values = (0..w * h)
        .into_par_iter()
        .map(|i| {
            let m_y = roughness::m_y_clamped(input.luma, i % w, i / w);
            let place = input.habitat.map_or(1.0, |h| h.data()[i]);
            // Chang eq. (18), with wet = 1/2 (w/a + D/D_max), times the
            // habitat [choice: eq. 18 alone lets moss take anywhere the
            // rain wetted; real growth keeps to where water stands, and
            // those places are wet whether a streak passes or not (splash,
            // standing water on a ledge), so they count as at least half
            // wet.
            // They hold water on any surface, so they count as at least
            // that rough too].
            let (wet, m_y) = match input.habitat {
                Some(_) => (wet.data()[i].max(0.5 * place), m_y.max(0.4 * place)),
                None => (wet.data()[i], m_y),
            };
            (wet * m_y * p.gamma * place).clamp(0.0, 1.0)
        })
        .collect();
    RowMajor::new(w, h, values)
}

/// The grown moss: its layer and what is in it.
#[derive(Debug, Clone)]
pub struct Moss {
    /// Straight-alpha RGBA at photo size.
    pub layer: RgbaImage,
    /// Every colony, in the order they took hold.
    pub colonies: Vec<Colony>,
    /// Numbers.
    pub stats: MossStats,
}

/// The per-year stream of eq. 18's candidate sites (colonies use the others).
const CANDIDATES: u64 = u64::MAX;
/// Layer id of the streams that draw each colony's dots.
const DOTS: u64 = 1 << 40;
/// Rows rendered together.
const BAND: usize = 16;

/// Grows `p.years` of moss on the wall and draws it at photo size.
///
/// # Errors
/// [`crate::Error::Cancelled`] when the progress's cancel flag is set.
pub fn grow(
    input: &MossInput,
    grid: &Grid,
    region: &Region,
    p: &MossParams,
    seed: u64,
    progress: &Progress,
) -> Result<Moss> {
    let f = probability(input, p);
    let baseline = input.baseline.max(1.0);
    let colonies = colonise(input, &f, grid, region, p, baseline, seed, progress)?;
    progress.update("moss", 0.5);
    let dots: Vec<Vec<Dot>> = colonies
        .par_iter()
        .enumerate()
        .map(|(i, c)| colony_dots(c, i, p, baseline, seed))
        .collect();
    let layer = render(&dots, region, p, baseline, progress)?;
    let coverage = coverage(&layer, region);
    let stats = MossStats {
        years: p.years,
        colonies: colonies.len(),
        from_neighbours: colonies.iter().filter(|c| c.from_neighbour).count(),
        dots: dots.iter().map(Vec::len).sum(),
        baseline_px: baseline,
        coverage,
    };
    progress.update("moss", 1.0);
    Ok(Moss {
        layer,
        colonies,
        stats,
    })
}

/// At most one colony per cell of half a baseline.
struct Occupancy {
    cell: f32,
    cols: usize,
    taken: Vec<bool>,
}

impl Occupancy {
    fn new(width: u32, height: u32, cell: f32) -> Occupancy {
        let cols = (width as f32 / cell).ceil() as usize + 1;
        let rows = (height as f32 / cell).ceil() as usize + 1;
        Occupancy {
            cell,
            cols,
            taken: vec![false; cols * rows],
        }
    }

    /// Takes the cell of (x, y) if free; the point must be on the photo.
    fn take(&mut self, x: f32, y: f32) -> bool {
        let i = (y / self.cell) as usize * self.cols + (x / self.cell) as usize;
        !std::mem::replace(&mut self.taken[i], true)
    }
}

#[allow(clippy::too_many_arguments)]
fn colonise(
    input: &MossInput,
    f: &RowMajor<f32>,
    grid: &Grid,
    region: &Region,
    p: &MossParams,
    baseline: f32,
    seed: u64,
    progress: &Progress,
) -> Result<Vec<Colony>> {
    let (w, h) = input.size();
    let sample = |field: &RowMajor<f32>, x: f32, y: f32| {
        let (gx, gy) = grid.to_grid(x, y);
        field.get(
            (gx.max(0.0) as usize).min(w - 1),
            (gy.max(0.0) as usize).min(h - 1),
        )
    };
    let radius = ((baseline / 2.0) / grid.scale).round().max(1.0) as usize;
    let local = box_mean(f, input.region, radius);
    let in_region = local.data().iter().zip(input.region.data());
    let f_ref = percentile(
        in_region.filter(|(_, r)| **r).map(|(v, _)| *v),
        0.99,
        Rank::Below,
    )
    .unwrap_or(0.0)
    .max(1e-9);
    let vigour = |x: f32, y: f32| (sample(&local, x, y) / f_ref).min(1.0);
    let mut taken = Occupancy::new(region.width(), region.height(), baseline / 2.0);
    let candidates = (p.seed_rate as f64 * region.area() as f64
        / (baseline as f64 * baseline as f64))
        .round() as u64;
    let mut colonies: Vec<Colony> = Vec::new();
    let new_colony = |x: f32, y: f32, born: u32, from_neighbour: bool, rng: &mut Rng| {
        let vigour = vigour(x, y);
        let (z, _) = random::box_muller(rng);
        let sigma = p.size_spread;
        Colony {
            x,
            y,
            born,
            // Log-normal with mean 1: a few colonies are much bigger.
            size: (sigma * z - 0.5 * sigma * sigma).exp(),
            angle: rng.random::<f32>() * std::f32::consts::TAU,
            vigour,
            from_neighbour,
        }
    };
    for year in 1..=p.years {
        progress.check()?;
        progress.update("moss", 0.5 * year as f32 / p.years as f32);
        // 1. Neighbours of the colonies that stood at the start of the year.
        for i in 0..colonies.len() {
            let mut rng = random::rng(seed, Stream::Moss, year as u64, i as u64);
            if rng.random::<f32>() >= p.spread * colonies[i].vigour {
                continue;
            }
            let (dx, dy) = random::box_muller(&mut rng);
            let d = p.spread_distance * baseline;
            let (x, y) = (colonies[i].x + dx * d, colonies[i].y + dy * d);
            if region.contains(x, y)
                && rng.random::<f32>() < vigour(x, y).powi(2)
                && taken.take(x, y)
            {
                colonies.push(new_colony(x, y, year, true, &mut rng));
            }
        }
        // 2. New colonies where eq. 18 says so.
        let mut rng = random::rng(seed, Stream::Moss, year as u64, CANDIDATES);
        for _ in 0..candidates {
            let (px, py) = region.sample(&mut rng);
            let (x, y) = (
                px as f32 + rng.random::<f32>(),
                py as f32 + rng.random::<f32>(),
            );
            let xi5: f32 = rng.random();
            // Chang eq. (18): moss takes at p iff f(p) >= xi5.
            let fp = sample(f, x, y);
            if fp > 0.0 && fp >= xi5 && taken.take(x, y) {
                colonies.push(new_colony(x, y, year, false, &mut rng));
            }
        }
    }
    Ok(colonies)
}

/// D_max for eq. 18: the `q`-quantile of the positive wall dirt over the
/// region (1 when the wall is clean).
pub fn d_max<O: Order>(dirt: &Field<f32, O>, region: &Field<bool, O>, q: f32) -> f32 {
    let positive = dirt
        .data()
        .iter()
        .zip(region.data())
        .filter(|(d, r)| **r && **d > 0.0)
        .map(|(d, _)| *d);
    percentile(positive, q, Rank::Below).map_or(1.0, |v| v.max(f32::MIN_POSITIVE))
}

/// One spore dot.
#[derive(Debug, Clone, Copy)]
struct Dot {
    x: f32,
    y: f32,
    color: [f32; 3],
}

/// Chang's point-based fractal: the generator replaces each segment of
/// `a`-`b`, `iterations` times; returns the vertices.
fn fractal(
    a: (f32, f32),
    b: (f32, f32),
    iterations: u32,
    peak: f32,
    rng: &mut Rng,
) -> Vec<(f32, f32)> {
    let mut pts = vec![a, b];
    for _ in 0..iterations {
        let mut next = Vec::with_capacity(pts.len() * 4);
        for s in pts.windows(2) {
            let (p, q) = (s[0], s[1]);
            let (dx, dy) = (q.0 - p.0, q.1 - p.1);
            let side = if rng.random::<bool>() { 1.0 } else { -1.0 };
            let h = peak * (0.5 + rng.random::<f32>()) * side;
            // The mountain generator (0,0) (1/3,0) (1/2,h) (2/3,0) (1,0) on p-q.
            let at = |u: f32, v: f32| (p.0 + u * dx - v * dy, p.1 + u * dy + v * dx);
            next.extend([p, at(1.0 / 3.0, 0.0), at(0.5, h), at(2.0 / 3.0, 0.0)]);
        }
        next.push(*pts.last().unwrap_or(&b));
        pts = next;
    }
    pts
}

/// The dots of colony `index` as it is after `p.years` years.
fn colony_dots(c: &Colony, index: usize, p: &MossParams, baseline: f32, seed: u64) -> Vec<Dot> {
    let mut rng = random::rng(seed, Stream::Moss, DOTS, index as u64);
    let age = (p.years + 1).saturating_sub(c.born) as f32 * c.vigour;
    let grown = if p.maturity > 0.0 {
        (age / p.maturity).min(1.0)
    } else {
        1.0
    };
    let arms = 1 + (5.0 * grown).round() as u32;
    let radius = baseline * c.size * (0.35 + 0.65 * grown);
    // [choice] No finer than about a pixel between vertices: a colony a
    // few pixels across at facade scale is a blotch, not a rosette.
    let mut iterations = p.iterations;
    while iterations > 1 && radius / 4f32.powi(iterations as i32) < 0.7 {
        iterations -= 1;
    }
    let base = species(p, &mut rng);
    let step = radius / 4f32.powi(iterations as i32);
    let mut dots = Vec::new();
    for arm in 0..arms {
        let angle = c.angle
            + std::f32::consts::TAU * arm as f32 / arms as f32
            + (rng.random::<f32>() - 0.5) * 0.6;
        let len = radius * (0.7 + 0.3 * rng.random::<f32>());
        let end = (c.x + len * angle.cos(), c.y + len * angle.sin());
        // The centre is shared by every arm: draw it once.
        let skip = usize::from(arm > 0);
        for (x, y) in fractal((c.x, c.y), end, iterations, p.peak, &mut rng)
            .into_iter()
            .skip(skip)
        {
            let jitter = |rng: &mut Rng| (rng.random::<f32>() - 0.5) * step;
            let (jx, jy) = (jitter(&mut rng), jitter(&mut rng));
            let color = base.map(|v| {
                (v + (rng.random::<f32>() * 2.0 - 1.0) * p.color_jitter).clamp(0.0, 255.0)
            });
            dots.push(Dot {
                x: x + jx,
                y: y + jy,
                color,
            });
        }
    }
    dots
}

/// Grey-green lichen, dark green moss and orange Caloplaca, with the
/// share of colonies each takes besides `moss.color` when `mixed_species`
/// is on (`how-facades-age.md`, "Living growth").
const SPECIES: [([f32; 3], f32); 3] = [
    ([138.0, 146.0, 122.0], 0.5),
    ([66.0, 84.0, 40.0], 0.3),
    ([170.0, 128.0, 70.0], 0.04),
];

/// A colony's base colour: its species', a little lighter or darker.
fn species(p: &MossParams, rng: &mut Rng) -> [f32; 3] {
    let mut base = p.color.rgb().map(f32::from);
    if p.mixed_species {
        let mut pick: f32 = rng.random();
        for (rgb, share) in SPECIES {
            if pick < share {
                base = rgb;
                break;
            }
            pick -= share;
        }
    }
    let light = 0.85 + 0.3 * rng.random::<f32>();
    base.map(|v| (v * light).min(255.0))
}

/// Draws the dots in colony order, row band by row band (each band is
/// independent, so the result does not depend on scheduling).
fn render(
    dots: &[Vec<Dot>],
    region: &Region,
    p: &MossParams,
    baseline: f32,
    progress: &Progress,
) -> Result<RgbaImage> {
    let (w, h) = (region.width() as usize, region.height() as usize);
    // [choice] A dot under a pixel covers its own area's share of one: a
    // colony a few pixels across is a soft tint, not solid (pasted) specks.
    let true_r = p.dot_size * baseline;
    let r = true_r.max(0.5);
    let cover = (true_r / r).powi(2);
    // Each colony's vertical extent, to find the bands it touches.
    let spans: Vec<(f32, f32)> = dots
        .iter()
        .map(|d| {
            d.iter()
                .fold((f32::MAX, f32::MIN), |(a, b), d| (a.min(d.y), b.max(d.y)))
        })
        .collect();
    let mut out = RgbaImage::new(w as u32, h as u32);
    out.par_chunks_mut(w * 4 * BAND)
        .enumerate()
        .try_for_each(|(band, rows)| {
            progress.check()?;
            let y0 = band * BAND;
            let n_rows = rows.len() / (w * 4);
            // Premultiplied colour and alpha.
            let mut acc = vec![[0.0f32; 4]; w * n_rows];
            let (top, bottom) = (y0 as f32 - r - 1.0, (y0 + n_rows) as f32 + r + 1.0);
            for (colony, &(lo, hi)) in dots.iter().zip(&spans) {
                if hi < top || lo > bottom {
                    continue;
                }
                for d in colony {
                    splat(d, r, cover, y0, n_rows, w, &mut acc);
                }
            }
            let mut weight = vec![0.0f32; w];
            for (row_i, row) in rows.chunks_exact_mut(w * 4).enumerate() {
                region.weights((y0 + row_i) as u32, &mut weight);
                for (x, px) in row.chunks_exact_mut(4).enumerate() {
                    let [pr, pg, pb, a] = acc[row_i * w + x];
                    if a <= 0.0 || weight[x] == 0.0 {
                        continue;
                    }
                    let c = |v: f32| (v / a).round().clamp(0.0, 255.0) as u8;
                    let alpha = (a * weight[x] * 255.0).round().clamp(0.0, 255.0) as u8;
                    px.copy_from_slice(&[c(pr), c(pg), c(pb), alpha]);
                }
            }
            Ok::<(), crate::Error>(())
        })?;
    Ok(out)
}

/// One anti-aliased dot of radius `r` and opacity `cover`, over the band.
fn splat(d: &Dot, r: f32, cover: f32, y0: usize, n_rows: usize, w: usize, acc: &mut [[f32; 4]]) {
    let x_lo = (d.x - r - 0.5).floor().max(0.0) as usize;
    let x_hi = ((d.x + r + 0.5).ceil().max(0.0) as usize).min(w);
    let y_lo = ((d.y - r - 0.5).floor().max(y0 as f32) as usize).max(y0);
    let y_hi = ((d.y + r + 0.5).ceil().max(0.0) as usize).min(y0 + n_rows);
    for y in y_lo..y_hi {
        for x in x_lo..x_hi {
            let (dx, dy) = (x as f32 + 0.5 - d.x, y as f32 + 0.5 - d.y);
            let cov = cover * (r + 0.5 - (dx * dx + dy * dy).sqrt()).clamp(0.0, 1.0);
            if cov <= 0.0 {
                continue;
            }
            let a = &mut acc[(y - y0) * w + x];
            // Premultiplied "over": (c, 1) * cov + acc * (1 - cov).
            for (v, c) in a.iter_mut().zip([d.color[0], d.color[1], d.color[2], 1.0]) {
                *v = c * cov + *v * (1.0 - cov);
            }
        }
    }
}

/// Mean alpha of the layer over the wall pixels.
fn coverage(layer: &RgbaImage, region: &Region) -> f64 {
    let w = layer.width() as usize;
    let sum: u64 = layer
        .as_raw()
        .par_chunks_exact(w * 4)
        .enumerate()
        .map(|(y, row)| {
            row.chunks_exact(4)
                .enumerate()
                .filter(|(x, px)| px[3] != 0 && region.contains(*x as f32, y as f32))
                .map(|(_, px)| px[3] as u64)
                .sum::<u64>()
        })
        .sum();
    sum as f64 / (255.0 * region.area().max(1) as f64)
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::GrayImage;

    fn flat(w: usize, h: usize) -> (RowMajor<f32>, RowMajor<bool>) {
        // A rough wall: luminance alternates every row, so M_y = 0.4.
        let luma = RowMajor::from_fn(w, h, |_, y| if y.is_multiple_of(2) { 100.0 } else { 202.0 });
        (luma, RowMajor::filled(w, h, true))
    }

    #[test]
    fn probability_follows_eq_18() {
        let (w, h) = (4, 4);
        let (luma, region) = flat(w, h);
        let water = RowMajor::filled(w, h, 0.15);
        let dirt = RowMajor::filled(w, h, 2.0);
        let input = MossInput {
            luma: &luma,
            region: &region,
            wet: Some(Wet {
                water: &water,
                saturation: 0.3,
                dirt: &dirt,
                d_max: 4.0,
            }),
            habitat: None,
            baseline: 1.0,
        };
        let p = MossParams {
            gamma: 1.0,
            ..MossParams::default()
        };
        let f = probability(&input, &p);
        // 1/2 (0.5 + 0.5) * 0.4 * 1.0
        assert!((f.get(0, 0) - 0.2).abs() < 1e-6, "{}", f.get(0, 0));
        assert_eq!(f.get(0, h - 1), 0.0, "last row: index clamped, M_y = 0");
    }

    #[test]
    fn fractal_has_4_pow_n_plus_1_vertices_and_keeps_its_ends() {
        let mut rng = random::rng(1, Stream::Moss, 0, 0);
        let pts = fractal((0.0, 0.0), (27.0, 0.0), 3, 0.4, &mut rng);
        assert_eq!(pts.len(), 65);
        assert_eq!((pts[0], pts[64]), ((0.0, 0.0), (27.0, 0.0)));
        assert!(
            pts.iter().any(|p| p.1.abs() > 3.0),
            "the peaks rise off the baseline"
        );
    }

    /// Moss on a wall whose left half is wet and right half dry.
    fn half_wet(p: &MossParams) -> (Moss, RowMajor<f32>) {
        let (w, h) = (160, 120);
        let (luma, region) = flat(w, h);
        let water = RowMajor::from_fn(w, h, |x, _| if x < w / 2 { 0.3 } else { 0.0 });
        let dirt = RowMajor::from_fn(w, h, |x, _| if x < w / 2 { 1.0 } else { 0.1 });
        let input = MossInput {
            luma: &luma,
            region: &region,
            wet: Some(Wet {
                water: &water,
                saturation: 0.3,
                dirt: &dirt,
                d_max: 1.0,
            }),
            habitat: None,
            baseline: w as f32 / 40.0,
        };
        let grid = Grid::new(w as u32, h as u32, None, 0).unwrap();
        let photo_region = Region::new(w as u32, h as u32, None).unwrap();
        let moss = grow(&input, &grid, &photo_region, p, 5, &Progress::none()).unwrap();
        (moss, water)
    }

    #[test]
    fn moss_grows_where_it_is_wet_and_with_the_years() {
        let p = MossParams {
            years: 6,
            ..MossParams::default()
        };
        let (moss, _) = half_wet(&p);
        let left = moss.colonies.iter().filter(|c| c.x < 80.0).count();
        let right = moss.colonies.len() - left;
        assert!(left > 3 * right.max(1), "wet {left} vs dry {right}");
        let (older, _) = half_wet(&MossParams {
            years: 12,
            ..p.clone()
        });
        assert!(older.stats.colonies > moss.stats.colonies);
        assert!(older.stats.coverage > moss.stats.coverage);
        assert!(older.stats.from_neighbours > 0, "colonies seed neighbours");
        assert_eq!(
            &older.colonies[..moss.colonies.len()],
            &moss.colonies[..],
            "years add colonies"
        );
        assert_eq!(half_wet(&MossParams { years: 0, ..p }).0.stats.colonies, 0);
    }

    #[test]
    fn dots_stay_inside_the_mask() {
        let (w, h) = (120usize, 90usize);
        let mask = GrayImage::from_fn(w as u32, h as u32, |x, _| {
            image::Luma([if x < 60 { 255 } else { 0 }])
        });
        let grid = Grid::new(w as u32, h as u32, Some(&mask), 0).unwrap();
        assert_eq!(grid.width, 60);
        let (luma, grid_region) = flat(60, h);
        let input = MossInput {
            luma: &luma,
            region: &grid_region,
            wet: None,
            habitat: None,
            baseline: 1.5,
        };
        let region = Region::new(w as u32, h as u32, Some(&mask)).unwrap();
        let p = MossParams {
            years: 8,
            humidity: 1.0,
            seed_rate: 4.0,
            ..MossParams::default()
        };
        let moss = grow(&input, &grid, &region, &p, 2, &Progress::none()).unwrap();
        assert!(moss.stats.colonies > 0);
        for (x, _, px) in moss.layer.enumerate_pixels() {
            if x >= 60 {
                assert_eq!(px[3], 0);
            }
        }
    }
}
