//! What is wall: sky, vegetation, ground and window glass are found from
//! colour and texture statistics and where they sit (sky touches the top,
//! ground the bottom, glass forms dark compact blobs, bare branches are
//! surrounded by sky); the rest is wall. `matte.rs` makes the hard labels
//! a soft matte.

use rayon::prelude::*;
use serde::Serialize;

use super::crowns::{Closings, behind_branches};
use super::features::{Features, box_mean, l1, luma, texture_radius};

/// What an analysis pixel shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Class {
    /// The wall (frames and sills included).
    Wall,
    /// Sky.
    Sky,
    /// Trees, bushes, grass.
    Vegetation,
    /// Window glass.
    Glass,
    /// Road, pavement.
    Ground,
    /// What stands before the wall and is not the building: umbrellas,
    /// awnings, sign boards ([`super::things`]).
    Thing,
}

impl Class {
    /// Label for the overlay.
    pub fn label(self) -> &'static str {
        match self {
            Class::Wall => "wall",
            Class::Sky => "sky",
            Class::Vegetation => "vegetation",
            Class::Glass => "glass",
            Class::Ground => "ground",
            Class::Thing => "thing",
        }
    }
}

/// Sky is smoother than this (mean luma gradient).
pub(super) const SKY_TEXTURE: f32 = 0.05;

/// Sky this much bluer than red (0..1) seeds the sky fill wherever it is
/// in the upper half.
pub(super) const CLEAR_BLUE: f32 = 0.25;

/// The colour step (L1, 0..3) the sky fills do not flood across: sky is
/// smooth, a roof edge is a step.
pub(super) const SKY_STEP: f32 = 0.08;

/// A dusk sky (dark blue, below `is_sky_colour`'s blue floor) is bluer
/// than red by more than this (0..1) (measured on LabelMeFacade train: the
/// one dusk photo's sky has 0.16 at the median, 0.08 at the 5th
/// percentile; 0.04 takes 1.7 times the facade's pixels there).
const DUSK_BLUE: f32 = 0.08;

/// A dusk (or night) sky runs along at least this share of the top row
/// (measured on LabelMeFacade train and held out: the dusk photo 0.72,
/// dark blue walls and glass touching the top 0.07 at most; train IoU /
/// sky spill with the dusk rule alone: 0.05 to 0.5 0.7322 / 0.052, 0.8
/// 0.7314 / 0.058 as without it).
const DUSK_TOP: f32 = 0.3;

/// A night sky is darker than this (luma, 0..1) and runs along at least
/// [`DUSK_TOP`] of the top row (the two night photos of LabelMeFacade,
/// train and held out, have 0.62 and 0.69 of it this dark, no other photo
/// 0.3; CMP's black rectification margins too, which are not wall either).
/// Measured (train IoU / sky spill, held-out IoU / sky spill, NIGHT_STEP
/// 0.02): 0.03 0.7323 / 0.049, 0.7067 / 0.081; 0.04 0.7323 / 0.049,
/// 0.7071 / 0.077; 0.05 0.7321 / 0.049.
const NIGHT_LUMA: f32 = 0.04;

/// A night sky is flooded down only over steps smaller than this (L1,
/// 0..3): the unlit tops of the walls are nearly as dark (measured as
/// [`NIGHT_LUMA`]: 0.01 finds nothing, 0.02 0.7323 / 0.049, 0.7071 /
/// 0.077, 0.03 0.7321 / 0.049, 0.7071 / 0.077 with more wall taken).
const NIGHT_STEP: f32 = 0.02;

/// Sky beyond a thin line is looked for within the long side over this
/// (plus the line and the texture window) of the sky found (measured on
/// LabelMeFacade: 2% of the side, IoU 0.614 for the same sky spill; with
/// no limit white walls across the roof edge become sky, IoU 0.611).
const SKY_REACH: usize = 100;

/// Sky beyond a thin line is within this colour distance (L1, 0..3) of
/// the mean colour of the sky found.
const SKY_MATCH: f32 = 0.05;

