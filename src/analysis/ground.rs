//! The ground at the photo's foot: road and pavement. Each wide stretch of
//! smooth, unsaturated pixels on the bottom row grows upward with its own
//! colour model (see [`ground`]); narrower stretches (a road between tree
//! shadows, a pavement between a kerb and a parked car) grow too when what
//! they reach lies flat: seen from eye level the ground is foreshortened,
//! so its gradients point up and down ([`super::plane::Sideways`]), while
//! the smooth plaster of a wall's lowest storey, which the fill of such a
//! stretch would otherwise climb, stands up.

use rayon::prelude::*;

use super::features::{Features, box_mean, l1};
use super::light::Light;
use super::perspective::{nearer_smoother, oblique};
use super::plane::{Sideways, UPRIGHT};
use super::wall::{Class, flood};

mod across;
mod climbs;
mod crest;
use climbs::{like_above, off_the_climbs};

/// Ground: connected to the bottom edge, below 45% of the height, smooth,
/// not strongly coloured. Each wide stretch of such pixels on the bottom row
/// (a road, a pavement: not the foot of a brick) grows with its own colour
/// model, and the fill does not cross a colour step (a kerb, the foot of
/// the wall), except the thin joints of paving in the bottom fifth. A stretch's ground is refused when it looks like what lies
/// above it, and all ground when it nearly everywhere stops at the 45%
/// limit (a close-up's texture, a facade down to the photo's edge, reach
/// the bottom too).
pub(super) fn ground(f: &Features, steps: &[[f32; 3]], side: &Sideways, class: &mut [Class]) {
    let (w, h) = (f.w, f.h);
    let r = (w.max(h) / 150).max(1);
    let smooth: Vec<Vec<f32>> = f.rgb.iter().map(|p| box_mean(p, w, h, r)).collect();
    let at = |i: usize| [smooth[0][i], smooth[1][i], smooth[2][i]];
    let top = h * 45 / 100;
    let light = Light::of(f, class);
    // Lawn is vegetation, and tells the pavement below it ([`super::lawn`]).
    let lawn = super::lawn::lawn(f, side, class, &at, (h as f32 * FLAT_GROUND_FROM) as usize);
    for (c, &l) in class.iter_mut().zip(&lawn) {
        if l {
            *c = Class::Vegetation;
        }
    }
    // Wall that could be ground: smooth, not strongly coloured.
    let groundlike = |i: usize| {
        class[i] == Class::Wall
            && f.texture[i] < GROUND_TEXTURE
            && light.saturation(at(i)) < GROUND_SATURATION
    };
    let basic: Vec<bool> = (0..w * h)
        .into_par_iter()
        .map(|i| i / w >= top && groundlike(i))
        .collect();
    let row = (h - 1) * w;
    let mut g = vec![false; w * h];
    let mut x = 0;
    while x < w {
        let start = x;
        // A stretch ends where ground stops or the colour steps (road to
        // pavement, not a paving joint).
        while x < w
            && basic[row + x]
            && (x == start || l1(steps[row + x], steps[row + x - 1]) < GROUND_STEP)
        {
            x += 1;
        }
        let wide = x - start >= w / 8;
        if wide || x - start >= w / NARROW {
            let mut stretch: Vec<[f32; 3]> = (start..x).map(|c| at(row + c)).collect();
            let model = median3(&mut stretch);
            let cand: Vec<bool> = (0..w * h)
                .into_par_iter()
                .map(|i| basic[i] && l1(at(i), model) < GROUND_COLOUR)
                .collect();
            let seeds = (row + start..row + x).collect();
            let mut part = flood(&cand, w, h, seeds, |i, j| {
                l1(steps[i], steps[j]) < GROUND_STEP
            });
            if (wide || lies_flat(&part, side)) && !like_above(&part, &at, w, h, top) {
                let like = |i: usize| groundlike(i) && l1(at(i), model) < GROUND_COLOUR;
                off_the_climbs(&mut part, side, w, h, top, Some(&like));
                g.iter_mut().zip(&part).for_each(|(a, &b)| *a |= b);
            }
        }
        if x == start {
            x += 1;
        }
    }
    let before = g.clone();
    flat_ground(f, steps, side, class, light, &at, &mut g);
    // The road past the flat ground's cut, up to its crest.
    let road = crest::Road {
        f,
        top,
        cut: (h as f32 * FLAT_GROUND_FROM) as usize,
        basic: &basic,
        at: &at,
        steps,
        side,
    };
    crest::past_the_cut(&road, &before, &mut g);
    // The road across a shadow's edge, up to the kerb.
    across::past_the_step(&road, &before, &mut g);
    let grey = (FLAT_GROUND, FLAT_GROUND_SATURATION, light);
    super::lawn::below(f, side, class, &lawn, grey, &mut g);
    let (at_cap, cols) = up_to_the_limit(&g, w, top);
    if cols == 0 || at_cap * 10 > cols * 9 {
        return;
    }
    for (c, &is) in class.iter_mut().zip(&g) {
        if is {
            *c = Class::Ground;
        }
    }
}

