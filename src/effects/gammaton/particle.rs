//! One γ-ton: motion by Russian roulette (thesis eq. 3.10), deterioration
//! (eq. 3.21) and substance transport (eqs. 3.23-3.27) at each contact.
//! It runs on the deterministic patch scheduler ([`crate::effects::patches`]).

use rand::Rng as _;
use rayon::prelude::*;

use crate::effects::patches::{Particle, Space};
use crate::preset::MAX_SUBSTANCES;
use crate::random::Rng;

/// Largest interaction radius, whole pixels.
pub const MAX_RADIUS: usize = 4;

/// Pixels within [`MAX_RADIUS`] at most.
const MAX_CELLS: usize = (2 * MAX_RADIUS + 1) * (2 * MAX_RADIUS + 1);

/// How a γ-ton moves until its next contact.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Motion {
    /// A straight hop across the wall.
    Straight,
    /// A bounce off the wall, falling back under gravity.
    Parabolic,
    /// Running down the wall's slope.
    Flow,
}

/// Where a γ-ton ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fate {
    /// Still moving (or parked at a patch border).
    Moving,
    /// Settled on the wall.
    Settled,
    /// Left the wall (region or grid) carrying what it held.
    Left,
}

/// Constants every γ-ton shares.
#[derive(Debug, Clone)]
pub struct Laws {
    /// Substances in use.
    pub substances: usize,
    /// Absorption rate a per substance.
    pub absorb: [f32; MAX_SUBSTANCES],
    /// Deposition rate k per substance.
    pub deposit: [f32; MAX_SUBSTANCES],
    /// Consistent (true) or classic transport.
    pub consistent: bool,
    /// Deteriorations Δ_s, Δ_p, Δ_f.
    pub deteriorate: [f32; 3],
    /// Interaction radius, whole pixels.
    pub radius: usize,
    /// Contacts before a γ-ton settles regardless.
    pub max_depth: u32,
    /// Straight and parabolic hop length.
    pub hop: f32,
    /// Flow segment length.
    pub flow_step: f32,
    /// Sideways wander of flow.
    pub wander: f32,
}

/// One γ-ton.
#[derive(Debug, Clone)]
pub struct Gammaton {
    /// Emission index in its batch (the order γ-tons end in).
    pub index: usize,
    /// Position, grid pixels (continuous).
    pub x: f32,
    /// Position, grid pixels (continuous).
    pub y: f32,
    vx: f32,
    vy: f32,
    motion: Motion,
    /// Path left until the next contact; <= 0: at a contact.
    left: f32,
    /// p_s, p_p, p_f.
    probs: [f32; 3],
    /// Substance held, s_i.
    pub carried: [f32; MAX_SUBSTANCES],
    /// Substance that vanished with it or was made by k > 1 on settling
    /// (positive: lost), per substance.
    pub balance: [f32; MAX_SUBSTANCES],
    /// Contacts made.
    pub depth: u32,
    /// How it ended.
    pub fate: Fate,
    rng: Rng,
}

