//! The sky behind bare crowns: in a closing of the photo's upper half (a
//! max then a min filter, Serra 1982) thin dark twigs vanish, so the sky
//! between them is smooth there and grows from the sky already found
//! ([`behind_branches`]). Under a blue sky a wider closing finds denser
//! crowns too. The closings need only the photo: [`Closings::new`] runs
//! beside the sky's fills.

use rayon::prelude::*;

use super::features::{Features, l1, luma, texture, texture_radius};
use super::wall::{SKY_STEP, SKY_TEXTURE, grow, is_sky_colour, mean_colour, rim};

/// Sky behind bare branches is looked for in the photo's luma-and-colour
/// closing (a max then a min filter over a box of this radius: dark lines
/// up to twice this wide vanish), where the twigs no longer raise the
/// texture (measured on LabelMeFacade train, IoU / spill / sky spill:
/// none 0.679 / 0.240 / 0.076, 2 0.679 / 0.235 / 0.066, 3 0.658 / 0.233 /
/// 0.058: window frames and cornices of pale walls vanish too).
const BRANCH_GAP: usize = 2;

/// Sky found behind branches is within this colour distance (L1, 0..3)
/// of the mean colour of the sky found before (measured on LabelMeFacade
/// train: unlimited IoU 0.673, 0.4 0.678, 0.3 0.679 with sky spill 0.066,
/// 0.2 0.679 with 0.069).
const BRANCH_MATCH: f32 = 0.3;

/// Under a blue sky the sky behind denser bare crowns is looked for in a
/// wider closing too, over a box of this radius (lines up to 9 pixels wide
/// vanish); only the blue pixels of that crown are taken ([`BLUE_SKY`]), as
/// a white wall's window frames vanish in it as well (measured on
/// LabelMeFacade train, sky px called wall / wall px called sky / IoU, with
/// BLUE_SKY 0.1: none 193.8 k / 433.3 k / 0.7424, 3 190.4 k / 434.4 k /
/// 0.7427, 4 188.0 k / 435.1 k / 0.7428; held out 446.9 k / 983.2 k /
/// 0.7146, 3 434.7 k / 989.4 k / 0.7148, 4 434.3 k / 989.5 k / 0.7148).
const BLUE_GAP: usize = 4;

/// A blue sky: its mean colour (the sky found before the crowns) is bluer
/// than red by more than this (0..1); the pixels of the wider closing's
/// crown taken as sky are too, and bluer than green (measured as
/// [`BLUE_GAP`], 4: 0.05 186.4 k / 435.4 k / 0.7430 on train but held out
/// 434.0 k / 1003.4 k / 0.7143; 0 (any sky) 187.0 k / 435.5 k / 0.7421;
/// the pixels bluer than 0.15 instead of 0.1: 189.1 k / 434.8 k / 0.7427
/// with the sky's 0.05). Without the pixel test (the wider closing alone
/// under a blue sky, radius 3) a white front under a blue sky with white
/// clouds became sky (coruna IMG_8106 -0.06).
const BLUE_SKY: f32 = 0.1;

/// The narrow ([`BRANCH_GAP`]) and the wide ([`BLUE_GAP`]) closing.
pub(super) struct Closings(Closed, Closed);

impl Closings {
    /// Both closings of `f`, side by side.
    pub(super) fn new(f: &Features) -> Closings {
        let (narrow, wide) =
            rayon::join(|| Closed::new(f, BRANCH_GAP), || Closed::new(f, BLUE_GAP));
        Closings(narrow, wide)
    }
}

/// The upper half's closing (over a box of radius [`BRANCH_GAP`] or
/// [`BLUE_GAP`]), where bare twigs vanish, and its texture. Needs only the
/// photo: made beside the sky's fills.
struct Closed {
    /// Red, green, blue planes of the closing, `band` rows.
    rgb: [Vec<f32>; 3],
    /// Mean luma gradient of the closing, as [`Features::texture`].
    texture: Vec<f32>,
}

impl Closed {
    fn new(f: &Features, gap: usize) -> Closed {
        let (w, h) = (f.w, f.h);
        // The upper half and a little more (the box's reach).
        let band = (h / 2 + 2 * gap).min(h);
        let rgb: [Vec<f32>; 3] =
            std::array::from_fn(|k| close(&f.rgb[k][..band * w], w, band, gap));
        let luma: Vec<f32> = (0..band * w)
            .into_par_iter()
            .map(|i| luma([rgb[0][i], rgb[1][i], rgb[2][i]]))
            .collect();
        let texture = texture(&luma, w, band, texture_radius(w, h));
        Closed { rgb, texture }
    }
}