/// How many columns of `set` (`w` wide) run up to the `top` limit row,
/// and how many hold any of it from `top` down.
fn up_to_the_limit(set: &[bool], w: usize, top: usize) -> (usize, usize) {
    let h = set.len() / w.max(1);
    let (mut at_cap, mut cols) = (0, 0);
    for x in 0..w {
        if let Some(y) = (top..h).find(|&y| set[y * w + x]) {
            cols += 1;
            at_cap += (y == top) as usize;
        }
    }
    (at_cap, cols)
}

/// Ground that lies flat, for roads the stretches miss: a crossing's
/// stripes, lane markings and tree shadows split the bottom row into
/// stretches whose fills stop at each colour step, and a car parked on the
/// road is short and its panels, trim and shadow run across the view. Wall
/// pixels from [`FLAT_GROUND_FROM`] of the height down that lie flat
/// (sideways share under [`FLAT_GROUND`]) and are unsaturated, connected to
/// the bottom row with no colour test, join `g` when they and the ground
/// already found cover [`WIDE_STREET`] of what lies in the bottom fifth
/// (what stands up there, people crossing the road and posts, hides the
/// road: it is not counted), or [`STREET`] of the bottom fifth with
/// gradients that run [`OBLIQUE`]ly: a road seen in perspective converges
/// to its vanishing point, while the grooves, signs and sills of a
/// facade's lowest storey seen square on (CMP's rectified facades) run
/// level. A road seen along a street between parked cars runs level too
/// (Palma IMG_0675): it is kept when its texture coarsens toward the
/// camera ([`nearer_smoother`] under [`NEARER_SMOOTHER`]), as a plane
/// seen in perspective does and a facade seen square on does not. A
/// zebra crossing's stripes run level too: two people on it kept coruna
/// IMG_8106's whole road wall. Saturation is measured under the
/// photo's [`Light`]. Once a street is found, its coarse asphalt joins it
/// too: grain seen close runs every way (a sideways share near 0.5, over
/// [`FLAT_GROUND`]) and was wall under the parked cars and at the photo's
/// foot. It is taken up to [`GRAIN_GROUND`], within [`GRAIN_COLOUR`] of
/// the flat part's median colour (not a dark storey's foot beside the
/// pavement), not across a colour step (the kerb, the wall's foot), and
/// not what it climbed ([`climbs::off_the_climbs`]). Where the grain is most of
/// the road (wet asphalt seen close, Boston IMG_3619), the flat part
/// covers less than [`STREET`]: a flat part covering [`GRAIN_STREET`]
/// that runs oblique is a street when with the grain it covers [`STREET`].
fn flat_ground(
    f: &Features,
    steps: &[[f32; 3]],
    side: &Sideways,
    class: &[Class],
    light: Light,
    at: &(dyn Fn(usize) -> [f32; 3] + Sync),
    g: &mut [bool],
) {
    let (w, h) = (f.w, f.h);
    let from = (h as f32 * FLAT_GROUND_FROM) as usize * w;
    let (flat, sat) = (FLAT_GROUND, FLAT_GROUND_SATURATION);
    let cand = super::plane::flat_wall(f, side, class, from, flat, sat, light);
    let row = (h - 1) * w;
    let part = flood(&cand, w, h, (row..row + w).collect(), |_, _| true);
    let bottom = h * 4 / 5 * w..w * h;
    // Pixels of the bottom fifth that are ground, and those that lie
    // (ground, or not standing up).
    let (ground, lying) = bottom
        .clone()
        .into_par_iter()
        .map(|i| {
            let is = part[i] || g[i];
            (is as usize, (is || side.at(i) <= UPRIGHT) as usize)
        })
        .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1));
    let covered = ground as f32 / bottom.len() as f32;
    let wide = ground as f32 >= WIDE_STREET * lying as f32 && ground > 0;
    let oblique_part = oblique(f, &part);
    let street = covered >= STREET
        && (oblique_part > OBLIQUE || nearer_smoother(f, &part, from / w) < NEARER_SMOOTHER);
    // The coarse asphalt: grain that runs every way, of the flat part's
    // colour, not across a colour step.
    let grain = || {
        let mut grain = super::plane::flat_wall(f, side, class, from, GRAIN_GROUND, sat, light);
        if let Some(m) = median_of(&part, at) {
            grain
                .par_iter_mut()
                .enumerate()
                .for_each(|(i, p)| *p = *p && l1(at(i), m) < GRAIN_COLOUR);
        }
        flood(&grain, w, h, (row..row + w).collect(), |i, j| {
            l1(steps[i], steps[j]) < GROUND_STEP
        })
    };
    let grain = if wide || street {
        Some(grain())
    } else if covered >= GRAIN_STREET && oblique_part > OBLIQUE {
        // Wet or coarse asphalt seen close: the flat part is short of a
        // street, with the grain it is one.
        let grain = grain();
        let with = bottom
            .clone()
            .into_par_iter()
            .filter(|&i| part[i] || g[i] || grain[i])
            .count();
        (with as f32 >= STREET * bottom.len() as f32).then_some(grain)
    } else {
        None
    };
    if let Some(mut grain) = grain {
        g.par_iter_mut().zip(&part).for_each(|(a, &b)| *a |= b);
        off_the_climbs(&mut grain, side, w, h, from / w, None);
        g.par_iter_mut().zip(&grain).for_each(|(a, &b)| *a |= b);
    }
}

