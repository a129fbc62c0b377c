//! Windows from their frames: the ledge detector finds a window's head, its
//! meeting rail or transom and its sill as short level lines of like span
//! stacked over each other ([`super::super::ledges`]); between two such
//! lines, where a jamb stands at both ends (an upright luma step, as
//! `ledge_kinds::crosses_a_frame` measures it), lies a cell of the window:
//! the glass between the frame's members. It is glass where it differs from
//! the wall beside it at the same rows (in luma or in colour: a pane
//! reflects the sky or the street, a curtain or a blind is not brick),
//! whether darker or lighter than the wall (the dark rule in `glass.rs`
//! finds only the darker half). The frame, the sill and the head stay
//! wall: the cell is inset from the lines and from the jambs, and over a
//! sill it ends at the sill's top. A head or a sill with no line stacked
//! on it bounds a cell as tall as the windows found between two lines, kept
//! when one of those lies in its row or column (windows repeat).
//! Called after the ledges (which it needs), so the ledges, the shelter
//! and the scale are as before; the cells leave the wall's matte.
//! Measured against the labelled windows by `scene_eval` (see
//! BENCHMARKS.md, twenty-second pass, helper glass24): LabelMeFacade train
//! glass recall / precision 0.050 / 0.236 -> 0.090 / 0.337, CMP 0.124 /
//! 0.568 -> 0.213 / 0.634.

use std::ops::Range;

use super::super::features::{Features, luma};
use super::super::wall::Class;
use super::super::{Ledge, LedgeKind};
use super::Bbox;

/// A line longer than this share of the width is a string course or a
/// cornice over many windows, not one window's member.
const MAX_SPAN: f32 = 0.2;

/// A line shorter than this many analysis pixels is too short to bound a
/// window.
const MIN_SPAN: f32 = 6.0;

/// Two stacked lines bound one cell when they share this share of the
/// shorter line's span.
const STACK: f32 = 0.6;

/// A cell is at most this many times as tall as it is wide (a window's
/// two sashes, a tall French window's pane).
const MAX_TALL: f32 = 2.5;

/// ... and at least this share of its width tall (a transom light).
const MIN_TALL: f32 = 0.2;

/// A jamb: the mean horizontal luma step (over two columns) down a column
/// at the cell's end over this (`ledge_kinds::FRAME_STEP` is 0.07 for a
/// frame through a ledge's ends) ... Measured on the cells between stacked
/// lines of LabelMeFacade train, their pixels on labelled windows against
/// those on labelled building: over 0.05 and [`JAMB_OVER_WALL`] 0.74 on
/// windows, over 0.1 0.79 (0.15: LabelMeFacade train recall 0.084 ->
/// 0.078, wall IoU 0.7584 -> 0.7585).
const JAMB: f32 = 0.1;

/// ... and over this many times the wall's texture beside the cell (brick
/// and stone make steps everywhere; a frame stands out of them). On the
/// cells as for [`JAMB`] (with [`SIDES_ALIKE`] and the colour test), share
/// on windows: none 0.52, 1.0 0.61, 1.5 0.74, 2.0 0.76 (LabelMeFacade
/// train recall 0.083 at 1.5, 0.071 at 2).
const JAMB_OVER_WALL: f32 = 1.5;

/// The wall left and right of a cell is one wall: their lumas differ by
/// less than this share (a pier between a window and a lighter wall, or a
/// railing between two openings, has unlike sides). Share on windows
/// without it 0.38, with it 0.52 (0.1: 0.74 against 0.74 at 0.15 with
/// [`JAMB_OVER_WALL`], recall 0.079 against 0.083).
const SIDES_ALIKE: f32 = 0.15;

/// Columns either side of a line's end where its jamb is looked for ...
const JAMB_REACH: isize = 3;

/// ... and inward, up to this share of the span (a head or a sill reaching
/// past the frame; LabelMeFacade train recall 0.106 -> 0.109 against the
/// outward reach alone, 0.3: 0.103, precision 0.326 -> 0.303).
const JAMB_INWARD: f32 = 0.2;

