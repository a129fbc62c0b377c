//! The wall's foot as one path across the photo, found without starting
//! from the class map's lowest wall row (which sits on top of the ground
//! fill where the fill climbed the wall, or on a kerb where it stopped
//! short of it): per column, every row of the lower part of the photo is
//! scored by how much it looks like a wall standing on the ground (a
//! colour step, what is above standing up and what is below lying flat,
//! the wall seen above it; where both sides are plain, as a rendered wall
//! over asphalt, the colour step alone), and one path through the columns is chosen
//! by dynamic programming (Viterbi: the best sum of scores less a penalty
//! per row the path steps from one column to the next, with a state "no
//! foot here" entered and left at a cost), as a seam is carved (S. Avidan,
//! A. Shamir, "Seam carving for content-aware image resizing", SIGGRAPH
//! 2007).

use std::ops::Range;

use rayon::prelude::*;

use super::super::features::{Features, texture_radius};
use super::super::wall::Class;

/// The path is looked for below this share of the height (the ground
/// fill never reaches above 45%: `ground.rs`).
const BAND_TOP: f32 = 0.3;

/// Rows averaged on each side of a candidate step, share of the height
/// (as foot22's `STEP_SIDE`).
const STEP_SIDE: f32 = 0.006;

/// The boxes above and below a row whose gradients are compared are this
/// share of the height tall (as foot22's `SIDE_BOX`) ...
const SIDE_BOX: f32 = 0.03;

/// ... and this many pixels either side of the column wide.
const SIDE_HALF_WIDTH: usize = 4;

/// What must be wall above the foot: from this share of the height above
/// it ...
const WALL_FROM: f32 = 0.12;

/// ... to this share above it (the ground fill may climb the wall this
/// far: 2-4% of the height on LabelMeFacade train's shop fronts) ...
const WALL_TO: f32 = 0.02;

/// ... in at least this share of the rows.
const WALL_SHARE: f32 = 0.6;

/// Ground must be classed within this share of the height below the
/// foot ...
const GROUND_BELOW: f32 = 0.06;

/// ... in at least this share of the rows [choice, LabelMeFacade train,
/// foot precision / recall (before [`STANDS_UP`]): 0.3 0.248 / 0.222, 0.6
/// 0.268 / 0.225].
const GROUND_SHARE: f32 = 0.6;

/// What stands above the foot has a sideways share of the gradients'
/// energy (over [`SIDE_BOX`] of the height, as `stands_over_flat` in
/// foot22) at least this much more than what lies below it; a row where
/// it has less is no foot [choice, LabelMeFacade train, precision /
/// recall: none 0.268 / 0.225, 0.3 0.332 / 0.182, 0.35 0.348 / 0.146, 0.4
/// 0.399 / 0.125 (held-out 0.302 / 0.107); the old snap's 0.05 lets cars'
/// sills and kerbs through: they have a road below and a car's body or a
/// pavement, which also lie flat, above].
const STANDS_UP: f32 = 0.4;

/// Weight of the sideways share's difference against the colour step
/// [choice: 1 and 3 gave train precision 0.204 and 0.195 before
/// [`STANDS_UP`]; 2 after it 0.267 against 0.314 for 1].
const SIDE_WEIGHT: f32 = 1.0;

/// A row's score less this is what a column gains by having its foot
/// there (the "no foot" state gains nothing) [choice, train precision /
/// recall: 0.3 0.378 / 0.120, 0.4 0.399 / 0.125, 0.55-0.6 lower recall].
const BIAS: f32 = 0.4;

