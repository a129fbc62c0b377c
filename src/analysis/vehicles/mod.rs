//! What stands on the street in front of the wall: parked cars (and the
//! people, bollards and kiosks beside them). The wall stands on the ground
//! along its foot; anything seen below the foot's line is nearer than the
//! wall, so it is not wall. Where a car stands at the kerb, the ground
//! found stops at the car's wheels, lower in the photo than where it meets
//! the wall in the columns beside the car: the ground's top dips under the
//! car. The foot's line is read from the columns around: the ground's top
//! that [`REACHED`] of them reach or pass, within [`REACH`] of the width.
//! Wall below that line, unlike the wall just above the line, is ground
//! (where the ground fill leaked up a wall in some columns, the line is
//! read too high, and what lies under it is that same wall). Only where
//! the ground is seen in perspective (its edges run [`PERSPECTIVE`]ly
//! oblique): a facade seen square on, as in CMP, whose "ground" is a
//! pavement strip or the fill leaking up its lowest storey, has no cars
//! in front of it to find. Cars parked at the kerb, whose wheels stand
//! where the wall's foot is, are found by their level lines
//! ([`KERB_HEIGHT`]); what is left of a car once the ground is drawn
//! round it is a piece of wall the road surrounds ([`ISLAND`]). In any
//! photo, street scene or not, a short piece of wall unlike the wall over
//! it, standing on the ground and lying flat, is a car ([`SHORT`]): the
//! wall goes on up, shop fronts stand up. In a street scene the cars
//! nearest the camera stand taller; a grey piece may be taller there
//! ([`SHORT_IN_STREET`]).

use rayon::prelude::*;

use super::features::{Features, box_mean, l1};
use super::glass::components;
use super::plane::saturation;
use super::wall::{Class, flood};

/// The foot's line at a column is read over the columns within this share
/// of the width on either side (measured on LabelMeFacade train's class
/// dumps of main, street scenes, car / other negatives / wall pixels
/// called wall below the line, with [`REACHED`] 0.25 and no colour test:
/// 0.05 37k / 81k / 50k, 0.1 60k / 129k / 89k, 0.15 80k / 164k / 108k).
/// A car wider than about 1.5 times this hides the foot in most columns
/// around its middle, so only its ends were taken at 0.1; built, LMF train
/// IoU / car spill: 0.1 0.737 / 0.461, 0.15 0.739 / 0.454, 0.2 0.740 /
/// 0.437, 0.25 0.740 / 0.433, 0.3 0.740 / 0.430; held out at 0.2 0.712 /
/// 0.468 (0.711 / 0.475 at 0.1); CMP sill + cornice recall 4626 -> 4625.
const REACH: f32 = 0.2;

/// The foot's line is the ground's top that this share of the columns
/// around reach or pass (the highest ground, 0, is fooled by the ground
/// fill leaking up a few columns; measured as [`REACH`], at 0.1: 0.1
/// 128k car / 239k other / 194k wall without the street test, 0.25 60k /
/// 129k / 89k, 0.35 38k / 89k / 50k, 0.5 18k / 39k / 16k).
const REACHED: f32 = 0.25;

/// The wall's colour at the foot is the median over the wall pixels in
/// this share of the height just above the line.
const BAND: f32 = 0.08;

/// A pixel below the line is taken when its colour is this far (L1, 0..3)
/// from the wall's colour at the foot (the median of the columns' within
/// [`REACH`]); measured by simulation on main's LabelMeFacade train class
/// dumps, IoU / car / wall pixels taken: none 0.7108 / 60k / 89k, 0.15
/// 0.7109 / 52k / 61k, 0.25 0.7107 / 46k / 48k, 0.35 0.7106 / 41k / 37k.
const UNLIKE: f32 = 0.25;

