//! Rain streaks over time (Chang, Yoshida & Mukai; Endo et al.).
//!
//! [`simulate`] runs the rainfalls on the simulation grid and returns, per
//! rainfall, the dirt it deposited, plus the final wall water and dirt that
//! moss grows from. [`stain`] turns deposits into layer coverage.

pub mod breaks;
pub mod deposit;
pub mod droplets;
pub mod fall;
pub mod habit;
pub mod regrid;
pub mod soak;
pub mod soot;
pub mod sources;
pub mod stain;
pub mod texture;
pub mod twins;
pub mod wall;
pub mod wander;

use rand::Rng as _;
use rayon::prelude::*;
use serde::Serialize;

use crate::effects::patches;
use crate::error::{Error, Result};
use crate::field::{ColumnMajor, RowMajor};
use crate::preset::RainParams;
use crate::progress::Progress;
use crate::random::{self, Stream};
use droplets::{Droplet, End, Laws, Runner};
use sources::{Release, Source, Warp};
use wall::{Column, Wall};

/// What the rain runs on: the wall's luminance and region on the grid.
#[derive(Debug, Clone)]
pub struct RainInput<'a> {
    /// Luminance B in 0..255.
    pub luma: &'a RowMajor<f32>,
    /// Region mask, the size of `luma`.
    pub region: &'a RowMajor<bool>,
    /// Source polylines in grid coordinates.
    pub source_lines: Vec<Vec<(f32, f32)>>,
    /// Per source line, the share of the rain it catches: 1 in the open,
    /// less under an overhang (the scene's rain shelter); missing = 1.
    pub catch: Vec<f32>,
    /// Where along the sources water leaves, grid pixels.
    pub release: Release,
    /// Whether to keep the dirt the droplets washed off
    /// ([`RainOutput::washed`]).
    pub washed: bool,
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
    /// Dirt this rainfall's droplets left, per grid pixel (max(D - D without
    /// them, 0)), column by column: the order the wall is stored and water
    /// runs in.
    pub deposit: ColumnMajor<f32>,
    /// Numbers.
    pub stats: LayerStats,
    /// Every droplet's start and end.
    pub paths: Vec<Path>,
}

/// The rain's result.
#[derive(Debug, Clone)]
pub struct RainOutput {
    /// One entry per rainfall, oldest first.
    pub layers: Vec<RainLayer>,
    /// Wall water w after the last rainfall.
    pub water: RowMajor<f32>,
    /// Wall dirt D after the last rainfall.
    pub dirt: RowMajor<f32>,
    /// Vertical roughness M_y of the final surface (eq. 1).
    pub roughness_y: RowMajor<f32>,
    /// The dirt the droplets took off the wall net of what they left, per
    /// pixel, summed over the rainfalls (each rainfall's baseline minus D):
    /// positive where the rain cleaned the wall, negative where it stained
    /// it; `None` unless [`RainInput::washed`].
    pub washed: Option<ColumnMajor<f32>>,
}

/// Droplets per rainfall for a region `width` grid pixels wide.
pub fn droplet_count(p: &RainParams, width: usize) -> u32 {
    if p.reference_width == 0 || p.droplets == 0 {
        return p.droplets;
    }
    ((p.droplets as f64 * width as f64 / p.reference_width as f64).round() as u32).max(1)
}

/// Half a patch's width, in grid columns, for [`patches::run`].
const BAND: usize = 64;

/// Droplets started and scheduled together at most [choice: a rainfall's
/// droplets run in batches of this many, so the droplets in flight take a
/// bounded amount of memory (about 400 bytes each) however many fall; a
/// batch ends before the next starts, which only changes which droplets
/// cross a patch border after which, and the droplet counts of the presets
/// and demos are far below it].
const SCHEDULE: usize = 1 << 16;

/// Most droplet steps a simulation starts, estimated by [`Cost`]: minutes of
/// work on a desktop.
pub const MAX_STEPS: u64 = 10_000_000_000;

/// Most memory a simulation may need, estimated by [`Cost`].
pub const MAX_BYTES: u64 = 4 << 30;

