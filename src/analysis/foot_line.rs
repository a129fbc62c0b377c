//! The wall's foot: the line where the wall meets the ground, seen in the
//! photo. `how-facades-age.md`, "Near the ground": soil thrown up from the
//! ground soils the bottom 0.3-0.5 m of a wall that stands on it, so the
//! effects need that line, and only where the wall is seen right above it.
//!
//! The class map's lowest wall row over ground (what the effects used
//! before, [`class_line`]) is often something else on a street photo: a
//! kerb, a shadow's edge, a car's sill, a walker's feet. The foot seen in
//! the photo is
//! - a step of colour (wall above, ground below) near the class map's
//!   lowest wall row: each column's row is moved to the strongest step
//!   within [`SNAP`] of it, and a column with no clear step has no foot;
//! - under wall: the column is wall for [`WALL_ABOVE`] of the height right
//!   above it (not a car's or a walker's lower edge, whose top is near);
//! - over flat ground: the gradients above it point more sideways than
//!   below it ([`stands_over_flat`]);
//! - long and straight (a plane's edge under perspective is a straight
//!   line): columns are grouped into runs whose rows step little, each run
//!   is fitted with a line, columns off it are dropped (a walker's feet, a
//!   bollard, a wheel: in front of the wall, so lower) and the fit
//!   repeated; a run shorter than [`MIN_RUN`] of the width, or not
//!   straight, has no foot;
//! - behind what stands in front: a run between two that continue each
//!   other, and off their line, is a car's roof or sill ([`in_front`]).
//!
//! Measured against LabelMeFacade's labels ([`super::eval`], columns
//! within 1.5% of the height of the labelled foot): train precision /
//! recall 0.117 / 0.282 for the class line, 0.368 / 0.107 for this;
//! held-out 0.104 / 0.254 and 0.191 / 0.044.

use super::features::Features;
use super::wall::Class;

/// How far from the class map's lowest wall row the foot's colour step is
/// looked for, share of the height.
const SNAP: f32 = 0.015;

/// Rows averaged on each side of a candidate step, share of the height.
const STEP_SIDE: f32 = 0.006;

/// A step of colour weaker than this (L1 of the mean colours above and
/// below, 0..3) is no foot [choice: the step's strength tells the foot
/// little on LabelMeFacade train (median 0.49 at the true foot, 0.56
/// elsewhere); this only drops flat colour].
const MIN_STEP: f32 = 0.02;

/// Share of the height right above the foot that must be wall ...
const WALL_ABOVE: f32 = 0.05;

/// ... in at least this share of its rows [choice, LabelMeFacade train:
/// 0.6, 0.8, 0.95 gave foot precision 0.38, 0.42, 0.32].
const WALL_SHARE: f32 = 0.8;

/// The boxes above and below a candidate foot whose gradients are
/// compared ([`stands_over_flat`]) are this share of the height tall ...
const SIDE_BOX: f32 = 0.03;

/// ... and this many pixels either side of the column wide.
const SIDE_HALF_WIDTH: usize = 4;

/// What stands above the foot has a sideways share of the gradients'
/// energy at least this much more than the ground below it [choice,
/// LabelMeFacade train (prototype on main's class dumps), foot precision /
/// recall with runs of 5%: no test 0.26 / 0.13, 0 0.32 / 0.11, 0.05 0.36 /
/// 0.10].
const STANDS_UP: f32 = 0.05;

/// Consecutive columns of one run step by at most this, share of the
/// height.
const RUN_STEP: f32 = 0.006;

/// Gaps narrower than this, share of the width, do not end a run.
const RUN_GAP: f32 = 0.01;

/// A foot shorter than this, share of the width, is not kept [choice,
/// LabelMeFacade train, precision / recall: 0.03 0.30 / 0.15, 0.05 0.36
/// / 0.10, 0.08 0.41 / 0.06].
const MIN_RUN: f32 = 0.05;

/// Columns further than this from a run's fitted line, share of the
/// height, are dropped (and the line fitted again).
const OFF_LINE: f32 = 0.006;

/// A run keeps its foot only if at least this share of its columns lie on
/// its line.
const ON_LINE: f32 = 0.7;

/// Two runs of the foot either side of a third continue each other when
/// each one's line meets the other's near end within this share of the
/// height; the run between is in front of the foot when it lies further
/// than this off the line between them ([`in_front`]).
const BRIDGE: f32 = 0.015;

/// Per column of the `w` x `h` class map, the lowest wall row with ground
/// right below it, as the boundary row between them (`y` of the first
/// ground row), or `NaN` where the column ends in anything else (what the
/// effects used before the seen foot).
pub fn class_line(classes: &[Class], w: usize, h: usize) -> Vec<f32> {
    (0..w)
        .map(|x| {
            let class = |y: usize| classes[y * w + x];
            let mut y = h;
            while y > 0 && class(y - 1) == Class::Ground {
                y -= 1;
            }
            if y < h && y > 0 && class(y - 1) == Class::Wall {
                y as f32
            } else {
                f32::NAN
            }
        })
        .collect()
}

