//! Courses: stacks of evenly spaced, closely set horizontal edges (clapboard
//! siding, brick or stone courses, shutter slats) are the wall's texture, not
//! ledges. Each board of a clapboard wall sheds water onto the next over its
//! whole width, so no streak starts at any one of them (`how-facades-age.md`:
//! streaks start where a projection concentrates the run-off).
//!
//! A ledge is a course line when, among the ledges overlapping it along at
//! least half the shorter one's width, it sits in a run of at least
//! [`MIN_RUN`] lines whose consecutive gaps are alike (each within
//! [`GAP_RATIO`] of the next: perspective changes them slowly) and small
//! beside the lines' common width (at most [`MAX_GAP_PER_WIDTH`] of it). A
//! storey's sills are a storey apart and a window wide, a tall building's
//! floor slabs 3 m apart and tens of metres wide: both far above that.
//! The run is walked from the line up and down, each step to the line
//! nearest where the next course would lie, so a stray line between two
//! courses (a short sill on the siding) does not break it.
//! Boards cut into short pieces (by a vent, an electric box, a door) have
//! gaps large beside their width; weak lines (under [`WEAK`]) also stack
//! when the gap is under [`MAX_GAP_PER_HEIGHT`] of the photo's height, and
//! any lines when it is also under [`STEP_GAP_PER_WIDTH`] of their width (a
//! flight of steps, whose treads blind review p22 found streaking).
//! The stack's lowest line stays: the water that sheets down the boards
//! leaves the wall there.

use super::{Ledge, LedgeKind};

/// Fewest evenly spaced lines that make a course stack.
const MIN_RUN: usize = 4;
/// Largest ratio between neighbouring gaps in a stack.
const GAP_RATIO: f32 = 1.5;
/// Largest gap, as a share of the common width of the two lines it separates.
const MAX_GAP_PER_WIDTH: f32 = 0.08;

/// Largest gap between two weak lines, as a share of the photo's height: a
/// board pieces' stack (LabelMeFacade test, the clapboard wall of blind
/// reviews 9b and 10: laps about 3% of the height apart). Measured on CMP
/// with [`WEAK`] 0.35: 0.03 to 0.05 all keep the recall (4636 bands) and
/// drop 116-171 of 11,927 detections; 0.04 drops 163 (precision 0.322 ->
/// 0.323) and 5 of the 13 board lines by the vent.
const MAX_GAP_PER_HEIGHT: f32 = 0.04;
/// Confidence under which a line may stack by [`MAX_GAP_PER_HEIGHT`]
/// (0.5 drops 526 on CMP but loses 8 labelled ledges; a sill that sheds
/// real water is long or strong).
const WEAK: f32 = 0.35;
/// Any lines also stack when their gap is under [`MAX_GAP_PER_HEIGHT`] of
/// the photo's height and under this share of their common width: a flight
/// of steps (rises about 0.17 m under treads 1-1.5 m wide, gaps 0.1-0.15 of
/// the width), siding laps over a porch; a storey's sills and a tower's floor
/// slabs lie farther apart. Measured on CMP (from a dump of the detections):
/// 0.12 drops 25 of 11,971 counted detections, 1 on a labelled sill or
/// cornice, and finds the same ledges; 0.15 drops 41, 2 on a label, 3
/// labelled ledges fewer.
const STEP_GAP_PER_WIDTH: f32 = 0.15;

fn span(l: &Ledge) -> (f32, f32) {
    let (a, b) = (l.polyline[0][0], l.polyline[l.polyline.len() - 1][0]);
    (a.min(b), a.max(b))
}

/// The polyline's height at `x` (clamped to its ends).
pub(super) fn y_at(l: &Ledge, x: f32) -> f32 {
    let p = &l.polyline;
    if x <= p[0][0] {
        return p[0][1];
    }
    for s in p.windows(2) {
        let ([x0, y0], [x1, y1]) = (s[0], s[1]);
        if x <= x1 {
            let t = if x1 > x0 { (x - x0) / (x1 - x0) } else { 0.0 };
            return y0 + t * (y1 - y0);
        }
    }
    p[p.len() - 1][1]
}

