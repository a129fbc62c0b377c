//! The wall's foot: the line where the wall meets the ground, seen in the
//! photo. `how-facades-age.md`, "Near the ground": soil thrown up from the
//! ground soils the bottom 0.3-0.5 m of a wall that stands on it, so the
//! effects need that line, and only where the wall is seen right above it.
//!
//! The class map's lowest wall row over ground (what the effects used
//! before, [`class_line`]) is often something else on a street photo: a
//! kerb, a shadow's edge, a car's sill, a walker's feet. The foot seen in
//! the photo is
//! - one path across the photo's lower part, not started from the class
//!   line (which sits on the ground fill's top where the fill climbed
//!   the wall, on a kerb where it stopped short): per column, the row
//!   where a colour step has the wall classed above it (allowing for a
//!   climbing fill), the ground below, and what stands up above what
//!   lies flat, or plain surfaces on both sides ([`path`]: dynamic
//!   programming over the columns, a penalty per row it steps, a "no
//!   foot" state);
//! - long and straight (a plane's edge under perspective is a straight
//!   line): columns are grouped into runs whose rows step little, each run
//!   is fitted with a line, columns off it are dropped (a walker's feet, a
//!   bollard, a wheel: in front of the wall, so lower) and the fit
//!   repeated; a run shorter than [`MIN_RUN`] of the width, or not
//!   straight, has no foot;
//! - behind what stands in front: a run between two that continue each
//!   other, and off their line, is a car's roof or sill ([`in_front`]);
//! - sure where the class map's wall stands on ground that runs on down
//!   the photo ([`sure`]): a confidence per stretch.
//!
//! Measured against LabelMeFacade's labels ([`super::eval`], columns
//! within 1.5% of the height of the labelled foot): train precision /
//! recall 0.117 / 0.282 for the class line, 0.390 / 0.125 for this
//! (0.368 / 0.107 snapping the class line to the nearest colour step);
//! held-out 0.104 / 0.254 and 0.296 / 0.107 (0.191 / 0.044).

use super::features::Features;
use super::wall::Class;

mod path;
mod sure;

/// A stretch of the seen foot this sure or more ([`sure`]) is the sure
/// foot's: the splash soiling keeps to it (`effects/foot.rs`) and the
/// evaluation's "sure seen foot" counts it (half way up the confidence;
/// LabelMeFacade train, the soiling's columns right 0.403 -> 0.510,
/// BENCHMARKS foot28).
pub const SURE: f32 = 0.5;

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
/// straight stretch (see the module's documentation), each with how sure
/// it is, 0..1 ([`sure`]).
pub fn find(f: &Features, classes: &[Class]) -> Vec<(Vec<[f32; 2]>, f32)> {
    let lines = runs(&path::rows(f, classes), f.w, f.h);
    let class = class_line(classes, f.w, f.h);
    lines
        .into_iter()
        .map(|l| {
            let s = sure::sure(classes, &class, (f.w, f.h), &l);
            (l, s)
        })
        .collect()
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
