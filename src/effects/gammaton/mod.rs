//! γ-tons on the image plane (Chen et al. 2005 as Stadler's `aitios`
//! implements them, thesis ch. 3): particles that carry substances (water,
//! dirt, rust, salt, or the user's own) from sources over the wall.
//!
//! Each iteration emits `particles` γ-tons from the sources (the sky: a
//! first contact anywhere on the wall the ledges do not shelter from the
//! rain's direction, [`sky`]; the ground: thrown up the foot of the wall;
//! a line: a fixing or railing, by default the rain's ledges; a painted
//! mask),
//! traces each through contacts where it exchanges substance with the wall
//! ([`particle::exchange`]), deteriorates its motion probabilities
//! ([`particle::deteriorate`]) and picks its next motion by Russian roulette
//! until it settles, leaves the wall or reaches `max_depth`. Then the ageing
//! rules run ([`rules`]). Each substance becomes a layer through its blend
//! stops.
//!
//! The image plane is the wall: "straight" is a hop across it, "parabolic"
//! a bounce off it that gravity brings back lower, "flow" a run down the
//! slope of the photo's luminance (the height field of Chang eq. 1).
//! γ-tons run on the rain's deterministic patch scheduler, each from its
//! own random stream (seed, iteration, emission index), so the result is
//! the same at any thread count.

pub mod particle;
pub mod rules;
pub mod sky;

use rand::Rng as _;
use rayon::prelude::*;
use std::path::Path;

use image::GrayImage;
use serde::Serialize;

use self::particle::{Fate, Gammaton, Laws, MAX_RADIUS, Motion, World};
use self::sky::Overhang;
use super::{Context, Effect, Produced, Products, Stats, patches};
use crate::error::{Error, Result};
use crate::field::RowMajor;
use crate::grid::Grid;
use crate::preset::{GammatonParams, MAX_SUBSTANCES, Preset, SourceKind};
use crate::progress::Progress;
use crate::random::rng;
use crate::stack::{BlendMode, Layer, LayerPixels};

/// γ-tons traced at once (bounds memory: about 100 bytes each).
const BATCH: usize = 1 << 16;

/// Patch half-width for the scheduler, columns.
const BAND: usize = 32;

/// What the γ-tons did, for the report.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GammaStats {
    /// γ-tons emitted, over all iterations.
    pub emitted: u64,
    /// Settled on the wall.
    pub settled: u64,
    /// Left the wall (region or grid).
    pub left: u64,
    /// Contacts made.
    pub contacts: u64,
    /// Per substance, in `substances` order.
    pub substances: Vec<SubstanceStats>,
}

/// The balance of one substance: `initial + emitted = on_wall + lost`,
/// up to rounding, plus what the ageing rules moved and removed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SubstanceStats {
    /// Its name.
    pub name: String,
    /// On the wall before the first iteration.
    pub initial: f64,
    /// Carried in by γ-tons at emission.
    pub emitted: f64,
    /// Carried off by γ-tons that left or settled holding it, minus what
    /// deposition rates above 1 made (`k > 1`).
    pub lost: f64,
    /// Net change by the ageing rules.
    pub rules: f64,
    /// On the wall at the end.
    pub on_wall: f64,
}

/// The substance maps (grid-sized, row-major) and the stats.
pub struct Outcome {
    /// One map per substance.
    pub maps: Vec<RowMajor<f32>>,
    /// What happened.
    pub stats: GammaStats,
}

/// What the sources take from the scene, on the grid.
#[derive(Default)]
pub struct Scenery {
    /// Polylines in grid pixels for line sources without points of their
    /// own (the rain's ledges).
    pub lines: Vec<Vec<(f32, f32)>>,
    /// Per source, the painted masks of mask sources (0..1, 1 = emit; see
    /// [`mask_on_grid`]).
    pub masks: Vec<Option<RowMajor<f32>>>,
    /// The ledges that shelter the wall from the sky's rain.
    pub overhangs: Vec<Overhang>,
}