/// Vegetation is greener than this (excess green over the sum, ExG).
const GREEN_EXCESS: f32 = 0.1;

/// Share of green-excess pixels around a pixel (within 0.5% of the long
/// side) above which it is vegetation (measured on LabelMeFacade: 0.5
/// left more trees as wall, spill 0.333 -> 0.325, IoU 0.616 -> 0.615; 0.3
/// takes yellow and green-tinted walls, IoU 0.612).
const VEGETATION_VOTE: f32 = 0.4;

/// Below this share of non-wall pixels the photo is a close-up: all wall.
const CLOSE_UP: f32 = 0.02;

/// Labels every analysis pixel.
pub fn classify(f: &Features) -> Vec<Class> {
    let (w, h) = (f.w, f.h);
    let n = w * h;
    let mut class = vec![Class::Wall; n];
    // The sky's fills run on one thread: the paving joints, the
    // gradients' directions and the foliage's texture go beside them.
    let ((sky, leaves), (steps, side)) = rayon::join(
        || rayon::join(|| sky(f), || super::foliage::Foliage::new(f)),
        || {
            (
                super::joints::unjoint(f, (h as f32 * super::ground::JOINT_BAND) as usize),
                super::plane::Sideways::new(f),
            )
        },
    );
    // The windows in the sky beside the vegetation's vote (which needs
    // only the photo): the hole search is serial.
    let (sky, green) = rayon::join(
        || {
            let mut sky = sky;
            super::sky_windows::windows_in_sky(f, &mut sky);
            sky
        },
        || {
            // Vegetation: green excess, smoothed by a vote (foliage has sky
            // and bright leaves between its green).
            let veg_cand: Vec<f32> = (0..n)
                .into_par_iter()
                .map(|i| {
                    let [r, g, b] = f.rgb_at(i);
                    let exg = super::foliage::green_excess([r, g, b]);
                    (exg > GREEN_EXCESS && g > r && g > b * 0.9) as u8 as f32
                })
                .collect();
            let veg = box_mean(&veg_cand, w, h, (w.max(h) / 200).max(1));
            veg.par_iter()
                .map(|&v| v > VEGETATION_VOTE)
                .collect::<Vec<bool>>()
        },
    );
    class.par_iter_mut().zip(&sky).for_each(|(c, &s)| {
        if s {
            *c = Class::Sky;
        }
    });
    // Bare branches: thin structure with sky all around (a wall's edge
    // has sky on one side only, at most half its neighbourhood). In a
    // thumbnail the neighbourhood is a few pixels: a wall's jagged edge.
    if w.max(h) >= BRANCHES_MIN_SIDE {
        let sky_share: Vec<f32> = sky.par_iter().map(|&s| s as u8 as f32).collect();
        let near = box_mean(&sky_share, w, h, w.max(h) / 100 + 1);
        class
            .par_iter_mut()
            .zip(sky.par_iter().zip(&near))
            .for_each(|(c, (&s, &near))| {
                if !s && near > BRANCHES {
                    *c = Class::Vegetation;
                }
            });
    }
    leaves.mark(f, &green, &mut class);
    super::ground::ground(f, &steps, &side, &mut class);
    super::glass::find(f, &mut class);
    super::plane::settle(f, &side, &mut class);
    super::appearance::relabel(f, &side, &mut class);
    leaves.fringe(f, &mut class);
    leaves.canopy(f, &mut class);
    leaves.twigs(f, &mut class);
    let other = class.iter().filter(|&&c| c != Class::Wall).count();
    if (other as f32) < CLOSE_UP * n as f32 {
        class.iter_mut().for_each(|c| *c = Class::Wall);
    }
    class
}

