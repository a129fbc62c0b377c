//! What stands before the wall and is not the building: café umbrellas,
//! awnings, white sign boards. The classifier calls them wall (their
//! colour is no sky's, vegetation's or glass's), so rain and dirt were laid
//! on them: the blind checks' first tell. They are found **relative to the
//! photo's own wall** (absolute thresholds fail: walls elsewhere share
//! them; BENCHMARKS.md, "bare crowns called wall: twigs"): a thick, smooth,
//! near-white blob, much brighter and smoother than the wall the
//! classifier was sure of and far from its colour, in the lower part of the
//! photo. Frames, sills and trims of another colour stay wall: they are
//! thin (the opening by [`THICK`] removes them), or as textured as the
//! wall, or coloured. The blobs become [`Class::Thing`]; the matte's soft
//! edge is made from the classes as for any other class.
//!
//! Measured on LabelMeFacade train (BENCHMARKS.md, twenty-fourth pass,
//! things26): the candidates' other signs, relative or absolute, take as
//! much labelled wall as things (colour rarity under a Lab histogram of the
//! wall, chroma above the wall's, distance from the wall's colour alone,
//! touching the ground); the near-white test is what left only umbrellas,
//! an awning and sign boards among the blobs picked.

use rayon::prelude::*;

use super::appearance::lab;
use super::features::{Features, box_mean};
use super::glass::components;
use super::ground::median3;
use super::wall::{Class, flood};
use crate::effects::percentile::{Rank, percentile};

/// The wall's sure pixels: wall within this many pixels all round.
const SURE: usize = 2;

/// A thing's texture is under this share of the sure wall's median texture
/// (umbrellas, awnings and boards: 0.19-0.39 on LabelMeFacade train; 0.6
/// took lit stretches of the wall and pale bands).
const SMOOTH: f32 = 0.4;

/// A thing is brighter than the sure wall's median by this much (L*, 0..100;
/// the umbrellas of img_0383 by 40; 25 gave the same blobs).
const BRIGHTER: f32 = 15.0;

/// A thing's colour is further from the sure wall's median colour (CIELAB)
/// than the wall's own pixels are, by this many of their median absolute
/// deviations (the wall's 90th percentile is at 2.2 on LabelMeFacade
/// train; 1.5 took pale bands of the wall).
const FAR: f32 = 2.5;

/// Near-white: chroma (CIELAB, sqrt(a*^2 + b*^2)) under this ...
const WHITE_CHROMA: f32 = 5.0;

/// ... and L* over this (the umbrellas 89-95, the boards and awning 95-97;
/// what this left out among the smooth bright blobs: a sunlit stretch of
/// an orange wall (chroma 47), a cream wall (19), pale grey concrete bands
/// (L* 76)).
const WHITE_L: f32 = 85.0;

/// The blob is at least this thick: the long side over this, in pixels, is
/// the radius of the opening (6 px at 683: a window's white frame or a sill
/// is thinner and stays wall).
const THICK: usize = 110;

/// ... at least this share of the photo ...
const MIN_AREA: f32 = 0.002;

/// ... and its top below this share of the height (what stands on the
/// street; the pale top of a far wall against the sky is higher).
const BELOW: f32 = 0.3;

/// The blob grows over the wall's pixels brighter than it by [`BRIGHTER`]
/// with a chroma under this.
const GROW_CHROMA: f32 = 10.0;

/// A grown blob is kept when it is at most this many times its seeds
/// (LabelMeFacade train: the umbrellas 2.4, the awning 1.9, a white car
/// 1.3; white plinths flush with a white wall grew 20 times, over the wall).
const GROW_MAX: f32 = 3.0;

/// The sure wall's statistics are taken from every this-many-th pixel
/// (about 25k of a 1024 x 768 analysis image's; the medians of all its
/// sure pixels cost a sixth of the analysis at 12 MP).
const SAMPLE: usize = 31;

/// ... of which at least this many must be sure wall to compare with.
const MIN_SAMPLE: usize = 50;

/// Only pixels whose 3 x 3 mean has every channel (sRGB, 0..1) over this
/// are converted to CIELAB for the near-white test (a colour of L\* over
/// [`WHITE_L`] with chroma under [`WHITE_CHROMA`] has all three over 0.75).
const PALE_MIN: f32 = 0.7;

