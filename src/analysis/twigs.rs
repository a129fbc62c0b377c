//! Bare crowns in front of walls and against a white sky (Boston in
//! April: the labels draw the crown, the wall or sky shows through its
//! twigs). The foliage test ([`super::foliage`]) misses them: their twigs
//! rise from the trunk, so in a box of a fiftieth of the side one
//! orientation leads (coherence 0.35-0.45 where foliage's is under 0.3).
//! Two signs find them instead, each against the photo's own wall:
//! - twigs are thin dark lines: a grey-scale closing of luma (a max then a
//!   min filter, Serra, "Image analysis and mathematical morphology",
//!   1982) fills lines up to [`LINE_GAP`] * 2 + 1 pixels wide, and the
//!   closing less the luma (the black top-hat) is over [`DARK_LINE`] on
//!   them; a crown has two to three times the wall's share of them;
//! - their gradients point every way over a wider box (a tenth of the
//!   side), where a wall's frames, courses and joints keep to the axes.
//!
//! Both are compared with the photo's median over the cells that are
//! wall, so a facade whose ornament (railings, rusticated joints) is dense
//! all over is its own reference and stays wall; a crown stands out from
//! the wall beside it. The cells that pass are kept where most of the box
//! of a twentieth of the side around them passes too (a crown is a blob; a
//! railing or a course's edge is a strip).
//!
//! Measured on LabelMeFacade train (the classes of main 5ac8f04, flipped
//! in Python as here, scored as `scene_eval` scores; BENCHMARKS.md,
//! nineteenth pass, veg21), on the pixels called wall, medians on
//! vegetation and on wall: share on thin dark lines 0.37 and 0.18, less
//! the photo's wall median +0.10 and 0.00; wide diagonal share less the
//! photo's wall median +0.07 and 0.00. The rule takes 12.5% of that
//! vegetation and 0.16% of that wall: train IoU 0.754 -> 0.759,
//! vegetation called wall 938k -> 825k px (held-out 0.726 -> 0.727,
//! 1068k -> 1020k px).

use rayon::prelude::*;

use super::crowns::close;
use super::features::{Features, box_mean};
use super::wall::Class;
use crate::effects::percentile::{Rank, percentile};

/// The closing that finds thin dark lines is over a box of this radius
/// (lines up to 5 pixels wide: twigs at the analysis size).
const LINE_GAP: usize = 2;

/// A pixel is on a thin dark line where the closing of luma (0..1) is
/// over the luma by more than this.
const DARK_LINE: f32 = 0.05;

/// The share of pixels on thin dark lines is taken over a box of the long
/// side over this.
const LINE_BOX: usize = 20;

/// The diagonal share of the gradient energy (as in
/// [`super::foliage`]) is taken over a box of the long side over this.
const WIDE_BOX: usize = 10;

/// A crown's share of pixels on thin dark lines is over this (LabelMeFacade
/// train IoU with the other knobs as chosen: 0.45 +0.0045, 0.5 +0.0045,
/// **0.55 +0.0049**, 0.6 about the same with less vegetation found).
const LINES: f32 = 0.55;

/// ... and over the photo's median on its wall by more than this (0.15
/// +0.0051 with 23.0k px of wall lost, **0.2 +0.0049 with 13.0k**, 0.25
/// less).
const MORE_LINES: f32 = 0.2;

/// The crown's diagonal share over a tenth of the side is over the photo's
/// median on its wall by more than this (0.1 +0.0050 with 19.7k px of
/// wall lost, **0.14 +0.0049 with 13.0k**, 0.18 +0.0045).
const MORE_DIAGONAL: f32 = 0.14;

/// Share of the box of [`LINE_BOX`] around a cell that must pass too
/// (none: +0.0048 with 27.4k px of wall lost; 1/33 of the side 0.5: 20.9k;
/// **1/20 0.5: 13.0k**; 1/12 0.5: +0.0044, 4.0k).
const CROWN_VOTE: f32 = 0.5;

/// Per cell of the foliage grid, the signs of a bare crown.
pub(super) struct Twigs {
    /// Share of the box of [`LINE_BOX`] around the cell on thin dark lines.
    lines: Vec<f32>,
    /// Diagonal share of the gradient energy over the box of [`WIDE_BOX`].
    diagonal: Vec<f32>,
}