/// What a rain simulation will need, estimated before it starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Cost {
    /// Droplet runs: droplets per rainfall x rainfalls.
    pub runs: u64,
    /// Droplet steps, about: each run for the grid's height at `v_max`
    /// pixels a step, at most `max_steps`.
    pub steps: u64,
    /// Bytes: the wall, every rainfall's deposit, the washed dirt, every
    /// droplet's path and start, and the droplets in flight.
    pub bytes: u64,
}

impl Cost {
    /// The cost of `p` on a `width` x `height` grid.
    pub fn of(p: &RainParams, width: usize, height: usize) -> Cost {
        let n = droplet_count(p, width) as u64;
        let layers = p.layers as u64;
        let runs = n * layers;
        let per_run = ((height as f64 / p.v_max.max(1e-3) as f64).ceil() as u64)
            .clamp(1, p.max_steps.max(1) as u64);
        let cells = width as u64 * height as u64;
        let padded = (width as u64 + 2) * (height as u64 + 2);
        let f32s = std::mem::size_of::<f32>() as u64;
        let bytes = padded * 7 * f32s
            + cells * (layers + 1) * f32s
            + runs * std::mem::size_of::<Path>() as u64
            + n * 2 * f32s
            + n.min(SCHEDULE as u64) * 2 * std::mem::size_of::<Runner>() as u64;
        Cost {
            runs,
            steps: runs.saturating_mul(per_run),
            bytes,
        }
    }

    /// Refuses a cost over [`MAX_STEPS`] or [`MAX_BYTES`].
    ///
    /// # Errors
    /// [`Error::TooMuchWork`] naming the preset fields that lower it.
    pub fn check(&self) -> Result<()> {
        let gb = |b: u64| format!("{:.1} GB", b as f64 / 1e9);
        if self.steps > MAX_STEPS {
            return Err(Error::TooMuchWork {
                need: format!(
                    "the rain would take about {:.1e} droplet steps ({} droplet runs)",
                    self.steps as f64, self.runs
                ),
                limit: format!("{:.0e}", MAX_STEPS as f64),
                fix: "lower rain.droplets, rain.layers or rain.max_steps, raise \
                      rain.reference_width, or lower sim.max_side"
                    .into(),
            });
        }
        if self.bytes > MAX_BYTES {
            return Err(Error::TooMuchWork {
                need: format!("the rain would need about {} of memory", gb(self.bytes)),
                limit: gb(MAX_BYTES),
                fix: "lower rain.layers, rain.droplets or sim.max_side, or raise \
                      rain.reference_width"
                    .into(),
            });
        }
        Ok(())
    }
}

/// Runs `p.layers` rainfalls (Chang sec. 3), reporting progress and stopping
/// when cancelled.
///
/// # Errors
/// [`Error::TooMuchWork`] when the preset asks for more than [`Cost::check`]
/// allows on this grid, [`Error::Cancelled`] when the progress's cancel
/// flag is set.
pub fn simulate(
    input: &RainInput,
    p: &RainParams,
    seed: u64,
    progress: &Progress,
) -> Result<RainOutput> {
    Ok(simulate_keeping(input, p, seed, progress, &[])?.0)
}