/// Sky: bright, smooth, bluish or white-grey, connected to the top edge
/// (or to clear blue in the upper half).
pub(super) fn sky(f: &Features) -> Vec<bool> {
    let (w, h) = (f.w, f.h);
    let n = w * h;
    let sky_colour: Vec<bool> = (0..n)
        .into_par_iter()
        .map(|i| is_sky_colour(f.rgb_at(i)))
        .collect();
    let sky_cand: Vec<bool> = (0..n)
        .into_par_iter()
        .map(|i| sky_colour[i] && f.texture[i] < SKY_TEXTURE)
        .collect();
    // Sky is smooth: the fill does not cross a colour step (a roof edge).
    let smooth_step = |i: usize, j: usize| l1(f.rgb_at(i), f.rgb_at(j)) < SKY_STEP;
    // Seeds: the top row, and clear blue sky in the upper half (seen
    // between branches or beside a tower, not touching the top).
    let mut seeds: Vec<usize> = (0..w).collect();
    seeds.par_extend((0..h / 2 * w).into_par_iter().filter(|&i| {
        let [r, g, b] = f.rgb_at(i);
        b - r > CLEAR_BLUE && b > g && f.texture[i] < SKY_TEXTURE
    }));
    // The closings for the sky behind branches need only the photo: they
    // are made beside the fills.
    let (core, closed) = rayon::join(
        || {
            let core = flood(&sky_cand, w, h, seeds, smooth_step);
            // Sky cut off from the seeds by a wire, a lamp post or a branch.
            match across_lines(f, &core, &sky_cand) {
                Some(more) => grow(core, &sky_cand, w, h, more, smooth_step),
                None => core,
            }
        },
        || Closings::new(f),
    );
    // Then up to the roof edge, where the texture window already sees the
    // roof: flooding on from the core's rim only (the core is all seen);
    // the sky behind branches beside it.
    let (mut sky, (behind, dark)) = rayon::join(
        || {
            grow(
                core.clone(),
                &sky_colour,
                w,
                h,
                rim(&core, w, h),
                smooth_step,
            )
        },
        || {
            // Dusk floods over the other fills' steps, night over smaller.
            let dark =
                dark_sky(f, is_dusk_colour, SKY_STEP).or_else(|| dark_sky(f, is_night, NIGHT_STEP));
            (behind_branches(f, &core, &sky_colour, &closed), dark)
        },
    );
    // The sky behind branches and the dark sky are added last: their
    // colours are not flooded on (a pale wall's window frames vanish in
    // the closing too; a dark sky's colour is a dark wall's).
    for more in [behind, dark].into_iter().flatten() {
        sky.par_iter_mut().zip(&more).for_each(|(s, &b)| *s |= b);
    }
    sky
}

/// A dusk or night sky: dark (`colour`: [`is_dusk_colour`],
/// [`is_night`]), smooth, along much of the top edge ([`DUSK_TOP`]) and
/// flooded down from it over steps below `step`. A dark blue wall or glass
/// tower reaches the top edge only between other things; the sky above
/// the roofs spans it. None when the top row has too little of it (most
/// photos: then nothing is flooded).
fn dark_sky(f: &Features, colour: fn([f32; 3]) -> bool, step: f32) -> Option<Vec<bool>> {
    let (w, h) = (f.w, f.h);
    let dark = |i: usize| f.texture[i] < SKY_TEXTURE && colour(f.rgb_at(i));
    let along = (0..w).filter(|&i| dark(i)).count();
    if (along as f32) < DUSK_TOP * w as f32 {
        return None;
    }
    let cand: Vec<bool> = (0..w * h).into_par_iter().map(dark).collect();
    let step_ok = |i: usize, j: usize| l1(f.rgb_at(i), f.rgb_at(j)) < step;
    Some(flood(&cand, w, h, (0..w).collect(), step_ok))
}

/// Dark blue ([`DUSK_BLUE`]), too dark for [`is_sky_colour`].
fn is_dusk_colour([r, g, b]: [f32; 3]) -> bool {
    b - r > DUSK_BLUE && b >= g - 0.03 && !is_sky_colour([r, g, b])
}

/// Black ([`NIGHT_LUMA`]).
fn is_night([r, g, b]: [f32; 3]) -> bool {
    luma([r, g, b]) < NIGHT_LUMA
}

/// Bright and bluish, or bright and grey-white.
pub(super) fn is_sky_colour([r, g, b]: [f32; 3]) -> bool {
    let luma = luma([r, g, b]);
    let sat = super::plane::saturation([r, g, b]);
    let blue = b - r > 0.03 && b >= g - 0.03 && b > 0.35;
    blue || (luma > 0.62 && sat < 0.16)
}