/// The rule runs when at least this share of the ground's gradient energy
/// runs oblique ([`super::perspective::oblique`]; over the ground of the photos
/// the street test of [`super::plane::settle`] passes, LabelMeFacade train:
/// quartiles 0.37 / 0.44 / 0.50, CMP: 0.28 / 0.31 / 0.37). Measured by
/// simulation on main's LabelMeFacade train class dumps, IoU: no test
/// 0.7107, 0.3 0.7107, 0.35 0.7103, 0.4 0.7098; without it the rule
/// turned the wall between the ground's leaks up CMP's lowest storeys into
/// ground, sill + cornice recall 4615 -> 4613.
const PERSPECTIVE: f32 = 0.35;

/// Parked cars stand at most this share of the height above the ground's
/// top in their column ([`on_the_kerb`]; measured on LabelMeFacade train's
/// class dumps of main, street scenes: of the car pixels called wall 0.36
/// lie within 0.05 of the height, 0.64 within 0.1, 0.80 within 0.15).
const KERB_HEIGHT: f32 = 0.08;

/// Pixels on the kerb join the ground when the sideways share of their
/// gradients is under this (LabelMeFacade train, street scenes, called
/// wall within 0.15 of the height above the ground's top, quartiles: cars
/// 0.28 / 0.40 / 0.50, wall 0.43 / 0.58 / 0.74).
const KERB_SIDEWAYS: f32 = 0.45;

/// ... and when their colour is this far (L1, 0..3) from the wall's above
/// the cars (median: cars 0.60, wall 0.40).
const KERB_UNLIKE: f32 = 0.4;

/// The cars stand on a road or pavement: the ground they are joined to
/// is grey, its saturation under this. The ground fill that leaked up
/// the lowest storey of a facade (CMP's b0020, b0191: ochre stone) is
/// not, and growing it up took the heads and string courses at its top.
/// Measured by simulation on main's class dumps (IoU gain summed over
/// LabelMeFacade train's / held-out's photos, CMP wall pixels taken): no
/// such test 0.221 / 0.724 / 240k, 0.3 0.216 / 0.688 / 166k, 0.2 0.242 /
/// 0.677 / 124k, 0.15 0.258 / 0.680 / 111k.
const KERB_GREY: f32 = 0.15;

/// A piece of wall (4-connected) smaller than this share of the photo,
/// whose borders with the other classes are [`SURROUNDED`] ground, over
/// half of it grey (under [`KERB_GREY`]: a road or pavement), stands on
/// the street, not along it: a wall stands on the ground at its foot, the
/// ground does not enclose it. Such pieces are cars (the roofs, windows
/// and wheels left when the kerb and foot rules took the body around
/// them), kiosks, or patches of road. Measured by simulation on main's
/// class dumps (street scenes; car / wall / road pixels taken, IoU gain
/// over all photos), LabelMeFacade train: 0.005 30k / 17k / 27k 0.0019,
/// 0.01 35k / 17k / 31k 0.0024, 0.02 36k / 31k / 37k 0.0019 (at
/// [`SURROUNDED`] 0.5, without the grey test); held out 0.0016 / 0.0018 /
/// 0.0018. Built: see [`islands`].
const ISLAND: f32 = 0.01;

/// ... and at least this share of the piece's borders is ground
/// (simulated as [`ISLAND`], at 0.01, train / held out: 0.5 0.0024 /
/// 0.0018, 0.7 0.0022 / 0.0018, 0.9 0.0020 / 0.0017; built, all LMF train
/// IoU 0.741).
const SURROUNDED: f32 = 0.7;

/// The wall's colour over the cars is the median of the columns' within
/// this share of the width (as [`REACH`] was when [`on_the_kerb`] was
/// measured).
const KERB_REACH: f32 = 0.1;

/// The wall's colour above the cars is read between these shares of the
/// height above the ground's top (over the tallest cars, under the first
/// floor's windows).
const WALL_ABOVE: (f32, f32) = (0.2, 0.4);