/// [`simulate`], also keeping the wall after each rainfall count in `keep`
/// (a time-lapse's frames): each kept state, with [`RainOutput::prefix`],
/// is the output of a run with that many rainfalls. A kept count begins
/// its next rainfall in a pass of its own, which gives the same numbers.
///
/// # Errors
/// As [`simulate`].
pub fn simulate_keeping(
    input: &RainInput,
    p: &RainParams,
    seed: u64,
    progress: &Progress,
    keep: &[u32],
) -> Result<(RainOutput, Vec<Kept>)> {
    let (width, height) = (input.luma.width(), input.luma.height());
    Cost::of(p, width, height).check()?;
    let mut wall = Wall::new(input.luma, input.region);
    let mut sources = Vec::new();
    if p.top_edge {
        let edge = sources::top_edge(&wall);
        if !edge.is_empty() {
            sources.push(Source::TopEdge(edge));
        }
    }
    for line in &input.source_lines {
        sources.push(Source::line(padded(line)));
    }
    // [choice, beyond Chang:] a source catches rain in proportion to its
    // length times how open it is, so droplets start less often on a
    // ledge under a balcony or an eave.
    let top = usize::from(p.top_edge && sources.len() > input.source_lines.len());
    // Each source's own key: its draws do not change when another source
    // comes or goes.
    let keys: Vec<u64> = (0..sources.len())
        .map(|i| match i.checked_sub(top) {
            Some(line) => sources::line_key(&input.source_lines[line]),
            None => 0,
        })
        .collect();
    let warps = sources
        .iter()
        .zip(&keys)
        .map(|(s, &key)| match key {
            0 => sources::top_warp(seed, s.length(), &input.release),
            key => sources::line_warp(seed, key, s.length(), &input.release),
        })
        .collect();
    let spans: Vec<f32> = sources
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let catch = i.checked_sub(top).and_then(|l| input.catch.get(l));
            s.length() * catch.copied().unwrap_or(1.0).clamp(0.0, 1.0)
        })
        .collect();
    let total_len: f32 = spans.iter().sum();
    let n = if total_len > 0.0 {
        droplet_count(p, width) as usize
    } else {
        0
    };
    let clouds = Clouds {
        owners: owners(seed, &spans, &keys, n),
        spans,
        sources,
        warps,
        keys,
        p,
        seed,
    };
    let laws = Laws::new(p);
    let rounds = p.diffusion_rounds.max(1) as usize;
    let area = input.region.data().iter().filter(|&&r| r).count().max(1);
    // Per droplet: (position along the sources, mass), carried between layers.
    let mut starts: Vec<(f32, f32)> = vec![(0.0, 0.0); n];
    let mut layers: Vec<RainLayer> = Vec::with_capacity(p.layers as usize);
    let mut kept = Vec::new();
    let mut washed = input
        .washed
        .then(|| ColumnMajor::filled(width, height, 0.0));
    if keep.contains(&0) {
        kept.push(Kept::of(&wall, 0, washed.as_ref()));
    }

    for layer in 0..p.layers {
        if layer == 0 {
            let noise = grime_noise(&wall, p, seed, 0);
            let begin = Begin::new(p, seed, 0, &wall, noise.as_ref());
            wall.columns(None, |mut col| begin.column(&mut col));
        } else {
            // Chang eq. (15): deposited dirt raises the surface for the next
            // rain [choice: eps is a fraction of full scale, and D is what the
            // previous rainfall deposited, so streak channels rise (and later
            // droplets follow them) while the rest of the wall keeps its
            // texture; raising by the total dirt lifts the whole wall to 255
            // within a few rainfalls and erases the roughness].
            if let Some(previous) = layers.last()
                && previous.stats.max_dirt > 0.0
            {
                let raise = 255.0 * p.eps / previous.stats.max_dirt;
                let rows = wall.rows;
                wall.b[rows..(wall.cols - 1) * rows]
                    .par_chunks_mut(rows)
                    .zip(previous.deposit.data().par_chunks(previous.deposit.line()))
                    .for_each(|(b, deposit)| {
                        for (b, d) in b[1..].iter_mut().zip(deposit) {
                            *b = (*b + raise * d).min(255.0);
                        }
                    });
            }
        }
        let mut stats = LayerStats::default();
        let mut paths = Vec::with_capacity(n);
        let mut columns = Vec::new();
        let mut deposit = ColumnMajor::filled(width, height, 0.0);
        for round in 0..rounds {
            // The droplets before this round's diffusion, SCHEDULE at a time.
            let batch = (round * n).div_ceil(rounds)..((round + 1) * n).div_ceil(rounds);
            for first in batch.clone().step_by(SCHEDULE) {
                let end = (first + SCHEDULE).min(batch.end);
                let mut runners = Vec::with_capacity(end - first);
                for (k, start) in starts[first..end].iter_mut().enumerate() {
                    if let Some((runner, s0)) = clouds.droplet(layer, first + k, start) {
                        stats.dirt_from_ledges += s0 as f64;
                        runners.push(runner);
                    }
                }
                for r in patches::run(&mut wall, runners, &laws, BAND, progress)? {
                    stats.count(&r);
                    paths.push(Path {
                        start: (r.start.0 - 1.0, r.start.1 - 1.0),
                        end: (r.trace.end.0 - 1.0, r.trace.end.1 - 1.0),
                        steps: r.trace.steps,
                    });
                }
            }
            // After the last round, the next rainfall begins in the same pass.
            let last = round + 1 == rounds;
            let next = layer + 1;
            let kept_here = keep.contains(&next);
            let begins_next = last && next < p.layers && !kept_here;
            let noise = begins_next
                .then(|| grime_noise(&wall, p, seed, next))
                .flatten();
            let begin = begins_next.then(|| Begin::new(p, seed, next, &wall, noise.as_ref()));
            let output = last.then_some(deposit.data_mut());
            columns = diffusion_round(&mut wall, p, rounds, output, begin.as_ref(), input.washed);
            progress.update(
                "rain",
                (layer as f32 + (round + 1) as f32 / rounds as f32) / p.layers as f32,
            );
        }

        // The deposit pass wrote D minus its baseline: the rainfall's net
        // cleaning is its negative, the deposit its positive part.
        if let Some(washed) = washed.as_mut() {
            washed
                .data_mut()
                .par_iter_mut()
                .zip(deposit.data_mut())
                .for_each(|(w, d)| {
                    *w -= *d;
                    *d = d.max(0.0);
                });
        }
        // Column sums in column order: the same at any thread count.
        let (sum, max) = columns
            .iter()
            .fold((0.0, 0.0f32), |(s, m), &(cs, cm)| (s + cs, m.max(cm)));
        stats.mean_dirt = sum / area as f64;
        stats.max_dirt = max;
        layers.push(RainLayer {
            deposit,
            stats,
            paths,
        });
        if keep.contains(&(layer + 1)) {
            kept.push(Kept::of(&wall, layer + 1, washed.as_ref()));
            if layer + 1 < p.layers {
                let noise = grime_noise(&wall, p, seed, layer + 1);
                let begin = Begin::new(p, seed, layer + 1, &wall, noise.as_ref());
                wall.columns(None, |mut col| begin.column(&mut col));
            }
        }
    }
    progress.update("rain", 1.0);
    // The outputs go into buffers the wall no longer needs: fresh ones cost
    // page faults.
    let [water, dirt, roughness] =
        [&mut wall.carry, &mut wall.baseline, &mut wall.inside].map(std::mem::take);
    let out = RainOutput {
        layers,
        water: unpad(&wall, |i| wall.w[i], water),
        dirt: unpad(&wall, |i| wall.d[i], dirt),
        roughness_y: unpad(&wall, |i| wall.roughness(i).1, roughness),
        washed,
    };
    Ok((out, kept))
}

