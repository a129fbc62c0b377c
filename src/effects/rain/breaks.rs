//! Streaks break at the building's shape: water running down the wall to
//! a projecting ledge below its source is caught by it.
//!
//! [choice, beyond Chang, whose droplets run on down the wall until they
//! dry or leave it:] a projecting course, sill or window head collects the
//! water that runs down to it and releases it again at a few points
//! (`how-facades-age.md`, "Where water goes": "ledges collect it and
//! release it at a few points"; "a wall with sills every storey shows
//! short streaks that restart at each storey"). With the droplets running
//! on, a streak from a cornice crossed every course below it, and the
//! lower ledge's fade ([`super::fall`]) showed the cornice's runs below it
//! as if they were its own: blind check p44 saw streaks "cross projecting
//! courses, drip edges and rustication as an overlay, like tree shadows".
//!
//! So the wall the droplets run on ([`cut`]) leaves out a strip
//! [`GAP`] rows high just above each sure ledge's line, over the ledge's
//! span, wherever a source lies above it: a droplet reaching the strip
//! leaves the wall there (its water and dirt go onto the ledge's top),
//! and the ledge's own droplets start on its line, below the strip. Below
//! a course only its own drip points' streaks run; the cornice's stop on
//! its top. The stain's blur ([`crate::preset::StainParams`]'s `blur_m`)
//! softens the stop over a few centimetres.
//!
//! [choice:] a course the analysis did not keep as a ledge still shows in
//! the photo as a long, lone horizontal line, bright above and dark below
//! (its lit face over the shadow it casts). [`caught`] finds such lines
//! ([`edge_catch`]) and gives the share of the water running down that
//! they catch, as a running sum down each column that [`super::fall`]
//! uses: the fade of a streak from above falls past such a line to
//! [`1 - EDGE_CATCH`] of itself, over [`SOFT_M`] (a break without a new
//! source).

use crate::effects::habitat::row_at;
use crate::field::RowMajor;

/// Rows left out of the wall above a ledge's line [choice: 2, so a droplet
/// moving at most `rain.v_max` (1 pixel) a step cannot step over the strip;
/// the row just above the line stays wall, so the ledge's own droplets,
/// which start on the line, begin inside it].
pub const GAP: usize = 2;

/// A ledge for [`cut`]: its line in grid pixels and how sure the analysis
/// is of it ([`super::fall::sure`]).
#[derive(Debug, Clone, Copy)]
pub struct Catcher<'a> {
    /// The polyline, grid coordinates.
    pub line: &'a [(f32, f32)],
    /// 0..1: only a sure ledge (1) catches the water [choice: a doubtful
    /// one is as often a joint of rusticated stone or a shutter's edge
    /// (`fall::SURE_AT`), which water runs across; the fade lets the
    /// streaks from above run on through it in proportion].
    pub sure: f32,
}

/// Fills the strips [`cut`] left out of `region` (`cut`: the region the
/// droplets ran on) in a map of the rain's output (its wall water or
/// dirt): a ledge's top is as wet and as dirty as the wall just above or
/// just below it, whichever is more [choice: the water the strip stopped
/// ran onto the ledge; left at 0, moss no longer grew on the ledges' tops
/// (`how-facades-age.md`: moss holds to sill and cornice tops)].
pub fn fill(map: &mut RowMajor<f32>, region: &RowMajor<bool>, cut: &RowMajor<bool>) {
    let (width, height) = (map.width(), map.height());
    for x in 0..width {
        // A strip pixel: in the region, not run on.
        let strip = |y: usize| region.get(x, y) && !cut.get(x, y);
        let mut y = 0;
        while y < height {
            if !strip(y) {
                y += 1;
                continue;
            }
            let start = y;
            while y < height && strip(y) {
                y += 1;
            }
            let above = (start > 0 && cut.get(x, start - 1)).then(|| map.get(x, start - 1));
            let below = (y < height && cut.get(x, y)).then(|| map.get(x, y));
            let value = above.into_iter().chain(below).fold(0.0, f32::max);
            for r in start..y {
                let i = map.index(x, r);
                map.data_mut()[i] = value;
            }
        }
    }
}