/// Marks the things before the wall (see the module's documentation) as
/// [`Class::Thing`]. Nothing when the photo is all wall (a close-up) or the
/// wall has too few sure pixels to compare with.
pub(super) fn mark(f: &Features, class: &mut [Class]) {
    let (w, h) = (f.w, f.h);
    let n = w * h;
    if class.iter().all(|&c| c == Class::Wall) {
        return;
    }
    let wall: Vec<f32> = class
        .iter()
        .map(|&c| (c == Class::Wall) as u8 as f32)
        .collect();
    let sure: Vec<bool> = box_mean(&wall, w, h, SURE)
        .iter()
        .map(|&v| v > 1.0 - 1e-4)
        .collect();
    // CIELAB of pixel i's 3 x 3 mean colour.
    let lab_at = |i: usize| {
        let (x, y) = (i % w, i / w);
        let (mut sum, mut k) = ([0f32; 3], 0f32);
        for yy in y.saturating_sub(1)..(y + 2).min(h) {
            for xx in x.saturating_sub(1)..(x + 2).min(w) {
                let c = f.rgb_at(yy * w + xx);
                (0..3).for_each(|j| sum[j] += c[j]);
                k += 1.0;
            }
        }
        lab(sum.map(|v| v / k))
    };
    // The sure wall's statistics from every SAMPLE-th pixel.
    let sample: Vec<usize> = (0..n).step_by(SAMPLE).filter(|&i| sure[i]).collect();
    if sample.len() < MIN_SAMPLE {
        return;
    }
    let mut sample_lab: Vec<[f32; 3]> = sample.iter().map(|&i| lab_at(i)).collect();
    // The upper middle of `v` (the sample is never empty).
    let median = |v: Vec<f32>| percentile(v, 0.5, Rank::Nearest).unwrap_or(0.0);
    let med = median3(&mut sample_lab);
    let dist = |d: [f32; 3]| {
        ((d[0] - med[0]).powi(2) + (d[1] - med[1]).powi(2) + (d[2] - med[2]).powi(2)).sqrt()
    };
    let d_med = median(sample_lab.iter().map(|&l| dist(l)).collect());
    let d_mad = median(
        sample_lab
            .iter()
            .map(|&l| (dist(l) - d_med).abs())
            .collect(),
    ) + 1.0;
    let tex = median(sample.iter().map(|&i| f.texture[i]).collect()).max(1e-4);
    let cand: Vec<f32> = (0..n)
        .into_par_iter()
        .map(|i| {
            let cheap = class[i] == Class::Wall
                && f.texture[i] < SMOOTH * tex
                && f.rgb.iter().all(|p| p[i] > PALE_MIN);
            let thing = cheap && {
                let [l, a, b] = lab_at(i);
                l > med[0] + BRIGHTER
                    && (dist([l, a, b]) - d_med) / d_mad > FAR
                    && a.hypot(b) < WHITE_CHROMA
                    && l > WHITE_L
            };
            thing as u8 as f32
        })
        .collect();
    // Opening: what a square of radius r fits in.
    let r = (w.max(h) / THICK).max(1);
    // Half a pixel of the box: the box means' rounding stays under it.
    let half = 0.5 / ((2 * r + 1) * (2 * r + 1)) as f32;
    let inner: Vec<f32> = box_mean(&cand, w, h, r)
        .iter()
        .map(|&v| (v > 1.0 - half) as u8 as f32)
        .collect();
    let opened: Vec<bool> = box_mean(&inner, w, h, r)
        .iter()
        .zip(&cand)
        .map(|(&v, &c)| v > half && c > 0.0)
        .collect();
    let top = (BELOW * h as f32) as usize;
    let seeds: Vec<usize> = components(&opened, w, h)
        .into_iter()
        .filter(|blob| {
            let high = blob.iter().map(|&i| i / w).min().unwrap_or(0);
            (blob.len() as f32) >= MIN_AREA * n as f32 && high >= top
        })
        .flatten()
        .collect();
    if seeds.is_empty() {
        return;
    }
    // The blob's rim (a canopy's edge, its shaded folds) is rougher and
    // less white: grown into (hysteresis, as Canny's edges) over the wall
    // still pale and much brighter than the wall.
    let pale: Vec<bool> = (0..n)
        .into_par_iter()
        .map(|i| {
            let [l, a, b] = lab_at(i);
            class[i] == Class::Wall && l > med[0] + BRIGHTER && a.hypot(b) < GROW_CHROMA
        })
        .collect();
    let mut seed = vec![false; n];
    seeds.iter().for_each(|&i| seed[i] = true);
    let grown = flood(&pale, w, h, seeds, |_, _| true);
    // A pale stretch of wall, not a thing, is far larger than its seeds.
    for piece in components(&grown, w, h) {
        let core = piece.iter().filter(|&&i| seed[i]).count();
        if piece.len() as f32 <= GROW_MAX * core as f32 {
            piece.into_iter().for_each(|i| class[i] = Class::Thing);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::photo::Photo;

    /// 400 x 300: blue sky down to row 40, a grey street from row 260,
    /// between them a brick wall (mortar courses and joints, a little
    /// grain) with a pale stone sill 6 rows thick (rows 100..106), a white
    /// sill as thick (rows 130..136) and, standing before the wall in rows
    /// 170..215, a white café umbrella's canopy (columns 100..240).
    fn street() -> image::RgbImage {
        image::RgbImage::from_fn(400, 300, |x, y| {
            let grain = ((x * 7 + y * 13) % 5) as u8 * 4;
            image::Rgb(if y < 40 {
                [90, 150, 230]
            } else if y >= 260 {
                [120 + grain, 120 + grain, 124 + grain]
            } else if (170..215).contains(&y) && (100..240).contains(&x) {
                [242, 242, 240]
            } else if (100..106).contains(&y) && (60..340).contains(&x) {
                [214, 200, 176]
            } else if (130..136).contains(&y) && (60..340).contains(&x) {
                [240, 240, 238]
            } else if y % 9 == 0 || (x + (y / 9) * 11) % 24 == 0 {
                [120 + grain, 80, 70]
            } else {
                [160 + grain, 95 + grain, 78]
            })
        })
    }

    /// How many pixels of rows `ys`, columns `xs` (400 wide) satisfy `p`.
    fn count(
        ys: std::ops::Range<usize>,
        xs: std::ops::Range<usize>,
        p: impl Fn(usize) -> bool,
    ) -> usize {
        ys.flat_map(|y| xs.clone().map(move |x| y * 400 + x))
            .filter(|&i| p(i))
            .count()
    }

    #[test]
    fn an_umbrella_before_the_wall_is_a_thing_and_the_sills_stay_wall() {
        let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(street())), 400);
        let mut class: Vec<Class> = (0..400 * 300)
            .map(|i| match i / 400 {
                y if y < 40 => Class::Sky,
                y if y >= 260 => Class::Ground,
                _ => Class::Wall,
            })
            .collect();
        mark(&f, &mut class);
        let canopy = count(172..213, 102..238, |i| class[i] == Class::Thing);
        assert!(
            canopy * 10 > 41 * 136 * 9,
            "{canopy} canopy pixels are things"
        );
        for sill in [100..106, 130..136] {
            let wall = count(sill.clone(), 60..340, |i| class[i] == Class::Wall);
            assert_eq!(wall, 6 * 280, "the sill at {sill:?} stays wall");
        }
        let brick = count(45..165, 0..400, |i| class[i] == Class::Wall);
        assert_eq!(brick, 120 * 400, "the brick stays wall");
    }

    #[test]
    fn the_umbrella_takes_no_grime_in_the_analysis() {
        let photo = Photo::new(image::DynamicImage::ImageRgb8(street()));
        let a = crate::analysis::analyse(&photo, &crate::analysis::Options::default()).unwrap();
        let m = a.matte.as_raw();
        let canopy = count(175..210, 105..235, |i| m[i] >= crate::grid::WALL);
        assert!(canopy * 20 < 35 * 130, "{canopy} canopy pixels are wall");
        let sills = count(100..106, 80..320, |i| m[i] >= crate::grid::WALL)
            + count(130..136, 80..320, |i| m[i] >= crate::grid::WALL);
        assert!(sills * 10 > 12 * 240 * 9, "{sills} sill pixels are wall");
    }
}
