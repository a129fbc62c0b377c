//! The ground plane against what stands up from it. Seen from eye level
//! the ground is foreshortened: its texture, joints, kerbs and markings run
//! across the view, so its luma gradients point mostly up and down. A wall
//! stands up: its jambs, corners and pipes are vertical edges, whose
//! gradients point sideways. The share of the gradient energy that points
//! sideways (from the structure tensor, Jxx / (Jxx + Jyy), over a box of a
//! fortieth of the long side) tells the two apart where colour does not:
//! - ground whose structure stands up is wall (the ground fill climbed a
//!   shadowed wall's foot by its colour), above the bottom fifth;
//! - in a street scene (ground along half the photo's bottom fifth), flat,
//!   unsaturated pixels connected to the ground and below the farthest
//!   ground seen are ground: a crossing's stripes and the road beyond
//!   them, the far kerb, and what stands low on the road with no tall
//!   edges (parked cars below the wall's foot);
//! - then what is seen below the wall's foot is in front of the wall
//!   ([`super::vehicles`]).

use rayon::prelude::*;

use super::features::{Features, box_mean};
use super::ground::JOINT_BAND;
use super::light::Light;
use super::wall::{Class, flood};

/// Ground whose sideways share is over this is wall, and what stands up
/// on the road ([`super::ground`]'s wide street) (measured on
/// LabelMeFacade train, applied alone: IoU 0.615 -> 0.622 at 0.8, 0.624
/// at 0.7, 0.625 at 0.6 with more ground and car spill).
pub(super) const UPRIGHT: f32 = 0.7;

/// Pixels whose sideways share is under this lie flat (LabelMeFacade, in
/// the lower half, called wall: median 0.54 on walls, 0.25 on ground,
/// 0.33 on cars).
const FLAT: f32 = 0.45;

/// Flat pixels join the ground only this saturated or less.
const FLAT_SATURATION: f32 = 0.5;

/// Flat pixels join the ground from this share of the height down (above
/// it the ground is far off and the wall's horizontal bands are near).
const FLAT_FROM: f32 = 0.6;

/// Flat pixels join the ground only in a street scene: ground that does
/// not stand up covers at least this share of the photo's bottom fifth
/// (LabelMeFacade, all ground: half its
/// photos have 0.74 or more; CMP's rectified facades, whose "ground" is
/// mostly a pavement strip or the fill leaking up a plinth: a quarter have
/// 0.27 or more).
pub(super) const STREET: f32 = 0.5;

/// The grid the structure tensor is summed on is at most this long.
const GRID: usize = 256;

/// Re-draws the ground in `class` (see the module's documentation). No
/// ground, no change: close-ups and facades cut at their foot stay as they
/// are.
pub fn settle(f: &Features, side: &Sideways, class: &mut [Class]) {
    if !class.contains(&Class::Ground) {
        return;
    }
    let (w, h) = (f.w, f.h);
    // Not in the bottom band, where paving stones are near and large:
    // their joints run both ways, and the box can hold only upright ones.
    let near = (h as f32 * JOINT_BAND) as usize * w;
    class[..near].par_iter_mut().enumerate().for_each(|(i, c)| {
        if *c == Class::Ground && side.at(i) > UPRIGHT {
            *c = Class::Wall;
        }
    });
    // The street test counts only ground that lies flat or is neither.
    let bottom = h * 4 / 5 * w..w * h;
    let n = bottom.len();
    let on_ground = bottom
        .filter(|&i| class[i] == Class::Ground && side.at(i) <= UPRIGHT)
        .count();
    if (on_ground as f32) < STREET * n as f32 {
        return;
    }
    let from = farthest(class, w, h).max((h as f32 * FLAT_FROM) as usize) * w;
    let flat = flat_wall(f, side, class, from, FLAT, FLAT_SATURATION, Light::WHITE);
    let seeds: Vec<usize> = (from..w * h)
        .filter(|&i| flat[i] && super::neighbours(i, w, h).any(|j| class[j] == Class::Ground))
        .collect();
    let joined = flood(&flat, w, h, seeds, |_, _| true);
    class.par_iter_mut().zip(&joined).for_each(|(c, &g)| {
        if g {
            *c = Class::Ground;
        }
    });
    super::vehicles::in_front(f, class);
}

/// The farthest ground seen: the highest row the ground reaches in all but
/// 2% of the columns that have ground (a leak up a few columns does not
/// count).
fn farthest(class: &[Class], w: usize, h: usize) -> usize {
    let mut top = vec![h; w];
    for (y, row) in class.chunks_exact(w).enumerate() {
        for (t, &c) in top.iter_mut().zip(row) {
            if *t == h && c == Class::Ground {
                *t = y;
            }
        }
    }
    let mut tops: Vec<usize> = top.into_iter().filter(|&t| t < h).collect();
    if tops.is_empty() {
        return h;
    }
    let k = tops.len() / 50;
    *tops.select_nth_unstable(k).1
}

/// Wall pixels from index `from` on whose gradients run sideways less
/// than `flat` (they lie flat) and whose saturation under the photo's
/// `light` is under `sat`.
pub(super) fn flat_wall(
    f: &Features,
    side: &Sideways,
    class: &[Class],
    from: usize,
    flat: f32,
    sat: f32,
    light: Light,
) -> Vec<bool> {
    (0..f.w * f.h)
        .into_par_iter()
        .map(|i| {
            i >= from
                && class[i] == Class::Wall
                && side.at(i) < flat
                && light.saturation(f.rgb_at(i)) < sat
        })
        .collect()
}

/// HSV saturation, 0..1 (0 for black).
pub(super) fn saturation([r, g, b]: [f32; 3]) -> f32 {
    let mx = r.max(g).max(b);
    if mx <= 1e-3 {
        0.0
    } else {
        (mx - r.min(g).min(b)) / mx
    }
}

