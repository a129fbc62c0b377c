//! The windows the dark rule and the frames missed, from the grid of the
//! windows they found for sure: a facade's windows stand in rows and
//! columns, so where the row of one trusted window crosses the column of
//! another of a like size and no window was found (its panes joined to a
//! shaded pier or to its surround's shadow, a reflection, a light blind),
//! a window is proposed: the column window's span across, the row
//! window's span up and down, inset by a frame (spec
//! `how-facades-age.md`: dirt sits on the wall, not on the glass).
//! Measured against the labelled windows by `scene_eval` (BENCHMARKS.md,
//! thirty-sixth pass, helper glass37).
//!
//! [choice: only trusted boxes propose (a dark window filling over
//! `LONE_FILL` of its box, or a frames cell), because ragged dark blobs
//! (a window with the shadow under its sill) gave cells that covered
//! sills and spandrels (glass36, d4f4e6f: LabelMeFacade wall IoU 0.759 ->
//! 0.751).] [choice: the grid runs after the ledges, like the frames, so
//! the sills and cornices found are as before; a cell is stopped over a
//! sill (or any ledge) crossing its lower half and under one crossing its
//! upper half, so the ledge's rows keep their dirt.] [choice: a cell is
//! kept when it is mostly wall in the class map, not lighter than the
//! wall ring around it (a closed blind is lost; a lit spandrel or blank
//! bay between windows is not taken) and not much darker (a dark the
//! dark rule turned down).]

use super::super::features::Features;
use super::super::wall::Class;
use super::super::{Ledge, LedgeKind};
use super::frames::{Stats, alike, sill_top};
use super::{Bbox, LONE_FILL, bbox, components, is_window};
use crate::effects::habitat::row_at;

/// The frame: the cell is inset by this share of its width on every side
/// (at least one analysis pixel; `frames::FRAME`).
const FRAME: f32 = 0.08;

/// The wall ring around a cell is this share of its width on each side
/// (of its height above and below).
const AROUND: f32 = 0.3;

/// A cell is kept when at least this share of its pixels is wall.
const WALL_SHARE: f32 = 0.8;

/// ... and its mean luma is at least this share of the wall ring's: a
/// cell darker than that lies in a dark the dark rule saw and turned down
/// for its shape (a shutter, a shadow joined to a pier). On the new cells
/// of 40 CMP photos (every ninth), those under 0.75 were 9 of 11 off the
/// labelled windows (shutters, shadowed roofs), those between 0.75 and
/// 1.0 most on them (77 of 91 cells) ...
const DARKEST: f32 = 0.75;

/// ... and at most this share (a cell as light as the wall is a spandrel
/// or a blank bay as often as a blind).
const NOT_LIGHTER: f32 = 1.0;

/// A ledge stops a cell when it spans this share of the cell's width.
const CROSSES: f32 = 0.5;

/// The windows found for sure so far: the dark rule's (components of
/// glass in `class`) that fill over [`LONE_FILL`] of their box and have a
/// window's size, and the frames' cells (`cells`, exclusive ends).
pub(super) fn trusted(f: &Features, class: &[Class], cells: &[Bbox]) -> Vec<Bbox> {
    let (w, h) = (f.w, f.h);
    let glass: Vec<bool> = class.iter().map(|&c| c == Class::Glass).collect();
    let mut out: Vec<Bbox> = components(&glass, w, h)
        .into_iter()
        .filter_map(|m| {
            let b = bbox(&m, w);
            let area = (b.2 - b.0 + 1) * (b.3 - b.1 + 1);
            (is_window(&b, m.len(), w, h) && m.len() as f32 > LONE_FILL * area as f32).then_some(b)
        })
        .collect();
    out.extend(cells);
    out
}