/// A piece of wall unlike the wall over it ([`PIECE_UNLIKE`]) that stands
/// on the ground ([`STANDING`]) is a car when nine tenths of it lie within
/// this share of the height above the ground's top in their columns (a car
/// is about 1.5 m tall, a shop front a storey) and its gradients lie flat
/// ([`PIECE_FLAT`]): [`short_pieces`], in every photo, street scene or
/// not (the cars seen square on or in a row of `insidecity_bost29`,
/// `urb362`, `urb808`, `par194` stand on a strip of ground, or on the
/// photo's bottom edge, that the street test refuses). The scale does not
/// help: read through the estimated metres per pixel, the labelled cars
/// of LabelMeFacade train are 0.8 / 2.8 / 7.1 m tall (10th / 50th / 90th
/// percentiles; the scale is the far facade's, the cars stand near).
/// Simulated on main's class dumps (mean IoU gain; car / wall pixels
/// taken), at [`PIECE_UNLIKE`] 0.5 and [`PIECE_FLAT`] 0.35, LabelMeFacade
/// train: 0.12 +0.0003, 0.15 +0.0018 (65k / 12k), 0.18 +0.0015 (84k /
/// 29k); held out: 0.12 +0.0010, 0.15 +0.0013, 0.18 +0.0020. Built (train
/// IoU / car spill, held out, CMP sill + cornice recall): 0.12 0.745 /
/// 0.391, 0.717 / 0.430; 0.15 0.745 / 0.370, 0.718 / 0.418, 4627; 0.18
/// 0.747 / 0.355, 0.719 / 0.400, 4629; 0.21 0.746 / 0.352, 0.719 / 0.396,
/// 4619 (taller pieces reach CMP's plinths and ground-floor sills).
/// Without the flat test (the short pieces car13 tried and dropped) 0.15
/// simulated 115k car for 199k wall (-0.0092): shop fronts, awnings and
/// plinths stand up.
const SHORT: f32 = 0.18;

/// ... whose lowest pixel lies within this share of the height of the
/// ground's top (or of the photo's bottom edge, where no ground is found;
/// built at [`SHORT`] 0.15, train / held out IoU and car spill: 0.01
/// 0.745 / 0.374, 0.718 / 0.421; 0.02 0.745 / 0.370, 0.718 / 0.418; 0.04
/// 0.745 / 0.367, 0.718 / 0.414) ...
const STANDING: f32 = 0.02;

/// ... whose pixels are each this far (L1, 0..3) from the wall's colour
/// over the cars (as [`on_the_kerb`]'s; within 0.3 of the height above
/// the ground's top, medians 0.56 on the cars called wall, 0.32 on the
/// wall; built at [`SHORT`] 0.15: 0.4 0.745 / 0.371, 0.717 / 0.428; 0.5
/// 0.745 / 0.370, 0.718 / 0.418; 0.6 0.746 / 0.372, 0.718 / 0.417) ...
const PIECE_UNLIKE: f32 = 0.5;

/// ... and whose median sideways share is under this (in the photos the
/// street test refuses, within 0.3 of the height above the ground's top,
/// quartiles: cars 0.18 / 0.29 / 0.44, wall 0.35 / 0.56 / 0.75; built at
/// [`SHORT`] 0.15: 0.3 0.745 / 0.381, 0.717 / 0.429; 0.35 0.745 / 0.370,
/// 0.718 / 0.418; 0.4 0.746 / 0.362, 0.718 / 0.411; at 0.18: 0.35 0.747
/// / 0.355, 0.719 / 0.400, CMP 4629; 0.4 0.747 / 0.345, 0.719 / 0.391,
/// but CMP 4620 and more wall missed as ground, 0.047 / 0.061 against
/// 0.046 / 0.060).
const PIECE_FLAT: f32 = 0.35;