/// The wall's foot as polylines in analysis pixels, left to right, one per
/// straight stretch (see the module's documentation).
pub fn find(f: &Features, classes: &[Class]) -> Vec<Vec<[f32; 2]>> {
    let (w, h) = (f.w, f.h);
    let start = class_line(classes, w, h);
    let rows: Vec<f32> = (0..w)
        .map(|x| {
            let y = start[x];
            if y.is_nan() {
                return f32::NAN;
            }
            snap(f, x, y as usize)
                .filter(|&y| wall_above(classes, w, h, x, y) && stands_over_flat(f, x, y))
                .map_or(f32::NAN, |y| y as f32)
        })
        .collect();
    runs(&rows, w, h)
}

/// The row of the strongest colour step within [`SNAP`] of row `y` in
/// column `x` (the first row below it), if it is strong enough.
fn snap(f: &Features, x: usize, y: usize) -> Option<usize> {
    let (w, h) = (f.w, f.h);
    let reach = ((SNAP * h as f32).round() as usize).max(1);
    let side = ((STEP_SIDE * h as f32).round() as usize).max(1);
    let mean = |y0: usize, y1: usize| {
        let mut s = [0f32; 3];
        let (x0, x1) = (x.saturating_sub(1), (x + 2).min(w));
        for yy in y0..y1 {
            for xx in x0..x1 {
                let i = yy * w + xx;
                for (k, v) in s.iter_mut().enumerate() {
                    *v += f.rgb[k][i];
                }
            }
        }
        let n = ((y1 - y0) * (x1 - x0)).max(1) as f32;
        s.map(|v| v / n)
    };
    let lo = y.saturating_sub(reach).max(side);
    let hi = (y + reach).min(h.saturating_sub(side));
    let mut best: Option<(f32, usize)> = None;
    for r in lo..=hi {
        let step = super::features::l1(mean(r - side, r), mean(r, r + side));
        if best.is_none_or(|(s, _)| step > s) {
            best = Some((step, r));
        }
    }
    best.filter(|&(s, _)| s >= MIN_STEP).map(|(_, r)| r)
}

/// Whether column `x` is wall right above row `y` ([`WALL_ABOVE`]).
fn wall_above(classes: &[Class], w: usize, h: usize, x: usize, y: usize) -> bool {
    let n = ((WALL_ABOVE * h as f32).round() as usize).max(2);
    if y < n {
        return false;
    }
    let walls = (y - n..y)
        .filter(|&r| classes[r * w + x] == Class::Wall)
        .count();
    walls as f32 >= WALL_SHARE * n as f32
}

/// Whether what lies above row `y` in column `x` stands up and what lies
/// below lies flat: the share of the luma gradients' energy that points
/// sideways (structure tensor, `Jxx / (Jxx + Jyy)`, as
/// [`super::plane`]) over [`SIDE_BOX`] of the height above is at least
/// [`STANDS_UP`] more than below. Seen from eye level the ground is
/// foreshortened (its joints and kerbs run across the view), a wall has
/// jambs, corners and pipes; a kerb, a car's sill or a shadow on the road
/// has flat ground on both sides.
fn stands_over_flat(f: &Features, x: usize, y: usize) -> bool {
    let (w, h) = (f.w, f.h);
    let n = ((SIDE_BOX * h as f32).round() as usize).max(2);
    // Each row's share over the box's width, averaged over its rows.
    let sideways = |y0: usize, y1: usize| {
        let (mut sum, mut rows) = (0f32, 0usize);
        for r in y0.max(1)..y1.min(h - 1) {
            let (mut jxx, mut jyy) = (0f32, 0f32);
            for c in x.saturating_sub(SIDE_HALF_WIDTH).max(1)..(x + SIDE_HALF_WIDTH + 1).min(w - 1)
            {
                let at = |dx: isize, dy: isize| {
                    f.luma[(r as isize + dy) as usize * w + (c as isize + dx) as usize]
                };
                // Sobel.
                let gx = at(1, -1) + 2.0 * at(1, 0) + at(1, 1)
                    - at(-1, -1)
                    - 2.0 * at(-1, 0)
                    - at(-1, 1);
                let gy = at(-1, 1) + 2.0 * at(0, 1) + at(1, 1)
                    - at(-1, -1)
                    - 2.0 * at(0, -1)
                    - at(1, -1);
                jxx += gx * gx;
                jyy += gy * gy;
            }
            sum += jxx / (jxx + jyy + 1e-6);
            rows += 1;
        }
        sum / rows.max(1) as f32
    };
    sideways(y.saturating_sub(n), y) - sideways(y, y + n) >= STANDS_UP
}