/// Runs every iteration on the wall of `luma` and `region` with what the
/// sources take from `scenery`.
///
/// # Errors
/// [`Error::Cancelled`], and [`Error::Preset`] for a line source with no
/// points anywhere, a mask source without a mask or one that paints no
/// wall pixel, or a wall with no pixel.
pub fn simulate(
    luma: &RowMajor<f32>,
    region: &RowMajor<bool>,
    scenery: &Scenery,
    p: &GammatonParams,
    seed: u64,
    progress: &Progress,
) -> Result<Outcome> {
    let (w, h) = (luma.width(), luma.height());
    let n = p.substances.len().min(MAX_SUBSTANCES);
    let col = |f: &(dyn Fn(usize, usize) -> f32 + Sync)| -> Vec<f32> {
        (0..w * h)
            .into_par_iter()
            .map(|i| f(i / h, i % h))
            .collect()
    };
    let maps = p
        .substances
        .iter()
        .map(|s| col(&|x, y| if region.get(x, y) { s.initial } else { 0.0 }))
        .collect();
    let wall = (0..w * h).map(|i| region.get(i / h, i % h)).collect();
    let mut world = World::new(w, h, maps, wall, &col(&|x, y| luma.get(x, y)));
    let emitters = Emitters::new(&world, p, scenery, seed)?;
    let mut laws = Laws {
        substances: n,
        absorb: [0.0; MAX_SUBSTANCES],
        deposit: [0.0; MAX_SUBSTANCES],
        consistent: p.consistent,
        deteriorate: [p.d_straight, p.d_parabolic, p.d_flow],
        radius: (p.radius.round() as usize).min(MAX_RADIUS),
        max_depth: p.max_depth,
        hop: p.hop,
        flow_step: p.flow_step,
        wander: p.wander,
    };
    for (i, s) in p.substances.iter().take(n).enumerate() {
        laws.absorb[i] = s.absorb;
        laws.deposit[i] = s.deposit;
    }
    let initial: Vec<f64> = world.maps.iter().map(|m| total(m)).collect();
    let mut stats = GammaStats {
        emitted: 0,
        settled: 0,
        left: 0,
        contacts: 0,
        substances: p
            .substances
            .iter()
            .zip(&initial)
            .map(|(s, &initial)| SubstanceStats {
                name: s.name.clone(),
                initial,
                emitted: 0.0,
                lost: 0.0,
                rules: 0.0,
                on_wall: 0.0,
            })
            .collect(),
    };
    let count = p.particles as usize;
    let batches = count.div_ceil(BATCH).max(1) * p.iterations.max(1) as usize;
    let mut done = 0;
    for it in 0..p.iterations {
        for start in (0..count).step_by(BATCH) {
            progress.update("gamma-tons", done as f32 / batches as f32);
            // Each from its own stream: emitted side by side, in order.
            let tons: Vec<Gammaton> = (start..(start + BATCH).min(count))
                .into_par_iter()
                .map(|k| emitters.emit(p, seed, it, k))
                .collect();
            for t in &tons {
                for (s, c) in stats.substances.iter_mut().zip(t.carried) {
                    s.emitted += c as f64;
                }
            }
            let ended = patches::run(&mut world, tons, &laws, BAND, progress)?;
            for t in &ended {
                stats.emitted += 1;
                stats.contacts += t.depth as u64;
                match t.fate {
                    Fate::Left => stats.left += 1,
                    _ => stats.settled += 1,
                }
                for (s, b) in stats.substances.iter_mut().zip(t.balance) {
                    s.lost += b as f64;
                }
            }
            done += 1;
        }
        let before: Vec<f64> = world.maps.iter().map(|m| total(m)).collect();
        rules::apply(&mut world.maps, p);
        for ((s, m), b) in stats.substances.iter_mut().zip(&world.maps).zip(before) {
            s.rules += total(m) - b;
        }
    }
    for (s, m) in stats.substances.iter_mut().zip(&world.maps) {
        s.on_wall = total(m);
    }
    let maps = world
        .maps
        .iter()
        .map(|m| RowMajor::from_fn(w, h, |x, y| m[x * h + y]))
        .collect();
    Ok(Outcome { maps, stats })
}

fn total(map: &[f32]) -> f64 {
    map.iter().map(|&v| v as f64).sum()
}

/// Where γ-tons start, precomputed on the grid.
struct Emitters {
    /// Each source's cumulative share, 0..1.
    shares: Vec<f32>,
    /// Wall pixels (column-major indices) for the sky.
    wall: Vec<u32>,
    /// (column, lowest wall row) for the ground.
    feet: Vec<(u32, u32)>,
    /// Per source: its polylines in grid pixels (line sources).
    lines: Vec<Vec<Vec<(f32, f32)>>>,
    /// Per source: its fixed spots (fractions along its lines), if any.
    spots: Vec<Vec<f32>>,
    /// Per source: where its painted mask emits (mask sources).
    painted: Vec<Painted>,
    /// The ledges that shelter the wall from the sky.
    overhangs: Vec<Overhang>,
    rows: usize,
    /// Pixels on the grid.
    pixels: usize,
}

