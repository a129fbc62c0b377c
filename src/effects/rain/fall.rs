//! Where a streak can be seen: below its ledge, fading over a fall of a
//! metre or two (`how-facades-age.md`: "narrow at the release point, wider
//! and fainter over a fall of about 0.5 to 2 m").
//!
//! [choice, beyond Chang:] a droplet in Chang's model runs until it dries
//! or leaves the wall, however far that is in metres, so at facade scale a
//! streak would run the whole height of a building. The stain's coverage is
//! multiplied by `exp(-ln 10 (d / fall)^2)`, where d is the distance below
//! the nearest source above in the same column: a tenth of its darkness at
//! `fall`, none above the highest source.
//!
//! [choice, beyond the uniform fall:] a streak's length follows its water
//! (`how-facades-age.md`: "a tall bare wall below a cornice shows long,
//! regular streaks; a wall with sills every storey shows short streaks"):
//! under a ledge releasing at points ([`Warp`]), a column's fall is `fall`
//! times the water leaving above it (in ledge drained per drip spacing,
//! times the ledge's catch: a rivulet runs until the wall has soaked up
//! its water, so its length grows with its flow), within [`SHORTEST`]..
//! [`LONGEST`]: the spec's 0.5 to 2 m at the default 1.5 m. Its streak
//! begins where its water meets the wall, `onset` times the warp's onset
//! noise below the ledge, and darkens over another `onset` (smoothstep), so
//! the streaks' tops are not one straight line. Past a ledge's ends the
//! fade dies out as a Gaussian of width `reach` instead of stopping at a
//! column, so a band of streaks has no straight side.
//!
//! Under drip points the fade is also scaled by the streak's strength
//! ([`Warp::strength`], `rain.uneven`): its water, times its ledge's
//! drain, over the water that shows in full; the drain lengthens or
//! shortens the fall too.

use rayon::prelude::*;

use super::sources::Warp;
use crate::field::RowMajor;

/// ln 10: the fade reaches a tenth at the fall length.
const LN_10: f32 = std::f32::consts::LN_10;

/// Shortest fall, as a share of `fall` [choice: with `LONGEST`, the spec's
/// 0.5..2 m at the default 1.5 m].
pub const SHORTEST: f32 = 0.33;

/// Longest fall, as a share of `fall`.
pub const LONGEST: f32 = 1.33;

/// `rain.sure_at`'s default: the confidence at which a found ledge's
/// streaks show in full [choice: 0.6. The analysis takes many joints of
/// rusticated stone and shutter edges for window heads, with confidence
/// 0.2-0.3 (p1010899: 9 of its 34 ledges under 0.3); each shed a flat grey
/// block down to the next joint, with a straight top on open wall (blind
/// review 25, tell 1, and its combs, tell 5). A ledge at confidence c
/// shows c / 0.6 of its streaks and lets the streaks from above run on
/// through the rest].
pub const SURE_AT: f32 = 0.6;

/// How sure a ledge of `confidence` is for its streaks to show, 0..1
/// (1 at `sure_at` and above; 1 for every ledge when `sure_at` <= 0).
pub fn sure(confidence: f32, sure_at: f32) -> f32 {
    if sure_at <= 0.0 {
        return 1.0;
    }
    (confidence / sure_at).clamp(0.0, 1.0)
}

/// How many `reach`es past its ends a ledge's fade is computed: the
/// Gaussian side is below 4e-4 there.
const SIDE_REACHES: f32 = 4.0;

/// A source line for [`fade`].
#[derive(Debug, Clone, Copy)]
pub struct Ledge<'a> {
    /// The polyline, grid coordinates.
    pub line: &'a [(f32, f32)],
    /// Where it releases its water; `None` = uniform (a full-length fall
    /// from the line itself).
    pub warp: Option<&'a Warp>,
    /// The share of the rain it catches (1 in the open).
    pub catch: f32,
    /// How much its streaks show ([`sure`]): the streaks from above show
    /// through the rest.
    pub sure: f32,
}

