//! Foliage by its texture, whatever its colour (trees in shade, autumn
//! leaves, bare crowns against a white sky). A wall's structure is
//! straight: courses, frames and jambs put its luma gradients near the
//! horizontal and the vertical, and a wall with windows has both, so its
//! orientation is mixed but axis-aligned. Leaves and twigs point every way.
//! Two statistics of the gradients over a box of a fiftieth of the long
//! side tell them apart:
//! - the coherence of the structure tensor J (Bigün and Granlund, "Optimal
//!   orientation detection of linear symmetry", 1987; Jähne, "Digital
//!   Image Processing", eq. (13.14)): sqrt((Jxx - Jyy)^2 + 4 Jxy^2) /
//!   (Jxx + Jyy), low where no orientation dominates;
//! - the share of the gradient energy that is diagonal (between 15 and 75
//!   degrees of the axes: |sin 2 theta| > 1/2, i.e. 4 |gx gy| > gx^2 +
//!   gy^2): 2/3 for isotropic texture, low on a grid of frames, whose
//!   coherence is low too.
//!
//! Where both say "every way", the texture is strong and most of the box
//! around agrees, a wall pixel is vegetation. The texture's strength is
//! its relative contrast (Weber's: the gradient over the luma, i.e. the
//! gradient of log luma to first order): a canopy in shade is
//! as leafy as one in sun, and a sunlit pale wall's faint grain is not
//! leafy because it is bright (BENCHMARKS.md, fourteenth pass). Measured
//! on LabelMeFacade train (pixels the classifier called wall): median
//! coherence 0.25 on vegetation, 0.48 on walls; median diagonal share 0.64
//! and 0.44. With the rule: IoU 0.669 -> 0.674, vegetation called wall
//! 0.526 -> 0.383 (BENCHMARKS.md, seventh pass).
//!
//! After the other classes, [`Foliage::fringe`] looks at the regions'
//! outlines: where the sky's outline nearby is ragged (a canopy's fringe,
//! holed by the sky seen through it; a roof line is a few straight runs)
//! and the texture points every way, wall pixels are vegetation
//! (BENCHMARKS.md, thirteenth pass).
//!
//! A canopy in shade against the sky (a dark crown over a lit house) is
//! missed by the vote: its leaves point every way (coherence median 0.2)
//! but the box's diagonal share sits just under [`DIAGONAL`] (median 0.62
//! on the vegetation called wall of the ten worst LabelMeFacade train
//! photos, where 71% of those pixels fail the diagonal test, 46% the
//! coherence test and 15% the strength). Loosening the diagonal test alone
//! takes walls with it (any of coherence under 0.15 to 0.25 and diagonal
//! over 0.55 to 0.62, voted or not: train IoU falls or gains 0.001 while
//! 55k to 550k px of wall go). [choice: a crown is one blob with the sky:
//! the looser texture ([`CROWN_COHERENCE`], [`CROWN_DIAGONAL`], voted as
//! [`VOTE`]) is vegetation only where its blob touches a ragged sky, as
//! the canopy's outline and holes do and a wall's ornament under a
//! straight cornice does not ([`Foliage::canopy`]).]

use rayon::prelude::*;

use super::features::{Features, box_mean};
use super::twigs::Twigs;
use super::wall::Class;

/// The grid the gradients are summed on is at most this long.
const GRID: usize = 256;

/// The statistics are taken over a box of the long side over this
/// (LabelMeFacade train IoU 0.674; 100: 0.673, 25: 0.669).
const BOX: usize = 50;

/// The vote is taken over a box of the long side over this.
const VOTE_BOX: usize = 33;

/// Foliage's coherence is under this (LabelMeFacade train IoU 0.674;
/// 0.25: 0.674, 0.35: 0.673, 0.4: 0.672 with less spill).
const COHERENCE: f32 = 0.3;

/// Foliage's diagonal share is over this (LabelMeFacade train IoU 0.674;
/// 0.6: 0.672, 0.68: 0.671).
const DIAGONAL: f32 = 0.65;

