//! Ledges on a wall seen in perspective. Its level lines (sills, heads,
//! courses) slant in the photo, all the same way on one side of the
//! vanishing point, and its storeys look taller near the camera than the
//! photo's storey (measured on all its windows). On a wall seen square on,
//! the slanted edges the tracer finds are an arch's lit shoulder or a
//! pediment's rake among level lines, and a cable or a crack slants
//! anywhere (`ledge_kinds::a_line_on_one_surface` drops those). Blind
//! review p82: new 6, main 2 (BENCHMARKS.md, thirty-fifth pass, slope36).

use super::{Ledge, LedgeKind};

/// A ledge slanted more than this (dy/dx, about 14 degrees) lies on a wall
/// seen in perspective.
pub(super) const LEVEL: f32 = 0.25;
/// On such a wall a ledge repeats up to this many of the photo's storeys
/// above or below (the storey is measured on the windows of the whole
/// photo; a near wall's storeys are taller).
const OBLIQUE_STOREYS: f32 = 2.5;
/// See [`against_the_slant`]. CMP base (rectified facades: their slanted
/// lines are arches' shoulders and pediments' rakes), ledges found / on a
/// labelled ledge-like element: main (no slant followed past 0.25) 8838 /
/// 5616; slants followed, no test 9193 / 5727; against only the other way,
/// 3 times, 9125 / 5691; against the level too, once, 8845 / 5614.
const SLANT_MAJORITY: f32 = 1.0;

/// The ledge's slope (dy/dx) from its first point to its last.
pub(super) fn slope(l: &Ledge) -> f32 {
    let (a, b) = (l.polyline[0], l.polyline[l.polyline.len() - 1]);
    (b[1] - a[1]) / (b[0] - a[0]).max(1.0)
}

/// The way the ledge leans: its slope's sign when slanted more than
/// [`LEVEL`], else 0.
pub(super) fn way(l: &Ledge) -> f32 {
    let s = slope(l);
    if s.abs() > LEVEL { s.signum() } else { 0.0 }
}

/// True when two ledges `dy` apart (photo rows) are a storey apart on a
/// wall seen in perspective: from half to [`OBLIQUE_STOREYS`] of the
/// photo's `storey`.
pub(super) fn storeys_apart(dy: f32, storey: f32) -> bool {
    (0.5 * storey..OBLIQUE_STOREYS * storey).contains(&dy.abs())
}

/// How far above or below a slanted ledge [`against_the_slant`] looks:
/// [`OBLIQUE_STOREYS`] storeys.
pub(super) fn reach(storey: f32) -> f32 {
    OBLIQUE_STOREYS * storey
}

/// True when ledge `i` is slanted (more than [`LEVEL`]) against the lines
/// near it: on a wall seen in perspective every level line leans the same
/// way, towards the vanishing point, while on a wall seen square on the
/// slanted edges found are an arch's shoulder or a pediment's rake (lit
/// on one side, so found on one side only) among level sills and
/// courses. Near: over its columns widened by its span on each side,
/// within `reach` above or below (a long course far below is another
/// part of the wall); kept when the lines leaning its way (itself among
/// them) outweigh those level or leaning the other way [`SLANT_MAJORITY`]
/// times (by columns).
pub(super) fn against_the_slant(ledges: &[Ledge], i: usize, reach: f32) -> bool {
    let slant = |l: &Ledge| {
        let (a, b) = (l.polyline[0], l.polyline[l.polyline.len() - 1]);
        (a[0], b[0], (a[1] + b[1]) / 2.0, way(l))
    };
    let (x0, x1, y, way) = slant(&ledges[i]);
    if way == 0.0 || ledges[i].kind == LedgeKind::RoofLine {
        return false;
    }
    let span = x1 - x0;
    let (mut with, mut against) = (0.0, 0.0);
    for o in ledges.iter().filter(|o| o.kind != LedgeKind::RoofLine) {
        let (c, d, yo, s) = slant(o);
        let cols = if (yo - y).abs() < reach {
            (x1 + span).min(d) - (x0 - span).max(c)
        } else {
            0.0
        };
        if cols > 0.0 && s == way {
            with += cols;
        } else if cols > 0.0 {
            against += cols;
        }
    }
    with < SLANT_MAJORITY * against
}

#[cfg(test)]
mod tests {
    use super::super::ledges::detect;
    use super::super::synthetic::sky_over_wall;
    use super::*;

    #[test]
    fn a_walls_sills_seen_in_perspective_are_ledges_a_cable_or_an_archs_shoulder_is_not() {
        // Wall 0.7 under a strip of sky. On the right, two columns of
        // windows seen in perspective: their sills (0.9 over a shadow 0.45)
        // slant up to the right at 0.5, three storeys of 80 px. On the left,
        // a wall seen square on: a long level course (0.9 over 0.45) at
        // y 150 and, under it, an arch's lit shoulder slanting the same way.
        let slant =
            |x: u32, y: u32, x0: u32, y0: u32| y as f32 - (y0 as f32 - 0.5 * (x - x0) as f32);
        let img = image::RgbImage::from_fn(400, 340, |x, y| {
            let sill = [100, 180, 260].iter().any(|&y0| {
                [(220, 250), (300, 330)]
                    .iter()
                    .any(|&(a, b)| (a..b).contains(&x) && (0.0..4.0).contains(&slant(x, y, a, y0)))
            });
            let shadow = [100, 180, 260].iter().any(|&y0| {
                [(220, 250), (300, 330)]
                    .iter()
                    .any(|&(a, b)| (a..b).contains(&x) && (4.0..8.0).contains(&slant(x, y, a, y0)))
            });
            let cable = (220..330).contains(&x) && (0.0..2.0).contains(&slant(x, y, 220, 325));
            let shoulder = (60..100).contains(&x) && (0.0..4.0).contains(&slant(x, y, 60, 200));
            let shoulder_shadow =
                (60..100).contains(&x) && (4.0..8.0).contains(&slant(x, y, 60, 200));
            let v = match (x, y) {
                _ if sill || shoulder => 0.9,
                _ if shadow || shoulder_shadow => 0.45,
                _ if cable => 0.3,
                (20..180, 150..154) => 0.9,
                (20..180, 154..158) => 0.45,
                _ => 0.7,
            };
            image::Rgb([(v * 255.0) as u8; 3])
        });
        let (f, class) = sky_over_wall(img, 30);
        let ledges = detect(&f, &class, Some(80.0));
        let slanted = |l: &Ledge| {
            let (a, b) = (l.polyline[0], l.polyline[1]);
            (b[1] - a[1]) / (b[0] - a[0]) < -0.3
        };
        let sills = ledges
            .iter()
            .filter(|l| slanted(l) && l.polyline[0][0] > 200.0)
            .count();
        assert!(sills >= 5, "the slanted sills: {ledges:?}");
        let on_the_cable = |l: &Ledge| {
            let [x, y] = l.polyline[0];
            x > 200.0 && (y - (325.0 - 0.5 * (x - 220.0))).abs() < 6.0
        };
        assert!(
            !ledges.iter().any(|l| slanted(l) && on_the_cable(l)),
            "the cable: {ledges:?}"
        );
        assert!(
            !ledges
                .iter()
                .any(|l| slanted(l) && l.polyline[0][0] < 200.0),
            "the shoulder under the course: {ledges:?}"
        );
        assert!(
            ledges
                .iter()
                .any(|l| l.polyline[0][0] < 40.0 && (l.polyline[0][1] - 154.0).abs() < 4.0),
            "the course: {ledges:?}"
        );
    }
}