/// The tallest course [`course_top`] looks for above a ledge's line,
/// metres [choice: 0.45 m; string and sill courses are 0.15 to 0.4 m tall].
pub const COURSE_M: f32 = 0.45;

/// The least step up in luma (0..255), from the wall above to a course's
/// lit face below, that [`course_top`] takes for a course's top [choice:
/// 20 levels. img-manmade6's sill course steps up 60 to 110 from the
/// glass and 25 to 40 from the wall between the windows; a rusticated
/// stone's joint is a dark line, a step down and up again, which the
/// span's mean smooths out].
const STEP: f32 = 20.0;

/// The shortest run of water between two breaks, metres: a ledge catches
/// the water from above only where the nearest source above it lies at
/// least this far up [choice: 0.9 m. Cut shorter, the piece of run between
/// the two (the upper source's own streak, stopped at the lower one's
/// strip) is a blob a few times as long as it is wide that starts and
/// stops in mid-wall: blind check p50 saw "round dark blotches on the
/// brick not tied to anything" on IMG_6586, whose brick bands lie 0.5 to
/// 0.9 m apart. Not cut, the piece joins the run below, as the droplets
/// did without breaks; a streak 0.9 m long, 5 to 9 times as long as it is
/// wide (0.1 to 0.2 m), reads as a streak (`how-facades-age.md`: "short
/// streaks that restart at each storey", a storey being about 3 m). At 1 m
/// a course exactly 1 m under a cornice (`tests/breaks.rs`) fell on the
/// threshold].
pub const RUN_M: f32 = 0.9;

/// The least sureness of a source above a ledge that counts as the start
/// of a run for [`RUN_M`] [choice: 0.5; a fainter source's streaks show
/// at under half their strength (`fall::sure`), so its short piece is
/// faint, and a doubtful line close above a course (a joint, a shutter's
/// edge) should not keep the course from catching the water from higher
/// up].
const RUN_FROM_SURE: f32 = 0.5;

/// The region the droplets run on: `region` without a strip just above
/// each sure ledge of `ledges` (grid coordinates, `luma` 0..255 the wall's
/// on the grid), in the columns where the nearest source above it
/// (another ledge's line at least [`RUN_FROM_SURE`] sure, or the region's
/// top edge when `top_edge`) lies at least `run` grid pixels up
/// ([`RUN_M`]); `None` when nothing is cut. The strip runs from the row
/// above the course's top ([`course_top`], at most `course` grid pixels
/// above the line) or, when none is seen, [`GAP`] rows above the line,
/// down to the row above it.
pub fn cut(
    region: &RowMajor<bool>,
    luma: &RowMajor<f32>,
    ledges: &[Catcher],
    top_edge: bool,
    course: f32,
    run: f32,
) -> Option<RowMajor<bool>> {
    let (width, height) = (region.width(), region.height());
    // Per column, the rows of the lines crossing it.
    let mut rows = vec![Vec::new(); width];
    let mut spans = Vec::with_capacity(ledges.len());
    for ledge in ledges {
        let span = crossings(ledge.line, width);
        if ledge.sure >= RUN_FROM_SURE {
            for &(x, row) in &span {
                rows[x].push(row);
            }
        }
        spans.push(span);
    }
    // Per column, the region's top edge when it is a source.
    let tops: Vec<Option<f32>> = (0..width)
        .map(|x| match top_edge {
            true => (0..height).find(|&y| region.get(x, y)).map(|y| y as f32),
            false => None,
        })
        .collect();
    let mut out: Option<RowMajor<bool>> = None;
    for (ledge, span) in ledges.iter().zip(&spans) {
        if ledge.sure < 1.0 {
            continue;
        }
        let strip = course_top(luma, span, course).unwrap_or(0).max(GAP);
        let reach = strip as f32 + 1.0;
        for &(x, row) in span {
            // The nearest source above, past the strip.
            let nearest = tops[x]
                .into_iter()
                .chain(rows[x].iter().copied())
                .filter(|&r| r < row - reach)
                .reduce(f32::max);
            if !nearest.is_some_and(|r| row - r >= run) {
                continue;
            }
            // The droplets start on row floor(row) (`Source::point`); the
            // strip ends a row above it.
            let end = row.floor() as isize - 1;
            for y in (end - strip as isize)..end {
                if (0..height as isize).contains(&y) && region.get(x, y as usize) {
                    let out = out.get_or_insert_with(|| region.clone());
                    let i = out.index(x, y as usize);
                    out.data_mut()[i] = false;
                }
            }
        }
    }
    out
}