/// Sky seen through bare branches (a crown against an overcast sky, whose
/// twigs keep the texture above [`SKY_TEXTURE`] everywhere): in the upper
/// half's closing the twigs vanish, and the smooth sky-coloured closing
/// 4-connected to the sky found (`core`) or to the top row is the crown's
/// extent; its pixels that are sky-coloured themselves (`colour`) and
/// within [`BRANCH_MATCH`] of the core's mean colour are the gaps between
/// the twigs. Under a blue sky ([`BLUE_SKY`]) a denser crown is looked for
/// too, in the wider closing, and only its blue pixels are taken
/// ([`BLUE_GAP`]). None when there is no core.
pub(super) fn behind_branches(
    f: &Features,
    core: &[bool],
    colour: &[bool],
    Closings(closed, wide): &Closings,
) -> Option<Vec<bool>> {
    let h = f.h;
    let found = core.par_iter().filter(|&&c| c).count();
    if found == 0 || h / 2 == 0 {
        return None;
    }
    let mean = mean_colour(f, core, found);
    let mut gaps = crown_gaps(f, core, colour, closed, mean, |_| true);
    if mean[2] - mean[0] > BLUE_SKY {
        let blue = |[r, g, b]: [f32; 3]| b - r > BLUE_SKY && b > g;
        let more = crown_gaps(f, core, colour, wide, mean, blue);
        gaps.par_iter_mut().zip(&more).for_each(|(s, &m)| *s |= m);
    }
    Some(gaps)
}

/// The gaps of the crown [`behind_branches`] finds in the closing
/// `closed`: the upper half's pixels of the crown that are sky-coloured
/// (`colour`), within [`BRANCH_MATCH`] of the sky's `mean` and `gap` (a
/// test of the pixel's own colour).
fn crown_gaps(
    f: &Features,
    core: &[bool],
    colour: &[bool],
    closed: &Closed,
    mean: [f32; 3],
    gap: impl Fn([f32; 3]) -> bool + Sync,
) -> Vec<bool> {
    let (w, h) = (f.w, f.h);
    let rows = h / 2;
    let at = |i: usize| [closed.rgb[0][i], closed.rgb[1][i], closed.rgb[2][i]];
    let texture = &closed.texture;
    let cand: Vec<bool> = (0..w * h)
        .into_par_iter()
        .map(|i| core[i] || (i < rows * w && texture[i] < SKY_TEXTURE && is_sky_colour(at(i))))
        .collect();
    let step = |i: usize, j: usize| l1(at(i), at(j)) < SKY_STEP;
    let mut seeds = rim(core, w, h);
    seeds.extend(0..w);
    let crown = grow(core.to_vec(), &cand, w, h, seeds, step);
    // Below the band the crown is the core: sky already.
    (0..w * h)
        .into_par_iter()
        .map(|i| {
            let p = f.rgb_at(i);
            i < rows * w && crown[i] && colour[i] && l1(p, mean) < BRANCH_MATCH && gap(p)
        })
        .collect()
}

/// Grey-scale closing (Serra, "Image analysis and mathematical
/// morphology", 1982): the max then the min over a (2r+1)^2 box, each
/// separable; dark lines narrower than 2r+1 vanish.
pub(super) fn close(src: &[f32], w: usize, h: usize, r: usize) -> Vec<f32> {
    let wider = extreme(src, w, h, r, max);
    extreme(&wider, w, h, r, min)
}

/// The larger of `a` and `b`: `f32::max` for the values filtered here
/// (no NaN, no negative zero), as a comparison the compiler vectorises
/// (`f32::max` was picked one lane at a time: 2.5% of the 12 MP bench's
/// samples, `perf`).
fn max(a: f32, b: f32) -> f32 {
    if a > b { a } else { b }
}

/// The smaller of `a` and `b`, as [`max`].
fn min(a: f32, b: f32) -> f32 {
    if a < b { a } else { b }
}

/// `pick` (max or min) over a (2r+1)^2 box clipped at the borders, rows
/// then columns, rows in parallel.
fn extreme(
    src: &[f32],
    w: usize,
    h: usize,
    r: usize,
    pick: impl Fn(f32, f32) -> f32 + Copy + Sync,
) -> Vec<f32> {
    let mut tmp = vec![0f32; w * h];
    tmp.par_chunks_mut(w)
        .zip(src.par_chunks(w))
        .for_each(|(out, row)| {
            // Each shift of the row picked in turn (vectorised).
            out.copy_from_slice(row);
            for d in 1..=r.min(w.saturating_sub(1)) {
                for (v, &t) in out[d..].iter_mut().zip(row) {
                    *v = pick(*v, t);
                }
                for (v, &t) in out.iter_mut().zip(&row[d..]) {
                    *v = pick(*v, t);
                }
            }
        });
    let mut out = vec![0f32; w * h];
    out.par_chunks_mut(w).enumerate().for_each(|(y, out)| {
        let (a, b) = (y.saturating_sub(r), (y + r + 1).min(h));
        out.copy_from_slice(&tmp[a * w..(a + 1) * w]);
        for row in tmp[(a + 1) * w..b * w].chunks_exact(w) {
            for (v, &t) in out.iter_mut().zip(row) {
                *v = pick(*v, t);
            }
        }
    });
    out
}