impl Gammaton {
    /// A γ-ton at `(x, y)` moving in `motion` along `(vx, vy)` for `left`
    /// pixels (0: its first contact is where it is).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        index: usize,
        (x, y): (f32, f32),
        (vx, vy): (f32, f32),
        motion: Motion,
        left: f32,
        probs: [f32; 3],
        carried: [f32; MAX_SUBSTANCES],
        rng: Rng,
    ) -> Gammaton {
        Gammaton {
            index,
            x,
            y,
            vx,
            vy,
            motion,
            left,
            probs,
            carried,
            balance: [0.0; MAX_SUBSTANCES],
            depth: 0,
            fate: Fate::Moving,
            rng,
        }
    }

    /// The γ-ton leaves the wall with what it holds.
    fn leave(&mut self) {
        self.fate = Fate::Left;
        for (b, c) in self.balance.iter_mut().zip(&mut self.carried) {
            *b += *c;
            *c = 0.0;
        }
    }

    /// The next motion by Russian roulette over p_s, p_p, p_f (eq. 3.10);
    /// `None` = settle.
    fn roulette(&mut self, laws: &Laws) -> Option<Motion> {
        if self.depth >= laws.max_depth {
            return None;
        }
        let xi: f32 = self.rng.random();
        let [ps, pp, pf] = self.probs;
        match xi {
            x if x < ps => Some(Motion::Straight),
            x if x < ps + pp => Some(Motion::Parabolic),
            x if x < ps + pp + pf => Some(Motion::Flow),
            _ => None,
        }
    }

    /// Starts `motion` from the current contact.
    fn launch(&mut self, motion: Motion, laws: &Laws) {
        self.motion = motion;
        let angle = |rng: &mut Rng, spread: f32| (rng.random::<f32>() * 2.0 - 1.0) * spread;
        match motion {
            // Diffuse sampling in the wall's plane: any direction.
            Motion::Straight => {
                let a = angle(&mut self.rng, std::f32::consts::PI);
                (self.vx, self.vy) = (a.sin(), a.cos());
                self.left = laws.hop * (0.5 + self.rng.random::<f32>());
            }
            // Off the wall and back: up and sideways, then gravity.
            Motion::Parabolic => {
                let a = angle(&mut self.rng, 1.0);
                (self.vx, self.vy) = (a.sin(), -a.cos());
                self.left = 2.0 * laws.hop * (0.5 + self.rng.random::<f32>());
            }
            Motion::Flow => {
                (self.vx, self.vy) = (0.0, 1.0);
                self.left = laws.flow_step;
            }
        }
    }
}

/// Motion deterioration after a contact (thesis eq. 3.21, Stadler's
/// sound form of Chen's eq. 3.20): `p_s' = max(p_s - Δ_s, 0)`,
/// `p_p' = max(p_p - Δ_p, 0)`,
/// `p_f' = min(max(p_f + p_p' - Δ_f, 0), 1 - p_s' - p_p')`.
pub fn deteriorate([ps, pp, pf]: [f32; 3], [ds, dp, df]: [f32; 3]) -> [f32; 3] {
    let ps2 = (ps - ds).max(0.0);
    let pp2 = (pp - dp).max(0.0);
    let pf2 = (pf + pp2 - df).max(0.0).min(1.0 - ps2 - pp2);
    [ps2, pp2, pf2.max(0.0)]
}

/// Exchange between a γ-ton holding `s` and the pixels `cells` of one
/// substance's `map` at a contact. Returns what the γ-ton holds after, and
/// the substance made (negative) or vanished (positive) beyond the
/// exchange: only classic settling with k != 1 has any.
///
/// - classic, not settling (eqs. 3.23-3.24): the γ-ton absorbs `a c_j / n`
///   from each cell; with a < 0 it gives that much instead, at most what it
///   holds [choice: scaled down so nothing is made from nothing];
/// - classic, settling (eq. 3.25): each cell gets `k s / n`;
/// - consistent (eqs. 3.26-3.27), at every contact, with `d = k - a`
///   clamped to -1..1: d >= 0: each cell gets `d s / n` and the γ-ton gives
///   `d s` [choice: the thesis gives `d s` to each of the n surfels and
///   takes `n d s`, more than a γ-ton holds for n d > 1; the 1/n share
///   conserves]; d < 0: each cell gives `-d c_j`, the γ-ton takes it.
///
/// Everything stays at or above zero.
pub fn exchange(
    s: f32,
    map: &mut [f32],
    cells: &[usize],
    (a, k): (f32, f32),
    consistent: bool,
    settling: bool,
) -> (f32, f32) {
    let n = cells.len().max(1) as f32;
    if consistent {
        let d = (k - a).clamp(-1.0, 1.0);
        if d >= 0.0 {
            let share = d * s / n;
            let given = each_cell(map, cells, |c| {
                *c += share;
                share
            });
            return ((s - given).max(0.0), 0.0);
        }
        let taken = each_cell(map, cells, |c| {
            let t = -d * *c;
            *c -= t;
            t
        });
        return (s + taken, 0.0);
    }
    if settling {
        let share = k * s / n;
        let given = each_cell(map, cells, |c| {
            *c += share;
            share
        });
        return (0.0, s - given);
    }
    if a >= 0.0 {
        let taken = each_cell(map, cells, |c| {
            let t = (a * *c / n).min(*c);
            *c -= t;
            t
        });
        return (s + taken, 0.0);
    }
    let want = each_cell(map, cells, |c| -a * *c / n);
    let scale = if want > s { s / want } else { 1.0 };
    let given = each_cell(map, cells, |c| {
        let g = -a * *c / n * scale;
        *c += g;
        g
    });
    ((s - given).max(0.0), 0.0)
}