/// Foliage's mean relative contrast (Weber's: the gradient magnitude of
/// luma in 0..1, central differences, over the pixel's luma plus
/// [`DARK`]) is over this. It was the gradient magnitude itself, over
/// 0.07: a canopy in shade was too faint, a sunlit pale wall's grain strong
/// enough. Measured as the gradient of ln(luma + [`DARK`]) (train IoU /
/// vegetation called wall / wall px called vegetation; held-out the same):
/// luma's gradient over 0.07: 0.7424 / 0.364 / 519794, 0.7146 / 0.336 /
/// 701680; log luma's over 0.17: 0.7424 / 0.357 / 526618, 0.7188 / 0.329 /
/// 675155; 0.18: 0.7425 / 0.357 / 522577, 0.7186 / 0.331 / 670965;
/// **0.19**: 0.7426 / 0.358 / 519678, 0.7189 / 0.334 / 660445; 0.2: 0.7424
/// / 0.359 / 518910, 0.7186 / 0.337 / 654148; 0.22: 0.7427 / 0.362 /
/// 513335, 0.7187 / 0.345 / 629796; 0.25: 0.7426 / 0.370 / 500782, 0.7198
/// / 0.355 / 580394; 0.3: 0.7427 / 0.386 / 466772, 0.7172 / 0.373 /
/// 547360. At 0.19 both errors fall on train and on held-out. The Weber
/// form (no logarithm per pixel, as fast as before) at 0.19: 0.743 / 0.358
/// / 519770, 0.719 / 0.333 / 661482.
const STRENGTH: f32 = 0.19;

/// Luma added to the pixel's in [`STRENGTH`], so that the noise of black
/// is no contrast (measured in the log form, at 0.2: 0.01 train 0.7424 /
/// 0.358 / 524090, held-out 0.7186 / 0.333 / 664491; 0.06 0.7424 / 0.364
/// / 514401, 0.7166 / 0.342 / 638876).
const DARK: f32 = 0.03;

/// Share of the vote box that must look like foliage (LabelMeFacade
/// train IoU 0.674; 0.3: 0.669, 0.4 and 0.6: 0.673).
const VOTE: f32 = 0.5;

/// Green is no foliage where one orientation dominates: coherence over
/// this (a greenish wall's courses, a painted shutter's slats). Measured
/// on LabelMeFacade train, pixels of the green vote: coherence median
/// 0.14 on vegetation, 0.35 on walls (q90 0.32 and 0.80). With the rule
/// (and [`STRAIGHT_DIAGONAL`], [`VIVID`]): IoU 0.697 -> 0.706, CMP recall
/// 4617 -> 4615; 0.4 / 0.5 / 0.35: IoU 0.707 but CMP 4609, 0.45 / 0.45 /
/// 0.35: 0.707 and 4612, 0.5 / 0.45 / 0.35: 0.706 and 4612, 0.6 / 0.4 /
/// 0.35: 0.704 and 4610.
const STRAIGHT_COHERENCE: f32 = 0.5;

/// Green is no foliage where the gradients keep to the axes: diagonal
/// share under this (a green wall's frames and jambs; LabelMeFacade
/// train, green vote: median 0.65 on vegetation, 0.52 on walls).
const STRAIGHT_DIAGONAL: f32 = 0.5;

/// Green this vivid (excess green, [`green_excess`]) is vegetation
/// whatever its texture: only paler green (greenish paint, a green cast
/// in shade or under street lamps) must not be straight (the synthetic
/// scenes' streaky crowns; 0.25: IoU 0.707 but CMP recall 4608).
const VIVID: f32 = 0.3;

/// A wall pixel whose texture points every way is vegetation where the
/// sky's outline within a box of [`RAGGED_BOX`] around runs more than this
/// many times the box's side: a canopy's fringe against the sky is ragged
/// and holed, a roof line is a few straight runs (one to two sides). On
/// LabelMeFacade train, wall-called pixels with sky in such a box: the
/// outline's length over the side, median 2.0 on walls, 3.0 on vegetation
/// (q75 3.2 and 5.4). Measured (train IoU / spill / wall called
/// vegetation, held-out IoU / spill / wall called vegetation; main 0.7374
/// / 0.171 / 517972 px, 0.7111 / 0.164 / 698537 px): 5 0.7379 / 0.169 /
/// 532821, 0.7115 / 0.162 / 730984; 6 0.7379 / 0.169 / 526722, 0.7117 /
/// 0.163 / 717978; 8 0.7379 / 0.170 / 521252, 0.7117 / 0.163 / 704983;
/// 10 0.7377 / 0.171 / 518834, 0.7116 / 0.164 / 700975. The outline alone
/// (any texture), 6: train 0.7341, ragged walls go too.
const RAGGED: f32 = 8.0;

/// The sky's outline is measured within a box of the long side over this
/// (measured as [`RAGGED`]; at 6, 15: 0.7380 / 0.7114 with 533696 and
/// 735519 px of wall called vegetation, 30: 0.7378 / 0.7116; at 8, 15:
/// train 0.7379 with 524980 px).
const RAGGED_BOX: usize = 20;

/// A crown in shade's coherence is under this ([`Foliage::canopy`];
/// measured in Python on the classes of main bd3ea3a, LabelMeFacade train,
/// wall IoU gain / vegetation + sky taken / wall lost with
/// [`CROWN_DIAGONAL`] 0.55: 0.15 and 0.2 without the sky's blob, unvoted,
/// -0.003 and -0.007; voted, with the blob: **0.2 +0.0017 / 91.8k / 17.2k
/// px**, 0.25 +0.0018 / 112k / 30k, 0.3 at 0.6 +0.0018 / 122k / 35k).
const CROWN_COHERENCE: f32 = 0.2;

