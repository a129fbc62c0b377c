//! Lawn at the photo's foot: a strip of grass between the pavement and
//! the wall, or beside the road. Grass in sun is green but often paler
//! than the vivid green that makes a straight texture vegetation
//! (foliage.rs's `VIVID`), and a strip of it seen from eye level is a
//! horizontal band whose edges make its texture "straight" there, so it
//! stayed wall (review 24: Dartmouth IMG_0731's sunlit lawn strip, excess
//! green 0.26-0.31). Seen from eye level, the ground is foreshortened: its
//! gradients point up and down (plane.rs's `Sideways`), while a wall
//! painted green stands up (its jambs, frames and courses' ends point
//! sideways too).

use rayon::prelude::*;

use super::features::Features;
use super::foliage::green_excess;
use super::glass::components;
use super::light::Light;
use super::plane::Sideways;
use super::wall::{Class, flood};

/// Pixels at the photo's foot, wall or vegetation, that are lawn (the
/// green vote's lawn pixels are often already vegetation: they make the
/// band whole): green (excess green
/// over [`LAWN_GREEN`] in the smoothed colour `at`, green the largest
/// channel), from `from` (a row) down, lying flat (sideways share under
/// [`LAWN_FLAT`]), in a connected band at least [`LAWN_WIDE`] of the
/// width across.
pub(super) fn lawn(
    f: &Features,
    side: &Sideways,
    class: &[Class],
    at: &(dyn Fn(usize) -> [f32; 3] + Sync),
    from: usize,
) -> Vec<bool> {
    let (w, h) = (f.w, f.h);
    let cand: Vec<bool> = (0..w * h)
        .into_par_iter()
        .map(|i| {
            let c = at(i);
            i / w >= from
                && matches!(class[i], Class::Wall | Class::Vegetation)
                && c[1] > c[0]
                && c[1] > c[2]
                && green_excess(c) > LAWN_GREEN
                && side.at(i) < LAWN_FLAT
        })
        .collect();
    // The smoothed colour bleeds over the band's edges by the smoothing
    // radius: the grain is read that far inside.
    let inside = (w.max(h) / 150).max(1) + 1;
    bands(&cand, &f.luma, w, (w as f32 * LAWN_WIDE) as usize, inside)
}

/// Adds to the ground `g` what lies below a `lawn` (under the median of
/// its columns' lowest rows): wall pixels that lie flat and are grey
/// under the photo's `light` (plane.rs's `flat_wall` with `flat` and
/// `sat`), connected to the bottom row through such pixels or ground. The
/// lawn tells that the photo's foot is the ground seen from eye level
/// (grass does not grow on a facade), so the pavement between it and the
/// road, which a kerb cuts off from the road's fill and whose level edges
/// leave it short of a street (`flat_ground`), is ground too (review 24:
/// Dartmouth IMG_0731's pavement).
pub(super) fn below(
    f: &Features,
    side: &Sideways,
    class: &[Class],
    lawn: &[bool],
    (flat, sat, light): (f32, f32, Light),
    g: &mut [bool],
) {
    let (w, h) = (f.w, f.h);
    let mut bottoms: Vec<usize> = (0..w)
        .filter_map(|x| (0..h).rev().find(|&y| lawn[y * w + x]))
        .collect();
    let row = (h - 1) * w;
    let road = g[row..].iter().filter(|&&g| g).count();
    if bottoms.is_empty() || road * 2 < w {
        return;
    }
    let mid = bottoms.len() / 2;
    let from = (*bottoms.select_nth_unstable(mid).1 + 1) * w;
    if from < h * 4 / 5 * w {
        return;
    }
    let mut cand = super::plane::flat_wall(f, side, class, from, flat, sat, light);
    cand.iter_mut().zip(g.iter()).for_each(|(c, &g)| *c |= g);
    let seeds = (row..row + w).filter(|&i| cand[i]).collect();
    let part = flood(&cand, w, h, seeds, |_, _| true);
    g.iter_mut().zip(&part).for_each(|(a, &b)| *a |= b);
}

/// The 4-connected components of `cand` that span at least `wide`
/// columns and whose grain (the differences of `luma` between neighbours
/// both at least `inside` pixels within the component, across and along
/// the difference: the band's own edges left out) does not run
/// sideways: grass is isotropic (its share of sideways energy near 0.5),
/// a green fascia's boards or a green door's panels run up and down.
fn bands(cand: &[bool], luma: &[f32], w: usize, wide: usize, inside: usize) -> Vec<bool> {
    let h = cand.len() / w;
    // True when the run of `n` pixels from `i` by steps of `d` stays in
    // the candidates (and, sideways, on `i`'s row).
    let run = |i: usize, d: usize, n: usize| {
        (1..=n).all(|k| {
            let j = i + k * d;
            j < cand.len() && (d == w || j / w == i / w) && cand[j]
        })
    };
    let back = |i: usize, d: usize, n: usize| {
        (1..=n).all(|k| k * d <= i && (d == w || (i - k * d) / w == i / w) && cand[i - k * d])
    };
    let mut out = vec![false; w * h];
    for comp in components(cand, w, h) {
        let (x0, x1) = comp
            .iter()
            .fold((w, 0), |(a, b), &i| (a.min(i % w), b.max(i % w)));
        let (mut sx, mut sy) = (0f32, 0f32);
        for &i in &comp {
            let deep = |d: usize| back(i, d, inside) && run(i, d, inside + 1);
            if deep(1) && deep(w) {
                sx += (luma[i + 1] - luma[i]).powi(2);
                sy += (luma[i + w] - luma[i]).powi(2);
            }
        }
        let grain = if sx + sy > 1e-9 { sx / (sx + sy) } else { 0.5 };
        if x1 + 1 >= x0 + wide && grain < LAWN_GRAIN {
            comp.iter().for_each(|&i| out[i] = true);
        }
    }
    out
}