/// The frame's members are this share of the cell's width (at least one
/// analysis pixel): the cell is inset by it on every side.
const FRAME: f32 = 0.08;

/// The wall beside a cell is looked at over this share of its width on
/// each side, past the frame.
const BESIDE: f32 = 0.4;

/// A cell whose mean luma is outside these shares of the wall beside it
/// is glass.
const LUMA_APART: (f32, f32) = (0.85, 1.18);

/// ... or whose mean colour is farther than this (L1 over r, g, b, 0..1,
/// after removing the luma difference) from the wall beside it.
const COLOUR_APART: f32 = 0.08;

/// At least this many windows found between two lines give the height of
/// a window under a head or over a sill alone (their median height over
/// width) ...
const LIKE_FOUND: usize = 2;

/// ... else it is this many times its width (sash windows are about 1.5
/// to 2 times as tall as wide).
const LONE_TALL: f32 = 1.6;

/// The sill's top is looked for in this lowest share of a cell.
const SILL_REACH: f32 = 0.3;

/// A window under a head or over a sill alone is kept when a window found
/// between two lines lies in its row or column, sharing this share of the
/// longer span across ... (LabelMeFacade train recall / precision / wall
/// IoU: no lone cells 0.084 / 0.330 / 0.7584; all lone cells 0.109 / 0.326
/// / 0.7558; those in a row or column of a found one 0.090 / 0.337 /
/// 0.7581).
const ALIGN: f32 = 0.5;

/// ... and its width (in a row) or height (in a column) is within this
/// factor of it.
const LIKE: f32 = 1.5;

/// A level line: its ends, in analysis pixels.
#[derive(Debug, Clone, Copy)]
struct Line {
    kind: LedgeKind,
    x0: f32,
    y0: f32,
    x1: f32,
    y1: f32,
}

impl Line {
    fn y_at(&self, x: f32) -> f32 {
        if self.x1 <= self.x0 {
            return self.y0;
        }
        self.y0 + (self.y1 - self.y0) * (x - self.x0) / (self.x1 - self.x0)
    }

    fn span(&self) -> f32 {
        self.x1 - self.x0
    }

    fn mid(&self) -> f32 {
        (self.y0 + self.y1) / 2.0
    }
}

/// A cell of a window: columns `x0..x1`, rows `y0..y1` (exclusive ends).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Cell {
    x0: usize,
    x1: usize,
    y0: usize,
    y1: usize,
    jamb: f32,
}

/// The wall pixels of the window cells found between stacked ledges
/// (`ledges` in analysis pixels), to be called glass; then under a window
/// head or over a sill alone, a cell as tall as the windows found
/// (relative to its width); then the windows of the grid the trusted
/// ones make (`grid`).
pub(crate) fn find(f: &Features, class: &[Class], ledges: &[Ledge]) -> Vec<usize> {
    let lines = lines(ledges, f.w);
    let (pairs, used): (Vec<Cell>, Vec<[usize; 2]>) = cells(&lines, f).into_iter().unzip();
    let found: Vec<(Cell, [usize; 2])> = pairs
        .iter()
        .zip(used)
        .filter_map(|(c, u)| Some((glass_cell(f, class, c)?, u)))
        .collect();
    let mut tall: Vec<f32> = found
        .iter()
        .map(|(c, _)| (c.y1 - c.y0) as f32 / (c.x1 - c.x0) as f32)
        .collect();
    tall.sort_by(f32::total_cmp);
    let tall = if tall.len() >= LIKE_FOUND {
        tall[tall.len() / 2]
    } else {
        LONE_TALL
    };
    let mut cells: Vec<Cell> = found.iter().map(|(c, _)| *c).collect();
    for (k, l) in lines.iter().enumerate() {
        if found.iter().any(|(_, u)| u.contains(&k)) {
            continue;
        }
        let lone = lone_cells(f, l, tall)
            .into_iter()
            .filter_map(|c| glass_cell(f, class, &c))
            .find(|c| !cells.iter().any(|o| o.meets(c)) && found.iter().any(|(o, _)| o.aligned(c)));
        cells.extend(lone);
    }
    let boxes: Vec<Bbox> = cells
        .iter()
        .map(|c| (c.x0, c.y0, c.x1 - 1, c.y1 - 1))
        .collect();
    let trusted = super::grid::trusted(f, class, &boxes);
    let mut out = super::grid::find(f, class, ledges, &trusted);
    for c in &cells {
        for y in c.y0..c.y1 {
            out.extend(
                (c.x0..c.x1)
                    .map(|x| y * f.w + x)
                    .filter(|&i| class[i] == Class::Wall),
            );
        }
    }
    out.sort_unstable();
    out.dedup();
    out
}

