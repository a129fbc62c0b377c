//! The road past the flat ground's cut. [`super::flat_ground`] looks for
//! ground only from [`super::FLAT_GROUND_FROM`] of the height down, so
//! where only it reaches the road (a pole's shadow or a tar seam splits
//! the road off from the bottom row's stretches, whose fills stop at the
//! colour step), the ground ended in a level line across the road and the
//! road above it, up to its crest, was wall: boston p1010753's road rising
//! away from the camera, whose crest the rain took for a ledge and
//! streaked the road from.

use super::super::features::{Features, l1};
use super::super::perspective::oblique;
use super::super::plane::Sideways;
use super::super::wall::flood;
use super::climbs::{like_above, off_the_climbs};
use super::{GROUND_COLOUR, GROUND_STEP, NARROW, OBLIQUE, lies_flat, median3};

/// What the photo's ground is read from (see [`super::ground`]).
pub(super) struct Road<'a> {
    pub f: &'a Features,
    /// The 45% limit: no ground above this row.
    pub top: usize,
    /// The row the flat ground is cut at.
    pub cut: usize,
    /// Wall pixels from the limit down that could be ground (smooth, not
    /// strongly coloured).
    pub basic: &'a [bool],
    /// A pixel's smoothed colour.
    pub at: &'a (dyn Fn(usize) -> [f32; 3] + Sync),
    /// The colours the fills' steps are read on.
    pub steps: &'a [[f32; 3]],
    pub side: &'a Sideways,
}

/// Grows the ground the flat test added to `g` (what `g` has that
/// `before` had not) up past its cut: each run of at least a
/// [`NARROW`]th of the width (the narrowest bottom-row stretch that
/// grows) where it reaches the `cut` row grows upward,
/// as a bottom-row stretch does in [`super::ground`], with its own colour
/// model (the median of the run's flat ground in the [`MODEL_ROWS`]th of
/// the height under the cut), through smooth unsaturated wall within
/// [`GROUND_COLOUR`] of it, across no colour step, up to the 45% limit.
/// What it reaches is kept on the stretches' terms and the flat street's:
/// it lies flat ([`lies_flat`]: the road beyond, foreshortened; plaster
/// stands up), the gradients on it and its rim run oblique (over
/// [`OBLIQUE`], see [`oblique`]: the lanes and kerbs of a road seen along
/// the street converge, asphalt's grain runs every way; a shutter's or a
/// panelled storey's grooves run level), it does not look like what lies
/// above it ([`like_above`]), and it loses what it climbed
/// ([`off_the_climbs`]).
pub(super) fn past_the_cut(road: &Road, before: &[bool], g: &mut [bool]) {
    let (w, h, cut) = (road.f.w, road.f.h, road.cut);
    if cut <= road.top || cut >= h {
        return;
    }
    let added: Vec<bool> = g.iter().zip(before).map(|(&a, &b)| a && !b).collect();
    let row = cut * w;
    let mut x = 0;
    while x < w {
        let start = x;
        while x < w && added[row + x] {
            x += 1;
        }
        if x - start >= (w / NARROW).max(1) {
            grow(road, start..x, &added, g);
        }
        if x == start {
            x += 1;
        }
    }
}

/// [`past_the_cut`] for the run of columns `cols`.
fn grow(road: &Road, cols: std::ops::Range<usize>, added: &[bool], g: &mut [bool]) {
    let (f, top, cut, at) = (road.f, road.top, road.cut, road.at);
    let (w, h) = (f.w, f.h);
    let under =
        (cut..(cut + h / MODEL_ROWS).min(h)).flat_map(|y| cols.clone().map(move |x| y * w + x));
    let mut under: Vec<[f32; 3]> = under.filter(|&i| added[i]).map(at).collect();
    if under.is_empty() {
        return;
    }
    let model = median3(&mut under);
    let seeds: Vec<usize> = cols.map(|x| cut * w + x).collect();
    let (f, w, h) = (road.f, road.f.w, road.f.h);
    let rim_oblique = |p: &[bool]| oblique(f, &with_rim(p, w, h)) > OBLIQUE;
    climb(road, &seeds, model, top..cut, rim_oblique, g);
}