/// In a street scene seen in perspective ([`street`]), a piece may reach
/// this share of the height above the ground's top (instead of [`SHORT`])
/// when it is grey ([`PALE_GREY`]): the cars parked nearest the camera
/// stand taller in the photo than a storey of the far facade
/// (`static_barcelona_street_city_outdoor_2005__img_0440`'s silver car
/// and white van, 0.25-0.3 of the height; review 24's strongest tell, the
/// streaks down their doors and roof). Built with [`PALE_GREY`] 0.2 and
/// [`CUT`] 2, LabelMeFacade train car spill / wall called ground (px):
/// 0.25 415056 / 684714 (img_0440 unchanged), 0.3 and 0.4 the same (and
/// img_0440's car called wall 37525 -> 26913 px); main 418196 / 687911;
/// with [`CUT`] 3 the same.
const SHORT_IN_STREET: f32 = 0.3;

/// ... and its median saturation is under this (grey: silver, white and
/// black cars; not the signs, awnings and shop fronts of a street's
/// lowest storey). Built at [`SHORT_IN_STREET`] 0.3, [`CUT`] 2,
/// LabelMeFacade train car spill / wall called ground (px): no test
/// 413469 / 685370; 0.3 and 0.2 415056 / 684714; 0.15 and 0.1 418209 /
/// 681044. Held out (checked, not tuned) without the test: IoU 0.726 ->
/// 0.724, the shop fronts of `par181` (-0.14), `dsc00384` (-0.03) and
/// `img_1286` (-0.02) taken; with 0.2 unchanged at 0.726.
const PALE_GREY: f32 = 0.2;

/// The candidate band reaches this many times the piece's height limit
/// ([`SHORT`] or [`SHORT_IN_STREET`]) above the ground's top: a piece of
/// wall that goes on up is cut there, and the cut piece can look short.
/// At 2 (car14) the wall of coruna `IMG_7927` cut at 0.36 of the height
/// was taken (7k px, IoU 0.73); at 3 and 4 it goes on and stays (0.77),
/// LabelMeFacade train car spill 418196 -> 418230 px, wall called ground
/// 687911 -> 681014; held out car 648872 -> 649120 px, IoU 0.726 both.
const CUT: f32 = 3.0;

/// A piece is left alone when over [`CAPPED`] of its columns a seam of
/// another class at most this share of the height thick (at least a
/// pixel) lies on it with more wall unlike the wall over the cars above
/// the seam: it is the foot of something taller (a shop front) that a
/// line was drawn across, not a car. On a flat shop front standing on
/// the road, the kerb rule takes a strip along its foot (the foot's edge
/// lies level), and by the end of `classify` the strip's inside is wall
/// again but not its outline: a ring of ground, whose inside was a short,
/// flat piece (a synthetic red front 0.21 of the height tall lost 0.12 of
/// itself). Measured at 0.002 (a pixel at LabelMeFacade's analysis sizes,
/// 512 to 768 px): see [`CAPPED`].
const SEAM: f32 = 0.002;

/// The share of a piece's columns capped (see [`SEAM`]), measured
/// (LabelMeFacade train: car pixels given back to the wall / wall pixels
/// kept; held out IoU, CMP sill + cornice recall): 0.3 483 / 105; 0.5
/// 483 / 77 (`boston383`'s car, under stray ground rows, given back), CMP
/// 4626 (unchanged); 0.9 12 / 3, held out 0.723 (car 15 px given back,
/// wall 174 px kept), CMP 4626. A car's roof is seldom capped over most of
/// its width.
const CAPPED: f32 = 0.9;

/// Turns the wall below the wall's foot into ground (see the module's
/// documentation), in `class`, whose ground is found.
pub(super) fn in_front(f: &Features, class: &mut [Class]) {
    on_the_kerb(f, class);
    below_the_foot(f, class);
}