/// The wall after some rainfalls of a longer run ([`simulate_keeping`]).
#[derive(Debug, Clone)]
pub struct Kept {
    /// Rainfalls so far.
    pub rainfalls: u32,
    /// Wall water, dirt and roughness then (as in [`RainOutput`]).
    pub water: RowMajor<f32>,
    /// Wall dirt D.
    pub dirt: RowMajor<f32>,
    /// Vertical roughness M_y.
    pub roughness_y: RowMajor<f32>,
    /// The net dirt washed off so far ([`RainOutput::washed`]).
    pub washed: Option<ColumnMajor<f32>>,
}

impl Kept {
    fn of(wall: &Wall, rainfalls: u32, washed: Option<&ColumnMajor<f32>>) -> Kept {
        Kept {
            rainfalls,
            water: unpad(wall, |i| wall.w[i], Vec::new()),
            dirt: unpad(wall, |i| wall.d[i], Vec::new()),
            roughness_y: unpad(wall, |i| wall.roughness(i).1, Vec::new()),
            washed: washed.cloned(),
        }
    }
}

impl RainOutput {
    /// The output of a run with `kept.rainfalls` rainfalls: this run's first
    /// layers (each rainfall depends only on those before it) and the wall
    /// kept then.
    pub fn prefix(&self, kept: &Kept) -> RainOutput {
        RainOutput {
            layers: self.layers[..kept.rainfalls as usize].to_vec(),
            water: kept.water.clone(),
            dirt: kept.dirt.clone(),
            roughness_y: kept.roughness_y.clone(),
            washed: kept.washed.clone(),
        }
    }
}