/// Grows the ground in `g` upward from `seeds` (pixels of `g` or next to
/// it) with the colour `model`, through smooth unsaturated wall in `rows`
/// within [`GROUND_COLOUR`] of it, across no colour step, and keeps what
/// it reaches (the seeds not already in `g` with it) on the terms of
/// [`past_the_cut`]: it lies flat, does not look like what lies above it,
/// passes the caller's test `keep` (past the cut: it runs oblique with
/// its rim, [`OBLIQUE`]), and loses what it climbed.
pub(super) fn climb(
    road: &Road,
    seeds: &[usize],
    model: [f32; 3],
    rows: std::ops::Range<usize>,
    keep: impl Fn(&[bool]) -> bool,
    g: &mut [bool],
) {
    let (f, top, at) = (road.f, road.top, road.at);
    let (w, h) = (f.w, f.h);
    let like = |i: usize| road.basic[i] && l1(at(i), model) < GROUND_COLOUR;
    let mut cand = vec![false; w * h];
    for (i, c) in cand
        .iter_mut()
        .enumerate()
        .take(rows.end * w)
        .skip(rows.start * w)
    {
        *c = !g[i] && like(i);
    }
    for &s in seeds {
        cand[s] = true;
    }
    let steps = road.steps;
    let mut part = flood(&cand, w, h, seeds.to_vec(), |i, j| {
        l1(steps[i], steps[j]) < GROUND_STEP
    });
    for &s in seeds {
        part[s] &= !g[s];
    }
    if !part.contains(&true)
        || !lies_flat(&part, road.side)
        || like_above(&part, at, w, h, top)
        || !keep(&part)
    {
        return;
    }
    off_the_climbs(&mut part, road.side, w, h, top, Some(&like));
    g.iter_mut().zip(&part).for_each(|(a, &b)| *a |= b);
}

/// `part` with the pixels within [`RIM`] of it: the lane lines and kerbs
/// a road's fill stops at are on its rim.
pub(super) fn with_rim(part: &[bool], w: usize, h: usize) -> Vec<bool> {
    let mut out = part.to_vec();
    for (i, _) in part.iter().enumerate().filter(|&(_, &p)| p) {
        let (x, y) = (i % w, i / w);
        for yy in y.saturating_sub(RIM)..(y + RIM + 1).min(h) {
            out[yy * w + x.saturating_sub(RIM)..yy * w + (x + RIM + 1).min(w)].fill(true);
        }
    }
    out
}

/// The rim's width, analysis pixels: the fill stops a pixel or two short
/// of a lane line (the steps are read on smoothed colours), so the line's
/// edges are within two (the synthetic test's lanes: oblique share 0.00
/// over the part alone, 0.73 with the rim; boston p1010753's road past
/// the cut 0.59).
const RIM: usize = 2;

/// The colour model is read over this share (one over it) of the height
/// under the cut (as [`super::climbs::like_above`] looks a twelfth up).
pub(super) const MODEL_ROWS: usize = 12;

#[cfg(test)]
mod tests {
    use super::super::tests::{classes_of, wall_in};

    /// The share of the road past the flat ground's cut (row 120 of 200)
    /// called wall, rows 98..118: a 240 x 200 street whose road rises to
    /// its crest at row 94, an orange wall above it. The road is grey with
    /// faint level grain (2 rows lighter, 2 darker: it lies flat) and
    /// white lane lines converging to (120, 94); two dark level shadows of
    /// wires cross it near the foot (rows 176 and 186), so the bottom
    /// row's fill stops there and is refused as like what lies above it,
    /// and only the flat ground, from 60% of the height down, reaches the
    /// road. With `level`, the lines run level too (a shop's shutter
    /// grooves, not a road): no converging lanes.
    fn past_the_crest(level: bool) -> f32 {
        let (w, h) = (240usize, 200usize);
        let img = image::RgbImage::from_fn(w as u32, h as u32, |x, y| {
            let (xf, yf) = (x as f32 - 120.0, y as f32 - 94.0);
            let lane = if level {
                y % 14 < 2
            } else {
                [-1.5f32, -0.6, 0.6, 1.5]
                    .iter()
                    .any(|&s| (yf - s * xf).abs() < 1.5 * (1.0 + s * s).sqrt())
            };
            image::Rgb(match y {
                ..94 => [204, 128, 76],
                176..178 | 186..188 => [40; 3],
                _ if lane && y > 96 => [225; 3],
                _ if y % 4 < 2 => [117; 3],
                _ => [124; 3],
            })
        });
        let class = classes_of(img);
        let wall = wall_in(&class, w, (0, w), (0, 88));
        assert!(wall > 0.99, "{wall} of the wall is wall");
        wall_in(&class, w, (0, w), (98, 118))
    }

    #[test]
    fn a_road_rising_past_the_flat_grounds_cut_is_ground_to_its_crest() {
        let road = past_the_crest(false);
        assert!(road < 0.2, "{road} of the road past the cut is wall");
    }
}