/// How many rows above a ledge's line its course's top lies, when the
/// photo shows one: the largest step up in luma, from above to below,
/// `3..course` rows above the line in the mean over the ledge's span
/// (`span`: its columns and rows), at least [`STEP`]; `None` when there
/// is none. A projecting course catches the water on its top and shows
/// a lit face below it down to its drip edge, the line the analysis finds
/// (blind check p44: img-manmade6's streaks ran down over the sill
/// course's face).
fn course_top(luma: &RowMajor<f32>, span: &[(usize, f32)], course: f32) -> Option<usize> {
    let (height, most) = (luma.height() as isize, course.floor() as usize);
    if span.is_empty() || most < 4 {
        return None;
    }
    // The span's mean luma k rows above its line, k = 0..=most + 1.
    let mean: Vec<f32> = (0..=most + 1)
        .map(|k| {
            let (mut sum, mut n) = (0.0, 0);
            for &(x, row) in span {
                let y = row.floor() as isize - k as isize;
                if (0..height).contains(&y) {
                    sum += luma.get(x, y as usize);
                    n += 1;
                }
            }
            if n > 0 { sum / n as f32 } else { f32::NAN }
        })
        .collect();
    // The step between rows k (the face's top row) and k + 1 (above it).
    (3..=most)
        .map(|k| (k, mean[k] - mean[k + 1]))
        .filter(|(_, step)| *step >= STEP)
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(k, _)| k)
}

/// The most of the water running down that a line seen only in the photo
/// catches [choice: 0.8; the analysis did not keep it, so it may be a
/// flush band of another colour, which water runs across: the water that
/// goes on is much fainter, not gone].
pub const EDGE_CATCH: f32 = 0.8;

/// The step (luma 0..255, the mean of two rows above a row boundary
/// minus the two below, averaged along [`ALONG_M`]) at which a line
/// begins to catch, and over how much more it catches in full [choice:
/// 12 and 24: img-manmade6's course shadow steps 40 to 90; a streak's own
/// edges are vertical and a window's head is glass below, out of the
/// wall].
const EDGE_FROM: f32 = 12.0;
const EDGE_OVER: f32 = 24.0;

/// Half the length a line's step is averaged along, metres [choice: 0.3;
/// a course runs metres, a block's or a shutter's edge less].
const ALONG_M: f32 = 0.3;

/// How far above and below a line no other line as strong may lie for it
/// to count, metres [choice: 0.25: a course stands alone on a plain wall;
/// brick courses (0.075 m) and rusticated joints come in rows, which water
/// runs down across (`how-facades-age.md`: growth and dirt keep the
/// joints' relief)]. The rows within [`NEAR_ROWS`] of it are its own edge.
const LONE_M: f32 = 0.25;
const NEAR_ROWS: usize = 3;

/// How far a line's catch is spread down the wall, metres [choice: 0.04,
/// a soft stop of a few centimetres rather than a cut].
pub const SOFT_M: f32 = 0.04;

/// The water caught by lines the photo shows ([`edge_catch`]) as a running
/// sum down each column of `-ln(1 - catch)`, spread over [`SOFT_M`]: the
/// share of the water running from row a down to row b that passes is
/// `exp(-(sum(b) - sum(a)))`. `luma` 0..255 and `region` on the grid,
/// `px_per_m` grid pixels a metre.
pub fn caught(luma: &RowMajor<f32>, region: &RowMajor<bool>, px_per_m: f32) -> RowMajor<f32> {
    let catch = edge_catch(luma, region, px_per_m);
    let (width, height) = (luma.width(), luma.height());
    let soft = (SOFT_M * px_per_m).round().max(1.0) as usize;
    let mut sum = RowMajor::filled(width, height, 0.0);
    for x in 0..width {
        let mut spread = vec![0.0f32; height + soft];
        for y in 0..height {
            let c = catch.get(x, y);
            if c > 0.0 {
                let e = -(1.0 - c.min(0.999)).ln() / soft as f32;
                spread[y..y + soft].iter_mut().for_each(|s| *s += e);
            }
        }
        let mut total = 0.0;
        for (y, e) in spread.iter().take(height).enumerate() {
            total += e;
            let i = sum.index(x, y);
            sum.data_mut()[i] = total;
        }
    }
    sum
}

