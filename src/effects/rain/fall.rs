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
//!
//! [choice, beyond the fade:] the dirt film (`stain.rs`) saturates, so a
//! streak's strength or its ledge's doubt folded into the coverage before
//! it showed only as length: forty rainfalls at a fifth of the coverage
//! still film `1 - (1 - 0.2 / 4)^40 = 0.87` of a spot, and a ledge at
//! confidence 0.1 streaked like a sure one (blind review 28). So [`fade`]
//! also splits the fade into a [`Fall::shape`], where the streaks run as if
//! every one were full and every ledge sure, laid before the film, and a
//! [`Fall::gain`] the film's alpha is multiplied by after it
//! (`rain.after_film`): the mean, over the walls with and without each
//! doubtful ledge, of the strength of the streak that runs there, so a
//! streak's final darkness is proportional to its strength and its
//! ledge's sureness.
//!
//! [choice, `rain.breaks`:] a line the photo shows below a source (a
//! course's shadow the analysis did not keep, [`super::breaks::caught`])
//! catches most of the water running down to it: each source's fade is
//! also times the share that passes the lines below it, so its streaks
//! stop softly there with no new source below.

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
    /// The water caught by lines the photo shows down to where this
    /// source's own streak is under way ([`super::breaks::caught`]'s
    /// running sum there; 0 without it).
    caught: f32,
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

    /// The share of this source's water that passes the lines the photo
    /// shows above a pixel whose running sum of caught water is `caught`.
    fn passes(&self, caught: f32) -> f32 {
        (-(caught - self.caught).max(0.0)).exp()
    }

    /// The fade `d` pixels below the source at `strength` (the streak's
    /// own, or 1), and how far down its fall that is (0..1).
    fn at(&self, d: f32, strength: f32) -> (f32, f32) {
        let onset = self.onset(d);
        let (fall, depth) = if self.fall > 0.0 {
            let t = d / self.fall;
            ((-LN_10 * t * t).exp(), t.min(1.0))
        } else {
            (1.0, 0.0)
        };
        (strength * self.side * onset * fall, depth)
    }
}

/// Where streaks show below their sources ([`fade`]).
#[derive(Debug, Clone)]
pub struct Fall {
    /// How much of the stain shows, 0..1: strengths and doubts included.
    pub fade: RowMajor<f32>,
    /// How far down its fall each pixel lies, 0..1 (1 at or past the
    /// fall length): how much a streak has widened there.
    pub depth: RowMajor<f32>,
    /// Where streaks run, 0..1, every streak at full strength and every
    /// ledge sure (the fade before the film when the gain is laid after).
    pub shape: RowMajor<f32>,
    /// How strong the streak running at each pixel is, 0..1: its
    /// strength, weighed over the walls with and without each doubtful
    /// ledge ([`seen`]); `shape * gain` is about `fade`.
    pub gain: RowMajor<f32>,
}

impl Fall {
    /// The fade laid before the film: [`Fall::shape`] when the gain is
    /// laid after it (`after`), else [`Fall::fade`].
    pub fn before_film(&self, after: bool) -> &RowMajor<f32> {
        match after {
            true => &self.shape,
            false => &self.fade,
        }
    }
}