/// Mean colour of the `found` pixels of `set`.
pub(super) fn mean_colour(f: &Features, set: &[bool], found: usize) -> [f32; 3] {
    std::array::from_fn(|k| {
        let sum: f64 = (0..f.w * f.h)
            .into_par_iter()
            .filter(|&i| set[i])
            .map(|i| f.rgb[k][i] as f64)
            .sum();
        (sum / found as f64) as f32
    })
}

/// Pixels of `set` with a 4-neighbour outside it (where a flood from the
/// set goes on).
pub(super) fn rim(set: &[bool], w: usize, h: usize) -> Vec<usize> {
    // Row by row (no division per pixel), in order.
    (0..h)
        .into_par_iter()
        .flat_map_iter(|y| {
            let row = |y: usize| &set[y * w..(y + 1) * w];
            let here = row(y);
            let up = (y > 0).then(|| row(y - 1));
            let down = (y + 1 < h).then(|| row(y + 1));
            (0..w)
                .filter(move |&x| {
                    here[x]
                        && ((x > 0 && !here[x - 1])
                            || (x + 1 < w && !here[x + 1])
                            || up.is_some_and(|r| !r[x])
                            || down.is_some_and(|r| !r[x]))
                })
                .map(move |x| y * w + x)
        })
        .collect()
}

/// More sky seeds beyond thin lines: smooth sky-coloured pixels (`cand`)
/// of the upper half, not yet sky, within [`SKY_REACH`] of the sky found so
/// far (`core`: across a wire, a lamp post, a branch) and of its mean colour
/// (within [`SKY_MATCH`]). None when there are none.
fn across_lines(f: &Features, core: &[bool], cand: &[bool]) -> Option<Vec<usize>> {
    let (w, h) = (f.w, f.h);
    let upper = h / 2 * w;
    let found = core.par_iter().filter(|&&c| c).count();
    if found == 0 || upper == 0 {
        return None;
    }
    let mean = mean_colour(f, core, found);
    let sky_share: Vec<f32> = core[..upper].par_iter().map(|&c| c as u8 as f32).collect();
    // Past the line and the texture it raises on each side, then the reach.
    let r = w.max(h) / SKY_REACH + 2 * texture_radius(w, h) + 2;
    let near = box_mean(&sky_share, w, h / 2, r);
    let more: Vec<usize> = (0..upper)
        .into_par_iter()
        .filter(|&i| {
            let c = f.rgb_at(i);
            cand[i] && !core[i] && near[i] > 0.0 && l1(c, mean) < SKY_MATCH
        })
        .collect();
    (!more.is_empty()).then_some(more)
}

/// Pixels of `cand` 4-connected to the seeds (indices into the row-major
/// grid) through steps `step_ok(from, to)` allows.
pub(super) fn flood(
    cand: &[bool],
    w: usize,
    h: usize,
    seeds: Vec<usize>,
    step_ok: impl Fn(usize, usize) -> bool,
) -> Vec<bool> {
    grow(vec![false; w * h], cand, w, h, seeds, step_ok)
}

/// [`flood`] that adds to an earlier flood's pixels `seen` (the same as
/// flooding from both sets of seeds, without going over `seen` again:
/// seeds already seen, such as its rim, are flooded on from too).
pub(super) fn grow(
    mut seen: Vec<bool>,
    cand: &[bool],
    w: usize,
    h: usize,
    seeds: Vec<usize>,
    step_ok: impl Fn(usize, usize) -> bool,
) -> Vec<bool> {
    // Depth first from a stack of (x, y): the pixels reached do not
    // depend on the order, and no division per pixel.
    let mut stack: Vec<(usize, usize)> = Vec::new();
    for s in seeds {
        if cand[s] {
            seen[s] = true;
            stack.push((s % w, s / w));
        }
    }
    while let Some((x, y)) = stack.pop() {
        let i = y * w + x;
        let mut visit = |j: usize, xy: (usize, usize)| {
            if cand[j] && !seen[j] && step_ok(i, j) {
                seen[j] = true;
                stack.push(xy);
            }
        };
        if x > 0 {
            visit(i - 1, (x - 1, y));
        }
        if x + 1 < w {
            visit(i + 1, (x + 1, y));
        }
        if y > 0 {
            visit(i - w, (x, y - 1));
        }
        if y + 1 < h {
            visit(i + w, (x, y + 1));
        }
    }
    seen
}

