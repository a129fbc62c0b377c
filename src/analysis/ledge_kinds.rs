//! What a traced ledge is, from what lies above and below it and at its
//! ends: glass above, a sill; glass below, a dark that goes on below, or
//! ends standing on a window's jambs, a window head; long near the wall
//! top, a cornice or coping; a frame running on through both ends, a
//! transom inside a window (not a ledge). Split from `ledges.rs`, which
//! traces and fits the lines.

use super::LedgeKind;
use super::features::Features;
use super::ledges::Fit;
use super::wall::Class;
use crate::effects::percentile::{Rank, percentile};

/// How far above and below an edge's ends a window frame is looked for,
/// in spans of the edge.
const FRAME_REACH: f32 = 0.4;
/// A window frame: mean horizontal luma step (over two columns) down a
/// column above this. Measured on CMP (scene_eval): see BENCHMARKS.md.
const FRAME_STEP: f32 = 0.07;

/// True when a frame runs on through both ends of the edge, above and
/// below it: the edge lies inside a window (a transom, a meeting rail, the
/// foot of a blind), between the jambs. A sill or a hood reaches past the
/// jambs, so at its ends the wall is plain on one side at least. The
/// frame's strength is the mean horizontal luma step down a column within
/// `FRAME_REACH` spans of the edge, the best column within 3 pixels of
/// each end; the weaker end decides.
pub(super) fn crosses_a_frame(f: &Features, fit: &Fit) -> bool {
    let reach = FRAME_REACH * fit.span();
    let end = |e: f32| {
        near_end(f, e)
            .filter_map(|x| {
                let y = fit.y_at(x as f32);
                Some(frame_step(f, x, y - reach, y - 2.0)?.min(frame_step(
                    f,
                    x,
                    y + 2.0,
                    y + reach,
                )?))
            })
            .fold(0f32, f32::max)
    };
    end(fit.x0).min(end(fit.x1 + 1.0)) > FRAME_STEP
}

/// A line whose ends stand on a window's jambs (a frame below both ends)
/// with no frame running on above them is the top of that window, not a
/// ledge over it: a window head, even where [`stays_dark`] does not see the
/// opening (a blind, a transom or a bright frame inside it) and the glass
/// class found no glass. The frame below is looked for in the lower half of
/// [`FRAME_REACH`] only: a ledge's own shadow band ends at its ends too.
/// `[choice]` The frame below must be over [`HEAD_JAMB`] and over
/// [`OPENS_BELOW`] times the frame above (the weaker end decides each).
/// Measured on CMP (counted detections renamed; strict / lenient precision
/// from 0.325 / 0.595, recall unchanged, offline on a dump of the
/// detections): below from 2 rows, over 0.07, 4 / 5 / 6 times: 0.335 /
/// 0.623, 0.337 / 0.622, 0.338 / 0.620; from a quarter of the reach 0.339 /
/// 0.624, 0.340 / 0.622, 0.341 / 0.621; from half of it, over 0.05: 0.343 /
/// 0.623, 0.344 / 0.622, 0.344 / 0.621 (over 0.07: 0.340 / 0.621). About
/// two thirds of the lines renamed lie at the top of a labelled window,
/// most of the rest under a labelled hood no wider than the jambs.
const OPENS_BELOW: f32 = 4.0;
/// See [`OPENS_BELOW`].
const HEAD_JAMB: f32 = 0.05;

/// True when the line tops a window: see [`OPENS_BELOW`].
pub(super) fn tops_a_window(f: &Features, fit: &Fit) -> bool {
    let reach = FRAME_REACH * fit.span();
    // The best column's frame step near end `e` over the rows `d0..d1`
    // from the line.
    let end = |e: f32, d0: f32, d1: f32| {
        near_end(f, e)
            .filter_map(|x| {
                let y = fit.y_at(x as f32);
                frame_step(f, x, y + d0, y + d1)
            })
            .fold(0f32, f32::max)
    };
    let side = |d0: f32, d1: f32| end(fit.x0, d0, d1).min(end(fit.x1 + 1.0, d0, d1));
    let below = side((reach / 2.0).max(2.0), reach);
    below > HEAD_JAMB && below > OPENS_BELOW * side(-reach, -2.0)
}