/// Turns the wall below the wall's foot line, unlike the wall just above
/// the line, into ground, where the ground is seen in perspective (see
/// the module's documentation).
fn below_the_foot(f: &Features, class: &mut [Class]) {
    let (w, h) = (f.w, f.h);
    let top = ground_top(class, w, h);
    if !in_perspective(f, class) {
        return;
    }
    let r = (w as f32 * REACH) as usize;
    let around = |x: usize| x.saturating_sub(r)..(x + r + 1).min(w);
    let mut near = Vec::with_capacity(2 * r + 1);
    let foot: Vec<usize> = (0..w)
        .map(|x| {
            near.clear();
            near.extend_from_slice(&top[around(x)]);
            let k = ((near.len() - 1) as f32 * REACHED) as usize;
            *near.select_nth_unstable(k).1
        })
        .collect();
    // The wall's colour just above the line, per column.
    let band = ((h as f32 * BAND) as usize).max(1);
    let mut c: [Vec<f32>; 3] = Default::default();
    let above: Vec<Option<[f32; 3]>> = (0..w)
        .map(|x| {
            let rows = foot[x].saturating_sub(band)..foot[x].min(h);
            let walls = rows.map(|y| y * w + x).filter(|&i| class[i] == Class::Wall);
            median(walls.map(|i| f.rgb_at(i)), &mut c)
        })
        .collect();
    for x in 0..w {
        if foot[x] + 1 >= top[x] {
            continue;
        }
        let Some(wall) = median(above[around(x)].iter().flatten().copied(), &mut c) else {
            continue;
        };
        for y in foot[x] + 1..top[x] {
            let i = y * w + x;
            let far = l1(f.rgb_at(i), wall) > UNLIKE;
            if class[i] == Class::Wall && far {
                class[i] = Class::Ground;
            }
        }
    }
}

/// Turns the cars parked on the ground strip of a street scene into
/// ground (see [`KERB_HEIGHT`]): wall pixels at most [`KERB_HEIGHT`] of
/// the height above the ground's top in their column, whose gradients
/// run sideways less than [`KERB_SIDEWAYS`] (a car seen side on is
/// horizontal lines: its roof, windows, sills and shadow; the wall's foot
/// has jambs, doors and shop-front mullions), unlike the wall higher up
/// by more than [`KERB_UNLIKE`], and joined to the ground through such
/// pixels. Runs in street scenes only (the caller's street test): there
/// is a road strip for the cars to stand on.
fn on_the_kerb(f: &Features, class: &mut [Class]) {
    let (w, h) = (f.w, f.h);
    let top = ground_top(class, w, h);
    let reach = ((h as f32 * KERB_HEIGHT) as usize).max(1);
    let from = top.iter().min().copied().unwrap_or(h).saturating_sub(reach);
    if from >= h {
        return;
    }
    let wall = wall_over(f, class, &top);
    let side = sideways(f, from);
    let cand: Vec<bool> = (0..w * h)
        .into_par_iter()
        .map(|i| {
            let (x, y) = (i % w, i / w);
            class[i] == Class::Wall
                && y >= from
                && y < top[x]
                && y + reach >= top[x]
                && side[i - from * w] < KERB_SIDEWAYS
                && wall[x].is_some_and(|c| l1(f.rgb_at(i), c) > KERB_UNLIKE)
        })
        .collect();
    let seeds: Vec<usize> = (from * w..w * h)
        .filter(|&i| {
            cand[i]
                && super::neighbours(i, w, h)
                    .any(|j| class[j] == Class::Ground && saturation(f.rgb_at(j)) < KERB_GREY)
        })
        .collect();
    let joined = flood(&cand, w, h, seeds, |_, _| true);
    for (c, &g) in class.iter_mut().zip(&joined) {
        if g {
            *c = Class::Ground;
        }
    }
}

/// Turns the short pieces of wall that stand on the ground, unlike the
/// wall over them and lying flat, into ground (see [`SHORT`]), on the
/// finished classes (`analyse` calls it after [`islands`]). The wall
/// stands on the ground too, but it goes on up, unlike a car's body; a
/// shop front or a plinth is short but stands up (jambs, mullions), a
/// car's lines lie level (roof, windows, sills, bumper, shadow). A piece
/// [`capped`] by a thin seam with more of the same over it is the foot of
/// something taller, cut off by a line another rule drew. Then the vans
/// ([`vans::take`]): taller than a car, their upper body is left wall.
pub(super) fn short_pieces(f: &Features, class: &mut [Class]) {
    cars(f, class);
    vans::take(f, class);
}