/// Applies `f` to the pixels `cells` of `map`, summing what it returns
/// (generic, so the exchange's arithmetic inlines into one loop).
fn each_cell(map: &mut [f32], cells: &[usize], f: impl Fn(&mut f32) -> f32) -> f32 {
    cells.iter().map(|&j| f(&mut map[j])).sum()
}

/// The wall the γ-tons run over: substance maps, region and the slope of
/// the luminance, column-major (`x * rows + y`).
pub struct World {
    /// Grid width.
    pub width: usize,
    /// Grid height.
    pub rows: usize,
    /// One map per substance.
    pub maps: Vec<Vec<f32>>,
    /// Wall pixels.
    pub region: Vec<bool>,
    /// The sideways slope flow runs down: `(L(x - 1) - L(x + 1)) / 64` of
    /// the luminance height field L (0..255), the edge columns repeated.
    /// Precomputed: one load a step instead of two a column apart.
    slope: Vec<f32>,
}

impl World {
    /// The wall of `width` x `rows` pixels with its substance `maps`,
    /// `region` and luminance `luma` (all column-major).
    pub fn new(
        width: usize,
        rows: usize,
        maps: Vec<Vec<f32>>,
        region: Vec<bool>,
        luma: &[f32],
    ) -> World {
        let at = |x: usize, y: usize| luma[x.min(width - 1) * rows + y];
        let slope = (0..width * rows)
            .into_par_iter()
            .map(|i| {
                let (x, y) = (i / rows, i % rows);
                (at(x.saturating_sub(1), y) - at(x + 1, y)) / 64.0
            })
            .collect();
        World {
            width,
            rows,
            maps,
            region,
            slope,
        }
    }
}

/// Columns `first..end` of the [`World`], owned by one queue of γ-tons.
pub struct Patch<'a> {
    first: usize,
    end: usize,
    rows: usize,
    width: usize,
    maps: Vec<&'a mut [f32]>,
    region: &'a [bool],
    slope: &'a [f32],
}

impl Space<Gammaton> for World {
    fn columns(&self) -> usize {
        self.width
    }

    fn patches(&mut self, bounds: &[usize]) -> Vec<Patch<'_>> {
        let rows = self.rows;
        let mut per_map: Vec<Vec<&mut [f32]>> = self
            .maps
            .iter_mut()
            .map(|m| {
                let mut rest: &mut [f32] = m;
                let mut parts = Vec::with_capacity(bounds.len());
                for w in bounds.windows(2) {
                    let (part, tail) = std::mem::take(&mut rest).split_at_mut((w[1] - w[0]) * rows);
                    parts.push(part);
                    rest = tail;
                }
                parts
            })
            .collect();
        bounds
            .windows(2)
            .enumerate()
            .map(|(i, w)| Patch {
                first: w[0],
                end: w[1],
                rows,
                width: self.width,
                maps: per_map
                    .iter_mut()
                    .map(|parts| std::mem::take(&mut parts[i]))
                    .collect(),
                region: &self.region,
                slope: &self.slope,
            })
            .collect()
    }
}