impl LayerStats {
    /// Counts one finished droplet.
    fn count(&mut self, r: &Runner) {
        self.droplets += 1;
        self.droplet_steps += r.trace.steps as u64;
        self.dirt_lost += r.trace.dirt_lost as f64;
        match r.trace.outcome {
            Some(End::Dried) => self.dried += 1,
            Some(End::LeftRegion) => self.left_region += 1,
            _ => {}
        }
    }
}

/// A source line (grid coordinates) on the padded grid the rain runs on.
pub fn padded(line: &[(f32, f32)]) -> Vec<(f32, f32)> {
    line.iter().map(|&(x, y)| (x + 1.0, y + 1.0)).collect()
}

/// Where droplets come from: the sources and the draws that start them.
struct Clouds<'a> {
    sources: Vec<Source>,
    /// Each source's length times the share of rain it catches.
    spans: Vec<f32>,
    /// Each source's release points ([`Warp`]); `None` = uniform.
    warps: Vec<Option<Warp>>,
    /// Each source's key ([`sources::line_key`]; 0 for the top edge).
    keys: Vec<u64>,
    /// Droplet k's source and its number there ([`owners`]).
    owners: Vec<(usize, u64)>,
    p: &'a RainParams,
    seed: u64,
}

/// The source and the number there of each of `n` droplets, in the order
/// they run: [choice, beyond Chang, who draws every droplet's start along
/// all sources joined end to end:] each source gets its share of the
/// droplets by its span (largest remainder), and droplet j of a source
/// draws from a stream of its own (the source's key and j), so a source
/// added or dropped elsewhere (a ledge found or drawn) leaves the others'
/// droplets where they were (blind check p77 judged a streak that moved
/// when a roof line was found across the photo). The droplets run in the
/// order of a seeded time each, so a source's droplets spread over all of
/// a rainfall's diffusion rounds as before.
fn owners(seed: u64, spans: &[f32], keys: &[u64], n: usize) -> Vec<(usize, u64)> {
    let total: f32 = spans.iter().sum();
    if total <= 0.0 || n == 0 {
        return Vec::new();
    }
    let share: Vec<f32> = spans.iter().map(|s| n as f32 * s / total).collect();
    let mut count: Vec<usize> = share.iter().map(|s| s.floor() as usize).collect();
    let mut rest: Vec<usize> = (0..spans.len()).filter(|&i| spans[i] > 0.0).collect();
    rest.sort_by(|&a, &b| {
        let (ra, rb) = (share[a] - share[a].floor(), share[b] - share[b].floor());
        rb.total_cmp(&ra)
            .then(keys[a].cmp(&keys[b]))
            .then(a.cmp(&b))
    });
    let short = n.saturating_sub(count.iter().sum());
    rest.iter().take(short).for_each(|&i| count[i] += 1);
    let mut timed: Vec<(u64, usize, u64)> = count
        .iter()
        .enumerate()
        .flat_map(|(i, &c)| {
            (0..c as u64).map(move |j| {
                let when = random::key(seed, Stream::Droplet, u64::MAX, own(keys[i], j));
                (when, i, j)
            })
        })
        .collect();
    timed.sort_unstable();
    timed.into_iter().map(|(_, i, j)| (i, j)).collect()
}

/// The index of droplet `j` of the source with key `key` in its random
/// streams ([`owners`]).
fn own(key: u64, j: u64) -> u64 {
    key ^ random::mix(j)
}

/// `x` folded into `0..=span` by turning back at each end, as a walker
/// on a segment does: a uniform spread stays uniform.
fn reflect(x: f32, span: f32) -> f32 {
    if span <= 0.0 {
        return 0.0;
    }
    let t = x.rem_euclid(2.0 * span);
    if t > span { 2.0 * span - t } else { t }
}