/// The share of the water running down that a line the photo shows
/// catches at each row boundary (above row y), 0..[`EDGE_CATCH`]: the
/// step from above to below averaged along [`ALONG_M`] either side
/// (rows outside `region` count as no step, so a short line is weak),
/// when no step down as strong lies within [`LONE_M`] above or below it
/// (a course's own top, a step up to its lit face, does not count).
pub fn edge_catch(luma: &RowMajor<f32>, region: &RowMajor<bool>, px_per_m: f32) -> RowMajor<f32> {
    let (width, height) = (luma.width(), luma.height());
    let step = RowMajor::from_fn(width, height, |x, y| {
        if y < 2 || y + 2 > height {
            return 0.0;
        }
        let rows = [y - 2, y - 1, y, y + 1];
        if rows.iter().any(|&r| !region.get(x, r)) {
            return 0.0;
        }
        let l = |r: usize| luma.get(x, r);
        0.5 * (l(y - 2) + l(y - 1)) - 0.5 * (l(y) + l(y + 1))
    });
    let half = (ALONG_M * px_per_m).round().max(2.0) as usize;
    // Running sums along each row.
    let mut sums = vec![0.0f64; width + 1];
    let mut along = RowMajor::filled(width, height, 0.0);
    for y in 0..height {
        for x in 0..width {
            sums[x + 1] = sums[x] + step.get(x, y) as f64;
        }
        for x in 0..width {
            let (lo, hi) = (x.saturating_sub(half), (x + half).min(width - 1));
            let i = along.index(x, y);
            along.data_mut()[i] = ((sums[hi + 1] - sums[lo]) / (2 * half + 1) as f64) as f32;
        }
    }
    let lone = (LONE_M * px_per_m).round() as usize;
    RowMajor::from_fn(width, height, |x, y| {
        let s = along.get(x, y);
        if s <= EDGE_FROM {
            return 0.0;
        }
        let (lo, hi) = (y.saturating_sub(lone), (y + lone).min(height - 1));
        let other = (lo..=hi)
            .filter(|&r| r.abs_diff(y) > NEAR_ROWS)
            .map(|r| along.get(x, r))
            .fold(0.0, f32::max);
        // The line's own strongest row only (a line's step spreads over
        // a few rows).
        let near = (y.saturating_sub(NEAR_ROWS)..=(y + NEAR_ROWS).min(height - 1))
            .any(|r| along.get(x, r) > s || (along.get(x, r) == s && r < y));
        if near || other >= 0.75 * s {
            return 0.0;
        }
        let t = ((s - EDGE_FROM) / EDGE_OVER).clamp(0.0, 1.0);
        EDGE_CATCH * crate::random::smoothstep(t)
    })
}