/// The cells a line alone may bound, `tall` times as tall as wide: over
/// it (a sill), and under it when it may be a head (not a sill).
fn lone_cells(f: &Features, l: &Line, tall: f32) -> Vec<Cell> {
    let (x0, x1) = (l.x0, l.x1);
    let xm = (x0 + x1) / 2.0;
    let (y, ht) = (l.y_at(xm), tall * l.span());
    let mut out = Vec::new();
    if l.kind != LedgeKind::WindowHead {
        out.extend(cell(f, x0, x1, y - ht, y, true));
    }
    if l.kind != LedgeKind::Sill {
        out.extend(cell(f, x0, x1, y, y + ht, false));
    }
    out
}
/// The ledges that may be a window's member: not roof lines, of a
/// window's span.
fn lines(ledges: &[Ledge], w: usize) -> Vec<Line> {
    ledges
        .iter()
        .filter(|l| l.kind != LedgeKind::RoofLine && l.polyline.len() >= 2)
        .map(|l| {
            let ([x0, y0], [x1, y1]) = (l.polyline[0], l.polyline[l.polyline.len() - 1]);
            Line {
                kind: l.kind,
                x0,
                y0,
                x1,
                y1,
            }
        })
        .filter(|l| l.span() >= MIN_SPAN && l.span() <= MAX_SPAN * w as f32)
        .collect()
}

/// Each line with the nearest line under it that shares [`STACK`] of the
/// shorter span, the columns they share, and a jamb at both ends; with
/// the two lines' indices.
fn cells(lines: &[Line], f: &Features) -> Vec<(Cell, [usize; 2])> {
    let mut out = Vec::new();
    for (ka, a) in lines.iter().enumerate() {
        let below = lines
            .iter()
            .enumerate()
            .filter(|(_, b)| b.mid() > a.mid() + 2.0)
            .filter(|(_, b)| {
                let common = a.x1.min(b.x1) - a.x0.max(b.x0);
                common >= STACK * a.span().min(b.span())
            })
            .min_by(|p, q| p.1.mid().total_cmp(&q.1.mid()));
        let Some((kb, b)) = below else { continue };
        let (x0, x1) = (a.x0.max(b.x0), a.x1.min(b.x1));
        let xm = (x0 + x1) / 2.0;
        let (top, bottom) = (a.y_at(xm), b.y_at(xm));
        let (wd, ht) = (x1 - x0, bottom - top);
        if ht < MIN_TALL * wd || ht > MAX_TALL * wd {
            continue;
        }
        out.extend(cell(f, x0, x1, top, bottom, true).map(|c| (c, [ka, kb])));
    }
    out
}

/// The cell between the rows `top` and `bottom` whose jambs stand near
/// `x0` and `x1`; when `sill`, its bottom is moved up to the sill's top.
fn cell(f: &Features, x0: f32, x1: f32, top: f32, bottom: f32, sill: bool) -> Option<Cell> {
    let (top, bottom) = (top.max(0.0), bottom.min(f.h as f32));
    let (jl, jr, jamb) = jambs(f, x0, x1, top, bottom)?;
    let y0 = top.round() as usize;
    let mut y1 = (bottom.round().max(0.0) as usize).min(f.h);
    if sill {
        y1 = sill_top(f, jl, jr, y0, y1);
    }
    (y1 > y0 + 2).then_some(Cell {
        x0: jl,
        x1: jr,
        y0,
        y1,
        jamb,
    })
}