impl Clouds<'_> {
    /// Droplet `k` of rainfall `layer`, from its own random stream, with the
    /// dirt it washed off its ledge; `None` when it is too light to run.
    /// `start` is its (position along the sources, mass), carried from the
    /// previous rainfall and updated.
    fn droplet(&self, layer: u32, k: usize, start: &mut (f32, f32)) -> Option<(Runner, f32)> {
        let p = self.p;
        let (si, j) = self.owners[k];
        let span = self.spans[si];
        let mut rng = random::rng(
            self.seed,
            Stream::Droplet,
            layer as u64,
            own(self.keys[si], j),
        );
        *start = if layer == 0 {
            (rng.random::<f32>() * span, rng.random::<f32>() * p.mass_max)
        } else {
            // Chang eqs. (16-17): normal steps from the previous layer's
            // position and mass (independent draws, Box-Muller's two outputs).
            let (z_pos, z_mass) = random::box_muller(&mut rng);
            (
                start.0 + p.sigma * z_pos,
                (start.1 + p.sigma * z_mass).max(0.0),
            )
        };
        // The walk stays on the droplet's own source, turning back at its
        // ends [choice: Chang wraps over all sources joined end to end].
        start.0 = reflect(start.0, span);
        if start.1 < p.mass_min {
            return None;
        }
        let along = start.0;
        let source = &self.sources[si];
        // Back from the span to the source's own length (an open source's
        // span is its length: its position is used as it is, bit for bit).
        let len = source.length();
        let u = if span == len {
            along
        } else {
            along * len / span.max(f32::MIN_POSITIVE)
        };
        let u = match &self.warps[si] {
            Some(warp) => warp.at(u, source.length()),
            None => u,
        };
        let (x, y) = source.point(u);
        // [choice] Chang makes deposition proportional to droplet mass: a
        // droplet washes dirt off its ledge in proportion to its water,
        // S_0 = ledge_dirt * m / m_max, so small droplets leave faint runs.
        let s0 = p.ledge_dirt * (start.1 / p.mass_max).min(1.0);
        let drop = Droplet {
            x,
            y,
            vx: 0.0,
            vy: 0.0,
            m: start.1,
            s: s0,
        };
        Some((Runner::new(k, drop, rng), s0))
    }
}

/// Chang eq. (12)'s fresh grime I_D0 for rainfall `layer`, or `None` when
/// there is none: smooth noise [choice: fBm, not white noise], transposed to
/// run down the wall's columns.
fn grime_noise(wall: &Wall, p: &RainParams, seed: u64, layer: u32) -> Option<random::Noise> {
    (p.initial_dirt > 0.0).then(|| {
        let key = random::key(seed, Stream::Grime, layer as u64, 0);
        let size = (wall.rows as u32, wall.cols as u32);
        random::Noise::new(key, size.0, size.1, p.initial_dirt_scale, 2)
    })
}

/// What happens to each pixel before a rainfall: drying, fresh grime and
/// the carry-over (Chang eqs. 11-14).
struct Begin<'a> {
    /// Drying and wind loss xi2, one per rainfall [choice]; 1 for the first.
    xi2: f32,
    /// Fresh grime I_D0.
    grime: Option<random::NoiseLines<'a>>,
    /// delta * k_D: the share of D carried over (eqs. 13-14).
    moved: f32,
}