impl Emitters {
    fn new(world: &World, p: &GammatonParams, scenery: &Scenery, seed: u64) -> Result<Emitters> {
        let (ledges, masks) = (&scenery.lines, &scenery.masks);
        let rows = world.rows;
        let wall: Vec<u32> = (0..world.region.len() as u32)
            .filter(|&i| world.region[i as usize])
            .collect();
        if wall.is_empty() {
            return Err(Error::EmptyRegion);
        }
        let feet = (0..world.width)
            .filter_map(|x| {
                let col = &world.region[x * rows..(x + 1) * rows];
                col.iter().rposition(|&r| r).map(|y| (x as u32, y as u32))
            })
            .collect();
        let sum: f32 = p
            .sources
            .iter()
            .map(|s| s.share.max(0.0))
            .sum::<f32>()
            .max(1e-9);
        let mut acc = 0.0;
        let shares = p
            .sources
            .iter()
            .map(|s| {
                acc += s.share.max(0.0) / sum;
                acc
            })
            .collect();
        let mut lines = Vec::with_capacity(p.sources.len());
        for (i, s) in p.sources.iter().enumerate() {
            let own = match (s.kind, s.points.is_empty()) {
                (SourceKind::Line, false) => vec![s.points.iter().map(|q| (q[0], q[1])).collect()],
                (SourceKind::Line, true) if !ledges.is_empty() => ledges.to_vec(),
                (SourceKind::Line, true) => {
                    return Err(Error::Preset(format!(
                        "gammaton.sources[{i}] is a line with no points, and there are no ledges (rain.source_lines) to use instead: give it points = [[x, y], ...]"
                    )));
                }
                _ => Vec::new(),
            };
            lines.push(own);
        }
        let mut painted = Vec::with_capacity(p.sources.len());
        for (i, s) in p.sources.iter().enumerate() {
            let here = match (s.kind, masks.get(i)) {
                (SourceKind::Mask, Some(Some(mask))) => Painted::new(mask, world),
                (SourceKind::Mask, _) => {
                    return Err(Error::Preset(format!(
                        "gammaton.sources[{i}] is a mask source whose mask {:?} was not loaded (gammaton::load_masks)",
                        s.mask
                    )));
                }
                _ => Some(Painted::default()),
            };
            painted.push(here.ok_or_else(|| {
                Error::Preset(format!(
                    "gammaton.sources[{i}].mask {:?} paints no wall pixel: paint white where the γ-tons start",
                    s.mask
                ))
            })?);
        }
        let spots = p
            .sources
            .iter()
            .enumerate()
            .map(|(i, s)| {
                let mut r = rng(seed, (Effect::Gammaton, u16::MAX), 1, i as u64);
                (0..s.spots).map(|_| r.random::<f32>()).collect()
            })
            .collect();
        Ok(Emitters {
            shares,
            wall,
            feet,
            lines,
            spots,
            painted,
            overhangs: scenery.overhangs.clone(),
            rows,
            pixels: world.region.len(),
        })
    }