/// A crown in shade's diagonal share is over this ([`Foliage::canopy`];
/// at [`CROWN_COHERENCE`] 0.2: 0.52 +0.0017 / 104k / 22.2k px, **0.55
/// +0.0017 / 91.8k / 17.2k**, 0.58 +0.0014 / 72.6k / 13.2k).
const CROWN_DIAGONAL: f32 = 0.55;

/// A crown in shade's blob is seeded only where the sky's outline within
/// the box of [`RAGGED_BOX`] runs more than this many times its side (a
/// straight roof line over an ornate wall runs about once; measured as
/// [`CROWN_COHERENCE`], seeded anywhere beside the sky: +0.0017 / 91.8k /
/// 17.2k px; 2: +0.0016 / 87.6k / 16.0k; **3 +0.0017 / 82.9k / 13.2k**;
/// 4: +0.0015 / 78.9k / 12.8k; 5: +0.0012 / 72.3k / 12.6k).
const CROWN_RAGGED: f32 = 3.0;

/// Excess green over the sum (ExG; Woebbecke et al., "Color indices for
/// weed identification under various soil, residue, and lighting
/// conditions", 1995), with a floor for dark pixels.
pub fn green_excess([r, g, b]: [f32; 3]) -> f32 {
    (2.0 * g - r - b) / (r + g + b + 0.05)
}

/// Where the texture is foliage's, on a grid of cells of `k` x `k`
/// analysis pixels. Found from the photo alone, so it is found beside the
/// sky's fills; [`Foliage::mark`] then applies it to the wall.
pub struct Foliage {
    /// Per cell: foliage voted.
    leafy: Vec<bool>,
    /// Per cell: a crown in shade's looser texture voted
    /// ([`Foliage::canopy`]).
    crown: Vec<bool>,
    /// Per cell: how its texture points.
    texture: Vec<Texture>,
    /// Analysis pixels per cell, along each side.
    k: usize,
    /// Grid width.
    gw: usize,
    /// Per cell: the signs of a bare crown.
    twigs: Twigs,
}

impl Foliage {
    /// Sums the photo's gradients into cells and votes.
    pub fn new(f: &Features) -> Foliage {
        let (w, h) = (f.w, f.h);
        let k = w.max(h).div_ceil(GRID).max(1);
        let (gw, gh) = (w.div_ceil(k), h.div_ceil(k));
        let sums = cell_sums(f, k, gw, gh);
        let r = (w.max(h) / BOX / k).max(1);
        let plane = |d: usize| box_mean(&sums.iter().map(|s| s[d]).collect::<Vec<_>>(), gw, gh, r);
        let (jxx, jyy, jxy, diag, mag) = (plane(0), plane(1), plane(2), plane(3), plane(4));
        // Per cell: (looks like foliage, like a crown in shade, how the
        // texture points).
        let cells: Vec<(f32, f32, Texture)> = (0..gw * gh)
            .into_par_iter()
            .map(|c| {
                let e = jxx[c] + jyy[c];
                if e <= 1e-9 {
                    return (0.0, 0.0, Texture::Flat);
                }
                let coherence = ((jxx[c] - jyy[c]).powi(2) + 4.0 * jxy[c].powi(2)).sqrt() / e;
                let diagonal = diag[c] / e;
                let like = coherence < COHERENCE && diagonal > DIAGONAL && mag[c] > STRENGTH;
                let crown =
                    coherence < CROWN_COHERENCE && diagonal > CROWN_DIAGONAL && mag[c] > STRENGTH;
                let straight = coherence > STRAIGHT_COHERENCE || diagonal < STRAIGHT_DIAGONAL;
                let texture = if straight {
                    Texture::Straight
                } else {
                    Texture::EveryWay
                };
                (like as u8 as f32, crown as u8 as f32, texture)
            })
            .collect();
        let voted = |plane: Vec<f32>| -> Vec<bool> {
            let vote = box_mean(&plane, gw, gh, (w.max(h) / VOTE_BOX / k).max(1));
            vote.iter().map(|&v| v > VOTE).collect()
        };
        Foliage {
            leafy: voted(cells.iter().map(|c| c.0).collect()),
            crown: voted(cells.iter().map(|c| c.1).collect()),
            texture: cells.iter().map(|c| c.2).collect(),
            k,
            gw,
            twigs: Twigs::new(f, &sums, k, gw, gh),
        }
    }

