//! The appearance relabel's flips to wall ([`super::appearance`]), kept
//! only where the building can be. The relabel turns a cell of sky or
//! ground into wall when it looks like the wall; most such flips mend the
//! classifier (a pale wall the sky's fill flooded, a wall's base the
//! ground's fill climbed), but some put wall where no building stands: a
//! car or a sunlit stretch of road in front of the wall, grey haze beside
//! a pylon. Those stand out from the wall the classifier was sure of:
//! - a group of flips (4-connected) mostly bordered by something else than
//!   that wall is an outgrowth, not a mended part of it;
//! - a flip of ground below the lowest sure wall of its column, whose run
//!   of flips up the column does not end on sure wall, hangs under a car or
//!   on the road, not under the wall.
//!
//! Measured on LabelMeFacade train (BENCHMARKS.md, twenty-third pass,
//! relabel25), in the pixels of the flipped cells: the cells flipped from
//! ground to wall held 298 thousand wall pixels and 257 thousand road and
//! car pixels; the outgrowths among them (border share under 0.35) 10.1
//! and 60.7 thousand, the columns' hanging flips 12.0 and 49.8 thousand
//! (the two overlap). The cells flipped from sky held 190 thousand wall
//! and 60 thousand sky pixels, the outgrowths (share under 0.2) 1.1 and
//! 6.8 thousand. Wall IoU / spill 0.758 / 0.131 -> 0.761 / 0.127 (train),
//! 0.726 / 0.139 -> 0.728 / 0.133 (held-out).

/// Index of the wall among the relabel's classes.
const WALL: usize = 0;
/// Index of the sky.
const SKY: usize = 1;
/// Index of the ground.
const GROUND: usize = 3;

/// A group of flips from sky stays wall only if at least this share of its
/// outer border is sure wall (LabelMeFacade train IoU / sky spill: no rule
/// 0.758 / 0.045; 0.2 0.758 / 0.044 with 1.1 thousand wall and 6.8
/// thousand sky pixels given back; 0.3 gives back 4.8 and 10.1 thousand;
/// 0.35 9.7 and 12.8).
const SKY_BORDER: f32 = 0.2;

/// The same for a group's flips from ground (train IoU / spill / car
/// spill: 0.2 without the column rule 0.759 / 0.130 / 0.310; with it,
/// 0.3 0.760 / 0.127 / 0.298, 0.35 0.761 / 0.127 / 0.294, 0.4 with the
/// sky's at 0.25 0.760 / 0.126 / 0.292; in the flipped cells' pixels,
/// under 0.35 gives back 10.1 thousand wall and 60.7 thousand road and car
/// pixels, under 0.4 19.4 and 72.0).
const GROUND_BORDER: f32 = 0.35;

/// Gives the cells of `label` flipped to wall from sky or ground back their
/// class in `old` where no building stands (see the module's
/// documentation). Both are per cell of the `gw` x `gh` grid, indices into
/// the relabel's classes (`None`: glass).
pub(super) fn constrain(label: &mut [Option<usize>], old: &[Option<usize>], gw: usize, gh: usize) {
    let n = gw * gh;
    let from = |c: usize, class: usize| label[c] == Some(WALL) && old[c] == Some(class);
    let flipped: Vec<bool> = (0..n).map(|c| from(c, SKY) || from(c, GROUND)).collect();
    // Sure wall: what is wall and was not flipped to it from sky or ground.
    let sure: Vec<bool> = (0..n)
        .map(|c| label[c] == Some(WALL) && !flipped[c])
        .collect();
    let mut undo = outgrowths(&flipped, &sure, gw, gh, |c, share| {
        (from(c, SKY) && share < SKY_BORDER) || (from(c, GROUND) && share < GROUND_BORDER)
    });
    for (c, u) in hanging(&flipped, &sure, gw, gh).into_iter().enumerate() {
        undo[c] |= u && from(c, GROUND);
    }
    for c in (0..n).filter(|&c| undo[c]) {
        label[c] = old[c];
    }
}

/// The 4-neighbours of cell `c` in the grid.
fn neighbours(c: usize, gw: usize, gh: usize) -> impl Iterator<Item = usize> {
    let (cx, cy) = (c % gw, c / gw);
    [
        (cx > 0).then(|| c - 1),
        (cx + 1 < gw).then(|| c + 1),
        (cy > 0).then(|| c - gw),
        (cy + 1 < gh).then(|| c + gw),
    ]
    .into_iter()
    .flatten()
}