/// True when ledge `i` is a course line but the lowest of its stack (roof
/// lines never are); `height`: the photo's height in the ledges' pixels.
pub fn is_course(ledges: &[Ledge], i: usize, height: f32) -> bool {
    let me = &ledges[i];
    if me.kind == LedgeKind::RoofLine || me.polyline.len() < 2 {
        return false;
    }
    let (a0, a1) = span(me);
    // The lines overlapping this one, with their common width (measured at
    // the middle of the overlap) and whether they are weak.
    let mut stack: Vec<(f32, f32, bool)> = ledges
        .iter()
        .filter(|l| l.kind != LedgeKind::RoofLine && l.polyline.len() >= 2)
        .filter_map(|l| {
            let (b0, b1) = span(l);
            let overlap = a1.min(b1) - a0.max(b0);
            let shorter = (a1 - a0).min(b1 - b0);
            (overlap > 0.0 && overlap >= 0.5 * shorter).then(|| {
                let x = 0.5 * (a0.max(b0) + a1.min(b1));
                (y_at(l, x) - y_at(me, x), overlap, l.confidence < WEAK)
            })
        })
        .collect();
    stack.sort_by(|p, q| p.0.total_cmp(&q.0));
    let Some(me_at) = stack.iter().position(|&(dy, _, _)| dy == 0.0) else {
        return false;
    };
    let fits = |a: usize, b: usize| {
        let gap = (stack[b].0 - stack[a].0).abs();
        let width = stack[a].1.min(stack[b].1);
        let weak = stack[a].2 && stack[b].2;
        gap > 0.0
            && (gap <= MAX_GAP_PER_WIDTH * width
                || gap <= MAX_GAP_PER_HEIGHT * height
                    && (weak || gap <= STEP_GAP_PER_WIDTH * width))
    };
    // From line `from`, `gap` away in the direction of `gap`'s sign: the
    // line nearest where the next course would lie, within [`GAP_RATIO`]
    // of the gap (so a stray piece of another line in between is passed
    // over, not taken for a course).
    let next = |from: usize, gap: f32| {
        let want = stack[from].0 + gap;
        (0..stack.len())
            .filter(|&k| {
                let g = (stack[k].0 - stack[from].0) * gap.signum();
                g >= gap.abs() / GAP_RATIO && g <= gap.abs() * GAP_RATIO && fits(from, k)
            })
            .min_by(|&a, &b| {
                (stack[a].0 - want)
                    .abs()
                    .total_cmp(&(stack[b].0 - want).abs())
            })
    };
    // The run through this line at each first gap to another line: walked
    // both ways, each step's gap taken from the last (perspective changes
    // the gaps slowly); no further than a run needs.
    let walk = |mut at: usize, mut gap: f32| {
        let mut n = 0;
        while n < MIN_RUN {
            let Some(k) = next(at, gap) else { break };
            gap = stack[k].0 - stack[at].0;
            at = k;
            n += 1;
        }
        n
    };
    // The stack's lowest line is its drip edge (the last board over the
    // plinth, a moulding stack's lip): kept.
    (0..stack.len())
        .filter(|&k| k != me_at && fits(me_at, k))
        .any(|k| {
            let gap = stack[k].0;
            let (below, above) = if gap > 0.0 {
                (walk(me_at, gap), walk(me_at, -gap))
            } else {
                (walk(me_at, -gap), walk(me_at, gap))
            };
            below >= 1 && 1 + below + above >= MIN_RUN
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ledges that are not course lines, in order.
    fn drop_courses(ls: Vec<Ledge>) -> Vec<Ledge> {
        (0..ls.len())
            .filter(|&i| !is_course(&ls, i, 1000.0))
            .map(|i| ls[i].clone())
            .collect()
    }

    fn ledge(kind: LedgeKind, x0: f32, x1: f32, y: f32) -> Ledge {
        Ledge {
            kind,
            polyline: vec![[x0, y], [x1, y + 0.02 * (x1 - x0)]],
            confidence: 1.0,
        }
    }

    #[test]
    fn clapboard_lines_are_dropped_and_ledges_beside_them_kept() {
        // Siding: 12 boards 17 px apart across 300 px (gap 0.057 of the width).
        let mut ls: Vec<Ledge> = (0..12)
            .map(|k| ledge(LedgeKind::WindowHead, 0.0, 300.0, 200.0 + 17.0 * k as f32))
            .collect();
        // A sill on the siding: short, so the boards' gaps are large beside it.
        ls.push(ledge(LedgeKind::Sill, 320.0, 380.0, 260.0));
        // A cornice far above.
        ls.push(ledge(LedgeKind::Cornice, 0.0, 600.0, 40.0));
        ls.push(Ledge {
            kind: LedgeKind::RoofLine,
            polyline: vec![[0.0, 10.0], [300.0, 11.0], [600.0, 10.0]],
            confidence: 1.0,
        });
        let kept = drop_courses(ls);
        let kinds: Vec<LedgeKind> = kept.iter().map(|l| l.kind).collect();
        assert_eq!(
            kinds,
            [
                LedgeKind::WindowHead,
                LedgeKind::Sill,
                LedgeKind::Cornice,
                LedgeKind::RoofLine
            ]
        );
        // The board kept is the lowest: where the sheet of water leaves.
        assert_eq!(kept[0].polyline[0][1], 200.0 + 17.0 * 11.0);
    }

    #[test]
    fn weak_board_pieces_stack_by_the_height_strong_or_storey_apart_lines_stay() {
        // Board pieces cut by a vent: 60 px wide, 25 px apart (2.5% of a
        // 1000 px photo, 0.42 of their width), weak.
        let piece = |k: usize, conf: f32| Ledge {
            confidence: conf,
            ..ledge(LedgeKind::Sill, 100.0, 160.0, 800.0 + 25.0 * k as f32)
        };
        let kept = drop_courses((0..6).map(|k| piece(k, 0.25)).collect());
        assert_eq!(kept.len(), 1, "{kept:?}");
        assert_eq!(kept[0].polyline[0][1], 800.0 + 25.0 * 5.0);
        // The same lines, confident (each a clear ledge): kept.
        let strong: Vec<Ledge> = (0..6).map(|k| piece(k, 0.6)).collect();
        assert_eq!(drop_courses(strong).len(), 6);
        // Weak sills a storey (10% of the height) apart: kept.
        let sills: Vec<Ledge> = (0..6)
            .map(|k| Ledge {
                confidence: 0.25,
                ..ledge(LedgeKind::Sill, 100.0, 160.0, 200.0 + 100.0 * k as f32)
            })
            .collect();
        assert_eq!(drop_courses(sills).len(), 6);
    }

    #[test]
    fn storeys_of_sills_and_floor_slabs_stay() {
        // Sills a storey apart in a column of windows, and a tall building's
        // floor slabs 3 m apart across 30 m (gap 0.1 of the width).
        let mut ls: Vec<Ledge> = (0..6)
            .map(|k| ledge(LedgeKind::Sill, 100.0, 140.0, 50.0 + 100.0 * k as f32))
            .collect();
        ls.extend(
            (0..8).map(|k| ledge(LedgeKind::Balcony, 200.0, 1200.0, 50.0 + 100.0 * k as f32)),
        );
        assert_eq!(drop_courses(ls.clone()).len(), ls.len());
    }

    #[test]
    fn a_sill_between_two_boards_does_not_break_their_stack() {
        // Six boards 17 px apart across 300 px; a short sill on the siding
        // between the third and the fourth (overlapping them all).
        let mut ls: Vec<Ledge> = (0..6)
            .map(|k| ledge(LedgeKind::WindowHead, 0.0, 300.0, 200.0 + 17.0 * k as f32))
            .collect();
        ls.push(ledge(LedgeKind::Sill, 120.0, 180.0, 242.0));
        let ys: Vec<f32> = drop_courses(ls).iter().map(|l| l.polyline[0][1]).collect();
        assert_eq!(ys, [200.0 + 17.0 * 5.0, 242.0]);
    }

    #[test]
    fn a_flight_of_steps_is_a_stack_sills_a_storey_apart_are_not() {
        // Five treads 150 px wide, 20 px apart (2% of the height, 0.13 of
        // the width: more than [`MAX_GAP_PER_WIDTH`]).
        let treads: Vec<Ledge> = (0..5)
            .map(|k| ledge(LedgeKind::Balcony, 100.0, 250.0, 600.0 + 20.0 * k as f32))
            .collect();
        let kept = drop_courses(treads);
        assert_eq!(kept.len(), 1, "{kept:?}");
        assert_eq!(kept[0].polyline[0][1], 680.0);
        // Windows' sills as wide, one storey (10% of the height) apart.
        let sills: Vec<Ledge> = (0..5)
            .map(|k| ledge(LedgeKind::Sill, 100.0, 250.0, 300.0 + 100.0 * k as f32))
            .collect();
        assert_eq!(drop_courses(sills).len(), 5);
    }

    #[test]
    fn three_close_lines_are_not_a_stack() {
        // A cornice's mouldings: three lines close together, kept.
        let ls: Vec<Ledge> = (0..3)
            .map(|k| ledge(LedgeKind::Cornice, 0.0, 500.0, 60.0 + 6.0 * k as f32))
            .collect();
        assert_eq!(drop_courses(ls).len(), 3);
    }

    #[test]
    fn uneven_gaps_are_not_courses() {
        // Four long lines, but the gaps are 10, 40 and 10 px: a string course
        // and a cornice's mouldings, not siding.
        let ys = [100.0, 110.0, 150.0, 160.0];
        let ls: Vec<Ledge> = ys
            .iter()
            .map(|&y| ledge(LedgeKind::StringCourse, 0.0, 800.0, y))
            .collect();
        assert_eq!(drop_courses(ls).len(), 4);
    }
}