impl Twigs {
    /// The signs on the grid of `k` x `k` cells (`gw` x `gh`), from the
    /// photo and the foliage's per-cell gradient `sums` (gx^2, gy^2, gx gy,
    /// diagonal energy, ...).
    pub(super) fn new(f: &Features, sums: &[[f32; 5]], k: usize, gw: usize, gh: usize) -> Twigs {
        let (w, h) = (f.w, f.h);
        let long = w.max(h);
        let closed = close(&f.luma, w, h, LINE_GAP);
        let on_line: Vec<f32> = (0..gh)
            .into_par_iter()
            .flat_map_iter(|cy| {
                let mut row = vec![0u32; gw];
                let ys = cy * k..((cy + 1) * k).min(h);
                for y in ys.clone() {
                    for x in 0..w {
                        let i = y * w + x;
                        row[x / k] += (closed[i] - f.luma[i] > DARK_LINE) as u32;
                    }
                }
                let rows = ys.len();
                row.into_iter().enumerate().map(move |(cx, n)| {
                    let cols = ((cx + 1) * k).min(w) - cx * k;
                    n as f32 / (rows * cols).max(1) as f32
                })
            })
            .collect();
        let lines = box_mean(&on_line, gw, gh, (long / LINE_BOX / k).max(1));
        let r = (long / WIDE_BOX / k).max(1);
        let plane = |d: usize| box_mean(&sums.iter().map(|s| s[d]).collect::<Vec<_>>(), gw, gh, r);
        let (jxx, jyy, diag) = (plane(0), plane(1), plane(3));
        let diagonal = (0..gw * gh)
            .map(|c| {
                let e = jxx[c] + jyy[c];
                if e <= 1e-9 { 0.0 } else { diag[c] / e }
            })
            .collect();
        Twigs { lines, diagonal }
    }

    /// Turns wall pixels of `class` (`w` wide) into vegetation in the cells
    /// (`k` x `k`, `gw` across) whose signs stand out from the photo's wall
    /// cells (those mostly wall) as a crown's, in a blob of them.
    pub(super) fn mark(&self, w: usize, k: usize, gw: usize, class: &mut [Class]) {
        let h = class.len() / w.max(1);
        let gh = h.div_ceil(k);
        let wall = wall_cells(class, w, k, gw, gh);
        let (Some(lines), Some(diagonal)) = (
            median_on(&self.lines, &wall),
            median_on(&self.diagonal, &wall),
        ) else {
            return;
        };
        let crown: Vec<f32> = (0..gw * gh)
            .map(|c| {
                let l = self.lines[c];
                (l > LINES && l - lines > MORE_LINES && self.diagonal[c] - diagonal > MORE_DIAGONAL)
                    as u8 as f32
            })
            .collect();
        let vote = box_mean(&crown, gw, gh, (w.max(h) / LINE_BOX / k).max(1));
        let keep: Vec<bool> = crown
            .iter()
            .zip(&vote)
            .map(|(&c, &v)| c > 0.0 && v > CROWN_VOTE)
            .collect();
        class.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
            let keep = &keep[(y / k) * gw..];
            for (x, c) in row.iter_mut().enumerate() {
                if *c == Class::Wall && keep[x / k] {
                    *c = Class::Vegetation;
                }
            }
        });
    }
}

/// Per cell: more than half its pixels are wall.
fn wall_cells(class: &[Class], w: usize, k: usize, gw: usize, gh: usize) -> Vec<bool> {
    let h = class.len() / w.max(1);
    (0..gh)
        .into_par_iter()
        .flat_map_iter(|cy| {
            let mut row = vec![(0u32, 0u32); gw];
            for y in cy * k..((cy + 1) * k).min(h) {
                for (x, &c) in class[y * w..(y + 1) * w].iter().enumerate() {
                    let cell = &mut row[x / k];
                    cell.0 += (c == Class::Wall) as u32;
                    cell.1 += 1;
                }
            }
            row.into_iter().map(|(n, all)| 2 * n > all)
        })
        .collect()
}