/// The short pieces of [`short_pieces`].
fn cars(f: &Features, class: &mut [Class]) {
    let (w, h) = (f.w, f.h);
    let short = if street(f, class) {
        SHORT_IN_STREET
    } else {
        SHORT
    };
    let top = ground_top(class, w, h);
    let tall = (CUT * short * h as f32) as usize;
    let from = top.iter().min().copied().unwrap_or(h).saturating_sub(tall);
    if from >= h {
        return;
    }
    let wall = wall_over(f, class, &top);
    // Wall unlike the wall over it, up to CUT times `short` above the
    // ground's top: a piece that goes on higher is cut there and is not
    // short.
    let rows = h - from;
    let cand: Vec<bool> = (from * w..w * h)
        .into_par_iter()
        .map(|i| {
            let (x, y) = (i % w, i / w);
            class[i] == Class::Wall
                && y < top[x]
                && y + tall >= top[x]
                && wall[x].is_some_and(|c| l1(f.rgb_at(i), c) > PIECE_UNLIKE)
        })
        .collect();
    let side = sideways(f, from);
    let standing = (STANDING * h as f32) as usize;
    let seam = ((SEAM * h as f32).round() as usize).max(1);
    let (mut above, mut flat, mut tops) = (Vec::new(), Vec::new(), Vec::new());
    for piece in components(&cand, w, rows) {
        let height = |&k: &usize| top[k % w] - (from + k / w);
        if !piece.iter().any(|k| height(k) <= standing) {
            continue;
        }
        above.clear();
        above.extend(piece.iter().map(height));
        let nine_tenths = (above.len() - 1) * 9 / 10;
        let reach = *above.select_nth_unstable(nine_tenths).1 as f32;
        if reach > short * h as f32 {
            continue;
        }
        if reach > SHORT * h as f32 && !grey(f, &piece, from, &mut flat) {
            continue;
        }
        if capped(f, class, &piece, (from, seam), &wall, &mut tops) {
            continue;
        }
        flat.clear();
        flat.extend(piece.iter().map(|&k| side[k]));
        let mid = flat.len() / 2;
        if *flat.select_nth_unstable_by(mid, f32::total_cmp).1 < PIECE_FLAT {
            piece
                .iter()
                .for_each(|&k| class[from * w + k] = Class::Ground);
        }
    }
}

/// True when the median saturation of `piece` (indices from row `from`)
/// is under [`PALE_GREY`]: a silver, white or black body, not a sign or an
/// awning; `sat` is scratch space.
fn grey(f: &Features, piece: &[usize], from: usize, sat: &mut Vec<f32>) -> bool {
    sat.clear();
    sat.extend(piece.iter().map(|&k| saturation(f.rgb_at(from * f.w + k))));
    let mid = sat.len() / 2;
    *sat.select_nth_unstable_by(mid, f32::total_cmp).1 < PALE_GREY
}

/// True when `piece` (indices from row `from`) is capped over [`CAPPED`]
/// of its columns by a seam of another class at most `seam` pixels thick
/// with wall unlike the wall over the cars (`wall`) above it (see
/// [`SEAM`]); `tops` is scratch space.
fn capped(
    f: &Features,
    class: &[Class],
    piece: &[usize],
    (from, seam): (usize, usize),
    wall: &[Option<[f32; 3]>],
    tops: &mut Vec<usize>,
) -> bool {
    let w = f.w;
    tops.clear();
    tops.resize(w, usize::MAX);
    for &k in piece {
        let t = &mut tops[k % w];
        *t = (*t).min(from + k / w);
    }
    let (mut cols, mut capped) = (0usize, 0usize);
    for (x, &y) in tops.iter().enumerate().filter(|(_, y)| **y != usize::MAX) {
        cols += 1;
        // The seam's rows, y - 1 up to y - d + 1, then the pixel over it.
        let mut d = 1;
        while d <= seam + 1 && y >= d && class[(y - d) * w + x] != Class::Wall {
            d += 1;
        }
        let over = (d > 1 && d <= seam + 1 && y >= d).then(|| (y - d) * w + x);
        let unlike = |i: usize| wall[x].is_some_and(|c| l1(f.rgb_at(i), c) > PIECE_UNLIKE);
        capped += over.is_some_and(unlike) as usize;
    }
    capped as f32 >= CAPPED * cols as f32
}