    /// Turns wall pixels of `f` into vegetation where their texture is
    /// foliage's, or where they are `green` (the colour's vote) and either
    /// vivid or not on a wall's straight structure.
    pub fn mark(&self, f: &Features, green: &[bool], class: &mut [Class]) {
        let (k, w) = (self.k, f.w);
        class
            .par_chunks_mut(w)
            .zip(green.par_chunks(w))
            .enumerate()
            .for_each(|(y, (row, green))| {
                let at = (y / k) * self.gw;
                let (leafy, texture) = (&self.leafy[at..], &self.texture[at..]);
                for (x, (c, &g)) in row.iter_mut().zip(green).enumerate() {
                    let straight = texture[x / k] == Texture::Straight;
                    let green = g && (!straight || green_excess(f.rgb_at(y * w + x)) >= VIVID);
                    if *c == Class::Wall && (leafy[x / k] || green) {
                        *c = Class::Vegetation;
                    }
                }
            });
    }

    /// Turns wall pixels into vegetation where their texture points every
    /// way and the sky's outline around them is ragged ([`RAGGED`]): the
    /// fringe of a canopy against the sky, with the sky seen through it.
    /// Run on the final classes (the sky as the fills and the appearance
    /// step left it).
    pub fn fringe(&self, f: &Features, class: &mut [Class]) {
        let ragged: Vec<bool> = self
            .outline(f, class)
            .iter()
            .zip(&self.texture)
            .map(|(&e, &t)| t == Texture::EveryWay && e > RAGGED)
            .collect();
        self.to_vegetation(f.w, &ragged, class);
    }

    /// Turns the wall pixels of the `cells` set into vegetation.
    fn to_vegetation(&self, w: usize, cells: &[bool], class: &mut [Class]) {
        let (k, gw) = (self.k, self.gw);
        class.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
            let cells = &cells[(y / k) * gw..];
            for (x, c) in row.iter_mut().enumerate() {
                if *c == Class::Wall && cells[x / k] {
                    *c = Class::Vegetation;
                }
            }
        });
    }

    /// Per cell: the length of the sky's outline within a box of
    /// [`RAGGED_BOX`] around, over the box's side.
    fn outline(&self, f: &Features, class: &[Class]) -> Vec<f32> {
        let (w, h, k, gw) = (f.w, f.h, self.k, self.gw);
        let gh = h.div_ceil(k);
        // Per cell: the pixel edges between sky and not sky whose left or
        // upper pixel is in the cell, per pixel.
        let sky = |i: usize| class[i] == Class::Sky;
        let outline: Vec<f32> = (0..gh)
            .into_par_iter()
            .flat_map_iter(|cy| {
                let mut row = vec![0u32; gw];
                for y in cy * k..((cy + 1) * k).min(h) {
                    for x in 0..w {
                        let (i, s) = (y * w + x, sky(y * w + x));
                        let edges = (x + 1 < w && sky(i + 1) != s) as u32
                            + (y + 1 < h && sky(i + w) != s) as u32;
                        row[x / k] += edges;
                    }
                }
                row.into_iter().map(move |e| e as f32 / (k * k) as f32)
            })
            .collect();
        let side = (w.max(h) / RAGGED_BOX).max(1);
        let near = box_mean(&outline, gw, gh, (side / 2 / k).max(1));
        near.into_iter().map(|e| e * side as f32).collect()
    }

    /// Turns wall pixels into vegetation in the blobs of crown cells
    /// ([`CROWN_COHERENCE`], [`CROWN_DIAGONAL`], voted) that touch a
    /// ragged sky: a crown cell with sky in it or in a cell beside it,
    /// whose sky's outline runs over [`CROWN_RAGGED`] sides of the box
    /// around ([`RAGGED_BOX`]), seeds a flood through the crown cells,
    /// eight ways. Run on the final classes, after [`Foliage::fringe`].
    pub fn canopy(&self, f: &Features, class: &mut [Class]) {
        let (w, h, k, gw) = (f.w, f.h, self.k, self.gw);
        let gh = h.div_ceil(k);
        let mut sky = vec![false; gw * gh];
        for (i, _) in class.iter().enumerate().filter(|(_, c)| **c == Class::Sky) {
            sky[(i / w / k) * gw + (i % w) / k] = true;
        }
        let around = |c: usize| {
            let (cx, cy) = (c % gw, c / gw);
            let ys = cy.saturating_sub(1)..(cy + 2).min(gh);
            ys.flat_map(move |y| (cx.saturating_sub(1)..(cx + 2).min(gw)).map(move |x| y * gw + x))
        };
        let outline = self.outline(f, class);
        let mut reached: Vec<bool> = (0..gw * gh)
            .map(|c| self.crown[c] && outline[c] > CROWN_RAGGED && around(c).any(|n| sky[n]))
            .collect();
        let mut stack: Vec<usize> = (0..gw * gh).filter(|&c| reached[c]).collect();
        while let Some(c) = stack.pop() {
            for n in around(c) {
                if self.crown[n] && !reached[n] {
                    reached[n] = true;
                    stack.push(n);
                }
            }
        }
        self.to_vegetation(w, &reached, class);
    }
}