/// The median of `v` over the cells where `on` holds (the upper one of an
/// even count), or None where it holds nowhere.
fn median_on(v: &[f32], on: &[bool]) -> Option<f32> {
    let picked = v.iter().zip(on).filter(|(_, o)| **o).map(|(&x, _)| x);
    percentile(picked, 0.5, Rank::Nearest)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::foliage::Foliage;
    use crate::analysis::foliage::tests::uniform;
    use crate::photo::Photo;

    /// A tangle of twigs in the disk of radius `r` about `c`: one-pixel
    /// lines at every angle, 6 to 30 pixels long, `n` of them (900 in a
    /// radius of 60: about 60% of the disk is on one, the rest shows what
    /// is behind).
    fn twigs(c: (f32, f32), r: f32, n: usize, w: usize, h: usize) -> Vec<bool> {
        let mut next = uniform(4242);
        let mut on = vec![false; w * h];
        let inside = |x: f32, y: f32| (x - c.0).powi(2) + (y - c.1).powi(2) < r * r;
        for _ in 0..n {
            let (x0, y0) = (
                c.0 + (next() * 2.0 - 1.0) * r,
                c.1 + (next() * 2.0 - 1.0) * r,
            );
            let (a, len) = (next() * std::f32::consts::PI, 6.0 + next() * 24.0);
            for s in 0..len as usize {
                let (x, y) = (x0 + a.cos() * s as f32, y0 + a.sin() * s as f32);
                if inside(x, y) && x >= 0.0 && y >= 0.0 && (x as usize) < w && (y as usize) < h {
                    on[y as usize * w + x as usize] = true;
                }
            }
        }
        on
    }

    /// A brick wall (courses every 8 pixels, head joints every 16); on the
    /// left a bare crown in front of it (dark twigs, the brick seen
    /// between them), on the right the crown's shadow on the wall (the
    /// same twigs, blurred over 7 pixels and faint, as a penumbra is).
    fn wall_with_bare_crown() -> (Features, Vec<bool>, Vec<bool>) {
        let (w, h) = (320usize, 256usize);
        let crown = twigs((80.0, 110.0), 60.0, 900, w, h);
        let shade = twigs((240.0, 110.0), 60.0, 900, w, h);
        // The shadow's darkening: the twigs' share over a 7 x 7 box.
        let share: Vec<f32> = shade.iter().map(|&s| s as u8 as f32).collect();
        let blur = box_mean(&share, w, h, 3);
        let img = image::RgbImage::from_fn(w as u32, h as u32, |x, y| {
            let (x, y) = (x as usize, y as usize);
            let i = y * w + x;
            let joint = y % 8 == 0 || (x + (y / 8 % 2) * 8) % 16 == 0;
            let brick = if joint {
                [150.0, 140.0, 130.0]
            } else {
                [170.0, 95.0, 75.0]
            };
            let p = if crown[i] {
                [70.0, 60.0, 55.0]
            } else {
                brick.map(|v| v * (1.0 - 0.25 * blur[i]))
            };
            image::Rgb(p.map(|v| v as u8))
        });
        let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 320);
        let disk = |cx: f32| {
            (0..w * h)
                .map(|i| {
                    ((i % w) as f32 - cx).powi(2) + ((i / w) as f32 - 110.0).powi(2) < 45.0 * 45.0
                })
                .collect::<Vec<bool>>()
        };
        (f, disk(80.0), disk(240.0))
    }

    #[test]
    fn a_bare_crown_before_a_brick_wall_is_vegetation_and_its_shadow_is_not() {
        let (f, crown, shadow) = wall_with_bare_crown();
        let mut class = vec![Class::Wall; f.w * f.h];
        Foliage::new(&f).twigs(&f, &mut class);
        let count = |area: &[bool]| {
            let n = area.iter().filter(|&&a| a).count();
            let v = (0..area.len())
                .filter(|&i| area[i] && class[i] == Class::Vegetation)
                .count();
            (v, n)
        };
        let ((leafy, n_crown), (shaded, n_shadow)) = (count(&crown), count(&shadow));
        assert!(leafy * 4 > n_crown * 3, "{leafy} of {n_crown} crown pixels");
        assert_eq!(shaded, 0, "{shaded} of {n_shadow} shadow pixels");
        let plain = (0..f.w * f.h).filter(|&i| !crown[i] && !shadow[i] && i % f.w > 180);
        let lost = plain.filter(|&i| class[i] != Class::Wall).count();
        assert_eq!(lost, 0, "{lost} brick pixels");
    }

    /// A facade whose fine dark ornament points every way all over (the
    /// crown's tangle, as dense, over the whole photo, on a pale render):
    /// the photo's own wall is the reference, so nothing stands out and it
    /// stays wall.
    #[test]
    fn a_facade_ornate_all_over_stays_wall() {
        let (w, h) = (320usize, 256usize);
        let ornament = twigs((160.0, 128.0), 205.0, 10500, w, h);
        let img = image::RgbImage::from_fn(w as u32, h as u32, |x, y| {
            let on = ornament[y as usize * w + x as usize];
            image::Rgb(if on { [90, 85, 80] } else { [200, 190, 175] })
        });
        let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 320);
        let mut class = vec![Class::Wall; f.w * f.h];
        Foliage::new(&f).twigs(&f, &mut class);
        let lost = class.iter().filter(|&&c| c != Class::Wall).count();
        assert_eq!(lost, 0, "{lost} ornate wall pixels");
    }
}