/// The wall pixels of the windows proposed where the rows and columns of
/// the `trusted` windows cross, stopped at the `ledges` (analysis
/// pixels), to be called glass.
pub(super) fn find(
    f: &Features,
    class: &[Class],
    ledges: &[Ledge],
    trusted: &[Bbox],
) -> Vec<usize> {
    let mut kept: Vec<Bbox> = Vec::new();
    for a in trusted {
        for c in trusted {
            if a == c || !like(a, c) {
                continue;
            }
            // The row of `a`, the column of `c`.
            let ht = (a.3 - a.1).min(c.3 - c.1);
            let proposed: Bbox = (c.0, a.1, c.2, a.1 + ht);
            if trusted.iter().chain(&kept).any(|o| meets(o, &proposed)) {
                continue;
            }
            if let Some(cell) = cell(f, class, ledges, &proposed) {
                kept.push(cell);
            }
        }
    }
    let mut out = Vec::new();
    for b in &kept {
        for y in b.1..=b.3 {
            out.extend(
                (b.0..=b.2)
                    .map(|x| y * f.w + x)
                    .filter(|&i| class[i] == Class::Wall),
            );
        }
    }
    out
}

/// True when `a` and `c` have widths and heights of a like size
/// ([`alike`]): two trusted windows then make a row and a column.
fn like(a: &Bbox, c: &Bbox) -> bool {
    alike(a.2 - a.0 + 1, c.2 - c.0 + 1) && alike(a.3 - a.1 + 1, c.3 - c.1 + 1)
}

/// True when the two boxes overlap.
fn meets(a: &Bbox, b: &Bbox) -> bool {
    a.0 <= b.2 && b.0 <= a.2 && a.1 <= b.3 && b.1 <= a.3
}