/// One source above a column: where and how its streaks start and fade.
#[derive(Debug, Clone, Copy)]
struct Top {
    row: f32,
    /// Fall length here, grid pixels.
    fall: f32,
    /// 1 within the ledge's span, a Gaussian past its ends.
    side: f32,
    /// How sure the ledge is ([`sure`]).
    sure: f32,
    /// Where the streak begins below the row, and over how far it darkens.
    start: f32,
    ramp: f32,
    /// How strong the streak is, 0..1 ([`Warp::strength`]).
    strength: f32,
}

impl Top {
    /// How far the streak has begun `d` pixels below the source, 0..1.
    fn onset(&self, d: f32) -> f32 {
        if self.ramp > 0.0 {
            let t = ((d - self.start) / self.ramp).clamp(0.0, 1.0);
            crate::random::smoothstep(t)
        } else {
            1.0
        }
    }

    /// The fade `d` pixels below the source, and how far down its fall
    /// that is (0..1).
    fn at(&self, d: f32) -> (f32, f32) {
        let onset = self.onset(d);
        let (fall, depth) = if self.fall > 0.0 {
            let t = d / self.fall;
            ((-LN_10 * t * t).exp(), t.min(1.0))
        } else {
            (1.0, 0.0)
        };
        (self.strength * self.side * onset * fall, depth)
    }
}

/// Where streaks show below their sources ([`fade`]).
#[derive(Debug, Clone)]
pub struct Fall {
    /// How much of the stain shows, 0..1.
    pub fade: RowMajor<f32>,
    /// How far down its fall each pixel lies, 0..1 (1 at or past the
    /// fall length): how much a streak has widened there.
    pub depth: RowMajor<f32>,
}

/// The fade map on a `width` x `height` grid for source ledges and,
/// optionally, a top-edge row per column; each ledge's fade dies out past
/// its ends over `reach` columns (water runs off a ledge's ends), and its
/// streaks begin `onset` pixels or so below it. `fall` <= 0 gives 1
/// everywhere below a source.
pub fn fade(
    width: usize,
    height: usize,
    ledges: &[Ledge],
    top_edge: Option<&[Option<usize>]>,
    fall: f32,
    reach: f32,
    onset: f32,
) -> Fall {
    // Per column, the sources crossing it or reaching it.
    let mut columns: Vec<Vec<Top>> = vec![Vec::new(); width];
    for ledge in ledges.iter().filter(|l| !l.line.is_empty()) {
        let mut line: Vec<[f32; 2]> = ledge.line.iter().map(|&(x, y)| [x, y]).collect();
        line.sort_by(|a, b| a[0].total_cmp(&b[0]));
        let (x_lo, x_hi) = (line[0][0], line[line.len() - 1][0]);
        let first = (x_lo - SIDE_REACHES * reach).floor().max(0.0) as usize;
        let last =
            ((x_hi + SIDE_REACHES * reach).ceil().max(0.0) as usize).min(width.saturating_sub(1));
        for (x, column) in columns.iter_mut().enumerate().take(last + 1).skip(first) {
            let x = x as f32 + 0.5;
            let past = (x_lo - x).max(x - x_hi).max(0.0);
            let side = match (past > 0.0, reach > 0.0) {
                (false, _) => 1.0,
                (true, true) => (-0.5 * (past / reach).powi(2)).exp(),
                (true, false) => 0.0,
            };
            let mut top = Top {
                row: row_at(&line, x),
                fall,
                side,
                sure: ledge.sure.clamp(0.0, 1.0),
                start: 0.0,
                ramp: 0.0,
                strength: 1.0,
            };
            if let Some(warp) = ledge.warp {
                let u = arc_at(ledge.line, x);
                let water = warp.water(u) * warp.drain() * ledge.catch.max(0.0);
                top.strength = warp.strength(water);
                top.fall = fall * water.clamp(SHORTEST, LONGEST);
                top.start = onset * warp.onset(u);
                top.ramp = onset;
            }
            column.push(top);
        }
    }
    if let Some(edge) = top_edge {
        for (column, row) in columns.iter_mut().zip(edge) {
            if let Some(y) = row {
                column.push(Top {
                    row: *y as f32,
                    fall,
                    side: 1.0,
                    sure: 1.0,
                    start: 0.0,
                    ramp: 0.0,
                    strength: 1.0,
                });
            }
        }
    }
    columns
        .iter_mut()
        .for_each(|c| c.sort_by(|a, b| a.row.total_cmp(&b.row)));
    let mut fade = RowMajor::filled(width, height, 0.0);
    let mut depth = RowMajor::filled(width, height, 0.0);
    fade.data_mut()
        .par_chunks_mut(width.max(1))
        .zip(depth.data_mut().par_chunks_mut(width.max(1)))
        .enumerate()
        .for_each(|(y, (fades, depths))| {
            let y = y as f32 + 0.5;
            for ((v, t), sources) in fades.iter_mut().zip(depths).zip(&columns) {
                let above = sources.partition_point(|s| s.row <= y);
                (*v, *t) = seen(sources[..above].iter().rev(), y, 1.0, (0.0, 0.0), DOUBTS);
            }
        });
    Fall { fade, depth }
}