/// The fade map on a `width` x `height` grid for source ledges and,
/// optionally, a top-edge row per column; each ledge's fade dies out past
/// its ends over `reach` columns (water runs off a ledge's ends), and its
/// streaks begin `onset` pixels or so below it. `fall` <= 0 gives 1
/// everywhere below a source. With `caught` ([`Caught`]), a source's
/// fade is also times the share of its water that passes the lines the
/// photo shows below it, counted from [`CAUGHT_FROM`] onsets below it
/// (its own shadow line is not a break) or from `caught.run` below it,
/// whichever is further (no short piece of run between the source and a
/// line, [`super::breaks::RUN_M`]).
#[allow(clippy::too_many_arguments)]
pub fn fade(
    width: usize,
    height: usize,
    ledges: &[Ledge],
    top_edge: Option<&[Option<usize>]>,
    fall: f32,
    reach: f32,
    onset: f32,
    caught: Option<Caught>,
) -> Fall {
    let caught_at = |x: usize, row: f32| match caught {
        Some(c) if height > 0 => {
            let from = (CAUGHT_FROM * onset.max(1.0)).max(c.run);
            let below = (row + from).floor().max(0.0) as usize;
            c.sum.get(x, below.min(height - 1))
        }
        _ => 0.0,
    };
    let caught = caught.map(|c| c.sum);
    // Per column, the sources crossing it or reaching it.
    let mut columns: Vec<Vec<Top>> = vec![Vec::new(); width];
    for ledge in ledges.iter().filter(|l| !l.line.is_empty()) {
        let mut line: Vec<[f32; 2]> = ledge.line.iter().map(|&(x, y)| [x, y]).collect();
        line.sort_by(|a, b| a[0].total_cmp(&b[0]));
        let (x_lo, x_hi) = (line[0][0], line[line.len() - 1][0]);
        let first = (x_lo - SIDE_REACHES * reach).floor().max(0.0) as usize;
        let last =
            ((x_hi + SIDE_REACHES * reach).ceil().max(0.0) as usize).min(width.saturating_sub(1));
        for (column_x, column) in columns.iter_mut().enumerate().take(last + 1).skip(first) {
            let x = column_x as f32 + 0.5;
            let past = (x_lo - x).max(x - x_hi).max(0.0);
            let side = match (past > 0.0, reach > 0.0) {
                (false, _) => 1.0,
                (true, true) => (-0.5 * (past / reach).powi(2)).exp(),
                (true, false) => 0.0,
            };
            let row = row_at(&line, x);
            let mut top = Top {
                row,
                fall,
                side,
                sure: ledge.sure.clamp(0.0, 1.0),
                start: 0.0,
                ramp: 0.0,
                strength: 1.0,
                caught: caught_at(column_x, row),
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
        for (x, (column, row)) in columns.iter_mut().zip(edge).enumerate() {
            if let Some(y) = row {
                column.push(Top {
                    row: *y as f32,
                    fall,
                    side: 1.0,
                    sure: 1.0,
                    start: 0.0,
                    ramp: 0.0,
                    strength: 1.0,
                    caught: caught_at(x, *y as f32),
                });
            }
        }
    }
    columns
        .iter_mut()
        .for_each(|c| c.sort_by(|a, b| a.row.total_cmp(&b.row)));
    let mut fade = RowMajor::filled(width, height, 0.0);
    let mut depth = RowMajor::filled(width, height, 0.0);
    let mut shape = RowMajor::filled(width, height, 0.0);
    let mut gain = RowMajor::filled(width, height, 0.0);
    let w = width.max(1);
    fade.data_mut()
        .par_chunks_mut(w)
        .zip(depth.data_mut().par_chunks_mut(w))
        .zip(shape.data_mut().par_chunks_mut(w))
        .zip(gain.data_mut().par_chunks_mut(w))
        .enumerate()
        .for_each(|(row, (((fades, depths), shapes), gains))| {
            let y = row as f32 + 0.5;
            for (x, sources) in columns.iter().enumerate() {
                let above = sources.partition_point(|s| s.row <= y);
                let at = Pixel {
                    y,
                    caught: caught.map_or(0.0, |c| c.get(x, row)),
                };
                let v = seen(sources[..above].iter().rev(), at, 1.0, Seen::NONE, DOUBTS);
                (fades[x], depths[x], shapes[x], gains[x]) = (v.fade, v.depth, v.shape, v.gain);
            }
        });
    Fall {
        fade,
        depth,
        shape,
        gain,
    }
}

/// `fall`'s gain ([`Fall::gain`]), or `None` when it is 1 wherever a
/// streak runs (every streak full and every ledge sure: nothing to scale).
pub fn gain_where_it_runs(fall: &Fall) -> Option<RowMajor<f32>> {
    let full = fall
        .gain
        .data()
        .par_iter()
        .zip(fall.shape.data())
        .all(|(g, s)| *g == 1.0 || *s <= 0.0);
    (!full).then(|| fall.gain.clone())
}

/// What [`seen`] finds at a pixel.
#[derive(Debug, Clone, Copy)]
struct Seen {
    /// The fade, strengths and doubts included, and its depth.
    fade: f32,
    depth: f32,
    /// The fade at full strength in the likeliest-streaked wall, and the
    /// strength of the streak there ([`Fall::shape`], [`Fall::gain`]).
    shape: f32,
    gain: f32,
}

impl Seen {
    const NONE: Seen = Seen {
        fade: 0.0,
        depth: 0.0,
        shape: 0.0,
        gain: 0.0,
    };
}

/// The share of the strongest wall's shape at which another wall's streak
/// counts in full toward the gain [choice: 0.5. After forty rainfalls the
/// film takes a streak at half the coverage of another to nearly the same
/// dark (`1 - (1 - 0.5 a / 4)^40` against `1 - (1 - a / 4)^40`: 0.92 of it
/// at a = 0.5), so a doubtful ledge inside the streaks from a sure one
/// above leaves no step where it lies].
const FULL_SHARE: f32 = 0.5;

/// The most doubtful ledges above a pixel [`seen`] weighs both ways; the
/// ones above them count as sure.
const DOUBTS: u32 = 6;

/// How many onsets below a source the lines the photo shows begin to
/// catch its water ([`fade`]'s `caught`) [choice: 2, about 0.1 m: the
/// shadow a ledge casts on the wall right under it is its own line].
const CAUGHT_FROM: f32 = 2.0;

/// The water caught by the lines the photo shows, for [`fade`].
#[derive(Debug, Clone, Copy)]
pub struct Caught<'a> {
    /// [`super::breaks::caught`]'s running sum down each column.
    pub sum: &'a RowMajor<f32>,
    /// How far below a source, grid pixels, the lines begin to catch its
    /// water at the least ([`super::breaks::RUN_M`]; 0 = from
    /// [`CAUGHT_FROM`] onsets).
    pub run: f32,
}

/// A pixel [`seen`] looks at: its row's centre, and the running sum of
/// the water caught above it ([`super::breaks::caught`]).
#[derive(Debug, Clone, Copy)]
struct Pixel {
    y: f32,
    caught: f32,
}

/// The fade and depth at row `y` under `sources` (nearest first) whose
/// water reaches it with share `through`, the best seen so far `best`:
/// the nearest source takes the water; past its ends (side < 1) and above
/// its streaks' onset, the sources above it show through the rest (no
/// clean line under a ledge that lies in another's streaks). A ledge the
/// analysis is unsure of ([`sure`] < 1) is there with that chance: the
/// fade is the mean of the two walls, with it and without it (up to
/// `doubts` such ledges; 1 when every ledge is sure: the fade of before).
///
/// The shape and gain of the same walls: the shape is the fade at full
/// strength of the wall with the most of it, and the gain the mean over
/// the walls of the strength of the streak each shows there, a wall
/// counting in full when its own shape is at least [`FULL_SHARE`] of that
/// most (else in proportion): a lone doubtful ledge's streaks have the
/// shape of a sure one's and its sureness as gain.
fn seen<'a>(
    mut sources: impl Iterator<Item = &'a Top> + Clone,
    at: Pixel,
    through: f32,
    best: Seen,
    doubts: u32,
) -> Seen {
    let Some(s) = sources.next() else {
        return best;
    };
    if through <= 0.0 {
        return best;
    }
    let d = at.y - s.row;
    let passes = s.passes(at.caught);
    let (value, depth) = s.at(d, s.strength);
    let (full, _) = s.at(d, 1.0);
    let (value, full) = (value * passes, full * passes);
    let mut there = best;
    if through * value > best.fade {
        (there.fade, there.depth) = (through * value, depth);
    }
    if through * full > best.shape {
        (there.shape, there.gain) = (through * full, s.strength);
    }
    let with = seen(
        sources.clone(),
        at,
        through * (1.0 - s.side * s.onset(d)),
        there,
        doubts,
    );
    if s.sure >= 1.0 || doubts == 0 {
        return with;
    }
    let without = seen(sources, at, through, best, doubts - 1);
    let q = s.sure;
    let shape = with.shape.max(without.shape);
    let counts = |v: f32| match shape > 0.0 {
        true => (v / (FULL_SHARE * shape)).min(1.0),
        false => 0.0,
    };
    Seen {
        fade: q * with.fade + (1.0 - q) * without.fade,
        depth: q * with.depth + (1.0 - q) * without.depth,
        shape,
        gain: q * with.gain * counts(with.shape) + (1.0 - q) * without.gain * counts(without.shape),
    }
}

