//! The wall's foot as one path across the photo, found without starting
//! from the class map's lowest wall row (which sits on top of the ground
//! fill where the fill climbed the wall, or on a kerb where it stopped
//! short of it): per column, every row of the lower part of the photo is
//! scored by how much it looks like a wall standing on the ground (a
//! colour step, what is above standing up and what is below lying flat,
//! the wall seen above it), and one path through the columns is chosen
//! by dynamic programming (Viterbi: the best sum of scores less a penalty
//! per row the path steps from one column to the next, with a state "no
//! foot here" entered and left at a cost), as a seam is carved (S. Avidan,
//! A. Shamir, "Seam carving for content-aware image resizing", SIGGRAPH
//! 2007).

use rayon::prelude::*;

use super::super::features::Features;
use super::super::wall::Class;

/// The path is looked for below this share of the height (the ground
/// fill never reaches above 45%: `ground.rs`).
const BAND_TOP: f32 = 0.3;

/// Rows averaged on each side of a candidate step, share of the height
/// (as [`super::STEP_SIDE`]).
const STEP_SIDE: f32 = 0.006;

/// The boxes above and below a row whose gradients are compared are this
/// share of the height tall (as [`super::SIDE_BOX`]) ...
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

/// Per column of the `w` x `h` analysis, the row of the wall's foot on
/// the best path (the first row below the wall), `NaN` where the path is
/// in its "no foot" state.
pub(super) fn rows(f: &Features, classes: &[Class]) -> Vec<f32> {
    let (w, h) = (f.w, f.h);
    let y0 = (BAND_TOP * h as f32) as usize;
    let side = ((STEP_SIDE * h as f32).round() as usize).max(1);
    let y1 = h.saturating_sub(side + 1);
    if y1 <= y0 + 1 || w < 3 {
        return vec![f32::NAN; w];
    }
    let score = scores(f, classes, y0, y1);
    viterbi(&score, w, y1 - y0)
        .into_iter()
        .map(|r| r.map_or(f32::NAN, |r| (r + y0) as f32))
        .collect()
}

/// Prefix sums down each column of `v` (`w` x `h`): `(h + 1) * w`.
fn column_sums(v: &[f32], w: usize, h: usize) -> Vec<f32> {
    let mut s = vec![0f32; (h + 1) * w];
    for y in 0..h {
        for x in 0..w {
            s[(y + 1) * w + x] = s[y * w + x] + v[y * w + x];
        }
    }
    s
}

/// Mean of column `x` of the summed plane `s` over rows `a..b`.
fn mean(s: &[f32], w: usize, x: usize, a: usize, b: usize) -> f32 {
    if b <= a {
        return 0.0;
    }
    (s[b * w + x] - s[a * w + x]) / (b - a) as f32
}

/// `v` averaged over `r` columns either side (a running sum per row).
fn across(v: &[f32], w: usize, h: usize, r: usize) -> Vec<f32> {
    let mut out = vec![0f32; w * h];
    out.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
        let src = &v[y * w..(y + 1) * w];
        let mut sum: f32 = src[..r.min(w)].iter().sum();
        for (x, o) in row.iter_mut().enumerate() {
            if x + r < w {
                sum += src[x + r];
            }
            if x > r {
                sum -= src[x - r - 1];
            }
            let (a, b) = (x.saturating_sub(r), (x + r + 1).min(w));
            *o = sum / (b - a) as f32;
        }
    });
    out
}

/// Per pixel, the share of the luma gradients' energy that points
/// sideways over the row's [`SIDE_HALF_WIDTH`] neighbours either side
/// (Sobel, `Jxx / (Jxx + Jyy)`, as `stands_over_flat`).
fn sideways(f: &Features) -> Vec<f32> {
    let (w, h) = (f.w, f.h);
    let mut jxx = vec![0f32; w * h];
    let mut jyy = vec![0f32; w * h];
    jxx.par_chunks_mut(w)
        .zip(jyy.par_chunks_mut(w))
        .enumerate()
        .for_each(|(y, (ox, oy))| {
            if y == 0 || y + 1 >= h {
                return;
            }
            let l = &f.luma;
            for x in 1..w - 1 {
                let at = |dx: isize, dy: isize| {
                    l[(y as isize + dy) as usize * w + (x as isize + dx) as usize]
                };
                let gx = at(1, -1) + 2.0 * at(1, 0) + at(1, 1)
                    - at(-1, -1)
                    - 2.0 * at(-1, 0)
                    - at(-1, 1);
                let gy = at(-1, 1) + 2.0 * at(0, 1) + at(1, 1)
                    - at(-1, -1)
                    - 2.0 * at(0, -1)
                    - at(1, -1);
                ox[x] = gx * gx;
                oy[x] = gy * gy;
            }
        });
    let (sx, sy) = (
        across(&jxx, w, h, SIDE_HALF_WIDTH),
        across(&jyy, w, h, SIDE_HALF_WIDTH),
    );
    sx.iter()
        .zip(&sy)
        .map(|(a, b)| a / (a + b + 1e-6))
        .collect()
}