impl Patch<'_> {
    /// Whether columns `x0..=x1`, cut to the grid, are all this patch's.
    fn holds(&self, x0: isize, x1: isize) -> bool {
        x0.max(0) >= self.first as isize && x1.min(self.width as isize - 1) < self.end as isize
    }

    fn wall(&self, x: isize, y: isize) -> bool {
        x >= 0
            && y >= 0
            && (x as usize) < self.width
            && (y as usize) < self.rows
            && self.region[x as usize * self.rows + y as usize]
    }

    /// The slope flow runs down at `(x, y)`; 0 off the grid (a line
    /// source's point may lie there).
    fn slope(&self, x: isize, y: isize) -> f32 {
        let inside = x >= 0 && y >= 0 && (x as usize) < self.width && (y as usize) < self.rows;
        match inside {
            true => self.slope[x as usize * self.rows + y as usize],
            false => 0.0,
        }
    }
}

impl Particle for Gammaton {
    type Patch<'a> = Patch<'a>;
    type Laws = Laws;

    fn index(&self) -> usize {
        self.index
    }

    fn column(&self) -> usize {
        self.x.max(0.0) as usize
    }

    fn ended(&self) -> bool {
        self.fate != Fate::Moving
    }

    fn step(&mut self, patch: &mut Patch<'_>, laws: &Laws) -> bool {
        if self.fate != Fate::Moving {
            return false;
        }
        let (cx, cy) = (floor(self.x), floor(self.y));
        if self.left <= 0.0 {
            let r = laws.radius as isize;
            if !patch.holds(cx - r, cx + r) {
                return false;
            }
            self.contact(patch, laws, cx, cy);
            return self.fate == Fate::Moving;
        }
        if self.motion == Motion::Flow {
            // Down the slope of the luminance height field, plus wander.
            let slope = patch.slope(cx, cy);
            let xi = self.rng.random::<f32>() * 2.0 - 1.0;
            self.vx = (slope + laws.wander * xi).clamp(-1.0, 1.0);
            self.vy = 1.0;
        }
        let len = (self.vx * self.vx + self.vy * self.vy).sqrt().max(1e-6);
        let (nx, ny) = (self.x + self.vx / len, self.y + self.vy / len);
        if self.motion == Motion::Parabolic {
            // Gravity bends the bounce back down over about one hop.
            self.vy += 2.0 / laws.hop;
        }
        let (ix, iy) = (floor(nx), floor(ny));
        if !patch.wall(ix, iy) {
            self.leave();
            return false;
        }
        if !patch.holds(ix, ix) {
            return false;
        }
        (self.x, self.y) = (nx, ny);
        self.left -= 1.0;
        true
    }
}

/// `v.floor() as isize`, inline: without SSE4.1 `floor` is a library
/// call, and the step takes four.
fn floor(v: f32) -> isize {
    let t = v as isize;
    t.saturating_sub(isize::from((t as f32) > v))
}

impl Gammaton {
    /// A contact at pixel `(cx, cy)`: deteriorate, choose the next motion,
    /// exchange substance with the wall pixels within the radius.
    fn contact(&mut self, patch: &mut Patch<'_>, laws: &Laws, cx: isize, cy: isize) {
        self.depth += 1;
        self.probs = deteriorate(self.probs, laws.deteriorate);
        let next = self.roulette(laws);
        let settling = next.is_none();
        let r = laws.radius as isize;
        let mut cells = [0usize; MAX_CELLS];
        let mut n = 0;
        for dx in -r..=r {
            for dy in -r..=r {
                let (x, y) = (cx + dx, cy + dy);
                if dx * dx + dy * dy <= r * r && patch.wall(x, y) {
                    cells[n] = (x as usize - patch.first) * patch.rows + y as usize;
                    n += 1;
                }
            }
        }
        let cells = &cells[..n];
        for i in 0..laws.substances {
            let (s, balance) = exchange(
                self.carried[i],
                patch.maps[i],
                cells,
                (laws.absorb[i], laws.deposit[i]),
                laws.consistent,
                settling,
            );
            self.carried[i] = s;
            self.balance[i] += balance;
        }
        match next {
            Some(motion) => self.launch(motion, laws),
            None => {
                self.fate = Fate::Settled;
                // What a consistent γ-ton still holds vanishes with it.
                for (b, c) in self.balance.iter_mut().zip(&mut self.carried) {
                    *b += *c;
                    *c = 0.0;
                }
            }
        }
    }
}