/// The median colour (of `at`) over `part`'s pixels; `None` when it has
/// none.
fn median_of(part: &[bool], at: &(dyn Fn(usize) -> [f32; 3] + Sync)) -> Option<[f32; 3]> {
    let mut v: Vec<[f32; 3]> = (0..part.len()).filter(|&i| part[i]).map(at).collect();
    (!v.is_empty()).then(|| median3(&mut v))
}

/// True when the median sideways share of the gradients over `part`'s
/// pixels is at most [`NARROW_FLAT`]: the part lies flat, as ground does.
fn lies_flat(part: &[bool], side: &Sideways) -> bool {
    let mut share: Vec<f32> = part
        .iter()
        .enumerate()
        .filter(|&(_, &p)| p)
        .map(|(i, _)| side.at(i))
        .collect();
    if share.is_empty() {
        return false;
    }
    let mid = share.len() / 2;
    *share.select_nth_unstable_by(mid, f32::total_cmp).1 <= NARROW_FLAT
}

/// Stretches of the bottom row an eighth of the width wide grow as they
/// are; from a sixteenth (this divisor) up they grow when their ground
/// lies flat (measured on LabelMeFacade train, IoU against 0.669: a
/// twelfth without the flat test 0.672, held out 0.669 -> 0.668; a
/// sixteenth without it 0.674 but CMP sill + cornice recall 0.810 ->
/// 0.803, the fill climbing the smooth plaster of the lowest storey).
const NARROW: usize = 16;

/// A narrow stretch's ground lies flat when the median sideways share
/// over it is at most this (plane.rs: median 0.25 on LabelMeFacade's road
/// and pavement, 0.54 on walls; measured: 0.35 LabelMeFacade train IoU
/// 0.673, CMP recall 0.806; 0.4 0.674 / 0.804; 0.5 0.673 / 0.800).
pub(super) const NARROW_FLAT: f32 = 0.35;

/// Paving joints are crossed in this bottom band (from this share of the
/// height down); above it a thin dark line may be the foot of the wall.
pub(super) const JOINT_BAND: f32 = 0.8;