/// The columns a polyline spans (pixel centres within its ends) and its
/// row at each.
fn crossings(line: &[(f32, f32)], width: usize) -> Vec<(usize, f32)> {
    let mut pts: Vec<[f32; 2]> = line.iter().map(|&(x, y)| [x, y]).collect();
    pts.sort_by(|a, b| a[0].total_cmp(&b[0]));
    let (Some(first), Some(last)) = (pts.first(), pts.last()) else {
        return Vec::new();
    };
    let lo = (first[0] - 0.5).ceil().max(0.0) as usize;
    let hi = ((last[0] - 0.5).floor().max(-1.0) + 1.0) as usize;
    (lo..hi.min(width))
        .filter_map(|x| row_at(&pts, x as f32 + 0.5).map(|row| (x, row)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sure_ledge_below_a_source_is_cut_above_its_line() {
        let region = RowMajor::filled(10, 40, true);
        let luma = RowMajor::filled(10, 40, 128.0);
        let (upper, lower) = (
            vec![(0.0, 5.0), (10.0, 5.0)],
            vec![(2.0, 20.0), (8.0, 20.0)],
        );
        let ledges = [
            Catcher {
                line: &upper,
                sure: 1.0,
            },
            Catcher {
                line: &lower,
                sure: 1.0,
            },
        ];
        let cut = cut(&region, &luma, &ledges, false, 8.0, 0.0).unwrap();
        // The strip, rows 17..19, within the lower ledge's span only.
        for y in 0..40 {
            assert_eq!(!cut.get(4, y), (17..19).contains(&y), "row {y}");
        }
        assert!(
            (0..40).all(|y| cut.get(0, y) && cut.get(9, y)),
            "past its ends"
        );
        // Nothing above the upper ledge (no top edge): not cut.
        assert!((0..10).all(|y| cut.get(4, y)));
        // A doubtful lower ledge catches nothing.
        let doubtful = [
            ledges[0],
            Catcher {
                sure: 0.9,
                ..ledges[1]
            },
        ];
        assert!(super::cut(&region, &luma, &doubtful, false, 8.0, 0.0).is_none());
        // With the top edge a source, the upper ledge is cut too.
        let both = super::cut(&region, &luma, &ledges, true, 8.0, 0.0).unwrap();
        assert!(!both.get(4, 2) && !both.get(4, 17));
    }

    /// A course drawn on the wall (a lit face 5 rows tall above the line):
    /// the strip runs from its top, so the streaks from above stop there
    /// and do not run down its face.
    #[test]
    fn the_strip_starts_at_a_drawn_courses_top() {
        let region = RowMajor::filled(10, 40, true);
        let luma = RowMajor::from_fn(10, 40, |_, y| match (15..20).contains(&y) {
            true => 200.0,
            false => 120.0,
        });
        let (upper, lower) = (
            vec![(0.0, 5.0), (10.0, 5.0)],
            vec![(0.0, 20.0), (10.0, 20.0)],
        );
        let ledges = [&upper, &lower].map(|line| Catcher { line, sure: 1.0 });
        let span = crossings(&lower, 10);
        assert_eq!(course_top(&luma, &span, 8.0), Some(5));
        let cut = cut(&region, &luma, &ledges, false, 8.0, 0.0).unwrap();
        for y in 0..40 {
            assert_eq!(!cut.get(4, y), (14..19).contains(&y), "row {y}");
        }
    }

    /// The rain on a wall under a cornice, a sure course below it: with the
    /// strip cut above the course the cornice's droplets leave the wall on
    /// it, and none of their dirt reaches the wall below it.
    #[test]
    fn the_cornices_droplets_stop_on_a_sure_course() {
        use crate::effects::rain::{RainInput, simulate, sources::Release};
        use crate::preset::RainParams;
        use crate::progress::Progress;
        let (w, h) = (64, 120);
        let luma = RowMajor::from_fn(w, h, |x, y| {
            120.0 + 30.0 * (((y * w + x) * 7919) % 13) as f32 / 13.0
        });
        let region = RowMajor::filled(w, h, true);
        let (cornice, course) = (
            vec![(2.0, 10.0), (62.0, 10.0)],
            vec![(2.0, 50.0), (62.0, 50.0)],
        );
        let ledges = [&cornice, &course].map(|line| Catcher { line, sure: 1.0 });
        let cut = cut(&region, &luma, &ledges, false, 8.0, 0.0).unwrap();
        let p = RainParams {
            layers: 3,
            droplets: 200,
            reference_width: 0,
            top_edge: false,
            ..RainParams::default()
        };
        let below = |region: &RowMajor<bool>| {
            let input = RainInput {
                luma: &luma,
                region,
                source_lines: vec![cornice.clone()],
                catch: vec![],
                release: Release::UNIFORM,
                washed: false,
            };
            let out = simulate(&input, &p, 5, &Progress::none()).unwrap();
            let sum = |rows: std::ops::Range<usize>| -> f32 {
                let mut s = 0.0;
                for l in &out.layers {
                    for x in 4..60 {
                        s += rows.clone().map(|y| l.deposit.get(x, y)).sum::<f32>();
                    }
                }
                s
            };
            (sum(30..46), sum(52..80))
        };
        let (above_run, below_run) = below(&region);
        let (above_cut, below_cut) = below(&cut);
        assert!(
            below_run > 0.2 * above_run,
            "{above_run} {below_run}: the droplets run on"
        );
        assert!(
            above_cut > 0.5 * above_run,
            "{above_cut}: the streaks above stay"
        );
        // Only the diffusion of the wall's dirt crosses the strip (0.0012
        // of the run's with this seed's droplets).
        assert!(
            below_cut < 2e-3 * below_run,
            "{below_run} -> {below_cut} below the course"
        );
    }

    /// Two sure courses 0.4 m apart under a cornice 1 m above the upper
    /// one, 40 grid pixels a metre: with the shortest run 0.9 m the lower
    /// course catches nothing (the upper one's runs join the run below it
    /// instead of stopping as a piece 0.4 m long) and the upper one still
    /// catches the cornice's water; with 0 (breaks25) both catch.
    #[test]
    fn a_course_close_below_another_lets_its_runs_join_the_run_below() {
        let region = RowMajor::filled(10, 120, true);
        let luma = RowMajor::filled(10, 120, 128.0);
        let lines = [
            vec![(0.0, 10.0), (10.0, 10.0)],
            vec![(0.0, 50.0), (10.0, 50.0)],
            vec![(0.0, 66.0), (10.0, 66.0)],
        ];
        let ledges = lines.each_ref().map(|line| Catcher { line, sure: 1.0 });
        let strip =
            |cut: &RowMajor<bool>, line: usize| (line - 3..line - 1).all(|y| !cut.get(4, y));
        let short = cut(&region, &luma, &ledges, false, 8.0, 0.0).unwrap();
        assert!(strip(&short, 50) && strip(&short, 66), "both cut");
        let run = cut(&region, &luma, &ledges, false, 8.0, RUN_M * 40.0).unwrap();
        assert!(
            strip(&run, 50),
            "the upper course catches the cornice's water"
        );
        assert!(
            (0..120).all(|y| run.get(4, y) || (47..49).contains(&y)),
            "the lower one none"
        );
        // A doubtful line between them (a joint) is no start of a run.
        let joint = vec![(0.0, 40.0), (10.0, 40.0)];
        let mut with_joint = ledges.to_vec();
        with_joint.push(Catcher {
            line: &joint,
            sure: 0.3,
        });
        let joint_cut = cut(&region, &luma, &with_joint, false, 8.0, RUN_M * 40.0).unwrap();
        assert!(strip(&joint_cut, 50), "a joint 0.25 m above");
    }

    /// A lone course shadow on a plain wall catches; the same line among
    /// rows of joints 0.075 m apart (brick courses) does not.
    #[test]
    fn a_lone_line_catches_and_rows_of_joints_do_not() {
        let px_per_m = 40.0;
        let region = RowMajor::filled(60, 80, true);
        let lone = RowMajor::from_fn(60, 80, |_, y| match (38..41).contains(&y) {
            true => 80.0,
            false => 170.0,
        });
        let catch = edge_catch(&lone, &region, px_per_m);
        let most = (0..80).map(|y| catch.get(30, y)).fold(0.0, f32::max);
        assert!((most - EDGE_CATCH).abs() < 1e-6, "{most}");
        assert!(catch.get(30, 38) > 0.0, "at the shadow's top");
        let rows = RowMajor::from_fn(60, 80, |_, y| match y % 3 == 0 {
            true => 80.0,
            false => 170.0,
        });
        let catch = edge_catch(&rows, &region, px_per_m);
        assert!(catch.data().iter().all(|&c| c == 0.0), "joints in rows");
        // Water from row 10 past the lone line: a fifth goes on.
        let sum = caught(&lone, &region, px_per_m);
        let passes = (-(sum.get(30, 70) - sum.get(30, 10))).exp();
        assert!((passes - (1.0 - EDGE_CATCH)).abs() < 1e-3, "{passes}");
    }

    /// The strip's water is the wetter of the wall's above and below it.
    #[test]
    fn a_strip_takes_the_wetter_neighbours_water() {
        let region = RowMajor::filled(1, 6, true);
        let ran = RowMajor::from_fn(1, 6, |_, y| !(2..4).contains(&y));
        let mut water = RowMajor::new(1, 6, vec![1.0, 3.0, 0.0, 0.0, 2.0, 1.0]);
        fill(&mut water, &region, &ran);
        assert_eq!(water.data(), &[1.0, 3.0, 3.0, 3.0, 2.0, 1.0]);
    }
}