/// Mean luma gradient ([`Features::texture`]) under which both boxes
/// either side of a row (kept [`Reach::margin`] off the row, so the
/// step's own edge does not count) are plain: rendered plaster over
/// asphalt, a smooth render over smooth paving. Their gradients are
/// noise, which points every way, so [`STANDS_UP`] cannot hold there and
/// the colour step alone decides ([`PLAIN_BIAS`]) [measured: the demo
/// facade's plaster 0.025-0.033 (5-95%), its asphalt 0.022; a brick
/// close-up's courses 0.04 and more (0.04 found a foot on it); LabelMeFacade
/// train with [`PLAIN_BIAS`] 0.4, precision / recall 0.025 0.381 / 0.126,
/// 0.035 0.377 / 0.125; 0.03 found the demo's foot in 66% of its width].
const PLAIN: f32 = 0.035;

/// A plain row's colour step less this is its score (it has no
/// uprightness to add) [choice, LabelMeFacade train with [`PLAIN`] 0.035,
/// precision / recall: 0.4 0.377 / 0.125, 0.7 0.390 / 0.125, 1.0 0.391 /
/// 0.125; the demo facade's plaster over asphalt steps by 1.16].
const PLAIN_BIAS: f32 = 0.7;

/// Score of a row where the wall is not seen above or the ground not
/// below.
const NOT_HERE: f32 = -1.0;

/// Penalty per row the path steps between neighbouring columns (the
/// foot is a straight line under perspective; 0.03 gave train precision
/// 0.204, 0.1 0.248 at the same recall).
const STEP_COST: f32 = 0.1;

/// The most rows the path steps between neighbouring columns: a slope of
/// 2 (63 degrees), steeper than a street's foot seen from the pavement
/// (1 gave the same numbers).
const MAX_STEP: usize = 2;

/// Cost of entering and of leaving the "no foot" state (1.0 gave the same
/// train numbers, 1.2-1.5 lower precision before [`STANDS_UP`]).
const SWITCH_COST: f32 = 0.6;

/// Where the path's column of scores reaches: the rows it is looked for
/// in and the boxes around each row, in rows of the `h`-tall analysis.
#[derive(Clone, Copy)]
struct Reach {
    /// Rows `y0..y1` are scored.
    y0: usize,
    y1: usize,
    /// The first row any score looks at (the boxes above `y0`).
    top: usize,
    /// Rows averaged either side of a colour step ([`STEP_SIDE`]).
    side: usize,
    /// Rows of the boxes whose gradients are compared ([`SIDE_BOX`]).
    boxed: usize,
    /// Rows from [`WALL_FROM`] to [`WALL_TO`] above, [`GROUND_BELOW`].
    wall_from: usize,
    wall_to: usize,
    ground: usize,
    /// Rows the texture of an edge spreads either side of it.
    margin: usize,
    /// The first row the sideways share is read on.
    up_from: usize,
}

impl Reach {
    fn new(w: usize, h: usize) -> Option<Reach> {
        let y0 = (BAND_TOP * h as f32) as usize;
        let side = ((STEP_SIDE * h as f32).round() as usize).max(1);
        let y1 = h.saturating_sub(side + 1);
        let boxed = ((SIDE_BOX * h as f32).round() as usize).max(2);
        let wall_from = (WALL_FROM * h as f32) as usize;
        (y1 > y0 + 1).then(|| Reach {
            y0,
            y1,
            top: y0.saturating_sub(wall_from.max(boxed).max(side)),
            side,
            boxed,
            wall_from,
            wall_to: ((WALL_TO * h as f32) as usize).max(1),
            ground: ((GROUND_BELOW * h as f32) as usize).max(2),
            margin: texture_radius(w, h) + 1,
            up_from: y0.saturating_sub(boxed),
        })
    }
}

/// Per column of the `w` x `h` analysis, the row of the wall's foot on
/// the best path (the first row below the wall), `NaN` where the path is
/// in its "no foot" state.
pub(super) fn rows(f: &Features, classes: &[Class]) -> Vec<f32> {
    let w = f.w;
    let Some(reach) = Reach::new(f.w, f.h).filter(|_| w >= 3) else {
        return vec![f32::NAN; w];
    };
    let score = scores(f, classes, reach);
    viterbi(&score, w, reach.y1 - reach.y0)
        .into_iter()
        .map(|r| r.map_or(f32::NAN, |r| (r + reach.y0) as f32))
        .collect()
}