/// How far down its fall a streak has spread into the wide blur, as a
/// share of the fall [choice: 0.5, with a smoothstep. `how-facades-age.md`:
/// "narrow at the release point, wider and fainter over a fall of about
/// 0.5 to 2 m": the run's water spreads sideways as it falls. Blended
/// linearly over the whole fall, the stain was still mostly narrow where
/// the Gaussian fade had taken most of it, so every visible edge closed to
/// a point: the "icicle-tipped daggers under the sills" of blind review
/// p44 and later. Measured on the one-ledge wall (`tests/streaks.rs`),
/// the width over half its row's darkest at 20 / 50 / 80% of a streak's
/// length: 22.6 / 20.8 / 20.6 columns on main; 0.5 with the smoothstep
/// and `SPREAD_M` 0.2, 23.1 / 37.2 / 42.8 (the top as narrow as before);
/// linear to 0.5, 23.5 / 33.6 / 42.3; smoothstep to 0.35, 27.3 / 63.4 /
/// 38.8 (the top wider, a darker band under the ledge); linear to 0.3,
/// 33.9 / 36.4 / 28.8 with `SPREAD_M` 0.1].
pub const SPREAD_BY: f32 = 0.5;

/// How much of the wide blur a streak shows at `depth` (0..1) down its
/// fall ([`SPREAD_BY`]).
fn spread(depth: f32) -> f32 {
    crate::random::smoothstep((depth / SPREAD_BY).clamp(0.0, 1.0))
}