/// Flat ground is looked for from this share of the height down
/// (measured on LabelMeFacade train, with the other flat-ground knobs
/// at 0.4 / 0.35 / 0.5 and no obliqueness test, IoU / CMP sill + cornice
/// recall: 0.5 0.699 / 0.737, 0.6 0.702 / 0.757, 0.7 0.697 / 0.764).
const FLAT_GROUND_FROM: f32 = 0.6;
/// Flat ground's sideways share is under this (plane.rs: median 0.25 on
/// LabelMeFacade's road and pavement, 0.33 on its cars, 0.54 on walls;
/// measured, LabelMeFacade train IoU: 0.3 0.691, 0.4 0.699).
const FLAT_GROUND: f32 = 0.4;
/// In a street already found, the road's grain is taken up to this
/// sideways share (isotropic grain is 0.5). Measured, LabelMeFacade train
/// IoU / spill / car spill / wall missed as ground, held out the same,
/// CMP sill + cornice recall: none 0.752 / 0.148 / 0.354 / 0.042, 0.725 /
/// 0.147 / 0.400 / 0.055, 4621; 0.55 0.753 / 0.140 / 0.328 / 0.046, 0.724
/// / 0.141 / 0.373 / 0.062, 4621. Tried: 0.55 with no colour-step test
/// and no [`off_the_climbs`], 0.751 / 0.137, held out 0.723 / 0.138, CMP
/// 4616 (it climbed plaster walls: Italy IMG_0242, london dsc07236); with
/// the colour step and no climb cut 0.752 / 0.140, 0.723 / 0.141; 0.55
/// for every flat test (not only in a street): 0.751 / 0.130, CMP 4490
/// (it takes plinths).
const GRAIN_GROUND: f32 = 0.55;
/// A flat part that runs oblique but covers under [`STREET`] of the
/// bottom fifth is a street when it covers this much and with the grain
/// [`STREET`] (Boston IMG_3619: 0.37, with the grain 0.69). Measured,
/// LabelMeFacade train IoU / spill / ground spill / car spill / wall
/// missed as ground, held out the same, CMP recall, with no colour test
/// on the grain: none 0.753 / 0.140 / 0.080 / 0.328 / 0.046, 0.724 /
/// 0.141 / 0.082 / 0.373 / 0.062, 4621; 0.35 0.752 / 0.138 / 0.079 /
/// 0.308 / 0.049, 0.724 / 0.140 / 0.082 / 0.368 / 0.062, 4621 (it adds
/// two train photos: insidecity_par194 +0.07, boston p1010898 -0.10,
/// whose dark storey the grain took; held out Palma IMG_0767 +0.04; CMP
/// recall 4621 both).
const GRAIN_STREET: f32 = 0.35;
/// The grain is within this colour distance (L1 of the smoothed colours,
/// 0..3) of the flat part's median. Measured with [`GRAIN_STREET`], as
/// above: 0.5 0.753 / 0.145 / 0.087 / 0.339 / 0.042, held out 0.726 /
/// 0.144 / 0.085 / 0.389 / 0.056 (it leaves shaded asphalt wall); 0.7
/// 0.754 / 0.142 / 0.082 / 0.336 / 0.043, 0.725 / 0.143 / 0.084 / 0.384
/// / 0.058; 0.9 0.753 / 0.139 / 0.080 / 0.315 / 0.046, 0.726 / 0.141 /
/// 0.083 / 0.373 / 0.059, CMP 4621; 1.2 0.753 / 0.139 / 0.080 / 0.311 /
/// 0.047, 0.724 / 0.141 / 0.082 / 0.371 / 0.062.
const GRAIN_COLOUR: f32 = 0.9;
/// Flat ground is less saturated than this (a painted car, a red door is
/// not taken).
const FLAT_GROUND_SATURATION: f32 = 0.35;
/// Flat ground is kept when it covers this share of the bottom fifth
/// (with the ground found before) and its gradients run oblique.
const STREET: f32 = 0.5;
/// Flat ground is kept when it covers this share of the bottom fifth
/// whatever its gradients (measured, with no obliqueness test: 0.5 IoU
/// 0.702, CMP recall 0.757; 0.8 0.699 / 0.798; 0.9 0.692 / 0.804). What
/// stands up (sideways share over plane.rs's `UPRIGHT`) is left out of the
/// bottom fifth (measured on LabelMeFacade train, IoU 0.732 -> 0.734,
/// held out 0.707 both, CMP sill + cornice recall 4624 both; standing up
/// from a share of 0.6: 0.734 / 0.707 / 4617; from 0.8: no change).
const WIDE_STREET: f32 = 0.9;
/// Flat ground covering [`STREET`] of the bottom fifth is kept when this
/// share of its gradient energy runs oblique (see [`oblique`]; measured
/// over the flat ground of the photos it would be kept in, median 0.41 on
/// LabelMeFacade train, 0.30 on CMP; measured, LabelMeFacade train IoU /
/// CMP sill + cornice recall: 0.35 0.699 / 0.796, 0.4 0.697 / 0.802,
/// 0.45 0.696 / 0.804).
const OBLIQUE: f32 = 0.4;
/// Flat ground covering [`STREET`] of the bottom fifth whose gradients run
/// level is kept when its nearer half's gradient energy per pixel is under
/// this share of its farther half's (see [`nearer_smoother`]; measured
/// over the flat ground refused for running level (oblique share at most
/// 0.4, coverage 0.5 or more): CMP's 161 such facades, lowest 0.28, tenth
/// percentile 0.65, median 1.37; Palma IMG_0675's road 0.16, porter
/// p1010951's pavement 0.39. Measured, LabelMeFacade train IoU / ground
/// spill / wall missed as ground, held out the same, CMP sill + cornice
/// recall: none 0.747 / 0.091 / 0.046, 0.723 / 0.090 / 0.058, 4626; 0.35
/// 0.747 / 0.089 / 0.047, 0.723 / 0.088 / 0.058, 4626; 0.4: held-out wall
/// missed as ground 0.061 (p1010951's stair faces and stone wall, labelled
/// wall, taken with its pavement); 0.5: CMP 4622).
const NEARER_SMOOTHER: f32 = 0.35;
/// Ground is less saturated than this.
const GROUND_SATURATION: f32 = 0.45;
/// Ground lies within this colour distance (L1, 0..3) of its stretch of
/// the bottom row.
const GROUND_COLOUR: f32 = 0.5;
/// The ground fill stops at a colour step this large between neighbours.
const GROUND_STEP: f32 = 0.2;

