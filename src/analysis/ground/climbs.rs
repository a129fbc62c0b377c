//! What a stretch's ground fill climbed: a wall as grey as the pavement,
//! joined to it by a soft shadow, which the fill runs up until the 45%
//! limit stops it ([`super::ground`]).

use rayon::prelude::*;

use super::super::features::l1;
use super::super::plane::Sideways;
use super::{NARROW_FLAT, median3};

/// True when what lies above the top of `part` (a twelfth of the height
/// up) looks like the part itself (median colours), or when two thirds of
/// its columns run up to the `top` limit: a brick of a close-up, the foot of a
/// facade, not a road.
pub(super) fn like_above(
    part: &[bool],
    at: &dyn Fn(usize) -> [f32; 3],
    w: usize,
    h: usize,
    top: usize,
) -> bool {
    let (mut above, mut inside, mut at_cap) = (Vec::new(), Vec::new(), 0);
    for x in 0..w {
        if let Some(y) = (0..h).find(|&y| part[y * w + x]) {
            at_cap += (y == top) as usize;
            above.push(at(y.saturating_sub(h / 12) * w + x));
            inside.push(at((y + h / 24).min(h - 1) * w + x));
        }
    }
    if above.is_empty() {
        return false;
    }
    if at_cap * 3 > above.len() * 2 {
        return true;
    }
    l1(median3(&mut above), median3(&mut inside)) < LIKE_ABOVE
}

/// Takes out of `part` what it climbed: in the columns where it runs up
/// to the `top` limit, the fill was stopped by the limit, not by the
/// wall's foot (a plaster or stone wall as grey as the pavement, joined to
/// it by a soft shadow: gerona IMG_2818, insidecity_art625, cambridge
/// IMG_8934). There, above the wall's foot (the [`CLIMB_FOOT`] quantile
/// of the rows where the part's other columns start) and above the bottom
/// fifth, only what lies flat (sideways share at most [`NARROW_FLAT`])
/// stays: the far road in a street's vanishing point does, the wall
/// stands up or has no direction. A wall's level courses lie flat too:
/// with `like` (the stretch's ground test) a column whose ground colour
/// goes on above the limit ([`goes_on_above`]) loses all of it there, a
/// road ends at its far facades. Once two thirds of the columns run to
/// the limit the whole part is refused ([`like_above`]).
pub(super) fn off_the_climbs(
    part: &mut [bool],
    side: &Sideways,
    w: usize,
    h: usize,
    top: usize,
    like: Option<&(dyn Fn(usize) -> bool + Sync)>,
) {
    let climbed: Vec<bool> = (0..w).map(|x| part[top * w + x]).collect();
    // Columns whose ground colour goes on above the limit: a wall.
    let goes_on: Vec<bool> = match like {
        Some(like) => (0..w)
            .map(|x| climbed[x] && goes_on_above(like, x, w, h, top))
            .collect(),
        None => vec![false; w],
    };
    // The row each column of the part starts at, read row by row.
    let mut start = vec![h; w];
    for (y, row) in part.chunks_exact(w).enumerate().skip(top) {
        for ((s, &p), &c) in start.iter_mut().zip(row).zip(&climbed) {
            if p && !c && *s == h {
                *s = y;
            }
        }
    }
    let mut starts: Vec<usize> = start.into_iter().filter(|&s| s < h).collect();
    let foot = if starts.is_empty() {
        h
    } else {
        let at = ((starts.len() as f32 * CLIMB_FOOT) as usize).min(starts.len() - 1);
        *starts.select_nth_unstable(at).1
    };
    let below = foot.min(h * 4 / 5);
    part[..below * w]
        .par_chunks_mut(w)
        .enumerate()
        .for_each(|(y, row)| {
            for (x, p) in row.iter_mut().enumerate() {
                if climbed[x] && *p && (goes_on[x] || side.at(y * w + x) > NARROW_FLAT) {
                    *p = false;
                }
            }
        });
}

/// True when, in column `x`, what lies above the `top` limit (a twelfth
/// of the height up) is ground-like (`like`: the stretch's own colour
/// model, smooth, unsaturated) in at least [`GOES_ON`] of its rows: the
/// fill was stopped by the limit in the middle of a surface of the
/// pavement's grey that goes on up, a wall (gerona IMG_2818's stone
/// retaining wall, insidecity_art625's plaster), not at a road's far end,
/// where the street's far facades or the sky begin.
fn goes_on_above(
    like: &(dyn Fn(usize) -> bool + Sync),
    x: usize,
    w: usize,
    h: usize,
    top: usize,
) -> bool {
    let n = (h / 12).max(1);
    let k = (top.saturating_sub(n)..top)
        .filter(|&y| like(y * w + x))
        .count();
    k as f32 >= GOES_ON * n as f32
}

/// A stretch's ground is refused when the colour a twelfth of the height
/// above its top is this close (L1 of medians) to its own.
const LIKE_ABOVE: f32 = 0.03;

/// A climbed column whose ground colour goes on above the limit in at
/// least this share of the twelfth of the height over it is a wall
/// (LabelMeFacade train, with [`CLIMB_FOOT`] 0.7: wall missed as ground
/// 689.6k -> 660.9k px, ground spill +2.4k px; 0.3 and 0.7 measured the
/// same within 1k px).
const GOES_ON: f32 = 0.5;

/// The wall's foot in the climbed columns: this quantile (from the top)
/// of the rows at which the part's other columns start (the median
/// before: 0.7 sets it lower, where the unclimbed columns under the
/// doors and dark windows of the wall's lowest storey do not pull it up;
/// LabelMeFacade train alone 689.6k -> 677.4k px wall missed as ground,
/// with [`GOES_ON`] 660.9k; 0.8 660.0k but ground spill +1.4k px more).
const CLIMB_FOOT: f32 = 0.7;