/// The columns within 3 pixels of a line's end at `e` (away from the
/// photo's sides).
fn near_end(f: &Features, e: f32) -> impl Iterator<Item = usize> {
    let (e, w) = (e as isize, f.w as isize);
    (e - 3..=e + 3)
        .filter(move |&x| x >= 1 && x < w - 1)
        .map(|x| x as usize)
}

/// Mean horizontal luma step (over two columns) down column `x` from row
/// `y0` to `y1` (rounded, clipped to the photo); `None` when that is empty.
fn frame_step(f: &Features, x: usize, y0: f32, y1: f32) -> Option<f32> {
    let (a, b) = (
        (y0.round() as isize).max(0) as usize,
        (y1.round() as isize).min(f.h as isize).max(0) as usize,
    );
    (b > a).then(|| {
        let s: f32 = (a..b)
            .map(|y| {
                let i = y * f.w + x;
                (f.luma[i + 1] - f.luma[i - 1]).abs()
            })
            .sum();
        s / (b - a) as f32
    })
}

/// Names a ledge by what lies above and below it.
pub(super) fn kind_of(f: &Features, class: &[Class], fit: &Fit) -> LedgeKind {
    let (w, h) = (f.w, f.h);
    let d = (h as isize / 25).max(4);
    let above = glass_share(class, w, h, fit, -2 * d, -1);
    if glass_below(class, w, h, fit) {
        return LedgeKind::WindowHead;
    }
    if stays_dark(f, fit) {
        return LedgeKind::WindowHead;
    }
    if above > 0.25 {
        return LedgeKind::Sill;
    }
    let span = fit.span() / w as f32;
    if span >= 0.35 {
        // How far below the wall's top edge (at the ledge's middle)?
        let xm = ((fit.x0 + fit.x1) / 2.0) as usize;
        let top = (0..h)
            .find(|&y| class[y * w + xm] == Class::Wall)
            .unwrap_or(0);
        let below_top = (fit.y_at(xm as f32) - top as f32) / h as f32;
        return if below_top < 0.04 {
            LedgeKind::Coping
        } else if below_top < 0.25 {
            LedgeKind::Cornice
        } else {
            LedgeKind::StringCourse
        };
    }
    if span >= 0.15 {
        LedgeKind::Balcony
    } else {
        LedgeKind::Sill
    }
}

/// The share of glass in the rows `d0..d1` from the line, over its columns.
fn glass_share(class: &[Class], w: usize, h: usize, fit: &Fit, d0: isize, d1: isize) -> f32 {
    let (mut glass, mut n) = (0usize, 0usize);
    for x in fit.x0 as usize..=(fit.x1 as usize).min(w - 1) {
        let y = fit.y_at(x as f32).round() as isize;
        for d in d0..d1 {
            let yy = y + d;
            if yy >= 0 && (yy as usize) < h {
                n += 1;
                glass += (class[yy as usize * w + x] == Class::Glass) as usize;
            }
        }
    }
    glass as f32 / n.max(1) as f32
}

/// True when glass lies below the line (over 35% of the rows down to a
/// twelfth of the height): a window head.
pub(super) fn glass_below(class: &[Class], w: usize, h: usize, fit: &Fit) -> bool {
    let d = (h as isize / 25).max(4);
    glass_share(class, w, h, fit, 2, 2 * d) > 0.35
}

/// True when the dark below the edge does not end in a thin shadow band
/// but goes on (glass, a doorway, an opening): the edge is the top of an
/// opening, not a projecting ledge.
fn stays_dark(f: &Features, fit: &Fit) -> bool {
    let (w, h) = (f.w, f.h);
    let d = (0.04 * h as f32).max(4.0) as isize;
    let mean = |d0: isize, d1: isize| {
        let (mut s, mut n) = (0f32, 0usize);
        for x in fit.x0 as usize..=(fit.x1 as usize).min(w - 1) {
            let y = fit.y_at(x as f32).round() as isize;
            for yy in (y + d0)..(y + d1) {
                if yy >= 0 && (yy as usize) < h {
                    s += f.luma[yy as usize * w + x];
                    n += 1;
                }
            }
        }
        s / n.max(1) as f32
    };
    let above = mean(-d, -1);
    let near = mean(2, 2 + d / 3);
    let far = mean(d, 2 * d);
    // Recovered less than 30% of the step: still dark.
    far - near < 0.3 * (above - near)
}