    /// γ-ton `k` of iteration `it`, from its own random stream.
    fn emit(&self, p: &GammatonParams, seed: u64, it: u32, k: usize) -> Gammaton {
        let mut r = rng(seed, (Effect::Gammaton, it as u16), 0, k as u64);
        let xi: f32 = r.random();
        let i = self
            .shares
            .iter()
            .position(|&s| xi < s)
            .unwrap_or(self.shares.len() - 1);
        let source = &p.sources[i];
        let mut carried = [0.0; MAX_SUBSTANCES];
        for (c, v) in carried.iter_mut().zip(&source.carries) {
            *c = *v;
        }
        let probs = [p.p_straight, p.p_parabolic, p.p_flow];
        let jitter = |r: &mut crate::random::Rng| r.random::<f32>();
        let (pos, vel, motion, left) = match source.kind {
            // Rain meets the wall anywhere a ledge does not shelter
            // ([`sky`]), a painted mask where it is painted: the first
            // contact is there.
            SourceKind::Sky | SourceKind::Mask => {
                let at = match source.kind {
                    SourceKind::Mask => self.painted[i].draw(&mut r),
                    _ => {
                        let j = r.random_range(0..self.wall.len());
                        // A whole-grid wall lists every pixel: skip the
                        // look-up (a cache miss per γ-ton on a large grid).
                        match self.wall.len() == self.pixels {
                            true => j,
                            false => self.wall[j] as usize,
                        }
                    }
                };
                let (x, y) = (at / self.rows, at % self.rows);
                let mut at = (x as f32 + jitter(&mut r), y as f32 + jitter(&mut r));
                // A ledge on the rain's way catches it (sky only).
                if source.kind == SourceKind::Sky
                    && source.shelter > 0.0
                    && !self.overhangs.is_empty()
                {
                    let spread = (jitter(&mut r) * 2.0 - 1.0) * source.spread;
                    let angle = (source.direction + spread).clamp(-sky::MAX_ANGLE, sky::MAX_ANGLE);
                    let reach = -(1.0 - jitter(&mut r)).ln() * source.shelter;
                    if let Some(ledge) =
                        sky::intercept(&self.overhangs, at, angle.to_radians(), reach)
                    {
                        at = ledge;
                    }
                }
                (at, (0.0, 1.0), Motion::Straight, 0.0)
            }
            // Splash: thrown up from the foot of the wall, most of it not
            // far [choice: heights exponential with mean `hop`, at most 4
            // hops, so the foot gets the most].
            SourceKind::Ground => {
                let (x, y) = self.feet[r.random_range(0..self.feet.len())];
                let a = (jitter(&mut r) * 2.0 - 1.0) * 0.5;
                let up = (-p.hop * (1.0 - jitter(&mut r)).ln()).min(4.0 * p.hop);
                (
                    (x as f32 + jitter(&mut r), y as f32 + 0.5),
                    (a.sin(), -a.cos()),
                    Motion::Straight,
                    up,
                )
            }
            SourceKind::Line => {
                let spots = &self.spots[i];
                let (x, y) = match spots.is_empty() {
                    true => point_on(&self.lines[i], jitter(&mut r)),
                    // A fixing: a spot a pixel or two wide.
                    false => {
                        let (x, y) =
                            point_on(&self.lines[i], spots[r.random_range(0..spots.len())]);
                        (x + (jitter(&mut r) - 0.5) * 5.0, y)
                    }
                };
                ((x, y), (0.0, 1.0), Motion::Straight, 0.0)
            }
        };
        Gammaton::new(k, pos, vel, motion, left, probs, carried, r)
    }
}

/// Where a painted mask emits: its wall pixels (column-major indices) with
/// the running sum of their grey levels.
#[derive(Default)]
struct Painted {
    cells: Vec<u32>,
    sums: Vec<f64>,
}

impl Painted {
    /// The mask's wall pixels above zero; `None` if there are none.
    fn new(mask: &RowMajor<f32>, world: &World) -> Option<Painted> {
        let mut painted = Painted::default();
        let mut sum = 0.0;
        for (i, &wall) in world.region.iter().enumerate() {
            let v = mask.get(i / world.rows, i % world.rows);
            if wall && v > 0.0 {
                sum += v as f64;
                painted.cells.push(i as u32);
                painted.sums.push(sum);
            }
        }
        (!painted.cells.is_empty()).then_some(painted)
    }

    /// A pixel, drawn in proportion to its grey level.
    fn draw(&self, r: &mut crate::random::Rng) -> usize {
        let total = self.sums.last().copied().unwrap_or(0.0);
        let xi = r.random::<f64>() * total;
        let j = self.sums.partition_point(|&s| s <= xi);
        self.cells[j.min(self.cells.len() - 1)] as usize
    }
}

/// A mask source's image (photo-sized, 255 = emit) on the grid: each cell
/// takes the mask at its centre, 0..1.
pub fn mask_on_grid(mask: &GrayImage, grid: &Grid) -> RowMajor<f32> {
    let (w, h) = mask.dimensions();
    RowMajor::from_fn(grid.width, grid.height, |x, y| {
        let (px, py) = grid.to_photo(x as f32 + 0.5, y as f32 + 0.5);
        let (px, py) = ((px as u32).min(w - 1), (py as u32).min(h - 1));
        mask.get_pixel(px, py)[0] as f32 / 255.0
    })
}

/// The painted masks of `p`'s mask sources (`None` for other sources),
/// read from their files and put on the grid.
///
/// # Errors
/// [`Error::Preset`] naming the source when a mask cannot be read or is
/// not `w` x `h` (the photo's size).
pub fn load_masks(
    p: &GammatonParams,
    grid: &Grid,
    (w, h): (u32, u32),
) -> Result<Vec<Option<RowMajor<f32>>>> {
    p.sources
        .iter()
        .enumerate()
        .map(|(i, s)| {
            if s.kind != SourceKind::Mask {
                return Ok(None);
            }
            let mask = crate::io::load_mask(Path::new(&s.mask), w, h).map_err(|e| {
                Error::Preset(format!(
                    "gammaton.sources[{i}].mask: {e}; give a greyscale image the photo's size ({w}x{h}), white where γ-tons start"
                ))
            })?;
            Ok(Some(mask_on_grid(&mask, grid)))
        })
        .collect()
}