/// Groups the per-column rows into long straight runs, each fitted with a
/// line; drops the runs in front of the foot ([`in_front`]); returns each
/// run's line over the columns on it.
fn runs(rows: &[f32], w: usize, h: usize) -> Vec<Vec<[f32; 2]>> {
    let step = RUN_STEP * h as f32;
    let gap = ((RUN_GAP * w as f32).round() as usize).max(1);
    let min_run = (MIN_RUN * w as f32).round() as usize;
    let mut found = Vec::new();
    let mut x = 0;
    while x < w {
        if rows[x].is_nan() {
            x += 1;
            continue;
        }
        // Extend the run while the next column found is near the last.
        let mut cols = vec![x];
        let mut last = x;
        let mut nx = x + 1;
        while nx < w && nx - last <= gap {
            if !rows[nx].is_nan() && (rows[nx] - rows[last]).abs() <= step {
                cols.push(nx);
                last = nx;
            }
            nx += 1;
        }
        x = last + 1;
        found.extend(straight(&cols, rows, h, min_run));
    }
    let tol = BRIDGE * h as f32;
    (0..found.len())
        .filter(|&i| !in_front(&found, i, tol))
        .flat_map(|i| found[i].pieces(gap))
        .collect()
}

/// A straight run of the foot: its line `y = a + b x` and the columns on
/// it, left to right (at least two).
struct Run {
    line: (f32, f32),
    kept: Vec<usize>,
}

impl Run {
    /// The line's row at column `x`.
    fn at(&self, x: usize) -> f32 {
        self.line.0 + self.line.1 * x as f32
    }

    /// A polyline per stretch of columns on the line (the columns between
    /// are what stands in front of the foot and hides it): from the left
    /// edge of a stretch's first column to the right edge of its last.
    fn pieces(&self, gap: usize) -> Vec<Vec<[f32; 2]>> {
        let y = |x: f32| self.line.0 + self.line.1 * (x - 0.5);
        let piece =
            |a: usize, b: usize| vec![[a as f32, y(a as f32)], [b as f32 + 1.0, y(b as f32 + 1.0)]];
        let mut out = Vec::new();
        let mut from = self.kept[0];
        for pair in self.kept.windows(2) {
            if pair[1] - pair[0] > gap {
                out.push(piece(from, pair[0]));
                from = pair[1];
            }
        }
        out.push(piece(from, self.kept[self.kept.len() - 1]));
        out
    }
}

/// Whether run `i` stands in front of the wall's foot: the runs on either
/// side of it continue each other (each one's line meets the other's near
/// end within `tol` rows) and it lies more than `tol` off the line between
/// them. A car's roof or sill, a planter's rim between two stretches of
/// the foot: the foot runs on behind them.
fn in_front(runs: &[Run], i: usize, tol: f32) -> bool {
    if i == 0 || i + 1 >= runs.len() {
        return false;
    }
    let (l, m, r) = (&runs[i - 1], &runs[i], &runs[i + 1]);
    let (xl, xr) = (l.kept[l.kept.len() - 1], r.kept[0]);
    let (yl, yr) = (l.at(xl), r.at(xr));
    let agree = (l.at(xr) - yr).abs() <= tol && (r.at(xl) - yl).abs() <= tol;
    let xm = m.kept[m.kept.len() / 2];
    let bridge = yl + (yr - yl) * (xm as f32 - xl as f32) / (xr as f32 - xl as f32).max(1.0);
    agree && (m.at(xm) - bridge).abs() > tol
}

/// The line through a run's columns (least squares, thrice, dropping the
/// columns off it); `None` when the run is short or not straight.
fn straight(cols: &[usize], rows: &[f32], h: usize, min_run: usize) -> Option<Run> {
    let tol = OFF_LINE * h as f32;
    let mut kept: Vec<usize> = cols.to_vec();
    let mut line = (0.0, 0.0);
    for _ in 0..3 {
        if kept.len() < 2 {
            return None;
        }
        line = fit(&kept, rows);
        kept = cols
            .iter()
            .copied()
            .filter(|&x| (rows[x] - (line.0 + line.1 * x as f32)).abs() <= tol)
            .collect();
    }
    let (first, last) = (*kept.first()?, *kept.last()?);
    (last - first >= min_run && kept.len() >= 2 && kept.len() as f32 >= ON_LINE * cols.len() as f32)
        .then_some(Run { line, kept })
}

/// Least-squares line `y = a + b x` through the columns' rows.
fn fit(cols: &[usize], rows: &[f32]) -> (f32, f32) {
    let n = cols.len() as f64;
    let (mut sx, mut sy, mut sxx, mut sxy) = (0f64, 0f64, 0f64, 0f64);
    for &x in cols {
        let (xf, yf) = (x as f64, rows[x] as f64);
        sx += xf;
        sy += yf;
        sxx += xf * xf;
        sxy += xf * yf;
    }
    let d = n * sxx - sx * sx;
    let b = if d.abs() < 1e-9 {
        0.0
    } else {
        (n * sxy - sx * sy) / d
    };
    (((sy - b * sx) / n) as f32, b as f32)
}