/// The luma profile across a line, in texture radii `r` of the photo
/// ([`super::features::texture_radius`], at least 2 pixels): the median
/// along the line of the luma at each row offset from it. A projecting
/// ledge casts a shadow band under its lit top that ends below it, back
/// toward the wall's tone above: a ridge or a bar. A change of paint,
/// siding or material is a step: bright above, dark below, and the dark
/// goes on (blind review 27, img_0847: streaks from a siding colour
/// change). Returns how much of the drop from above to the darkest row
/// just below comes back farther below: near 1 for a ledge's shadow band,
/// near 0 (or under) for a step. `None` when the line is too short or the
/// rows leave the photo.
pub(super) fn recovery(f: &Features, fit: &Fit) -> Option<f32> {
    let (above, dip, far) = profile(f, fit)?;
    let drop = above - dip;
    (drop > 1e-3).then(|| (far - dip) / drop)
}

/// True when the wall's tone comes back below the line's dark band to
/// within [`ALIKE`] of the drop of the tone above it: a thin dark line on
/// one surface (a cable, a crack, a joint, a cast shadow's edge), where a
/// sill or a course has another surface above its shadow (its lit top,
/// the glass over it) than below.
pub(super) fn a_line_on_one_surface(f: &Features, fit: &Fit) -> bool {
    profile(f, fit).is_some_and(|(above, dip, far)| {
        above - dip > 1e-3 && (far - above).abs() < ALIKE * (above - dip)
    })
}

/// See [`a_line_on_one_surface`]; applied to slanted lines only (blind
/// p81: cables on a white wall taken for a perspective wall's sills).
/// Slanted ledge pixels on LabelMeFacade train, on building or window:
/// 12033 (0.961) without it, 9811 (0.965) at 0.15; CMP ledges found 8845
/// -> 8836, sill + cornice recall 4631 -> 4630.
const ALIKE: f32 = 0.15;

/// The luma above a line, the darkest just below it and farther below
/// (see [`recovery`]).
fn profile(f: &Features, fit: &Fit) -> Option<(f32, f32, f32)> {
    let r = super::features::texture_radius(f.w, f.h).max(2) as isize;
    let (w, h) = (f.w as isize, f.h as isize);
    let median_at = |o: isize| {
        let v: Vec<f32> = (fit.x0 as isize..=(fit.x1 as isize).min(w - 1))
            .filter_map(|x| {
                let y = fit.y_at(x as f32).round() as isize + o;
                (y >= 0 && y < h).then(|| f.luma[(y * w + x) as usize])
            })
            .collect();
        // The upper median of an even count.
        (v.len() >= 3).then(|| percentile(v, 0.5, Rank::Nearest))?
    };
    let mean = |o0: isize, o1: isize| -> Option<f32> {
        let s: Option<Vec<f32>> = (o0..=o1).map(median_at).collect();
        s.map(|s| s.iter().sum::<f32>() / s.len() as f32)
    };
    let above = mean(-STEP_ABOVE.1 * r, -STEP_ABOVE.0 * r)?;
    let dip = (1..=STEP_DIP * r)
        .map(median_at)
        .collect::<Option<Vec<f32>>>()?
        .into_iter()
        .fold(f32::MAX, f32::min);
    let far = mean(STEP_FAR.0 * r, STEP_FAR.1 * r)?;
    Some((above, dip, far))
}

/// Rows above a line (from, to, in texture radii) whose luma is the
/// wall's tone over it.
const STEP_ABOVE: (isize, isize) = (1, 3);
/// Rows below a line (1 to this many texture radii) where a ledge's
/// shadow band is looked for (its darkest row).
const STEP_DIP: isize = 2;
/// Rows below a line (from, to, in texture radii) where a ledge's shadow
/// has ended and a step's dark goes on.
const STEP_FAR: (isize, isize) = (4, 8);