/// The sill's top over a sill's line at row `y1` (columns `x0..x1`, the
/// cell from row `y0`): the strongest step between the mean lumas of two
/// rows in the cell's lowest [`SILL_REACH`] (the lit sill under the
/// window's frame or glass); the sill stays wall.
pub(super) fn sill_top(f: &Features, x0: usize, x1: usize, y0: usize, y1: usize) -> usize {
    let reach = ((SILL_REACH * (y1 - y0) as f32) as usize).max(3);
    let lo = y1.saturating_sub(reach).max(y0 + 1);
    let row = |y: usize| f.luma[y * f.w + x0..y * f.w + x1].iter().sum::<f32>() / (x1 - x0) as f32;
    (lo..y1)
        .map(|y| ((row(y) - row(y - 1)).abs(), y))
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .map_or(y1, |(_, y)| y)
}

/// The columns of the left and right jambs near `x0` and `x1` over the
/// rows `top..bottom`: the strongest upright luma step within
/// [`JAMB_REACH`] of each end, when both are over [`JAMB`].
fn jambs(f: &Features, x0: f32, x1: f32, top: f32, bottom: f32) -> Option<(usize, usize, f32)> {
    let (a, b) = (
        (top.round() as isize + 1).max(0) as usize,
        (bottom.round() as isize - 1).min(f.h as isize).max(0) as usize,
    );
    if b <= a + 1 {
        return None;
    }
    let step = |x: usize| {
        (a..b)
            .map(|y| (f.luma[y * f.w + x + 1] - f.luma[y * f.w + x - 1]).abs())
            .sum::<f32>()
            / (b - a) as f32
    };
    // Outward up to JAMB_REACH, inward up to JAMB_INWARD of the span (a
    // head or a sill reaching past the frame).
    let inward = (JAMB_INWARD * (x1 - x0)).round() as isize;
    let best = |e: f32, dir: isize| {
        let e = e.round() as isize;
        let (a, b) = if dir > 0 {
            (e - JAMB_REACH, e + JAMB_REACH.max(inward))
        } else {
            (e - JAMB_REACH.max(inward), e + JAMB_REACH)
        };
        (a..=b)
            .filter(|&x| x >= 1 && x + 1 < f.w as isize)
            .map(|x| (step(x as usize), x as usize))
            .max_by(|p, q| p.0.total_cmp(&q.0))
    };
    let (l, r) = (best(x0, 1)?, best(x1, -1)?);
    (r.1 > l.1 + 2).then_some((l.1, r.1, l.0.min(r.0)))
}

impl Cell {
    /// True when `o` lies in this cell's row or column (their spans across
    /// that sharing [`ALIGN`] of the longer) and is of a like width or
    /// height (within [`LIKE`]).
    fn aligned(&self, o: &Cell) -> bool {
        let share = |a0: usize, a1: usize, b0: usize, b1: usize| {
            a1.min(b1).saturating_sub(a0.max(b0)) as f32 / (a1 - a0).max(b1 - b0).max(1) as f32
        };
        (share(self.y0, self.y1, o.y0, o.y1) >= ALIGN && alike(self.x1 - self.x0, o.x1 - o.x0))
            || (share(self.x0, self.x1, o.x0, o.x1) >= ALIGN
                && alike(self.y1 - self.y0, o.y1 - o.y0))
    }

    /// True when the two overlap.
    fn meets(&self, o: &Cell) -> bool {
        self.x0 < o.x1 && o.x0 < self.x1 && self.y0 < o.y1 && o.y0 < self.y1
    }
}

/// True when two sizes are within [`LIKE`] of each other.
pub(super) fn alike(a: usize, b: usize) -> bool {
    (a.max(b) as f32) < LIKE * a.min(b) as f32
}

/// Mean colour and texture of the wall pixels of a rectangle.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Stats {
    rgb: [f32; 3],
    texture: f32,
    pub(super) n: usize,
}