/// A pixel that is not sky with more than this share of sky within 1% of
/// the photo's size around it is a bare branch (vegetation).
const BRANCHES: f32 = 0.45;
/// Bare branches are looked for in photos at least this long (pixels).
const BRANCHES_MIN_SIDE: usize = 200;

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::photo::Photo;

    /// A brick wall's colour at row `y`: a mortar course every 9 rows.
    pub(in crate::analysis) fn brick(y: u32) -> [u8; 3] {
        if y.is_multiple_of(9) {
            [120, 80, 70]
        } else {
            [170, 100, 80]
        }
    }

    #[test]
    fn bare_branches_against_the_sky_are_not_wall() {
        // Blue sky over a wall; in the sky, dark brown twigs 1 pixel wide,
        // 4 apart.
        let (w, h) = (200u32, 200u32);
        let img = image::RgbImage::from_fn(w, h, |x, y| {
            image::Rgb(if y >= 120 {
                [200, 190, 170]
            } else if (40..160).contains(&x) && (30..90).contains(&y) && x % 4 == 0 {
                [70, 50, 35]
            } else {
                [90, 150, 230]
            })
        });
        let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 200);
        let class = classify(&f);
        let crown = (30..90)
            .flat_map(|y| (40..160).map(move |x| y * 200 + x))
            .filter(|&i| class[i] == Class::Wall)
            .count();
        assert!(crown < 120 * 60 / 20, "{crown} crown pixels are wall");
        assert!(
            class[121 * 200..].iter().all(|&c| c != Class::Vegetation),
            "the wall below is no branch"
        );
    }

    #[test]
    fn the_sky_beyond_a_wire_is_sky() {
        // An overcast sky (not blue enough to seed anywhere) over a brick
        // wall; a dark wire 2 pixels thick across the whole sky.
        let (w, h) = (600u32, 300u32);
        let img = image::RgbImage::from_fn(w, h, |x, y| {
            image::Rgb(if y >= 140 {
                if y % 9 == 0 || (x + (y / 9) * 11) % 24 == 0 {
                    [120, 80, 70]
                } else {
                    [170, 100, 80]
                }
            } else if (40..42).contains(&y) {
                [50, 50, 55]
            } else {
                [205, 210, 222]
            })
        });
        let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 600);
        let class = classify(&f);
        let beyond = &class[60 * 600..130 * 600];
        let sky = beyond.iter().filter(|&&c| c == Class::Sky).count();
        assert!(sky * 10 > beyond.len() * 9, "{sky} of {}", beyond.len());
        assert!(class[150 * 600..].iter().all(|&c| c == Class::Wall));
    }

    #[test]
    fn the_overcast_sky_behind_a_bare_crown_is_not_wall() {
        // An overcast sky over a brick wall; from the top down to row 130,
        // right of column 150, a crown of dark twigs 1 pixel wide, 5
        // apart (the texture is high all through it).
        let (w, h) = (400u32, 300u32);
        let twig = |x: u32, y: u32| x >= 150 && y < 130 && (x + y / 3).is_multiple_of(5);
        let img = image::RgbImage::from_fn(w, h, |x, y| {
            image::Rgb(if y >= 150 {
                brick(y)
            } else if twig(x, y) {
                [60, 50, 45]
            } else {
                [212, 216, 224]
            })
        });
        let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 400);
        let class = classify(&f);
        let crown: Vec<usize> = (10..120)
            .flat_map(|y| (200..390).map(move |x| (x, y)))
            .filter(|&(x, y)| !twig(x as u32, y as u32))
            .map(|(x, y)| y * 400 + x)
            .collect();
        let sky = crown.iter().filter(|&&i| class[i] == Class::Sky).count();
        assert!(
            sky * 10 > crown.len() * 9,
            "{sky} of {} gaps are sky",
            crown.len()
        );
        let wall = (10..120)
            .flat_map(|y| (200..390).map(move |x| y * 400 + x))
            .filter(|&i| class[i] == Class::Wall)
            .count();
        assert!(wall < 190 * 110 / 20, "{wall} crown pixels are wall");
        assert!(class[160 * 400..].iter().all(|&c| c == Class::Wall));
    }

    #[test]
    fn a_pale_panelled_tower_under_a_blue_sky_stays_wall() {
        // Blue sky; from column 250 a white tower up to the top, panelled
        // by dark joints 1 pixel wide, 5 apart (they vanish in the
        // closing, as twigs do, but the white is far from the sky's blue).
        let (w, h) = (400u32, 300u32);
        let img = image::RgbImage::from_fn(w, h, |x, y| {
            image::Rgb(if x >= 250 || y >= 200 {
                if x % 5 == 0 || y % 5 == 0 {
                    [70, 70, 75]
                } else {
                    [232, 230, 224]
                }
            } else {
                [90, 140, 215]
            })
        });
        let sky = count_in(&classes(img), 400, 260..390, 10..190, Class::Sky);
        assert!(sky * 20 < 130 * 180, "{sky} tower pixels are sky");
    }

    #[test]
    fn a_dark_blue_dusk_sky_over_a_stone_front_is_sky() {
        // A dusk sky, dark navy (too dark for `is_sky_colour`), down to
        // row 100 over a pale stone front with a mortar course every 9
        // rows.
        let (w, h) = (400u32, 300u32);
        let img = image::RgbImage::from_fn(w, h, |_, y| {
            image::Rgb(if y < 100 {
                [20, 45, 62]
            } else if y % 9 == 0 {
                [150, 145, 120]
            } else {
                [200, 195, 165]
            })
        });
        let class = classes(img);
        let sky = count_in(&class, 400, 0..400, 0..90, Class::Sky);
        assert!(sky * 10 > 90 * 400 * 9, "{sky} dusk pixels are sky");
        assert_eq!(count_in(&class, 400, 0..400, 110..300, Class::Sky), 0);
    }

    #[test]
    fn a_dark_blue_tower_beside_the_sky_is_not_sky() {
        // A bright blue sky over a stone front; from column 300 (a quarter
        // of the top edge) a smooth dark blue glass tower up to the top.
        let (w, h) = (400u32, 300u32);
        let img = image::RgbImage::from_fn(w, h, |x, y| {
            image::Rgb(if x >= 300 {
                [20, 45, 62]
            } else if y < 100 {
                [110, 160, 225]
            } else if y % 9 == 0 {
                [150, 145, 120]
            } else {
                [200, 195, 165]
            })
        });
        let sky = count_in(&classes(img), 400, 310..400, 0..290, Class::Sky);
        assert!(sky * 20 < 90 * 290, "{sky} tower pixels are sky");
    }

    #[test]
    fn a_black_night_sky_is_sky_and_the_unlit_wall_top_is_not() {
        // A black night sky down to row 100 over a wall whose top rows are
        // unlit (nearly as dark, a step of 0.06 from the sky) and whose
        // rest is lit brick.
        let (w, h) = (400u32, 300u32);
        let img = image::RgbImage::from_fn(w, h, |_, y| {
            image::Rgb(if y < 100 {
                [3, 3, 2]
            } else if y < 140 {
                [9, 9, 8]
            } else {
                brick(y)
            })
        });
        let class = classes(img);
        let sky = count_in(&class, 400, 0..400, 0..90, Class::Sky);
        assert!(sky * 10 > 90 * 400 * 9, "{sky} night pixels are sky");
        let top = count_in(&class, 400, 0..400, 110..140, Class::Sky);
        assert!(top * 20 < 30 * 400, "{top} unlit wall pixels are sky");
    }

    /// How many of the [`dense_gap`] pixels in rows `ys`, columns `xs` of a
    /// 400 pixels wide photo are sky, and of how many.
    fn sky_in_gaps(
        class: &[Class],
        ys: std::ops::Range<u32>,
        xs: std::ops::Range<u32>,
    ) -> (usize, usize) {
        let gaps: Vec<usize> = ys
            .flat_map(|y| xs.clone().map(move |x| (x, y)))
            .filter(|&(x, y)| dense_gap(x, y))
            .map(|(x, y)| (y * 400 + x) as usize)
            .collect();
        let sky = gaps.iter().filter(|&&i| class[i] == Class::Sky).count();
        (sky, gaps.len())
    }

    /// A crown of twigs 6 pixels wide, 10 apart each way (gaps of 4 x 4
    /// between them), in columns 100..300 and rows 20..120: whether (x, y)
    /// is a gap.
    fn dense_gap(x: u32, y: u32) -> bool {
        x % 10 >= 6 && y % 10 >= 6
    }

    #[test]
    fn the_blue_sky_in_a_dense_bare_crown_is_sky() {
        // A blue sky over a brick wall; the crown's twigs are too wide and
        // close for the narrow closing, its gaps closed in by them.
        let (w, h) = (400u32, 300u32);
        let crown = |x: u32, y: u32| (100..300).contains(&x) && (20..120).contains(&y);
        let img = image::RgbImage::from_fn(w, h, |x, y| {
            image::Rgb(if y >= 160 {
                brick(y)
            } else if crown(x, y) && !dense_gap(x, y) {
                [70, 50, 35]
            } else {
                [90, 150, 230]
            })
        });
        let class = classes(img);
        let (sky, gaps) = sky_in_gaps(&class, 30..110, 110..290);
        assert!(sky * 10 > gaps * 9, "{sky} of {gaps} gaps are sky");
    }

    #[test]
    fn a_pale_front_with_wide_frames_under_a_pale_blue_sky_stays_wall() {
        // A pale blue sky; from column 250 a blue-white front up to the
        // top, its panes 4 x 4 between frames 6 pixels wide (they vanish in
        // the wide closing as a dense crown's twigs do, and the panes are a
        // small step from the sky's colour, but not blue enough).
        let (w, h) = (400u32, 300u32);
        let img = image::RgbImage::from_fn(w, h, |x, y| {
            image::Rgb(if y >= 160 {
                brick(y)
            } else if x >= 250 {
                if dense_gap(x, y) {
                    [200, 208, 214]
                } else {
                    [60, 60, 65]
                }
            } else {
                [190, 205, 218]
            })
        });
        let class = classes(img);
        let (sky, panes) = sky_in_gaps(&class, 10..150, 260..390);
        assert!(sky * 20 < panes, "{sky} of {panes} panes are sky");
    }

    /// The classes of `img`, analysed at its own width.
    fn classes(img: image::RgbImage) -> Vec<Class> {
        let w = img.width();
        classify(&Features::new(
            &Photo::new(image::DynamicImage::ImageRgb8(img)),
            w,
        ))
    }

    /// How many pixels of columns `xs` and rows `ys` of `class` (rows
    /// `w` long) are `c`.
    fn count_in(
        class: &[Class],
        w: usize,
        xs: std::ops::Range<usize>,
        ys: std::ops::Range<usize>,
        c: Class,
    ) -> usize {
        ys.flat_map(|y| xs.clone().map(move |x| y * w + x))
            .filter(|&i| class[i] == c)
            .count()
    }

    #[test]
    fn a_thumbnail_keeps_its_wall_beside_the_sky() {
        // 40x30, blue over a greener bottom (the batch test's 16-bit
        // gradient): the few wall pixels next to the sky are not branches.
        let img = image::RgbImage::from_fn(40, 30, |x, y| {
            image::Rgb([(x * 1000 / 257) as u8, (y * 2000 / 257) as u8, 156])
        });
        let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 40);
        let class = classify(&f);
        assert!(class.contains(&Class::Wall), "{class:?}");
    }
}