/// Per column, the wall's colour over the cars: the median of the
/// columns' within [`KERB_REACH`] of the width, each the median of its
/// wall in [`WALL_ABOVE`] of the height above the ground's top `top`.
fn wall_over(f: &Features, class: &[Class], top: &[usize]) -> Vec<Option<[f32; 3]>> {
    let (w, h) = (f.w, f.h);
    let (lo, hi) = WALL_ABOVE;
    let buffers = <[Vec<f32>; 3]>::default;
    let above: Vec<Option<[f32; 3]>> = (0..w)
        .into_par_iter()
        .map_init(buffers, |c, x| {
            let rows = top[x].saturating_sub((h as f32 * hi) as usize)
                ..top[x].saturating_sub((h as f32 * lo) as usize);
            let walls = rows.map(|y| y * w + x).filter(|&i| class[i] == Class::Wall);
            median(walls.map(|i| f.rgb_at(i)), c)
        })
        .collect();
    let r = (w as f32 * KERB_REACH) as usize;
    (0..w)
        .into_par_iter()
        .map_init(buffers, |c, x| {
            let near = &above[x.saturating_sub(r)..(x + r + 1).min(w)];
            median(near.iter().flatten().copied(), c)
        })
        .collect()
}

/// Turns the pieces of wall that the ground surrounds into ground (see
/// [`ISLAND`]), in a street scene seen in perspective ([`street`]), on
/// the finished classes (`analyse` calls it after
/// [`super::wall::classify`]). Run earlier, at the end of [`in_front`],
/// the pieces taken taught the appearance models' ground the wall's
/// colour (LabelMeFacade train: car spill 0.461 -> 0.400, but wall missed
/// as ground 0.043 -> 0.054, IoU 0.737 -> 0.736). Without the perspective
/// and grey tests it took the pieces of wall left in the ground fill that
/// leaked up the lowest storey of CMP's facades, with their ledges (sill +
/// cornice recall 4625 -> 4614; with the perspective test 4617, with both
/// 4623).
pub(super) fn islands(f: &Features, class: &mut [Class]) {
    let (w, h) = (f.w, f.h);
    if !street(f, class) {
        return;
    }
    // Only below the highest ground: a piece of wall above it is not
    // surrounded by it, and one that reaches the band's top row may go on.
    let Some(y0) = class
        .iter()
        .position(|&c| c == Class::Ground)
        .map(|i| i / w)
    else {
        return;
    };
    let band = &mut class[y0 * w..];
    let rows = h - y0;
    let wall: Vec<bool> = band.iter().map(|&c| c == Class::Wall).collect();
    let largest = ISLAND * (w * h) as f32;
    for piece in components(&wall, w, rows) {
        if piece.len() as f32 >= largest || (y0 > 0 && piece.iter().any(|&i| i < w)) {
            continue;
        }
        // Over the piece's borders with the other classes: ground, and of
        // that, grey ground.
        let (mut ground, mut grey, mut other) = (0usize, 0usize, 0usize);
        for &i in &piece {
            for j in super::neighbours(i, w, rows) {
                match band[j] {
                    Class::Wall => {}
                    Class::Ground => {
                        ground += 1;
                        grey += (saturation(f.rgb_at(y0 * w + j)) < KERB_GREY) as usize;
                    }
                    _ => other += 1,
                }
            }
        }
        let on_road = 2 * grey >= ground && ground > 0;
        if on_road && ground as f32 >= SURROUNDED * (ground + other) as f32 {
            piece.iter().for_each(|&i| band[i] = Class::Ground);
        }
    }
}