/// The score of each row `y0..y1` of each column, `(y1 - y0) * w`, row
/// major.
fn scores(f: &Features, classes: &[Class], y0: usize, y1: usize) -> Vec<f32> {
    let (w, h) = (f.w, f.h);
    let side = ((STEP_SIDE * h as f32).round() as usize).max(1);
    let n = ((SIDE_BOX * h as f32).round() as usize).max(2);
    let rgb: Vec<Vec<f32>> = f
        .rgb
        .iter()
        .map(|p| column_sums(&across(p, w, h, 1), w, h))
        .collect();
    let side_sum = column_sums(&sideways(f), w, h);
    let is = |c: Class| -> Vec<f32> {
        classes
            .iter()
            .map(|&k| if k == c { 1.0 } else { 0.0 })
            .collect()
    };
    let wall = column_sums(&is(Class::Wall), w, h);
    let ground = column_sums(&is(Class::Ground), w, h);
    let (wf, wt) = (
        (WALL_FROM * h as f32) as usize,
        ((WALL_TO * h as f32) as usize).max(1),
    );
    let gb = ((GROUND_BELOW * h as f32) as usize).max(2);
    let mut out = vec![0f32; (y1 - y0) * w];
    out.par_chunks_mut(w).enumerate().for_each(|(i, row)| {
        let y = y0 + i;
        for (x, o) in row.iter_mut().enumerate() {
            let wall_ok = y >= wf && mean(&wall, w, x, y - wf, y - wt) >= WALL_SHARE;
            let ground_ok = mean(&ground, w, x, y, (y + gb).min(h)) >= GROUND_SHARE;
            if !(wall_ok && ground_ok) {
                *o = NOT_HERE;
                continue;
            }
            let step: f32 = rgb
                .iter()
                .map(|s| (mean(s, w, x, y - side, y) - mean(s, w, x, y, y + side)).abs())
                .sum();
            let up = mean(&side_sum, w, x, y.saturating_sub(n), y)
                - mean(&side_sum, w, x, y, (y + n).min(h));
            *o = if up < STANDS_UP {
                NOT_HERE
            } else {
                step + SIDE_WEIGHT * up - BIAS
            };
        }
    });
    out
}

/// The best path through the `w` columns of `score` (`rows` x `w`, row
/// major): per column its row, or `None` in the "no foot" state.
fn viterbi(score: &[f32], w: usize, rows: usize) -> Vec<Option<usize>> {
    let (cost, switch, d) = (STEP_COST, SWITCH_COST, MAX_STEP);
    // Per column: the best total ending on each row, and in "no foot"
    // (index `rows`); where each came from.
    let mut prev: Vec<f32> = (0..rows).map(|r| score[r * w]).collect();
    prev.push(0.0);
    let mut from = vec![0u32; w * (rows + 1)];
    let mut cur = vec![0f32; rows + 1];
    for x in 1..w {
        let (best_on, best_r) =
            prev[..rows]
                .iter()
                .enumerate()
                .fold(
                    (f32::NEG_INFINITY, 0),
                    |b, (r, &v)| {
                        if v > b.0 { (v, r) } else { b }
                    },
                );
        let off = prev[rows];
        for r in 0..rows {
            let (mut best, mut arg) = (off - switch, rows);
            let lo = r.saturating_sub(d);
            for (q, &p) in prev[lo..(r + d + 1).min(rows)].iter().enumerate() {
                let q = lo + q;
                let v = p - cost * q.abs_diff(r) as f32;
                if v > best {
                    best = v;
                    arg = q;
                }
            }
            cur[r] = best + score[r * w + x];
            from[x * (rows + 1) + r] = arg as u32;
        }
        if best_on - switch > off {
            cur[rows] = best_on - switch;
            from[x * (rows + 1) + rows] = best_r as u32;
        } else {
            cur[rows] = off;
            from[x * (rows + 1) + rows] = rows as u32;
        }
        std::mem::swap(&mut prev, &mut cur);
    }
    let mut state = (0..=rows)
        .max_by(|&a, &b| prev[a].total_cmp(&prev[b]))
        .unwrap_or(rows);
    let mut out = vec![None; w];
    for x in (0..w).rev() {
        out[x] = (state < rows).then_some(state);
        state = from[x * (rows + 1) + state] as usize;
    }
    out
}