/// Lawn is greener than this (excess green over the sum of the smoothed
/// colour; wall.rs's green vote takes 0.1). Sunlit grass is at 0.26-0.35
/// (Dartmouth IMG_0731). Measured on LabelMeFacade train, per photo: at
/// 0.1 and 0.15 insidecity_art1269's steps and balustrade under a cyan
/// cast (labelled wall) move by -0.01 to +0.04 of IoU; at 0.2 and 0.25
/// it does not move and IMG_0731's pavement is ground at both; the
/// whole-set numbers are in BENCHMARKS.md (eighteenth pass, ground18).
const LAWN_GREEN: f32 = 0.2;
/// Lawn lies flat: sideways share under this (plane.rs: median 0.25 on
/// LabelMeFacade's road and pavement, 0.54 on walls).
const LAWN_FLAT: f32 = 0.4;
/// A lawn's grain runs sideways less than this share of its energy
/// (isotropic grain 0.5; a fascia of vertical boards near 1).
const LAWN_GRAIN: f32 = 0.6;
/// A lawn is a band across the view: this share of the width at least
/// (a stretch of the bottom row grows as ground from an eighth, too).
const LAWN_WIDE: f32 = 0.125;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::ground::tests::wall_in;
    use crate::analysis::wall::classify;
    use crate::photo::Photo;

    /// The classes of a 240 x 200 photo seen from across a road: a brick
    /// front down to 72% of the height; a pale walkway; a band from 78%
    /// to 84% of `band`'s two colours (grass: in 2 x 2 blocks at random;
    /// `boards`: the second in vertical stripes 2 of every 8 columns); a
    /// white pavement from 84%
    /// to 91%, a dark kerb and a grey road marked with level white lines.
    fn across_the_road(band: [[u8; 3]; 2], boards: bool) -> Vec<Class> {
        let (w, h) = (240usize, 200usize);
        let img = image::RgbImage::from_fn(w as u32, h as u32, |x, y| {
            let (x, y) = (x as usize, y as usize);
            let mut hash = ((x / 2) * 1000 + y / 2) as u64;
            hash = hash.wrapping_mul(0x9E37_79B9_7F4A_7C15);
            hash ^= hash >> 29;
            let grain = if boards {
                (x % 8 < 2) as usize
            } else {
                ((hash >> 33) % 2) as usize
            };
            image::Rgb(match y {
                0..144 => crate::analysis::wall::tests::brick(y as u32),
                144..156 => [200; 3],
                156..168 => band[grain],
                168..182 => [245; 3],
                182..185 => [70; 3],
                _ if (y - 185) % 8 < 2 && x % 40 < 24 => [235; 3],
                _ => [150; 3],
            })
        });
        classify(&Features::new(
            &Photo::new(image::DynamicImage::ImageRgb8(img)),
            w as u32,
        ))
    }

    #[test]
    fn a_lawn_strip_and_the_pavement_below_it_are_not_wall() {
        // Sunlit grass, excess green 0.26 and 0.32: under foliage.rs's
        // VIVID where its texture is straight (the band's edges).
        let grass = [[160, 190, 100], [150, 190, 90]];
        let class = across_the_road(grass, false);
        let w = 240;
        let lawn = wall_in(&class, w, (0, w), (158, 166));
        let pavement = wall_in(&class, w, (0, w), (170, 180));
        assert!(lawn < 0.1, "{lawn} of the lawn is wall");
        assert!(pavement < 0.1, "{pavement} of the pavement is wall");
        assert!(
            wall_in(&class, w, (0, w), (0, 140)) > 0.95,
            "the front is wall"
        );
    }

    #[test]
    fn a_green_fascia_standing_up_stays_wall() {
        // The same band, green paint in vertical boards (a shop's fascia):
        // it stands up, so it is no lawn and tells nothing of the ground.
        let paint = [[160, 190, 100], [130, 155, 85]];
        let class = across_the_road(paint, true);
        let fascia = wall_in(&class, 240, (0, 240), (158, 166));
        assert!(fascia > 0.9, "{fascia} of the fascia is wall");
    }
}
