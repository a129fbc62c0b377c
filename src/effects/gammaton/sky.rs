//! The sky's rain on the image plane: a direction with a spread, and the
//! ledges that shelter the wall below them from it.
//!
//! A raindrop falls along its direction on the image plane (an angle from
//! vertical, positive to the right: wind from the left) while it closes in
//! on the wall. On a flat wall it can meet the wall anywhere, so where it
//! would land is drawn uniformly on the wall. A ledge that sticks out of the
//! wall catches the drops whose path crosses it less than the ledge's
//! shelter reach above where they would have landed: driving rain reaches
//! behind a projection of depth p down to about p / tan(angle) below it
//! (how-facades-age.md, "Rain shelter"). With the rain's angle toward the
//! wall varying over a storm, the reach is drawn per drop as an exponential
//! [choice: one unit exponential per drop times each ledge's mean reach, so
//! straight below a ledge the shelter fades as `exp(-d / reach)`, the scene
//! analysis's profile, src/analysis/shelter.rs]. So a ledge's shadow leans
//! with the rain: with the wind from the left, the wall just right of a
//! sill's right end is sheltered and the wall under its left end is not; a
//! spread blurs the shadow's sides.
//!
//! A caught drop's first contact is where its path crosses the ledge's
//! drip line, the highest ledge it crosses if several catch it [choice: the
//! water a ledge catches runs off its drip edge; the thesis's sky source
//! shoots rays at the scene and the first surface hit takes the drop].

use crate::analysis::{LedgeKind, shelter};

/// Steepest rain, degrees from vertical (a drop's angle is clamped to it).
pub const MAX_ANGLE: f32 = 85.0;

/// How far a ledge of `kind` shelters the wall, relative to a cornice
/// [choice: the ratios of the scene analysis's shelter reach by kind].
pub fn relative_reach(kind: LedgeKind) -> f32 {
    shelter::reach(kind) / shelter::reach(LedgeKind::Cornice)
}

/// A ledge that shelters the wall below it from the sky's γ-tons.
#[derive(Debug, Clone, PartialEq)]
pub struct Overhang {
    /// Its drip line, grid pixels.
    line: Vec<(f32, f32)>,
    /// Mean shelter reach below it, grid pixels per metre of a source's
    /// `shelter` (the ledge's kind and the scene's scale).
    reach: f32,
    /// Bounding box of `line`: x min, x max, y min, y max.
    bounds: [f32; 4],
}

impl Overhang {
    /// A ledge along `line` (grid pixels) whose shelter reaches `reach`
    /// grid pixels below it for each metre of a source's `shelter`.
    pub fn new(line: Vec<(f32, f32)>, reach: f32) -> Overhang {
        let mut bounds = [f32::MAX, f32::MIN, f32::MAX, f32::MIN];
        for &(x, y) in &line {
            bounds = [
                bounds[0].min(x),
                bounds[1].max(x),
                bounds[2].min(y),
                bounds[3].max(y),
            ];
        }
        Overhang {
            line,
            reach,
            bounds,
        }
    }
}

/// Where a drop that would land at `(x, y)` meets the wall, falling at
/// `angle` radians from vertical (positive: to the right) with a shelter
/// reach of `scale` metres: the crossing with the highest overhang whose
/// reach it is within, or `None` (it lands at `(x, y)`).
pub fn intercept(
    overhangs: &[Overhang],
    (x, y): (f32, f32),
    angle: f32,
    scale: f32,
) -> Option<(f32, f32)> {
    // Back up the path: P(t) = (x - t k, y - t), t = height above (x, y).
    let k = angle.tan();
    let mut best: Option<(f32, (f32, f32))> = None;
    for o in overhangs {
        let reach = scale * o.reach;
        let [bx0, bx1, by0, by1] = o.bounds;
        let (px0, px1) = (x.min(x - reach * k), x.max(x - reach * k));
        if reach <= 0.0 || bx1 < px0 || bx0 > px1 || by1 < y - reach || by0 > y {
            continue;
        }
        for seg in o.line.windows(2) {
            let (a, b) = (seg[0], seg[1]);
            // a + s (b - a) = P(t): [dx k; dy 1] [s; t] = [x - ax; y - ay].
            let (dx, dy) = (b.0 - a.0, b.1 - a.1);
            let det = dx - k * dy;
            if det.abs() < 1e-9 {
                continue;
            }
            let (rx, ry) = (x - a.0, y - a.1);
            let s = (rx - k * ry) / det;
            let t = (dx * ry - dy * rx) / det;
            let higher = best.is_none_or(|(bt, _)| t > bt);
            if (0.0..=1.0).contains(&s) && t > 0.0 && t <= reach && higher {
                best = Some((t, (x - t * k, y - t)));
            }
        }
    }
    best.map(|(_, at)| at)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sill() -> Vec<Overhang> {
        vec![Overhang::new(vec![(80.0, 40.0), (120.0, 40.0)], 10.0)]
    }

    #[test]
    fn straight_rain_is_caught_below_the_ledge_within_its_reach() {
        let o = sill();
        // 5 px below, reach 10: caught on the drip line above.
        assert_eq!(intercept(&o, (100.0, 45.0), 0.0, 1.0), Some((100.0, 40.0)));
        // 15 px below: out of reach; a wider reach catches it.
        assert_eq!(intercept(&o, (100.0, 55.0), 0.0, 1.0), None);
        assert!(intercept(&o, (100.0, 55.0), 0.0, 2.0).is_some());
        // Beside the ledge or above it: never.
        assert_eq!(intercept(&o, (125.0, 45.0), 0.0, 1.0), None);
        assert_eq!(intercept(&o, (100.0, 35.0), 0.0, 1.0), None);
    }

    #[test]
    fn slanted_rain_shelters_the_lee_side() {
        let o = sill();
        let right = 45f32.to_radians();
        // Falling to the right: the wall right of the ledge's right end is
        // reached only through the ledge, the wall under its left end
        // directly.
        let at = intercept(&o, (124.0, 45.0), right, 1.0).unwrap();
        assert!((at.0 - 119.0).abs() < 1e-4 && (at.1 - 40.0).abs() < 1e-4);
        assert_eq!(intercept(&o, (82.0, 45.0), right, 1.0), None);
        // Falling to the left: the other way round.
        assert_eq!(intercept(&o, (124.0, 45.0), -right, 1.0), None);
        assert!(intercept(&o, (82.0, 45.0), -right, 1.0).is_some());
    }

    #[test]
    fn the_highest_ledge_catches_first() {
        let o = vec![
            Overhang::new(vec![(0.0, 40.0), (50.0, 40.0)], 10.0),
            Overhang::new(vec![(0.0, 44.0), (50.0, 44.0)], 10.0),
        ];
        assert_eq!(intercept(&o, (20.0, 46.0), 0.0, 1.0), Some((20.0, 40.0)));
        // Out of the upper one's reach: the lower one catches it.
        let o = vec![
            Overhang::new(vec![(0.0, 30.0), (50.0, 30.0)], 10.0),
            Overhang::new(vec![(0.0, 44.0), (50.0, 44.0)], 10.0),
        ];
        assert_eq!(intercept(&o, (20.0, 46.0), 0.0, 1.0), Some((20.0, 44.0)));
    }
}