/// Per pixel of rows `top..h`, the share of the luma gradients' energy
/// that points sideways over the row's [`SIDE_HALF_WIDTH`] neighbours
/// either side (Sobel, `Jxx / (Jxx + Jyy)`, as foot22's `stands_over_flat`); 0 on
/// the photo's edge rows and columns.
fn sideways(f: &Features, top: usize) -> Vec<f32> {
    let (w, h) = (f.w, f.h);
    let r = SIDE_HALF_WIDTH;
    let mut out = vec![0f32; (h - top) * w];
    out.par_chunks_mut(w).enumerate().for_each(|(i, row)| {
        let y = top + i;
        if y == 0 || y + 1 >= h {
            return;
        }
        let l = &f.luma;
        let (mut jxx, mut jyy) = (vec![0f32; w], vec![0f32; w]);
        for x in 1..w - 1 {
            let at = |dx: isize, dy: isize| {
                l[(y as isize + dy) as usize * w + (x as isize + dx) as usize]
            };
            let gx =
                at(1, -1) + 2.0 * at(1, 0) + at(1, 1) - at(-1, -1) - 2.0 * at(-1, 0) - at(-1, 1);
            let gy =
                at(-1, 1) + 2.0 * at(0, 1) + at(1, 1) - at(-1, -1) - 2.0 * at(0, -1) - at(1, -1);
            jxx[x] = gx * gx;
            jyy[x] = gy * gy;
        }
        // Running sums over the (clipped) window of each column.
        let (mut sx, mut sy): (f32, f32) =
            (jxx[..r.min(w)].iter().sum(), jyy[..r.min(w)].iter().sum());
        for (x, o) in row.iter_mut().enumerate() {
            if x + r < w {
                sx += jxx[x + r];
                sy += jyy[x + r];
            }
            if x > r {
                sx -= jxx[x - r - 1];
                sy -= jyy[x - r - 1];
            }
            let n = ((x + r + 1).min(w) - x.saturating_sub(r)) as f32;
            let (a, b) = (sx / n, sy / n);
            *o = a / (a + b + 1e-6);
        }
    });
    out
}

/// Columns whose sums are taken together (one pass along each row of
/// the planes, not down them).
const BLOCK: usize = 64;

/// What a block of columns sums down its rows, in [`Block::sums`]' order.
const RED: usize = 0;
const SIDE: usize = 3;
const TEXTURE: usize = 4;
const WALL: usize = 5;
const GROUND: usize = 6;

/// Running sums down a block of columns from row `top`: for each of its
/// seven planes, entry `(y - top) * n + j` is column `j`'s sum over rows
/// `top..y`. The planes: red, green, blue (each over the column and its
/// neighbours), the sideways share, the texture, wall and ground.
struct Block {
    top: usize,
    n: usize,
    sums: [Vec<f32>; 7],
}

