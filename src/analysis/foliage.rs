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
//! around agrees, a wall pixel is vegetation. Measured on LabelMeFacade
//! train (pixels the classifier called wall): median coherence 0.25 on
//! vegetation, 0.48 on walls; median diagonal share 0.64 and 0.44. With
//! the rule: IoU 0.669 -> 0.674, vegetation called wall 0.526 -> 0.383
//! (BENCHMARKS.md, seventh pass).

use rayon::prelude::*;

use super::features::{Features, box_mean};
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

/// Foliage's mean gradient magnitude (central differences of luma in
/// 0..1) is over this (LabelMeFacade train IoU 0.674; 0.05: 0.674, 0.1:
/// 0.673).
const STRENGTH: f32 = 0.07;

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
    /// Per cell: a wall's straight structure (one orientation dominates,
    /// or the gradients keep to the axes).
    straight: Vec<bool>,
    /// Analysis pixels per cell, along each side.
    k: usize,
    /// Grid width.
    gw: usize,
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
        // Per cell: (looks like foliage, is straight).
        let (like, straight): (Vec<f32>, Vec<bool>) = (0..gw * gh)
            .into_par_iter()
            .map(|c| {
                let e = jxx[c] + jyy[c];
                if e <= 1e-9 {
                    return (0.0, false);
                }
                let coherence = ((jxx[c] - jyy[c]).powi(2) + 4.0 * jxy[c].powi(2)).sqrt() / e;
                let diagonal = diag[c] / e;
                let like = coherence < COHERENCE && diagonal > DIAGONAL && mag[c] > STRENGTH;
                let straight = coherence > STRAIGHT_COHERENCE || diagonal < STRAIGHT_DIAGONAL;
                (like as u8 as f32, straight)
            })
            .unzip();
        let vote = box_mean(&like, gw, gh, (w.max(h) / VOTE_BOX / k).max(1));
        Foliage {
            leafy: vote.iter().map(|&v| v > VOTE).collect(),
            straight,
            k,
            gw,
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
                let (leafy, straight) = (&self.leafy[at..], &self.straight[at..]);
                for (x, (c, &g)) in row.iter_mut().zip(green).enumerate() {
                    let green =
                        g && (!straight[x / k] || green_excess(f.rgb_at(y * w + x)) >= VIVID);
                    if *c == Class::Wall && (leafy[x / k] || green) {
                        *c = Class::Vegetation;
                    }
                }
            });
    }
}

/// Per cell of `k` x `k` analysis pixels, the means of gx^2, gy^2, gx gy,
/// the diagonal part of gx^2 + gy^2 and the gradient magnitude (central
/// differences of luma).
fn cell_sums(f: &Features, k: usize, gw: usize, gh: usize) -> Vec<[f32; 5]> {
    let (w, h) = (f.w, f.h);
    let l = &f.luma;
    (0..gh)
        .into_par_iter()
        .flat_map_iter(|cy| {
            let mut row = vec![[0f32; 5]; gw];
            let mut count = vec![0u32; gw];
            for y in cy * k..((cy + 1) * k).min(h) {
                let (up, down) = (y.saturating_sub(1) * w, (y + 1).min(h - 1) * w);
                for (cx, (s, m)) in row.iter_mut().zip(count.iter_mut()).enumerate() {
                    for x in cx * k..((cx + 1) * k).min(w) {
                        let gx = l[y * w + (x + 1).min(w - 1)] - l[y * w + x.saturating_sub(1)];
                        let gy = l[down + x] - l[up + x];
                        let e = gx * gx + gy * gy;
                        s[0] += gx * gx;
                        s[1] += gy * gy;
                        s[2] += gx * gy;
                        if 4.0 * (gx * gy).abs() > e {
                            s[3] += e;
                        }
                        s[4] += e.sqrt();
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
mod tests {
    use super::*;
    use crate::photo::Photo;

    /// A brick wall (courses every 8 pixels, head joints every 16, a grid
    /// of dark windows) with a brown, colourless crown in its left half.
    fn wall_with_crown() -> (Features, impl Fn(usize, usize) -> bool) {
        let (w, h) = (256u32, 256u32);
        let mut seed = 12345u32;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed as f32 / u32::MAX as f32
        };
        // Waves at every angle, 3.5 to 6 pixels long: texture that points
        // every way, antialiased as a photo is.
        let waves: Vec<[f32; 3]> = (0..48)
            .map(|_| {
                let (a, k) = (next() * std::f32::consts::PI, 1.0 + next() * 0.8);
                [a.cos() * k, a.sin() * k, next() * 6.3]
            })
            .collect();
        let crown = |x: usize, y: usize| {
            let (dx, dy) = (x as f32 - 65.0, y as f32 - 125.0);
            dx * dx + dy * dy < 50.0 * 50.0
        };
        let img = image::RgbImage::from_fn(w, h, |x, y| {
            let (xf, yf) = (x as f32, y as f32);
            if crown(x as usize, y as usize) {
                let s: f32 = waves
                    .iter()
                    .map(|v| (v[0] * xf + v[1] * yf + v[2]).sin())
                    .sum();
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
}