/// The proposed box `b` inset by its frame, stopped at the ledges that
/// cross it, when it is glass: mostly wall, not lighter than the wall
/// ring around it.
fn cell(f: &Features, class: &[Class], ledges: &[Ledge], b: &Bbox) -> Option<Bbox> {
    let (w, h) = (f.w, f.h);
    let wd = b.2 - b.0 + 1;
    let inset = ((FRAME * wd as f32).round() as usize).max(1);
    let (x0, x1) = (b.0 + inset, b.2.checked_sub(inset)?);
    let (mut y0, mut y1) = (b.1 + inset, b.3.checked_sub(inset)?);
    if x1 <= x0 + 1 || y1 <= y0 + 1 {
        return None;
    }
    // The ledges crossing the cell (over CROSSES of its width): a sill in
    // its lower half ends it at the sill's top, a head in its upper half
    // starts it under the head.
    let (top, bottom) = (y0, y1);
    let mid = (top + bottom) as f32 / 2.0;
    for l in ledges.iter().filter(|l| l.kind != LedgeKind::RoofLine) {
        let (lx0, lx1) = (l.polyline[0][0], l.polyline[l.polyline.len() - 1][0]);
        let common = lx1.min(x1 as f32 + 1.0) - lx0.max(x0 as f32);
        if common < CROSSES * (x1 - x0 + 1) as f32 {
            continue;
        }
        let Some(y) = row_at(&l.polyline, (x0 + x1) as f32 / 2.0) else {
            continue;
        };
        if y >= mid && y <= (b.3 + 2) as f32 {
            let ly = (y.round() as usize).min(h);
            y1 = y1.min(sill_top(f, x0, x1 + 1, top, ly).saturating_sub(1));
        } else if y < mid && y >= top as f32 - 2.0 {
            y0 = y0.max(y.round() as usize + 1);
        }
    }
    if y1 <= y0 + 2 {
        return None;
    }
    let (cw, ch) = (x1 - x0 + 1, y1 - y0 + 1);
    let inner = Stats::of(f, class, x0..x1 + 1, y0..y1 + 1);
    if (inner.n as f32) < WALL_SHARE * (cw * ch) as f32 {
        return None;
    }
    let (ax, ay) = (
        ((AROUND * cw as f32).round() as usize).max(2),
        ((AROUND * ch as f32).round() as usize).max(2),
    );
    let (ox0, ox1) = (x0.saturating_sub(ax), (x1 + 1 + ax).min(w));
    let (oy0, oy1) = (y0.saturating_sub(ay), (y1 + 1 + ay).min(h));
    let ring = [
        Stats::of(f, class, ox0..x0, oy0..oy1),
        Stats::of(f, class, x1 + 1..ox1, oy0..oy1),
        Stats::of(f, class, x0..x1 + 1, oy0..y0),
        Stats::of(f, class, x0..x1 + 1, y1 + 1..oy1),
    ];
    let wall = ring.iter().fold(Stats::default(), |s, r| s.and(r));
    let ratio = inner.luma() / wall.luma().max(1e-3);
    (2 * wall.n >= cw * ch && (DARKEST..=NOT_LIGHTER).contains(&ratio)).then_some((x0, y0, x1, y1))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::photo::Photo;

    fn features(img: image::RgbImage) -> Features {
        Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 300)
    }

    fn sill(x0: f32, x1: f32, y: f32) -> Ledge {
        Ledge {
            kind: LedgeKind::Sill,
            polyline: vec![[x0, y], [x1, y]],
            confidence: 1.0,
        }
    }

    /// Two storeys of three windows (30 x 45, x 40, 130, 220; y 30, 130)
    /// on a wall of luma 0.7, each over a light sill 5 px thick: all dark
    /// (0.2) but the middle one of the lower storey, only a little darker
    /// than the wall (0.62, under a light curtain), and the right one of
    /// the lower storey, a light sign (0.9).
    fn storeys() -> (Features, Vec<Ledge>) {
        let xs = [40u32, 130, 220];
        let img = image::RgbImage::from_fn(300, 240, |x, y| {
            let mut v = 0.7;
            for &x0 in &xs {
                for y0 in [30u32, 130] {
                    if (x0..x0 + 30).contains(&x) && (y0..y0 + 45).contains(&y) {
                        v = match (x0, y0) {
                            (130, 130) => 0.62,
                            (220, 130) => 0.9,
                            _ => 0.2,
                        };
                    }
                    if (x0 - 4..x0 + 34).contains(&x) && (y0 + 45..y0 + 50).contains(&y) {
                        v = 0.9;
                    }
                }
            }
            image::Rgb([(v * 255.0) as u8; 3])
        });
        let ledges = xs
            .iter()
            .flat_map(|&x0| [80.0, 180.0].map(|y| sill(x0 as f32 - 4.0, x0 as f32 + 34.0, y)))
            .collect();
        (features(img), ledges)
    }

    #[test]
    fn a_window_barely_darker_than_the_wall_in_the_grid_is_glass() {
        let (f, ledges) = storeys();
        let mut class = vec![Class::Wall; f.w * f.h];
        super::super::find(&f, &mut class);
        for i in super::super::frames::find(&f, &class, &ledges) {
            class[i] = Class::Glass;
        }
        let at = |x: usize, y: usize| class[y * f.w + x];
        // The dark windows are found by the dark rule.
        assert_eq!(at(55, 50), Class::Glass);
        // The one under a curtain, where their row and column cross.
        assert_eq!(at(145, 150), Class::Glass);
        assert_eq!(at(140, 165), Class::Glass);
        // Its sill, the wall between the storeys and between the windows
        // stay wall, and so does the light sign.
        assert_eq!(at(145, 177), Class::Wall);
        assert_eq!(at(145, 100), Class::Wall);
        assert_eq!(at(100, 150), Class::Wall);
        assert_eq!(at(235, 150), Class::Wall);
    }

    #[test]
    fn a_cell_ends_at_the_top_of_the_sill_under_it() {
        // A window (0.6) at x 40..70, y 20..75 over a sill (0.9) to row
        // 80, proposed down to row 95 (the row of a taller window).
        let img = image::RgbImage::from_fn(300, 240, |x, y| {
            let v = match (x, y) {
                (40..70, 20..75) => 0.6,
                (36..74, 75..80) => 0.9,
                _ => 0.7,
            };
            image::Rgb([(v * 255.0) as u8; 3])
        });
        let f = features(img);
        let class = vec![Class::Wall; f.w * f.h];
        let b = cell(&f, &class, &[sill(36.0, 74.0, 80.0)], &(40, 20, 69, 95)).unwrap();
        assert!(b.3 < 75, "the cell reaches row {}", b.3);
        assert!(b.3 > 65 && b.1 < 25, "{b:?}");
        // Without the sill found, it would cover the sill.
        let b = cell(&f, &class, &[], &(40, 20, 69, 95)).unwrap();
        assert!(b.3 > 80);
    }
}