impl Block {
    /// The sums of columns `xs` from row `reach.top` down; `up` is
    /// [`sideways`] from `reach.up_from`. `None` when no row of the block has the wall above it and the
    /// ground below ([`Block::here`]): its other sums are not taken.
    fn of(
        f: &Features,
        classes: &[Class],
        up: &[f32],
        reach: Reach,
        xs: Range<usize>,
    ) -> Option<Block> {
        let top = reach.top;
        let (w, h, n) = (f.w, f.h, xs.len());
        let down = |row: &dyn Fn(usize, &mut [f32])| {
            let mut out = vec![0f32; (h - top + 1) * n];
            let mut v = vec![0f32; n];
            for y in top..h {
                row(y, &mut v);
                let (done, next) = out.split_at_mut((y + 1 - top) * n);
                let last = &done[(y - top) * n..];
                for ((o, l), v) in next[..n].iter_mut().zip(last).zip(&v) {
                    *o = l + v;
                }
            }
            out
        };
        // A colour plane over each column and its neighbours (two at the
        // photo's edges).
        let (lo, hi) = (xs.start.max(1), xs.end.min(w - 1));
        let across = |p: &[f32]| {
            down(&|y, v| {
                let row = &p[y * w..(y + 1) * w];
                if lo < hi {
                    let three = row[lo - 1..hi - 1]
                        .iter()
                        .zip(&row[lo..hi])
                        .zip(&row[lo + 1..]);
                    for (o, ((a, b), c)) in v[lo - xs.start..].iter_mut().zip(three) {
                        *o = (a + b + c) / 3.0;
                    }
                }
                if xs.start == 0 {
                    v[0] = (row[0] + row[1]) / 2.0;
                }
                if xs.end == w {
                    v[n - 1] = (row[w - 2] + row[w - 1]) / 2.0;
                }
            })
        };
        let is = |c: Class| {
            down(&|y, v| {
                let row = &classes[y * w + xs.start..y * w + xs.end];
                for (o, &k) in v.iter_mut().zip(row) {
                    *o = (k == c) as u8 as f32;
                }
            })
        };
        let (wall, ground) = (is(Class::Wall), is(Class::Ground));
        let mut block = Block {
            top,
            n,
            sums: [vec![], vec![], vec![], vec![], vec![], wall, ground],
        };
        if !(0..n).any(|j| (reach.y0..reach.y1).any(|y| block.here(reach, j, y, h))) {
            return None;
        }
        let [r, g, b, side, texture, ..] = &mut block.sums;
        [*r, *g, *b] = [across(&f.rgb[0]), across(&f.rgb[1]), across(&f.rgb[2])];
        *side = down(&|y, v| {
            if y >= reach.up_from {
                let i = (y - reach.up_from) * w;
                v.copy_from_slice(&up[i + xs.start..i + xs.end]);
            } else {
                v.fill(0.0);
            }
        });
        *texture = down(&|y, v| v.copy_from_slice(&f.texture[y * w + xs.start..y * w + xs.end]));
        Some(block)
    }

    /// Column `j`'s mean of plane `k` over rows `a..b` (0 when empty).
    fn mean(&self, k: usize, j: usize, a: usize, b: usize) -> f32 {
        if b <= a {
            return 0.0;
        }
        let s = &self.sums[k];
        (s[(b - self.top) * self.n + j] - s[(a - self.top) * self.n + j]) / (b - a) as f32
    }

    /// Whether row `y` of column `j` has the wall classed above it
    /// ([`WALL_FROM`]..[`WALL_TO`]) and the ground below it
    /// ([`GROUND_BELOW`]).
    fn here(&self, r: Reach, j: usize, y: usize, h: usize) -> bool {
        let mean = |k: usize, a: usize, b: usize| self.mean(k, j, a, b);
        y >= r.wall_from
            && mean(WALL, y - r.wall_from, y - r.wall_to) >= WALL_SHARE
            && mean(GROUND, y, (y + r.ground).min(h)) >= GROUND_SHARE
    }

    /// The score of row `y` of column `j` of the `h`-tall analysis.
    fn score(&self, r: Reach, j: usize, y: usize, h: usize) -> f32 {
        if !self.here(r, j, y, h) {
            return NOT_HERE;
        }
        let mean = |k: usize, a: usize, b: usize| self.mean(k, j, a, b);
        let step: f32 = (RED..RED + 3)
            .map(|k| (mean(k, y - r.side, y) - mean(k, y, y + r.side)).abs())
            .sum();
        let (above, below) = (y.saturating_sub(r.boxed), (y + r.boxed).min(h));
        let up = mean(SIDE, above, y) - mean(SIDE, y, below);
        // The surfaces' texture, not the step's own (the texture is a box
        // mean, raised this far either side of the edge).
        let m = r.margin;
        let (ta, tb) = (above.saturating_sub(m).max(self.top), (below + m).min(h));
        let plain =
            mean(TEXTURE, ta, y - m.min(y - ta)).max(mean(TEXTURE, (y + m).min(tb), tb)) < PLAIN;
        if up >= STANDS_UP {
            step + SIDE_WEIGHT * up - BIAS
        } else if plain {
            step - PLAIN_BIAS
        } else {
            NOT_HERE
        }
    }
}