/// Per cell: whether it is in a 4-connected group of `flipped` cells for
/// which `drop(cell, share)` holds, `share` being the share of the group's
/// outer border (the sides it shares with cells not flipped) on `sure`
/// wall (0 for a group with no border).
fn outgrowths(
    flipped: &[bool],
    sure: &[bool],
    gw: usize,
    gh: usize,
    drop: impl Fn(usize, f32) -> bool,
) -> Vec<bool> {
    let n = gw * gh;
    let (mut seen, mut out) = (vec![false; n], vec![false; n]);
    for s in 0..n {
        if seen[s] || !flipped[s] {
            continue;
        }
        seen[s] = true;
        let mut group = vec![s];
        let (mut border, mut on_wall) = (0u32, 0u32);
        let mut i = 0;
        while let Some(&c) = group.get(i) {
            i += 1;
            for nb in neighbours(c, gw, gh) {
                if !flipped[nb] {
                    border += 1;
                    on_wall += sure[nb] as u32;
                } else if !seen[nb] {
                    seen[nb] = true;
                    group.push(nb);
                }
            }
        }
        let share = on_wall as f32 / border.max(1) as f32;
        for c in group {
            out[c] = drop(c, share);
        }
    }
    out
}

/// Per cell: whether it is a `flipped` cell below the lowest `sure` wall
/// of its column (or in a column with none) whose run of flipped cells up
/// the column does not end on sure wall.
fn hanging(flipped: &[bool], sure: &[bool], gw: usize, gh: usize) -> Vec<bool> {
    let mut out = vec![false; gw * gh];
    for cx in 0..gw {
        let at = |cy: usize| cy * gw + cx;
        let lowest = (0..gh).rev().find(|&cy| sure[at(cy)]);
        // The row the current run of flips started at.
        let mut top = 0;
        for cy in 0..gh {
            if !flipped[at(cy)] {
                top = cy + 1;
                continue;
            }
            let topped = top > 0 && sure[at(top - 1)];
            out[at(cy)] = lowest.is_none_or(|l| cy > l) && !topped;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A grid from rows of characters: `W` wall, `S` sky, `G` ground, `g`
    /// glass; the old classes and the labels after the relabel (`s`, `r`:
    /// sky, ground flipped to wall).
    fn grid(rows: &[&str]) -> (Vec<Option<usize>>, Vec<Option<usize>>, usize, usize) {
        let (mut old, mut label) = (Vec::new(), Vec::new());
        for ch in rows.iter().flat_map(|r| r.chars()) {
            let (o, l) = match ch {
                'W' => (Some(WALL), Some(WALL)),
                'S' => (Some(SKY), Some(SKY)),
                'G' => (Some(GROUND), Some(GROUND)),
                's' => (Some(SKY), Some(WALL)),
                'r' => (Some(GROUND), Some(WALL)),
                _ => (None, None),
            };
            old.push(o);
            label.push(l);
        }
        (old, label, rows[0].len(), rows.len())
    }

    fn constrained(rows: &[&str]) -> Vec<Option<usize>> {
        let (old, mut label, gw, gh) = grid(rows);
        constrain(&mut label, &old, gw, gh);
        label
    }

    #[test]
    fn an_island_of_flips_in_the_sky_is_sky_again() {
        let label = constrained(&["SSSSSS", "SssSSS", "SssSSS", "SSSSSS", "WWWWWW"]);
        assert_eq!(label[7], Some(SKY));
        assert_eq!(label[14], Some(SKY));
    }

    #[test]
    fn a_wall_top_the_sky_took_stays_mended() {
        // The sky's fill flooded a pale wall's top: the flips sit on the
        // wall and reach up to the sky.
        let rows = ["SSSSSS", "SsssSS", "WsssWW", "WWWWWW"];
        let (_, want, _, _) = grid(&rows);
        assert_eq!(constrained(&rows), want);
    }

    #[test]
    fn flips_hanging_below_the_wall_are_ground_again() {
        // Column 1: a car under the wall whose flips do not end on it (a
        // ground cell between); column 4: the wall's base the ground's fill
        // climbed, flips right under the wall.
        let label = constrained(&["WWWWWW", "WWWWWW", "WGWWrW", "WrGGrG", "GrrGGG", "GGGGGG"]);
        assert_eq!(label[6 * 3 + 1], Some(GROUND));
        assert_eq!(label[6 * 4 + 1], Some(GROUND));
        assert_eq!(label[6 * 2 + 4], Some(WALL));
        assert_eq!(label[6 * 3 + 4], Some(WALL));
    }

    #[test]
    fn glass_and_sure_wall_are_never_touched() {
        let rows = ["SSSS", "WgWW", "WWgW", "GGGG"];
        let (_, want, _, _) = grid(&rows);
        assert_eq!(constrained(&rows), want);
    }
}