/// Ground this textured (mean luma gradient) or more is not ground.
const GROUND_TEXTURE: f32 = 0.15;

pub(super) fn median3(v: &mut [[f32; 3]]) -> [f32; 3] {
    let mut out = [0.0; 3];
    for (k, o) in out.iter_mut().enumerate() {
        let mut c: Vec<f32> = v.iter().map(|p| p[k]).collect();
        let mid = c.len() / 2;
        *o = *c.select_nth_unstable_by(mid, f32::total_cmp).1;
    }
    out
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::analysis::wall::classify;
    use crate::photo::Photo;

    /// The classes of `img`, analysed at its own width.
    pub(super) fn classes_of(img: image::RgbImage) -> Vec<Class> {
        let w = img.width();
        classify(&Features::new(
            &Photo::new(image::DynamicImage::ImageRgb8(img)),
            w,
        ))
    }

    #[test]
    fn a_road_and_a_pavement_of_other_greys_are_both_ground() {
        // An orange wall over a dark road; a pale pavement along the
        // bottom-left. Each stretch of the bottom row is its own ground.
        let (w, h) = (200u32, 160u32);
        let img = image::RgbImage::from_fn(w, h, |x, y| {
            image::Rgb(if y < h * 6 / 10 {
                [204, 128, 76]
            } else if y >= h * 9 / 10 && x < w / 2 {
                [166; 3]
            } else {
                [90; 3]
            })
        });
        let class = classes_of(img);
        let below = (h as usize * 6 / 10 + 3) * w as usize;
        let ground = class[below..]
            .iter()
            .filter(|&&c| c == Class::Ground)
            .count();
        assert!(
            ground as f32 > 0.9 * (class.len() - below) as f32,
            "{ground}"
        );
        assert!(class[..w as usize * 80].iter().all(|&c| c == Class::Wall));
    }

    /// An orange wall over grey paving stones 16 pixels square, laid with
    /// darker joints 2 pixels wide (a colour step of 0.35, beyond
    /// `GROUND_STEP`), in the bottom fifth.
    fn paved(joint: u8) -> Vec<Class> {
        let (w, h) = (240u32, 200u32);
        let img = image::RgbImage::from_fn(w, h, |x, y| {
            image::Rgb(if y < 164 {
                [204, 128, 76]
            } else if x % 16 < 2 || (y - 164) % 16 < 2 {
                [joint; 3]
            } else {
                [150; 3]
            })
        });
        classes_of(img)
    }

    #[test]
    fn the_ground_fill_crosses_paving_joints() {
        let class = paved(120);
        let paving = &class[170 * 240..];
        let ground = paving.iter().filter(|&&c| c == Class::Ground).count();
        assert!(
            ground * 10 > paving.len() * 9,
            "{ground} of {}",
            paving.len()
        );
        assert!(class[..160 * 240].iter().all(|&c| c == Class::Wall));
    }

    /// An orange wall over a grey ground whose faint stripes (10 levels)
    /// run across the view (`flat`) or up it; along the bottom 10 rows the
    /// ground is red (too saturated) but for one stretch a tenth of the
    /// width wide, under an eighth.
    fn narrow_stretch(flat: bool) -> f32 {
        let (w, h) = (240u32, 200u32);
        let img = image::RgbImage::from_fn(w, h, |x, y| {
            let stripe = if flat { y } else { x } % 6 < 3;
            image::Rgb(if y < 120 {
                [204, 128, 76]
            } else if y >= 190 && !(100..124).contains(&x) {
                [190, 40, 40]
            } else if stripe {
                [90; 3]
            } else {
                [100; 3]
            })
        });
        let class = classes_of(img);
        let road = &class[125 * 240..185 * 240];
        road.iter().filter(|&&c| c == Class::Ground).count() as f32 / road.len() as f32
    }

    #[test]
    fn a_narrow_stretch_grows_over_ground_that_lies_flat() {
        let flat = narrow_stretch(true);
        assert!(flat > 0.9, "{flat} of the road is ground");
        let upright = narrow_stretch(false);
        assert!(upright < 0.1, "{upright} of the upright stripes are ground");
    }

    /// Share of the pixels in rows `y0..y1`, columns `x0..x1` of a
    /// `w`-wide `class` that are wall.
    pub(in crate::analysis) fn wall_in(
        class: &[Class],
        w: usize,
        (x0, x1): (usize, usize),
        (y0, y1): (usize, usize),
    ) -> f32 {
        let walls = (y0..y1)
            .flat_map(|y| (x0..x1).map(move |x| y * w + x))
            .filter(|&i| class[i] == Class::Wall)
            .count();
        walls as f32 / ((x1 - x0) * (y1 - y0)) as f32
    }

    /// The size of [`crossing`]'s photo.
    const CROSSING: (usize, usize) = (240, 200);

    /// The classes of a street 240 x 200: an orange wall down to row 110
    /// over a dark road crossed by white stripes 6 pixels high every 12
    /// (the bottom row is a stripe), with `front(x, y)` drawn over the road
    /// where it is `Some`.
    fn crossing(front: impl Fn(usize, usize) -> Option<[u8; 3]>) -> Vec<Class> {
        let (w, h) = CROSSING;
        let img = image::RgbImage::from_fn(w as u32, h as u32, |x, y| {
            let (x, y) = (x as usize, y as usize);
            image::Rgb(if y < 110 {
                [204, 128, 76]
            } else if let Some(c) = front(x, y) {
                c
            } else if (h - 1 - y) % 12 < 6 {
                [230; 3]
            } else {
                [90; 3]
            })
        });
        classes_of(img)
    }

    #[test]
    fn a_crossing_and_the_car_parked_on_it_leave_the_wall() {
        // An orange wall down to 55% of the height over a dark road
        // crossed by white stripes 6 pixels high every 12 (the bottom row
        // is a stripe: its fill stops at the first asphalt), and a grey car
        // on it: a dark window band, silver panels split by trim, a
        // bumper, and black tyres in its shadow.
        let class = crossing(|x, y| {
            if (60..150).contains(&x) && (120..166).contains(&y) {
                Some(match y {
                    120..130 => [60, 64, 70],
                    140..142 | 150..156 => [110; 3],
                    _ => [170, 170, 174],
                })
            } else if (60..150).contains(&x) && (166..174).contains(&y) {
                Some([20; 3])
            } else {
                None
            }
        });
        let (w, h) = (CROSSING.0, CROSSING.1);
        let road = wall_in(&class, w, (0, w), (125, h));
        assert!(road < 0.3, "{road} of the road and the car is wall");
        let car = wall_in(&class, w, (60, 150), (130, 174));
        assert!(car < 0.3, "{car} of the car is wall");
        let wall = wall_in(&class, w, (0, w), (0, 105));
        assert!(wall > 0.99, "{wall} of the wall is wall");
    }

    /// An orange wall down to 55% of the height over a zebra crossing (a
    /// dark road crossed by white stripes 6 pixels high every 12, level:
    /// no perspective), with two blue figures 16 pixels wide on it from
    /// 60% of the height down, 13% of the bottom fifth: people whose
    /// clothes' folds stand up (`upright`), or blue benches whose slats
    /// lie level. Returns the share of the road beside them that is wall.
    fn crossing_with_figures(upright: bool) -> f32 {
        let class = crossing(|x, y| {
            let figure = y >= 120 && ((80..96).contains(&x) || (140..156).contains(&x));
            let folds = if upright { x } else { y } % 4 < 2;
            figure.then_some(if folds { [70, 90, 230] } else { [10, 15, 90] })
        });
        let (w, h) = (CROSSING.0, CROSSING.1);
        let wall = wall_in(&class, w, (0, w), (0, 105));
        assert!(wall > 0.99, "{wall} of the wall is wall");
        wall_in(&class, w, (0, 70), (125, h))
    }

    #[test]
    fn people_on_a_crossing_do_not_keep_the_road_wall() {
        let road = crossing_with_figures(true);
        assert!(road < 0.3, "{road} of the road beside the people is wall");
        // Level slats lie flat: they are not excused, the road stays wall.
        let road = crossing_with_figures(false);
        assert!(road > 0.7, "{road} of the road beside the benches is wall");
    }

    #[test]
    fn a_shop_floor_seen_square_on_stays_wall() {
        // A facade down to the photo's foot: an orange upper storey, a
        // grey ground floor from 55% down with level grooves every 12
        // pixels and three dark doors; no ground at all. The grooves lie
        // flat and grey, but run level: no road's perspective.
        let (w, h) = (240usize, 200usize);
        let img = image::RgbImage::from_fn(w as u32, h as u32, |x, y| {
            let (x, y) = (x as usize, y as usize);
            image::Rgb(if y < 110 {
                [204, 128, 76]
            } else if y >= 130 && x % 80 >= 30 && x % 80 < 50 {
                [40, 36, 34]
            } else if y % 12 < 2 {
                [120; 3]
            } else {
                [165; 3]
            })
        });
        let class = classes_of(img);
        let floor = wall_in(&class, w, (0, w), (112, h));
        assert!(floor > 0.9, "{floor} of the shop floor is wall");
    }

    /// The share of a level-striped road called wall: an orange storey
    /// over a grey plinth of the road's colour (so the bottom row's
    /// stretch is refused as like what lies above it), a dark foot at 55%
    /// of the height, and a grey road whose level stripes (8 levels apart)
    /// are 2 pixels high in the farther half of the ground below 60% of the
    /// height and, when `coarsening`, 8 pixels high in the nearer half (a
    /// plane's texture seen in perspective), else 2 pixels high throughout
    /// (a plinth's courses seen square on). A red block on the road keeps
    /// the flat ground under the wide street's share.
    fn level_road(coarsening: bool) -> f32 {
        let (w, h) = (240usize, 200usize);
        let img = image::RgbImage::from_fn(w as u32, h as u32, |x, y| {
            let (x, y) = (x as usize, y as usize);
            let high = if coarsening && y >= 160 { 8 } else { 2 };
            image::Rgb(match y {
                0..60 => [204, 128, 76],
                60..106 => [100; 3],
                106..112 => [30; 3],
                150..186 if x < 80 => [180, 70, 60],
                _ if ((y + 4) / high) % 2 == 0 => [96; 3],
                _ => [104; 3],
            })
        });
        let class = classes_of(img);
        let wall = wall_in(&class, w, (0, w), (0, 96));
        assert!(wall > 0.99, "{wall} of the wall is wall");
        wall_in(&class, w, (80, w), (125, 185))
    }

    #[test]
    fn a_level_road_whose_texture_coarsens_toward_the_camera_is_ground() {
        let road = level_road(true);
        assert!(road < 0.1, "{road} of the coarsening road is wall");
        let plinth = level_road(false);
        assert!(plinth > 0.9, "{plinth} of the even courses are wall");
    }

    /// The share of a grey block called wall: the left half of a 240 x
    /// 200 photo is grey down to the bottom fifth, 10 levels lighter than
    /// the pavement under it (the ground fill climbs it to its 45% limit),
    /// the right half a red shop front; the block is plain (a plaster
    /// wall) or, when `level`, striped across every 3 rows (a road running
    /// to the horizon).
    /// The share of wall in a 240 x 200 photo's left half between rows 95
    /// and 155: a red wall on the right, grey pavement under row 160,
    /// and on the left from row `from` down a grey block, plain or striped
    /// across (`level`), red above it.
    fn grey_block(level: bool, from: u32) -> f32 {
        let (w, h) = (240usize, 200usize);
        let class = grey_block_classes(level, from);
        let pavement = wall_in(&class, w, (0, w), (165, h));
        assert!(pavement < 0.1, "{pavement} of the pavement is wall");
        wall_in(&class, w, (0, 120), (95, 155))
    }

    fn grey_block_classes(level: bool, from: u32) -> Vec<Class> {
        let (w, h) = (240u32, 200u32);
        classes_of(image::RgbImage::from_fn(w, h, |x, y| {
            image::Rgb(match (x, y) {
                (_, 160..) => [140; 3],
                (120.., _) => [180, 60, 50],
                _ if y < from => [180, 60, 50],
                _ if level && y % 6 < 3 => [140; 3],
                _ => [150; 3],
            })
        }))
    }

    #[test]
    fn the_ground_fill_does_not_keep_the_wall_it_climbed() {
        let wall = grey_block(false, 0);
        assert!(wall > 0.9, "{wall} of the plain wall is wall");
        // Near miss: the road ends at the far facades just above the limit.
        let road = grey_block(true, 85);
        assert!(road < 0.1, "{road} of the level road is wall");
    }

    #[test]
    fn a_wall_of_the_pavements_grey_going_on_above_the_limit_is_wall() {
        // Courses run level as a far road's texture does, but the grey goes
        // on up the photo: a wall, where the road ends at its far facades.
        // Under 60% of the height (row 120) what lies flat joins a street's
        // ground with no colour test (`flat_ground`): not measured here.
        let class = grey_block_classes(true, 0);
        let wall = wall_in(&class, 240, (0, 120), (95, 118));
        assert!(wall > 0.9, "{wall} of the coursed wall is wall");
    }

    /// The share of coarse asphalt called wall: a 240 x 200 street, an
    /// orange wall down to row 110 over a grey road marked with white lines
    /// 30 degrees off level (seen in perspective), whose right third is
    /// coarse grain (blocks of 3 x 3 pixels, light or dark at random: it
    /// runs every way); with `kerb`, dark bands 4 pixels wide cut the grain
    /// above row 150 off from the road below and beside it (colour
    /// steps).
    fn grain(kerb: bool) -> f32 {
        let (w, h) = (240usize, 200usize);
        let img = image::RgbImage::from_fn(w as u32, h as u32, |x, y| {
            let (bx, by) = (x / 3, y / 3);
            let hash = (bx * 7919 + by * 104_729) ^ (bx * by * 31);
            image::Rgb(match (x, y) {
                (_, ..110) => [204, 128, 76],
                (_, 150..154) | (156..160, 110..150) if kerb => [20; 3],
                (160.., _) if hash % 5 < 2 => [94; 3],
                (160.., _) => [108; 3],
                _ if (x as f32 * 0.577 + y as f32) % 24.0 < 3.0 => [230; 3],
                _ => [100; 3],
            })
        });
        let class = classes_of(img);
        let wall = wall_in(&class, w, (0, w), (0, 100));
        assert!(wall > 0.95, "{wall} of the wall is wall");
        wall_in(&class, w, (165, w), (125, 145))
    }

    #[test]
    fn a_streets_coarse_asphalt_is_ground_unless_a_kerb_cuts_it_off() {
        let asphalt = grain(false);
        assert!(asphalt < 0.5, "{asphalt} of the coarse asphalt is wall");
        let cut_off = grain(true);
        assert!(
            cut_off > 0.8,
            "{cut_off} of the grain beyond the kerb is wall"
        );
    }

    /// The share of the bottom 40% of a 240 x 200 photo called ground:
    /// a wall of colour `wall` down to 60% of the height, `foot` below.
    fn ground_under(wall: [u8; 3], foot: [u8; 3]) -> f32 {
        let (w, h) = (240usize, 200usize);
        let img = image::RgbImage::from_fn(w as u32, h as u32, |_, y| {
            image::Rgb(if y < 120 { wall } else { foot })
        });
        let class = classes_of(img);
        assert!(
            wall_in(&class, w, (0, w), (0, 115)) > 0.99,
            "the wall is wall"
        );
        1.0 - wall_in(&class, w, (0, w), (125, h))
    }

    #[test]
    fn a_road_at_dusk_is_ground() {
        // A mauve wall over a dark road, blue under the dusk sky: the
        // road's saturation is 0.48 as it stands (over the limit 0.45),
        // 0.43 with half the light taken out.
        let road = ground_under([150, 135, 155], [52, 58, 100]);
        assert!(road > 0.9, "{road} of the road is ground");
    }

    #[test]
    fn a_road_under_sodium_lamps_is_ground() {
        // Sodium light has no blue: the road's saturation is 0.98, with
        // any gain (its blue has nothing to scale up) still over the limit.
        let road = ground_under([110, 66, 4], [170, 104, 3]);
        assert!(road > 0.9, "{road} of the road is ground");
    }

    #[test]
    fn by_day_a_warm_plinth_stays_wall() {
        // An ochre facade over a terracotta plinth: warm, as sodium light
        // would make a road, but lit by day (its luma 0.5): its colour is
        // its own, not the light's.
        let plinth = ground_under([204, 128, 76], [120, 80, 50]);
        assert!(plinth < 0.1, "{plinth} of the plinth is ground");
    }
}