impl Foliage {
    /// Turns wall pixels into vegetation where the signs of a bare crown
    /// (thin dark lines and gradients every way, more than on the photo's
    /// wall: [`Twigs`]) hold over a blob. Run on the final classes.
    pub fn twigs(&self, f: &Features, class: &mut [Class]) {
        self.twigs.mark(f.w, self.k, self.gw, class);
    }
}

/// How a cell's texture points.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Texture {
    /// No gradients.
    Flat,
    /// A wall's straight structure: one orientation dominates, or the
    /// gradients keep to the axes.
    Straight,
    /// Every way (foliage, or a wall with ornament).
    EveryWay,
}

/// Per cell of `k` x `k` analysis pixels, the means of gx^2, gy^2, gx gy
/// and the diagonal part of gx^2 + gy^2 (central differences of luma), and
/// of the relative contrast ([`STRENGTH`]).
fn cell_sums(f: &Features, k: usize, gw: usize, gh: usize) -> Vec<[f32; 5]> {
    let (w, h) = (f.w, f.h);
    let l = &f.luma;
    (0..gh)
        .into_par_iter()
        .flat_map_iter(|cy| {
            let mut row = vec![[0f32; 5]; gw];
            let mut count = vec![0u32; gw];
            // Per pixel of a row first (loops the compiler vectorises: the
            // square root and the division were one pixel at a time), then
            // added into the cells in the same order as before.
            let (mut gx, mut gy, mut rel) = (vec![0f32; w], vec![0f32; w], vec![0f32; w]);
            for y in cy * k..((cy + 1) * k).min(h) {
                let line = |y: usize| &l[y * w..(y + 1) * w];
                let (here, up, down) =
                    (line(y), line(y.saturating_sub(1)), line((y + 1).min(h - 1)));
                for (x, g) in gx.iter_mut().enumerate() {
                    *g = here[(x + 1).min(w - 1)] - here[x.saturating_sub(1)];
                }
                for ((g, &d), &u) in gy.iter_mut().zip(down).zip(up) {
                    *g = d - u;
                }
                for (((r, &a), &b), &v) in rel.iter_mut().zip(&gx).zip(&gy).zip(here) {
                    *r = (a * a + b * b).sqrt() / (v + DARK);
                }
                for (cx, (s, m)) in row.iter_mut().zip(count.iter_mut()).enumerate() {
                    let cells = (cx * k).min(w)..((cx + 1) * k).min(w);
                    for ((&gx, &gy), &r) in gx[cells.clone()]
                        .iter()
                        .zip(&gy[cells.clone()])
                        .zip(&rel[cells])
                    {
                        let e = gx * gx + gy * gy;
                        s[0] += gx * gx;
                        s[1] += gy * gy;
                        s[2] += gx * gy;
                        if 4.0 * (gx * gy).abs() > e {
                            s[3] += e;
                        }
                        s[4] += r;
                        *m += 1;
                    }
                }
            }
            for (s, &m) in row.iter_mut().zip(&count) {
                let m = m.max(1) as f32;
                s.iter_mut().for_each(|v| *v /= m);
            }
            row
        })
        .collect()
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::photo::Photo;

    /// A xorshift generator of numbers in 0..1 (also drawn by
    /// `twigs.rs`'s tests).
    pub(in crate::analysis) fn uniform(mut seed: u32) -> impl FnMut() -> f32 {
        move || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed as f32 / u32::MAX as f32
        }
    }

    /// Texture that points every way: waves at every angle, 3.5 to 6
    /// pixels long, summed (about -7..7), antialiased as a photo is.
    fn every_way() -> impl Fn(f32, f32) -> f32 {
        let mut next = uniform(12345);
        let waves: Vec<[f32; 3]> = (0..48)
            .map(|_| {
                let (a, k) = (next() * std::f32::consts::PI, 1.0 + next() * 0.8);
                [a.cos() * k, a.sin() * k, next() * 6.3]
            })
            .collect();
        move |x, y| {
            waves
                .iter()
                .map(|v| (v[0] * x + v[1] * y + v[2]).sin())
                .sum()
        }
    }

    /// A brick wall (courses every 8 pixels, head joints every 16, a grid
    /// of dark windows) with a brown, colourless crown in its left half.
    fn wall_with_crown() -> (Features, impl Fn(usize, usize) -> bool) {
        let (w, h) = (256u32, 256u32);
        let waves = every_way();
        let crown = |x: usize, y: usize| {
            let (dx, dy) = (x as f32 - 65.0, y as f32 - 125.0);
            dx * dx + dy * dy < 50.0 * 50.0
        };
        let img = image::RgbImage::from_fn(w, h, |x, y| {
            let (xf, yf) = (x as f32, y as f32);
            if crown(x as usize, y as usize) {
                let s = waves(xf, yf);
                let l = (110.0 + 12.0 * s).clamp(20.0, 230.0);
                return image::Rgb([l as u8 + 20, l as u8 + 5, l as u8 - 10]);
            }
            let window = x % 64 >= 24 && x % 64 < 44 && y % 64 >= 16 && y % 64 < 48;
            let joint = y % 8 == 0 || (x + (y / 8 % 2) * 8) % 16 == 0;
            image::Rgb(if window {
                [40, 45, 55]
            } else if joint {
                [150, 140, 130]
            } else {
                [170, 90, 70]
            })
        });
        let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 256);
        (f, crown)
    }

    /// Pale green (excess green 0.18) or vivid (0.64), with brick courses
    /// on the left half, plain on the right; the vote calls it all green.
    fn pale_green(vivid: bool) -> (Features, Vec<Class>) {
        let img = image::RgbImage::from_fn(256, 256, |x, y| {
            let joint = y % 8 == 0 || (x + (y / 8 % 2) * 8) % 16 == 0;
            let g = if vivid {
                [70, 150, 50]
            } else {
                [120, 150, 110]
            };
            image::Rgb(if x >= 128 {
                g
            } else if joint {
                g.map(|v| v / 2)
            } else {
                g
            })
        });
        let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 256);
        let mut class = vec![Class::Wall; f.w * f.h];
        Foliage::new(&f).mark(&f, &vec![true; f.w * f.h], &mut class);
        (f, class)
    }

    #[test]
    fn a_pale_green_brick_wall_stays_wall_and_a_plain_green_patch_does_not() {
        let (f, class) = pale_green(false);
        let side = |left: bool| {
            (16..240)
                .flat_map(|y| (0..f.w).map(move |x| (x, y)))
                .filter(|&(x, _)| (x < 112) == left && !(112..=144).contains(&x))
                .filter(|&(x, y)| class[y * f.w + x] == Class::Vegetation)
                .count()
        };
        assert_eq!(side(true), 0, "brick pixels called vegetation");
        assert!(
            side(false) > 100 * 224 * 9 / 10,
            "{} plain pixels",
            side(false)
        );
    }

    #[test]
    fn a_vivid_green_brick_wall_is_vegetation() {
        // Ivy and hedges are vivid green, whatever lines they follow.
        let (f, class) = pale_green(true);
        let wall = (16..240)
            .flat_map(|y| (16..112).map(move |x| y * f.w + x))
            .filter(|&i| class[i] == Class::Wall)
            .count();
        assert!(wall * 4 < 96 * 224, "{wall} brick pixels stay wall");
    }

    #[test]
    fn a_colourless_crown_on_a_brick_wall_is_vegetation() {
        let (f, crown) = wall_with_crown();
        let mut class = vec![Class::Wall; f.w * f.h];
        Foliage::new(&f).mark(&f, &vec![false; f.w * f.h], &mut class);
        let (mut leafy, mut n_crown, mut wall_lost, mut n_wall) = (0, 0, 0, 0);
        for (i, &c) in class.iter().enumerate() {
            let (x, y) = (i % f.w, i / f.w);
            if crown(x, y) {
                n_crown += 1;
                leafy += (c == Class::Vegetation) as usize;
            } else if x > 130 {
                n_wall += 1;
                wall_lost += (c != Class::Wall) as usize;
            }
        }
        assert!(leafy * 2 > n_crown, "{leafy} of {n_crown} crown pixels");
        assert_eq!(wall_lost, 0, "{wall_lost} of {n_wall} brick pixels");
    }

    /// Left: a crown in deep shade (luma 20 +- 1.5 of 255, the texture
    /// [`every_way`]); right: a sunlit pale render whose grain points every
    /// way too (215 +- 3). Their gradients of luma are alike (about 0.05
    /// and 0.1); relative to their brightness the crown's are five times
    /// the render's.
    #[test]
    fn a_crown_in_shade_is_vegetation_and_a_sunlit_render_is_not() {
        let waves = every_way();
        let img = image::RgbImage::from_fn(256, 256, |x, y| {
            let s = waves(x as f32, y as f32);
            let (base, amplitude) = if x < 128 { (20.0, 1.5) } else { (215.0, 3.0) };
            let l = (base + amplitude * s).clamp(0.0, 255.0) as u8;
            image::Rgb([l, l, l.saturating_sub(2)])
        });
        let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 256);
        let mut class = vec![Class::Wall; f.w * f.h];
        Foliage::new(&f).mark(&f, &vec![false; f.w * f.h], &mut class);
        let leafy = |xs: std::ops::Range<usize>| {
            (20..236)
                .flat_map(|y| xs.clone().map(move |x| y * f.w + x))
                .filter(|&i| class[i] == Class::Vegetation)
                .count()
        };
        let (crown, render) = (leafy(20..100), leafy(156..236));
        // The texture's own coherence varies: a third of it votes as in sun.
        assert!(crown * 4 > 80 * 216, "{crown} crown pixels leafy");
        assert_eq!(render, 0, "{render} render pixels leafy");
    }

    /// Sky where `sky` says so, wall elsewhere, on a `w` x `h` grid.
    fn sky_or_wall(w: usize, h: usize, sky: &dyn Fn(usize, usize) -> bool) -> Vec<Class> {
        (0..w * h)
            .map(|i| {
                if sky(i % w, i / w) {
                    Class::Sky
                } else {
                    Class::Wall
                }
            })
            .collect()
    }

    /// Blue sky over a wall at row 150 (whole width), both with texture
    /// that points every way (a crown's leaves; the wall's ornament); on
    /// the left a crown of that texture (a disk of radius 100 about (130,
    /// 150)) with the sky showing through it in round holes of 1 to 3
    /// pixels (9000 of them over the photo, about half the crown). The
    /// classes: sky where the photo shows it, wall elsewhere.
    fn crown_against_the_sky() -> (Features, Vec<Class>, impl Fn(usize, usize) -> bool) {
        let (w, h) = (512usize, 400usize);
        let crown = |x: usize, y: usize| {
            let (dx, dy) = (x as f32 - 130.0, y as f32 - 150.0);
            dx * dx + dy * dy < 100.0 * 100.0
        };
        let mut next = uniform(777);
        let mut hole = vec![false; w * h];
        for _ in 0..9000 {
            let (cx, cy, r) = (next() * w as f32, next() * h as f32, 1.0 + next() * 2.0);
            for y in (cy - r).max(0.0) as usize..((cy + r + 1.0) as usize).min(h) {
                for x in (cx - r).max(0.0) as usize..((cx + r + 1.0) as usize).min(w) {
                    let (dx, dy) = (x as f32 - cx, y as f32 - cy);
                    hole[y * w + x] |= dx * dx + dy * dy <= r * r;
                }
            }
        }
        let sky = |x: usize, y: usize| {
            if crown(x, y) {
                hole[y * w + x]
            } else {
                y < 150
            }
        };
        let waves = every_way();
        let img = image::RgbImage::from_fn(w as u32, h as u32, |x, y| {
            let (x, y) = (x as usize, y as usize);
            if sky(x, y) {
                return image::Rgb([110, 160, 225]);
            }
            let l = (100.0 + 12.0 * waves(x as f32, y as f32)).clamp(20.0, 230.0) as u8;
            image::Rgb(if crown(x, y) {
                [l / 2 + 10, l / 2 + 20, l / 3]
            } else {
                [l + 40, l + 20, l]
            })
        });
        let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 512);
        let class = sky_or_wall(w, h, &sky);
        (f, class, crown)
    }

    #[test]
    fn a_crown_against_the_sky_is_vegetation_and_an_ornate_wall_under_a_straight_roof_is_not() {
        let (f, mut class, crown) = crown_against_the_sky();
        Foliage::new(&f).fringe(&f, &mut class);
        let count = |keep: &dyn Fn(usize, usize) -> bool, c: Class| {
            (0..f.w * f.h)
                .filter(|&i| keep(i % f.w, i / f.w) && class[i] == c)
                .count()
        };
        // The crown above the roof line, away from the photo's edge.
        let upper = |x: usize, y: usize| crown(x, y) && y < 140 && x > 40;
        let (leafy, wall) = (count(&upper, Class::Vegetation), count(&upper, Class::Wall));
        assert!(leafy > wall, "{leafy} crown pixels leafy, {wall} wall");
        // The ornate wall right of the crown, under its straight roof.
        let ornate = |x: usize, y: usize| x > 260 && y >= 150;
        let lost = count(&ornate, Class::Vegetation);
        assert_eq!(lost, 0, "{lost} wall pixels called vegetation");
    }

    /// Blue sky over a brick wall whose straight roof line runs at row
    /// 160 across the photo; on the left, in front of both, a crown in
    /// shade (a disk of radius 110 about (150, 150)): leaves 2 to 6 pixels
    /// across, dark (luma 15 to 65 of 255), seven in ten square, so its
    /// gradients point every way but its diagonal share is mostly under
    /// [`DIAGONAL`] (about 0.62, as a real crown in shade), holed by the
    /// sky in 120 round antialiased holes. The classes: sky where the
    /// photo shows it (over half a pixel), wall elsewhere.
    fn crown_in_shade() -> (Features, Vec<Class>, impl Fn(usize, usize) -> bool) {
        let (w, h) = (512usize, 400usize);
        let crown = |x: usize, y: usize| {
            let (dx, dy) = (x as f32 - 150.0, y as f32 - 150.0);
            dx * dx + dy * dy < 110.0 * 110.0
        };
        let mut next = uniform(4242);
        let mut leaves = vec![40f32; w * h];
        for _ in 0..40000 {
            let (cx, cy, r) = (next() * w as f32, next() * h as f32, 1.0 + next() * 2.0);
            let (l, square) = (15.0 + next() * 50.0, next() < 0.7);
            for y in (cy - r).max(0.0) as usize..((cy + r + 1.0) as usize).min(h) {
                for x in (cx - r).max(0.0) as usize..((cx + r + 1.0) as usize).min(w) {
                    let (dx, dy) = (x as f32 - cx, y as f32 - cy);
                    let inside = if square {
                        dx.abs() <= r && dy.abs() <= r
                    } else {
                        dx * dx + dy * dy <= r * r
                    };
                    if inside {
                        leaves[y * w + x] = l;
                    }
                }
            }
        }
        // Per pixel: the share of it the sky's holes cover.
        let mut hole = vec![0f32; w * h];
        for _ in 0..120 {
            let (a, d, r) = (next() * 6.3, next().sqrt() * 105.0, 1.0 + next() * 1.5);
            let (cx, cy) = (150.0 + d * a.cos(), 150.0 + d * a.sin());
            for y in (cy - r).max(0.0) as usize..((cy + r + 1.0) as usize).min(h) {
                for x in (cx - r).max(0.0) as usize..((cx + r + 1.0) as usize).min(w) {
                    let (dx, dy) = (x as f32 - cx, y as f32 - cy);
                    let cover = (r + 0.5 - (dx * dx + dy * dy).sqrt()).clamp(0.0, 1.0);
                    hole[y * w + x] = hole[y * w + x].max(cover);
                }
            }
        }
        let cover = |x: usize, y: usize| {
            if crown(x, y) {
                hole[y * w + x]
            } else {
                (y < 160) as u8 as f32
            }
        };
        let sky = |x: usize, y: usize| cover(x, y) > 0.5;
        let img = image::RgbImage::from_fn(w as u32, h as u32, |x, y| {
            let (x, y) = (x as usize, y as usize);
            let a = cover(x, y);
            let under = if crown(x, y) {
                // Antialiased: the mean over 2 x 2 pixels.
                let at = |x: usize, y: usize| leaves[y.min(h - 1) * w + x.min(w - 1)];
                let l = (at(x, y) + at(x + 1, y) + at(x, y + 1) + at(x + 1, y + 1)) / 4.0;
                [l, l + 8.0, l - 5.0]
            } else if y % 8 == 0 || (x + (y / 8 % 2) * 8) % 16 == 0 {
                [150.0, 140.0, 130.0]
            } else {
                [170.0, 90.0, 70.0]
            };
            let sky = [110.0, 160.0, 225.0];
            image::Rgb(std::array::from_fn(|c| {
                (under[c] * (1.0 - a) + sky[c] * a).round() as u8
            }))
        });
        let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 512);
        let class = sky_or_wall(w, h, &sky);
        let leafy = move |x: usize, y: usize| crown(x, y) && hole[y * w + x] <= 0.5;
        (f, class, leafy)
    }

    #[test]
    fn a_crown_in_shade_holed_by_the_sky_is_vegetation_and_the_brick_wall_under_the_sky_is_not() {
        let (f, mut class, leafy) = crown_in_shade();
        let leaves = Foliage::new(&f);
        leaves.mark(&f, &vec![false; f.w * f.h], &mut class);
        leaves.fringe(&f, &mut class);
        leaves.canopy(&f, &mut class);
        let count = |keep: &dyn Fn(usize, usize) -> bool, c: Class| {
            (0..f.w * f.h)
                .filter(|&i| keep(i % f.w, i / f.w) && class[i] == c)
                .count()
        };
        // The crown away from the photo's edge, over the sky and the wall.
        let inner = |x: usize, y: usize| leafy(x, y) && (60..240).contains(&x) && y > 50;
        let (veg, wall) = (count(&inner, Class::Vegetation), count(&inner, Class::Wall));
        assert!(veg > 2 * wall, "{veg} crown pixels leafy, {wall} wall");
        // The brick wall right of the crown, under its straight roof line.
        let brick = |x: usize, y: usize| x > 300 && y >= 160;
        let lost = count(&brick, Class::Vegetation);
        assert_eq!(lost, 0, "{lost} brick pixels called vegetation");
    }
}