/// The most doubtful ledges above a pixel [`seen`] weighs both ways; the
/// ones above them count as sure.
const DOUBTS: u32 = 6;

/// The fade and depth at row `y` under `sources` (nearest first) whose
/// water reaches it with share `through`, the best seen so far `best`:
/// the nearest source takes the water; past its ends (side < 1) and above
/// its streaks' onset, the sources above it show through the rest (no
/// clean line under a ledge that lies in another's streaks). A ledge the
/// analysis is unsure of ([`sure`] < 1) is there with that chance: the
/// fade is the mean of the two walls, with it and without it (up to
/// `doubts` such ledges; 1 when every ledge is sure: the fade of before).
fn seen<'a>(
    mut sources: impl Iterator<Item = &'a Top> + Clone,
    y: f32,
    through: f32,
    best: (f32, f32),
    doubts: u32,
) -> (f32, f32) {
    let Some(s) = sources.next() else {
        return best;
    };
    if through <= 0.0 {
        return best;
    }
    let d = y - s.row;
    let (value, depth) = s.at(d);
    let there = match through * value > best.0 {
        true => (through * value, depth),
        false => best,
    };
    let with = seen(
        sources.clone(),
        y,
        through * (1.0 - s.side * s.onset(d)),
        there,
        doubts,
    );
    if s.sure >= 1.0 || doubts == 0 {
        return with;
    }
    let without = seen(sources, y, through, best, doubts - 1);
    let q = s.sure;
    (
        q * with.0 + (1.0 - q) * without.0,
        q * with.1 + (1.0 - q) * without.1,
    )
}

/// Streaks widen and fade as they fall: `narrow` becomes `narrow` near
/// its source, blending into `wide` (the same stain blurred more) at the
/// fall length, times the fade.
pub fn widen(narrow: &mut RowMajor<f32>, wide: &RowMajor<f32>, fall: &Fall) {
    narrow
        .data_mut()
        .par_iter_mut()
        .zip(wide.data())
        .zip(fall.fade.data().par_iter().zip(fall.depth.data()))
        .for_each(|((n, w), (f, t))| {
            if *f <= 0.0 {
                *n = 0.0;
                return;
            }
            *n = (*n + (*w - *n) * t) * f;
        });
}

/// The arc length (from its first vertex, in its own order) of the point
/// of polyline `pts` at column `x`; past its ends, the nearer end's.
fn arc_at(pts: &[(f32, f32)], x: f32) -> f32 {
    let mut arc = 0.0;
    for pair in pts.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        let seg = (b.0 - a.0).hypot(b.1 - a.1);
        let (lo, hi) = (a.0.min(b.0), a.0.max(b.0));
        if x >= lo && x <= hi {
            let t = if hi > lo {
                (x - a.0) / (b.0 - a.0)
            } else {
                0.0
            };
            return arc + seg * t;
        }
        arc += seg;
    }
    let (first, last) = (pts[0].0, pts[pts.len() - 1].0);
    if (x - first).abs() <= (x - last).abs() {
        0.0
    } else {
        arc
    }
}