/// A stamp of the painted masks `p`'s mask sources read (their paths and
/// contents), so that a kept output goes stale when a mask is repainted
/// under the same preset ([`crate::pipeline::run_cached`]). A mask that
/// cannot be read stamps as such (the run then reports it).
pub fn files_stamp(p: &GammatonParams) -> u64 {
    use std::hash::{Hash as _, Hasher as _};
    let mut h = std::hash::DefaultHasher::new();
    for s in p.sources.iter().filter(|s| s.kind == SourceKind::Mask) {
        s.mask.hash(&mut h);
        std::fs::read(&s.mask).ok().hash(&mut h);
    }
    h.finish()
}

/// The point a fraction `t` along the polylines' total length.
fn point_on(lines: &[Vec<(f32, f32)>], t: f32) -> (f32, f32) {
    let segments = || {
        lines
            .iter()
            .flat_map(|l| l.windows(2).map(|w| (w[0], w[1])))
    };
    let length: f32 = segments().map(|(a, b)| (b.0 - a.0).hypot(b.1 - a.1)).sum();
    let mut rest = t * length;
    for (a, b) in segments() {
        let l = (b.0 - a.0).hypot(b.1 - a.1);
        if rest <= l && l > 0.0 {
            let u = rest / l;
            return (a.0 + (b.0 - a.0) * u, a.1 + (b.1 - a.1) * u);
        }
        rest -= l;
    }
    lines.iter().flatten().next().copied().unwrap_or((0.0, 0.0))
}

/// The γ-tons as a pipeline stage: one layer per substance.
pub(super) fn stage(
    ctx: &Context,
    _: &mut Products,
    preset: &Preset,
    progress: &Progress,
) -> Result<Produced> {
    let p = &preset.gammaton;
    let grid = ctx.grid;
    let ledges: Vec<Vec<(f32, f32)>> = preset
        .rain
        .source_lines
        .iter()
        .map(|l| l.iter().map(|q| grid.to_grid(q[0], q[1])).collect())
        .collect();
    let mut p_grid = p.clone();
    for s in &mut p_grid.sources {
        for q in &mut s.points {
            let (x, y) = grid.to_grid(q[0], q[1]);
            *q = [x, y];
        }
    }
    let per_metre = ctx.grid_px(1.0);
    let scenery = Scenery {
        lines: ledges,
        masks: load_masks(p, grid, ctx.size())?,
        overhangs: ctx
            .site
            .ledges
            .iter()
            .map(|l| {
                let line = l
                    .polyline
                    .iter()
                    .map(|q| grid.to_grid(q[0], q[1]))
                    .collect();
                Overhang::new(line, sky::relative_reach(l.kind) * per_metre)
            })
            .collect(),
    };
    let out = simulate(
        ctx.luma,
        ctx.region,
        &scenery,
        &p_grid,
        preset.seed,
        &progress.span(0.0, 0.9),
    )?;
    let (w, h) = ctx.size();
    let mut layers = Vec::with_capacity(out.maps.len());
    for (s, map) in p.substances.iter().zip(&out.maps) {
        progress.check()?;
        // Texture synthesis: the mean over the near wall pixels.
        let filtered;
        let map = match s.filter {
            0 => map,
            r => {
                filtered = crate::effects::box_mean::box_mean(map, ctx.region, r as usize);
                &filtered
            }
        };
        // What the γ-tons gathered beyond the wall's own content.
        let scaled = RowMajor::from_fn(map.width(), map.height(), |x, y| {
            ((map.get(x, y) - s.initial) / s.scale).clamp(0.0, 1.0)
        });
        let value = grid.upsample(&scaled, ctx.mask, w, h);
        layers.push(Layer {
            name: s.name.clone(),
            kind: Some(Effect::Gammaton),
            blend: BlendMode::Normal,
            opacity: 1.0,
            visible: true,
            pixels: LayerPixels::Rgba(rules::colour(&value, &s.stops, ctx.mask)),
        });
    }
    Ok(Produced {
        layer_stats: vec![None; layers.len()],
        layers,
        stats: Stats::Gammaton(out.stats),
    })
}

#[cfg(test)]
mod tests;
