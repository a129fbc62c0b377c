//! How sure a stretch of the seen foot is, 0..1: a wall's foot is where
//! the class map's wall stands on ground that runs on down the photo (the
//! pavement and the road in front). The seen foot's wrong stretches on
//! LabelMeFacade train are mostly where no foot is labelled at all (82% of
//! their columns): a car's roof or sill, café chairs, a roll shutter's top,
//! a walker's feet. There the class map's lowest wall over ground lies
//! elsewhere (wall, a car taken for wall, again below the line) or the
//! ground below the line is a short band.
//!
//! Measured per stretch (155 on train, 6718 columns, precision 0.378;
//! BENCHMARKS, foot28): these two cues keep 26% of the columns at
//! precision 0.554. Eighteen others (the unbroken wall's height above,
//! the share of wall or thing above, colour and texture above against the
//! wall's mean and the wall further up, texture, colour and darkness of
//! the ground below, length, slope, row) did no better than chance left out
//! photo by photo.

use super::super::wall::Class;
use crate::random::smoothstep;

/// A stretch is sure where the class map's lowest wall over ground lies
/// within this share of the height of it on average (over the columns
/// where the class map has one) ...
const AGREE_FULL: f32 = 0.01;

/// ... and not sure from this share on [choice, train: the median stretch
/// lies 0.015 off; below 0.015 precision 0.47, above 0.28].
const AGREE_NONE: f32 = 0.02;

/// The ground classed right below the line runs on unbroken this share
/// of the height for the stretch to be sure at all ...
const DEEP_NONE: f32 = 0.03;

/// ... and this share for it to be fully sure [choice, train: the median
/// stretch's ground runs 0.054; above it precision 0.43, below 0.31].
const DEEP_FULL: f32 = 0.09;

/// The unbroken ground below is followed at most this far, share of the
/// height.
const FOLLOW: f32 = 0.3;

/// How sure the stretch `line` (two points, analysis pixels) of the foot
/// is, on the `w` x `h` class map whose lowest wall rows over ground are
/// `class_line` ([`super::class_line`]).
pub(super) fn sure(
    classes: &[Class],
    class_line: &[f32],
    (w, h): (usize, usize),
    line: &[[f32; 2]],
) -> f32 {
    let (Some(a), Some(b)) = (line.first(), line.last()) else {
        return 0.0;
    };
    if w == 0 || h < 2 {
        return 0.0;
    }
    let hf = h as f32;
    let x0 = (a[0].max(0.0) as usize).min(w - 1);
    let x1 = (b[0].max(0.0) as usize).clamp(x0 + 1, w);
    let slope = (b[1] - a[1]) / (b[0] - a[0]).max(1.0);
    let follow = (FOLLOW * hf) as usize;
    let (mut gap, mut agreeing, mut deep) = (0f32, 0f32, 0f32);
    for x in x0..x1 {
        let y = (a[1] + slope * (x as f32 + 0.5 - a[0]))
            .round()
            .clamp(1.0, hf - 1.0) as usize;
        let mut d = y;
        while d < h && d - y < follow && classes[d * w + x] == Class::Ground {
            d += 1;
        }
        deep += (d - y) as f32 / hf;
        if class_line[x].is_finite() {
            gap += (class_line[x] - y as f32).abs() / hf;
            agreeing += 1.0;
        }
    }
    if agreeing == 0.0 {
        return 0.0;
    }
    let (gap, deep) = (gap / agreeing, deep / (x1 - x0) as f32);
    let ramp = |v: f32, from: f32, to: f32| smoothstep(((v - from) / (to - from)).clamp(0.0, 1.0));
    (1.0 - ramp(gap, AGREE_FULL, AGREE_NONE)) * ramp(deep, DEEP_NONE, DEEP_FULL)
}

#[cfg(test)]
mod tests {
    use super::super::class_line;
    use super::*;

    /// A 40 x 100 class map: wall, then bands of `(class, rows)` below.
    fn map(bands: &[(Class, usize)]) -> (Vec<Class>, Vec<f32>) {
        let w = 40;
        let mut classes = Vec::new();
        for &(c, rows) in bands {
            classes.extend(std::iter::repeat_n(c, rows * w));
        }
        let line = class_line(&classes, w, 100);
        (classes, line)
    }

    #[test]
    fn a_wall_standing_on_the_ground_is_a_sure_foot() {
        let (classes, line) = map(&[(Class::Wall, 70), (Class::Ground, 30)]);
        let s = sure(&classes, &line, (40, 100), &[[0.0, 70.0], [40.0, 70.0]]);
        assert!(s > 0.99, "{s}");
    }

    #[test]
    fn a_line_over_a_box_in_front_of_the_wall_is_not_sure() {
        // A car's roof: a band classed ground (its windows), its body
        // taken for wall, the road below it.
        let (classes, line) = map(&[
            (Class::Wall, 55),
            (Class::Ground, 5),
            (Class::Wall, 15),
            (Class::Ground, 25),
        ]);
        let roof = sure(&classes, &line, (40, 100), &[[0.0, 55.0], [40.0, 55.0]]);
        assert!(roof < 0.05, "{roof}");
        // Its foot on the road is the class map's, and the ground runs on.
        let road = sure(&classes, &line, (40, 100), &[[0.0, 75.0], [40.0, 75.0]]);
        assert!(road > 0.99, "{road}");
    }

    #[test]
    fn a_line_over_a_short_band_of_ground_is_not_sure() {
        let (classes, line) = map(&[(Class::Wall, 80), (Class::Ground, 2), (Class::Sky, 18)]);
        let s = sure(&classes, &line, (40, 100), &[[0.0, 80.0], [40.0, 80.0]]);
        assert_eq!(s, 0.0);
    }
}