impl Stats {
    pub(super) fn of(f: &Features, class: &[Class], xs: Range<usize>, ys: Range<usize>) -> Stats {
        let mut s = Stats::default();
        for y in ys {
            for x in xs.clone() {
                let i = y * f.w + x;
                if class[i] == Class::Wall {
                    let p = f.rgb_at(i);
                    (0..3).for_each(|k| s.rgb[k] += p[k]);
                    s.texture += f.texture[i];
                    s.n += 1;
                }
            }
        }
        let n = s.n.max(1) as f32;
        s.rgb = s.rgb.map(|v| v / n);
        s.texture /= n;
        s
    }

    pub(super) fn luma(&self) -> f32 {
        luma(self.rgb)
    }

    /// The two pooled.
    pub(super) fn and(&self, o: &Stats) -> Stats {
        let n = (self.n + o.n).max(1) as f32;
        let (a, b) = (self.n as f32 / n, o.n as f32 / n);
        Stats {
            rgb: [0, 1, 2].map(|k| self.rgb[k] * a + o.rgb[k] * b),
            texture: self.texture * a + o.texture * b,
            n: self.n + o.n,
        }
    }

    /// True when `self` differs from the wall `wall` in luma (outside
    /// [`LUMA_APART`] of it) or in colour (over [`COLOUR_APART`], the luma
    /// difference taken out).
    fn apart(&self, wall: &Stats) -> bool {
        let (li, lw) = (self.luma(), wall.luma().max(1e-3));
        let colour: f32 = (0..3)
            .map(|k| (self.rgb[k] - li - (wall.rgb[k] - lw)).abs())
            .sum();
        !(LUMA_APART.0..=LUMA_APART.1).contains(&(li / lw)) || colour > COLOUR_APART
    }
}

/// The cell inset by its frame, when it is glass: the wall on both sides
/// of it is alike (one wall, not a pier between two others), its jambs
/// stand out of the wall's own texture, and it differs from that wall in
/// luma or colour. Rows at its top and bottom that do not differ (the
/// wall under a window whose sill was not found) are left out.
fn glass_cell(f: &Features, class: &[Class], c: &Cell) -> Option<Cell> {
    let wd = c.x1 - c.x0;
    let inset = ((FRAME * wd as f32).round() as usize).max(1);
    let (x0, x1) = (c.x0 + inset, c.x1.saturating_sub(inset));
    let (y0, y1) = (c.y0 + inset, c.y1.saturating_sub(inset));
    if x1 <= x0 + 1 || y1 <= y0 + 1 {
        return None;
    }
    let beside = ((BESIDE * wd as f32).round() as usize).max(2);
    let left = Stats::of(
        f,
        class,
        c.x0.saturating_sub(inset + beside)..c.x0.saturating_sub(inset),
        y0..y1,
    );
    let right = Stats::of(
        f,
        class,
        (c.x1 + inset).min(f.w)..(c.x1 + inset + beside).min(f.w),
        y0..y1,
    );
    let area = (x1 - x0) * (y1 - y0);
    let (ll, lr) = (left.luma(), right.luma());
    if 8 * left.n < area
        || 8 * right.n < area
        || (ll - lr).abs() > SIDES_ALIKE * ll.max(lr)
        || c.jamb < JAMB
        || c.jamb < JAMB_OVER_WALL * (left.texture + right.texture) / 2.0
    {
        return None;
    }
    let wall = left.and(&right);
    // The rows that differ from the wall; the run from the first to the
    // last of them is the glass.
    let rows: Vec<bool> = (y0..y1)
        .map(|y| {
            let s = Stats::of(f, class, x0..x1, y..y + 1);
            2 * s.n >= x1 - x0 && s.apart(&wall)
        })
        .collect();
    let first = rows.iter().position(|&v| v)?;
    let last = rows.iter().rposition(|&v| v)?;
    let (y0, y1) = (y0 + first, y0 + last + 1);
    let inside = Stats::of(f, class, x0..x1, y0..y1);
    let tall = (y1 - y0) as f32 >= MIN_TALL * (x1 - x0) as f32;
    (tall && 2 * inside.n >= (x1 - x0) * (y1 - y0) && inside.apart(&wall)).then_some(Cell {
        x0,
        x1,
        y0,
        y1,
        jamb: c.jamb,
    })
}