/// The score of each row `y0..y1` of each column, column major
/// (`(y1 - y0) * w`).
fn scores(f: &Features, classes: &[Class], reach: Reach) -> Vec<f32> {
    let Reach { y0, y1, .. } = reach;
    let up = sideways(f, reach.up_from);
    let rows = y1 - y0;
    let mut out = vec![0f32; rows * f.w];
    out.par_chunks_mut(rows * BLOCK)
        .enumerate()
        .for_each(|(b, cols)| {
            let x0 = b * BLOCK;
            let Some(block) = Block::of(f, classes, &up, reach, x0..x0 + cols.len() / rows) else {
                cols.fill(NOT_HERE);
                return;
            };
            for (j, col) in cols.chunks_mut(rows).enumerate() {
                for (i, o) in col.iter_mut().enumerate() {
                    *o = block.score(reach, j, y0 + i, f.h);
                }
            }
        });
    out
}

/// The best path through the `w` columns of `score` (`rows` per column,
/// column major): per column its row, or `None` in the "no foot" state.
/// Only the rows some column can have its foot on are searched: a path
/// through the others does no better than one kept to the nearest of
/// those (it scores [`NOT_HERE`] there too, and steps no less).
fn viterbi(score: &[f32], w: usize, rows: usize) -> Vec<Option<usize>> {
    let here = |i: usize| score[i] > NOT_HERE;
    let (Some(lo), Some(hi)) = (
        (0..w * rows).filter(|&i| here(i)).map(|i| i % rows).min(),
        (0..w * rows).filter(|&i| here(i)).map(|i| i % rows).max(),
    ) else {
        return vec![None; w];
    };
    let n = hi + 1 - lo;
    let col = |x: usize| &score[x * rows + lo..x * rows + lo + n];
    let (cost, switch, d) = (STEP_COST, SWITCH_COST, MAX_STEP);
    // Per column: the best total ending on each row, and in "no foot"
    // (index `n`); where each came from.
    let mut prev: Vec<f32> = col(0).to_vec();
    prev.push(0.0);
    let mut from = vec![0u32; w * (n + 1)];
    let mut cur = vec![0f32; n + 1];
    for x in 1..w {
        let (best_on, best_r) =
            prev[..n]
                .iter()
                .enumerate()
                .fold(
                    (f32::NEG_INFINITY, 0),
                    |b, (r, &v)| if v > b.0 { (v, r) } else { b },
                );
        let off = prev[n];
        let s = col(x);
        let links = &mut from[x * (n + 1)..(x + 1) * (n + 1)];
        for r in 0..n {
            let (mut best, mut arg) = (off - switch, n);
            let q0 = r.saturating_sub(d);
            for (q, &p) in prev[q0..(r + d + 1).min(n)].iter().enumerate() {
                let q = q0 + q;
                let v = p - cost * q.abs_diff(r) as f32;
                if v > best {
                    best = v;
                    arg = q;
                }
            }
            cur[r] = best + s[r];
            links[r] = arg as u32;
        }
        if best_on - switch > off {
            cur[n] = best_on - switch;
            links[n] = best_r as u32;
        } else {
            cur[n] = off;
            links[n] = n as u32;
        }
        std::mem::swap(&mut prev, &mut cur);
    }
    let mut state = (0..=n)
        .max_by(|&a, &b| prev[a].total_cmp(&prev[b]))
        .unwrap_or(n);
    let mut out = vec![None; w];
    for x in (0..w).rev() {
        out[x] = (state < n).then_some(state + lo);
        state = from[x * (n + 1) + state] as usize;
    }
    out
}