impl<'a> Begin<'a> {
    fn new(
        p: &RainParams,
        seed: u64,
        layer: u32,
        wall: &Wall,
        noise: Option<&'a random::Noise>,
    ) -> Begin<'a> {
        Begin {
            xi2: if layer > 0 {
                random::rng(seed, Stream::RainLayer, layer as u64, 0).random()
            } else {
                1.0
            },
            grime: noise.map(|n| n.lines(wall.rows, p.initial_dirt)),
            moved: p.delta * (1.0 - p.k_s),
        }
    }

    /// Chang eqs. (11-12): w and D dry by xi2 and fresh grime settles.
    /// Eqs. (13-14): delta * k_D * D moves into this layer's source term
    /// I_D, returned to the wall over the rainfall's diffusion rounds. The
    /// baseline is what the dirt would be without droplets: diffused and
    /// topped up like D. The layer's deposit is D minus it, so the stain
    /// shows what the rain moved, not the smoothing of old grime.
    fn column(&self, col: &mut Column) {
        // The carry is rewritten below, so it holds the grime until then.
        match &self.grime {
            Some(lines) => lines.line(col.x, col.carry),
            None => col.carry.fill(0.0),
        }
        for ((((w, d), base), carry), inside) in col
            .w
            .iter_mut()
            .zip(col.d.iter_mut())
            .zip(col.baseline.iter_mut())
            .zip(col.carry.iter_mut())
            .zip(col.inside)
        {
            *w *= self.xi2;
            let fresh = *d * self.xi2 + *carry * inside;
            *carry = self.moved * fresh;
            *d = fresh - *carry;
            *base = *d;
        }
    }
}

/// Eqs. (9-10) diffusion; on each finished column, I_sun evaporation and
/// this round's share of the carried-over dirt (eq. 13's source term) to the
/// dirt and its baseline. After the rainfall's last round, also the
/// rainfall's deposit into `deposit` (column-major) and the start of the
/// next rainfall (`begin`). Returns each column's deposit sum and maximum
/// (zero but after the last round). `signed` writes D minus its baseline
/// where it is negative too.
fn diffusion_round(
    wall: &mut Wall,
    p: &RainParams,
    rounds: usize,
    deposit: Option<&mut [f32]>,
    begin: Option<&Begin>,
    signed: bool,
) -> Vec<(f64, f32)> {
    let (iterations, evaporation) = if p.diffusion_rounds > 0 {
        (p.diffusion_iterations, p.i_sun)
    } else {
        (0, 0.0)
    };
    let share = 1.0 / rounds as f32;
    let last = deposit.is_some();
    wall.diffuse(p.tau, p.dirt_coupling, iterations, deposit, |mut col| {
        if evaporation > 0.0 {
            col.w
                .iter_mut()
                .for_each(|w| *w = (*w - evaporation).max(0.0));
        }
        for ((d, base), c) in col
            .d
            .iter_mut()
            .zip(col.baseline.iter_mut())
            .zip(&*col.carry)
        {
            *d += c * share;
            *base += c * share;
        }
        if !last {
            return (0.0, 0.0);
        }
        let (mut sum, mut max) = (0.0, 0.0f32);
        let (d, base) = (&col.d[1..], &col.baseline[1..]);
        for ((dep, d), base) in col.output.iter_mut().zip(d).zip(base) {
            *dep = (d - base).max(0.0);
            sum += *dep as f64;
            max = max.max(*dep);
        }
        if signed {
            // The washed dirt is kept: the output is signed, its positive
            // part the deposit, its negative the washed dirt
            // (`simulate_keeping`).
            for ((dep, d), base) in col.output.iter_mut().zip(d).zip(base) {
                *dep = d - base;
            }
        }
        if let Some(begin) = begin {
            begin.column(&mut col);
        }
        (sum, max)
    })
}

/// Copies the unpadded interior of a padded (column-major) wall field into
/// a row-major grid (reusing `out`), tile by tile so reads and writes both
/// stay in cache.
fn unpad(wall: &Wall, f: impl Fn(usize) -> f32 + Sync, mut out: Vec<f32>) -> RowMajor<f32> {
    const TILE: usize = 32;
    let (w, h) = (wall.cols - 2, wall.rows - 2);
    out.resize(w * h, 0.0);
    out.par_chunks_mut(w * TILE)
        .enumerate()
        .for_each(|(band, rows)| {
            let y0 = band * TILE;
            let band_h = rows.len() / w;
            // Rows outer: a photo-sized row stride is often a power of two,
            // and strided writes would then all land in one cache set.
            for x0 in (0..w).step_by(TILE) {
                for dy in 0..band_h {
                    for x in x0..(x0 + TILE).min(w) {
                        rows[dy * w + x] = f(wall.idx(x + 1, y0 + dy + 1));
                    }
                }
            }
        });
    RowMajor::new(w, h, out)
}

#[cfg(test)]
mod tests;