/// The share of luma gradient energy that points sideways, Jxx / (Jxx +
/// Jyy), over a box of a fortieth of the long side. The squared central
/// differences are summed into cells of a grid at most [`GRID`] long (the
/// box is wide: a coarse grid sees the same) and box-averaged there; a
/// pixel reads its cell.
pub struct Sideways {
    share: Vec<f32>,
    /// Analysis pixels per cell, along each side.
    k: usize,
    /// Analysis width.
    w: usize,
    /// Grid width.
    gw: usize,
}

impl Sideways {
    /// Sums the photo's gradients.
    pub fn new(f: &Features) -> Sideways {
        let (w, h) = (f.w, f.h);
        let k = w.max(h).div_ceil(GRID).max(1);
        let (gw, gh) = (w.div_ceil(k), h.div_ceil(k));
        let l = &f.luma;
        let cells: Vec<[f32; 2]> = (0..gh)
            .into_par_iter()
            .flat_map_iter(|gy| {
                let mut row = vec![[0f32; 2]; gw];
                for y in gy * k..((gy + 1) * k).min(h) {
                    let (up, down) = (y.saturating_sub(1) * w, (y + 1).min(h - 1) * w);
                    for (cx, c) in row.iter_mut().enumerate() {
                        for x in cx * k..((cx + 1) * k).min(w) {
                            let gx = l[y * w + (x + 1).min(w - 1)] - l[y * w + x.saturating_sub(1)];
                            let gy = l[down + x] - l[up + x];
                            c[0] += gx * gx;
                            c[1] += gy * gy;
                        }
                    }
                }
                row
            })
            .collect();
        let r = (w.max(h) / 40 / k).max(1);
        let jxx = box_mean(&cells.iter().map(|c| c[0]).collect::<Vec<_>>(), gw, gh, r);
        let jyy = box_mean(&cells.iter().map(|c| c[1]).collect::<Vec<_>>(), gw, gh, r);
        let share = jxx
            .iter()
            .zip(&jyy)
            .map(|(a, b)| if a + b > 1e-9 { a / (a + b) } else { 0.5 })
            .collect();
        Sideways { share, k, w, gw }
    }

    /// The share at analysis pixel `i` (row-major), 0..1.
    pub fn at(&self, i: usize) -> f32 {
        self.share[(i / self.w / self.k) * self.gw + (i % self.w) / self.k]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::eval::{CAR, GROUND, WALL_LABEL};
    use crate::analysis::synthetic::{Kerb, Scene, kerbside};
    use crate::analysis::wall::classify;
    use crate::photo::Photo;

    fn features(img: image::RgbImage) -> Features {
        let side = img.width().max(img.height());
        Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), side)
    }

    /// Share of the pixels labelled `label` in rows `y0..y1` that `class`
    /// calls wall.
    fn wall_share(s: &Scene, class: &[Class], label: u8, y0: usize, y1: usize) -> f32 {
        let t = s.truth.labels.as_ref().unwrap();
        let w = s.truth.width as usize;
        let of: Vec<usize> = (y0 * w..y1 * w).filter(|&i| t[i] == label).collect();
        of.iter().filter(|&&i| class[i] == Class::Wall).count() as f32 / of.len() as f32
    }

    fn classes(s: &Scene) -> Vec<Class> {
        classify(&Features::new(&s.photo, 1024))
    }

    #[test]
    fn a_car_parked_in_front_of_the_wall_is_not_wall() {
        let s = kerbside(Kerb::ParkedCar, 480, 360);
        let class = classes(&s);
        // The car below the wall's foot (70% of the height) lies flat: its
        // trim, bumper and shadow run across; its sides stand up.
        let car = wall_share(&s, &class, CAR, 252, 324);
        assert!(car < 0.3, "{car} of the car is wall");
        // The wall, its foot and the pilasters stay wall.
        let wall = wall_share(&s, &class, WALL_LABEL, 60, 240);
        assert!(wall > 0.99, "{wall} of the wall is wall");
    }

    #[test]
    fn a_shaded_walls_boarding_is_not_ground() {
        let s = kerbside(Kerb::ShadedBoards, 480, 360);
        let class = classes(&s);
        // The ground fill climbs the grey boards up to its 45% limit by
        // colour; their vertical joints say they stand up.
        let boards = wall_share(&s, &class, WALL_LABEL, 170, 245);
        assert!(boards > 0.9, "{boards} of the boarded wall is wall");
        let road = wall_share(&s, &class, GROUND, 260, 360);
        assert!(road < 0.02, "{road} of the road is wall");
    }

    #[test]
    fn a_facades_plinth_beside_a_door_to_the_pavement_stays_wall() {
        let s = kerbside(Kerb::Plinth, 480, 360);
        let class = classes(&s);
        // The ground climbs the door to 60% of the height; the plinth's
        // grooves lie flat. But the pavement is a strip, not a street.
        let plinth = wall_share(&s, &class, WALL_LABEL, 216, 335);
        assert!(plinth > 0.95, "{plinth} of the plinth is wall");
    }

    #[test]
    fn stripes_across_the_view_lie_flat_and_pillars_stand_up() {
        let across = features(image::RgbImage::from_fn(200, 200, |_, y| {
            image::Rgb([if y % 10 < 5 { 60 } else { 200 }; 3])
        }));
        let up = features(image::RgbImage::from_fn(200, 200, |x, _| {
            image::Rgb([if x % 10 < 5 { 60 } else { 200 }; 3])
        }));
        assert!(Sideways::new(&across).at(100 * 200 + 100) < 0.05);
        assert!(Sideways::new(&up).at(100 * 200 + 100) > 0.95);
    }
}