/// The row at column `x` of a polyline sorted by x, clamped to its ends.
fn row_at(pts: &[[f32; 2]], x: f32) -> f32 {
    let (first, last) = (pts[0], pts[pts.len() - 1]);
    crate::effects::habitat::row_at(pts, x).unwrap_or(match x <= first[0] {
        true => first[1],
        false => last[1],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn uniform(line: &[(f32, f32)]) -> Ledge<'_> {
        Ledge {
            line,
            warp: None,
            catch: 1.0,
            sure: 1.0,
        }
    }

    /// A doubtful ledge (a joint taken for a sill) between a sure one above
    /// and the wall below: its own streaks show as much as it is sure, and
    /// the sure ledge's streaks run on through the rest instead of
    /// stopping in a straight line at the joint.
    #[test]
    fn a_doubtful_ledge_lets_the_streaks_from_above_run_through() {
        let lines = [
            vec![(0.0, 5.0), (10.0, 5.0)],
            vec![(0.0, 20.0), (10.0, 20.0)],
        ];
        let fade_with = |sure: f32| {
            let mut ledges: Vec<_> = lines.iter().map(|l| uniform(l)).collect();
            ledges[1].sure = sure;
            fade(10, 60, &ledges, None, 30.0, 0.0, 0.0).fade
        };
        let (sure, doubtful) = (fade_with(1.0), fade_with(super::sure(0.2, SURE_AT)));
        // Just above and just below the joint: a step with a sure ledge
        // (the lower one restarts the fall at full strength) ...
        let above = sure.get(4, 19);
        assert!(sure.get(4, 21) > above + 0.3, "{above} {}", sure.get(4, 21));
        // ... and none to speak of with a doubtful one: the streak from
        // above runs on.
        let step = doubtful.get(4, 21) - doubtful.get(4, 19);
        assert!(step.abs() < 0.1, "step {step} at the doubtful joint");
        assert!(doubtful.get(4, 21) < 0.8 * sure.get(4, 21));
        assert_eq!(super::sure(0.2, 0.0), 1.0, "sure_at 0: every ledge in full");
        assert_eq!(super::sure(0.9, SURE_AT), 1.0);
    }

    #[test]
    fn nothing_above_the_source_and_a_tenth_at_the_fall() {
        let line = vec![(2.0, 10.0), (8.0, 10.0)];
        let f = fade(12, 60, &[uniform(&line)], None, 20.0, 1.0, 0.0).fade;
        assert_eq!(f.get(5, 5), 0.0, "above the ledge");
        assert!(f.get(5, 10) > 0.99, "just below it");
        assert!((f.get(5, 30) - 0.1).abs() < 0.02, "{}", f.get(5, 30));
        assert!(f.get(11, 30) < 1e-3, "beside the ledge, past its reach");
        assert!(f.get(8, 30) > 0.05, "within the reach of its end");
    }

    #[test]
    fn a_lower_source_restarts_the_fall() {
        let lines = [
            vec![(0.0, 5.0), (10.0, 5.0)],
            vec![(0.0, 40.0), (10.0, 40.0)],
        ];
        let ledges: Vec<_> = lines.iter().map(|l| uniform(l)).collect();
        let f = fade(10, 60, &ledges, None, 10.0, 0.0, 0.0).fade;
        assert!(f.get(4, 35) < 0.01);
        assert!(f.get(4, 41) > 0.9, "{}", f.get(4, 41));
    }

    #[test]
    fn the_top_edge_is_a_source_per_column() {
        let edge = vec![Some(3), None];
        let f = fade(2, 10, &[], Some(&edge), 0.0, 0.0, 0.0).fade;
        assert_eq!(f.get(0, 2), 0.0);
        assert_eq!(f.get(0, 5), 1.0);
        assert_eq!(f.get(1, 5), 0.0);
    }
}