/// From row `from` down, per pixel, the share of the luma gradient energy
/// that points sideways, Jxx / (Jxx + Jyy), over a box of a fortieth of
/// the long side (as [`super::plane::Sideways`], at full resolution and
/// only over the rows the cars can stand in).
fn sideways(f: &Features, from: usize) -> Vec<f32> {
    let (w, h) = (f.w, f.h);
    let r = (w.max(h) / 40).max(1);
    let y0 = from.saturating_sub(r);
    let rows = h - y0;
    let l = &f.luma;
    let (mut jxx, mut jyy) = (vec![0f32; rows * w], vec![0f32; rows * w]);
    jxx.par_chunks_mut(w)
        .zip(jyy.par_chunks_mut(w))
        .enumerate()
        .for_each(|(k, (jxx, jyy))| {
            let y = y0 + k;
            let (up, down) = (y.saturating_sub(1) * w, (y + 1).min(h - 1) * w);
            for x in 0..w {
                let gx = l[y * w + (x + 1).min(w - 1)] - l[y * w + x.saturating_sub(1)];
                let gy = l[down + x] - l[up + x];
                jxx[x] = gx * gx;
                jyy[x] = gy * gy;
            }
        });
    let (jxx, jyy) = (box_mean(&jxx, w, rows, r), box_mean(&jyy, w, rows, r));
    jxx[(from - y0) * w..]
        .iter()
        .zip(&jyy[(from - y0) * w..])
        .map(|(a, b)| if a + b > 1e-9 { a / (a + b) } else { 0.5 })
        .collect()
}

/// Per column, the top of the ground run that rises from the bottom row
/// (`h`: no ground at the bottom).
fn ground_top(class: &[Class], w: usize, h: usize) -> Vec<usize> {
    (0..w)
        .map(|x| {
            let mut y = h;
            while y > 0 && class[(y - 1) * w + x] == Class::Ground {
                y -= 1;
            }
            y
        })
        .collect()
}

/// True when the ground is seen in perspective (see [`PERSPECTIVE`]).
fn in_perspective(f: &Features, class: &[Class]) -> bool {
    let ground: Vec<bool> = class.iter().map(|&c| c == Class::Ground).collect();
    super::perspective::oblique(f, &ground) >= PERSPECTIVE
}

/// True in a street scene seen in perspective: the ground covers
/// [`super::plane::STREET`] of the bottom fifth, and [`in_perspective`].
fn street(f: &Features, class: &[Class]) -> bool {
    let bottom = &class[f.h * 4 / 5 * f.w..];
    let ground = bottom.iter().filter(|&&c| c == Class::Ground).count();
    ground as f32 >= super::plane::STREET * bottom.len() as f32 && in_perspective(f, class)
}

/// In a street scene seen in perspective ([`street`]), per column the top
/// of the ground run that rises from the bottom row (`h`: none), where
/// parked cars stand; `None` elsewhere.
pub(super) fn street_top(f: &Features, class: &[Class]) -> Option<Vec<usize>> {
    street(f, class).then(|| ground_top(class, f.w, f.h))
}

/// Per-channel median of `colours` (None when there are none), `c` the
/// planes' scratch space.
fn median(colours: impl Iterator<Item = [f32; 3]>, c: &mut [Vec<f32>; 3]) -> Option<[f32; 3]> {
    c.iter_mut().for_each(Vec::clear);
    for p in colours {
        (0..3).for_each(|k| c[k].push(p[k]));
    }
    let mid = c[0].len() / 2;
    (!c[0].is_empty())
        .then(|| std::array::from_fn(|k| *c[k].select_nth_unstable_by(mid, f32::total_cmp).1))
}

#[cfg(test)]
mod tests;
mod vans;