/// Streaks widen and fade as they fall: `narrow` becomes `narrow` near
/// its source, blending into `wide` (the same stain blurred more) by
/// [`SPREAD_BY`] of the fall length, times `fade` ([`Fall::before_film`]).
/// Both blurs keep a row's ink, so the blend does too: the fade alone sets
/// how much a row holds, the blend how wide it lies (the peak falls as the
/// ink over the width).
pub fn widen(narrow: &mut RowMajor<f32>, wide: &RowMajor<f32>, fade: &RowMajor<f32>, fall: &Fall) {
    narrow
        .data_mut()
        .par_iter_mut()
        .zip(wide.data())
        .zip(fade.data().par_iter().zip(fall.depth.data()))
        .for_each(|((n, w), (f, t))| {
            if *f <= 0.0 {
                *n = 0.0;
                return;
            }
            *n = (*n + (*w - *n) * spread(*t)) * f;
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
            fade(10, 60, &ledges, None, 30.0, 0.0, 0.0, None).fade
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

    /// A lone ledge the analysis is unsure of: its streaks run as a sure
    /// one's before the film (the shape) and its sureness is their gain
    /// after it, so their final darkness is in proportion (folded into
    /// the fade before the film, the film took them to nearly the same
    /// dark).
    #[test]
    fn a_lone_doubtful_ledge_keeps_its_shape_and_takes_its_sureness_as_gain() {
        let line = vec![(0.0, 5.0), (10.0, 5.0)];
        let mut ledge = uniform(&line);
        let sure = fade(10, 40, &[ledge], None, 20.0, 0.0, 0.0, None);
        ledge.sure = 0.2;
        let doubtful = fade(10, 40, &[ledge], None, 20.0, 0.0, 0.0, None);
        assert_eq!(doubtful.shape.data(), sure.fade.data());
        for (i, s) in doubtful.shape.data().iter().enumerate() {
            if *s > 0.0 {
                assert!((doubtful.gain.data()[i] - 0.2).abs() < 1e-6);
                assert!((doubtful.fade.data()[i] - 0.2 * s).abs() < 1e-6);
            }
        }
        assert!(gain_where_it_runs(&sure).is_none(), "a sure ledge: no gain");
        assert!(gain_where_it_runs(&doubtful).is_some());
    }

    /// A doubtful ledge inside the streaks of a sure one above: the
    /// streaks from above run on through it, so the gain has no step
    /// where it lies (the film takes both walls' streaks to the same dark
    /// there), and falls toward its sureness below, where only its own
    /// streaks would reach.
    #[test]
    fn a_doubtful_ledge_in_a_sure_ones_streaks_leaves_no_step_in_the_gain() {
        let lines = [
            vec![(0.0, 5.0), (10.0, 5.0)],
            vec![(0.0, 20.0), (10.0, 20.0)],
        ];
        let mut ledges: Vec<_> = lines.iter().map(|l| uniform(l)).collect();
        ledges[1].sure = 0.2;
        let f = fade(10, 80, &ledges, None, 30.0, 0.0, 0.0, None);
        let (above, below) = (f.gain.get(4, 19), f.gain.get(4, 21));
        assert_eq!(above, 1.0);
        assert!(
            below > 0.95,
            "gain {above} -> {below} at the doubtful joint"
        );
        let low = f.gain.get(4, 45);
        assert!((0.2..0.6).contains(&low), "gain {low} far below it");
    }

    #[test]
    fn nothing_above_the_source_and_a_tenth_at_the_fall() {
        let line = vec![(2.0, 10.0), (8.0, 10.0)];
        let f = fade(12, 60, &[uniform(&line)], None, 20.0, 1.0, 0.0, None).fade;
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
        let f = fade(10, 60, &ledges, None, 10.0, 0.0, 0.0, None).fade;
        assert!(f.get(4, 35) < 0.01);
        assert!(f.get(4, 41) > 0.9, "{}", f.get(4, 41));
    }

    #[test]
    fn the_top_edge_is_a_source_per_column() {
        let edge = vec![Some(3), None];
        let f = fade(2, 10, &[], Some(&edge), 0.0, 0.0, 0.0, None).fade;
        assert_eq!(f.get(0, 2), 0.0);
        assert_eq!(f.get(0, 5), 1.0);
        assert_eq!(f.get(1, 5), 0.0);
    }

    /// A line the photo shows below a source (a course the analysis did
    /// not keep): the streak's fade falls past it to the share that
    /// passes, softly, and a source below the line is not dimmed by it.
    #[test]
    fn a_line_in_the_photo_catches_the_water_from_above() {
        let lines = [
            vec![(0.0, 5.0), (10.0, 5.0)],
            vec![(0.0, 50.0), (10.0, 50.0)],
        ];
        let ledges: Vec<_> = lines.iter().map(|l| uniform(l)).collect();
        // Half the water caught over rows 20..24 (ln 2 spread over them).
        let caught = RowMajor::from_fn(10, 80, |_, y| {
            std::f32::consts::LN_2 * ((y as f32 - 19.0).clamp(0.0, 4.0) / 4.0)
        });
        let plain = fade(10, 80, &ledges, None, 200.0, 0.0, 1.0, None).fade;
        let broken = fade(
            10,
            80,
            &ledges,
            None,
            200.0,
            0.0,
            1.0,
            Some(Caught {
                sum: &caught,
                run: 0.0,
            }),
        )
        .fade;
        assert_eq!(broken.get(4, 18), plain.get(4, 18), "above the line");
        let ratio = broken.get(4, 30) / plain.get(4, 30);
        assert!((ratio - 0.5).abs() < 1e-3, "past it: {ratio}");
        let mid = broken.get(4, 21) / plain.get(4, 21);
        assert!(mid > 0.55 && mid < 0.95, "a soft stop: {mid}");
        assert_eq!(
            broken.get(4, 60),
            plain.get(4, 60),
            "under the lower source"
        );
        // With the shortest run 20 rows, the line 15 rows below the upper
        // source leaves no short piece: its water runs on.
        let run = Caught {
            sum: &caught,
            run: 20.0,
        };
        let joined = fade(10, 80, &ledges, None, 200.0, 0.0, 1.0, Some(run)).fade;
        assert_eq!(joined.get(4, 30), plain.get(4, 30), "a line within the run");
    }
}
