//! The granularity mask (Santos sec. 5.3, eqs. 6-7, algorithms 1-3): coarse
//! dust elements (arcs, clumps and hairs), opaque and of one colour. The mask
//! only records whether an element covers a pixel (b in eq. 6); the layer's
//! colour is k (eq. 7).
//!
//! Element sizes derive from one parameter, the largest width w of Santos
//! Table 1 (12 to 36 px at 150 ppi):
//! - arc: radius r ~ U(w/8, w/2), arc length phi ~ U(pi/4, pi) [choice: the
//!   paper leaves r and phi free; these keep an arc within w];
//! - clump: a w_x by w_y rectangle with w_x, w_y ~ U(1, w/3) holding
//!   p = w_x w_y / 2 particles [choice: half the rectangle's pixels, a loose
//!   clump; the paper gives no values];
//! - hair: a quadratic Bezier curve through 3 points within a w by w box.
//!
//! [choice] Every shape is centred on its random pixel (the paper's
//! algorithms 2-3 put the pixel at the shape's corner), so elements spill
//! evenly over all edges of the region rather than only right and down.

use std::sync::atomic::{AtomicBool, Ordering};

use rand::Rng as _;
use rayon::prelude::*;

use super::Task;
use crate::effects::region::Region;
use crate::error::Result;
use crate::preset::DustParams;
use crate::progress::Progress;
use crate::random::{self, Rng, Stream};

/// The kinds of coarse element.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shape {
    /// Part of a circle (algorithm 1).
    Arc,
    /// Particles scattered in a rectangle (algorithm 2).
    Clump,
    /// A curved fibre (algorithm 3).
    Hair,
}

/// Element size and the mix of shapes.
#[derive(Debug, Clone, Copy)]
pub struct Looks {
    /// Largest width w, pixels.
    pub size: f32,
    /// Cumulative shares of arcs, clumps, hairs (last = 1).
    cumulative: [f32; 3],
}

impl Looks {
    /// The looks of a dust preset; shares are normalised to sum to 1.
    pub fn new(p: &DustParams) -> Looks {
        let shares = [p.arc_share, p.clump_share, p.hair_share].map(|s| s.max(0.0));
        let sum: f32 = shares.iter().sum();
        let sum = if sum > 0.0 { sum } else { 1.0 };
        Looks {
            size: p.granule_size.max(1.0),
            cumulative: [shares[0] / sum, (shares[0] + shares[1]) / sum, 1.0],
        }
    }

    /// The shape for a uniform draw `u` in [0, 1).
    pub fn shape(&self, u: f32) -> Shape {
        if u < self.cumulative[0] {
            Shape::Arc
        } else if u < self.cumulative[1] {
            Shape::Clump
        } else {
            Shape::Hair
        }
    }
}

/// floor(v) as an integer, without a libm call (hot in the plotting loops).
#[inline]
fn floor(v: f32) -> i64 {
    let t = v as i64;
    t - i64::from(v < t as f32)
}

/// Santos algorithm 1: an arc of radius `r` and angular length `phi` around
/// (cx, cy), starting at angle `start`. With n = ceil(2 pi r) steps of phi / n
/// consecutive points are less than a pixel apart, so the arc has no gaps.
pub fn arc(cx: f32, cy: f32, r: f32, start: f32, phi: f32, plot: &mut impl FnMut(i64, i64)) {
    let n = (std::f32::consts::TAU * r).ceil().max(1.0) as u32;
    // (sin g, cos g), advanced by phi / n per step with the angle-addition
    // formulas (one sin/cos per arc instead of per point).
    let (mut s, mut c) = start.sin_cos();
    let (ds, dc) = (phi / n as f32).sin_cos();
    for _ in 0..=n {
        plot(floor(cx + r * s), floor(cy + r * c));
        (s, c) = (s * dc + c * ds, c * dc - s * ds);
    }
}

/// Santos algorithm 2: `p` particles uniformly spread over a `wx` by `wy`
/// rectangle centred on (cx, cy).
pub fn clump(
    cx: f32,
    cy: f32,
    wx: f32,
    wy: f32,
    p: u32,
    rng: &mut Rng,
    plot: &mut impl FnMut(i64, i64),
) {
    for _ in 0..p {
        let bx = cx + (rng.random::<f32>() - 0.5) * wx;
        let by = cy + (rng.random::<f32>() - 0.5) * wy;
        plot(floor(bx), floor(by));
    }
}

/// Santos algorithm 3: the quadratic Bezier curve through control points
/// `pts`, evaluated by De Casteljau's construction.
///
/// The curve's speed |B'(t)| is at most 2 max(|P1 - P0|, |P2 - P1|), so with
/// that many steps consecutive points are at most one pixel apart and the
/// plotted pixels form an 8-connected curve (no gaps).
pub fn hair(pts: [(f32, f32); 3], plot: &mut impl FnMut(i64, i64)) {
    let len = |a: (f32, f32), b: (f32, f32)| ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
    let n = (2.0 * len(pts[0], pts[1]).max(len(pts[1], pts[2])))
        .ceil()
        .max(1.0) as u32;
    let lerp =
        |a: (f32, f32), b: (f32, f32), t: f32| (a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t);
    for s in 0..=n {
        let t = s as f32 / n as f32;
        // De Casteljau: two rounds of linear interpolation.
        let (a, b) = (lerp(pts[0], pts[1], t), lerp(pts[1], pts[2], t));
        let c = lerp(a, b, t);
        plot(floor(c.0), floor(c.1));
    }
}

/// Draws one random element centred on (cx, cy); returns its shape.
pub fn element(
    cx: f32,
    cy: f32,
    looks: &Looks,
    rng: &mut Rng,
    plot: &mut impl FnMut(i64, i64),
) -> Shape {
    let w = looks.size;
    let shape = looks.shape(rng.random());
    match shape {
        Shape::Arc => {
            let r = (w / 8.0 + rng.random::<f32>() * (w / 2.0 - w / 8.0)).max(1.0);
            let phi =
                std::f32::consts::FRAC_PI_4 + rng.random::<f32>() * 0.75 * std::f32::consts::PI;
            let start = rng.random::<f32>() * std::f32::consts::TAU;
            arc(cx, cy, r, start, phi, plot);
        }
        Shape::Clump => {
            let side = (w / 3.0 - 1.0).max(0.0);
            let wx = 1.0 + rng.random::<f32>() * side;
            let wy = 1.0 + rng.random::<f32>() * side;
            let p = ((wx * wy) / 2.0).round().max(1.0) as u32;
            clump(cx, cy, wx, wy, p, rng, plot);
        }
        Shape::Hair => {
            let pts = std::array::from_fn(|_| {
                (
                    cx + (rng.random::<f32>() - 0.5) * w,
                    cy + (rng.random::<f32>() - 0.5) * w,
                )
            });
            hair(pts, plot);
        }
    }
    shape
}

/// b of Santos eq. (6): whether a coarse element covers each pixel.
///
/// Elements are drawn in parallel; a pixel is only ever set, never cleared,
/// so the mask does not depend on scheduling.
#[derive(Debug)]
pub struct Mask {
    width: u32,
    height: u32,
    bits: Vec<AtomicBool>,
}

impl Clone for Mask {
    fn clone(&self) -> Mask {
        Mask {
            width: self.width,
            height: self.height,
            bits: self
                .bits
                .par_iter()
                .map(|b| AtomicBool::new(b.load(Ordering::Relaxed)))
                .collect(),
        }
    }
}

impl Mask {
    /// An empty mask.
    pub fn new(width: u32, height: u32) -> Mask {
        let n = width as usize * height as usize;
        Mask {
            width,
            height,
            bits: (0..n)
                .into_par_iter()
                .map(|_| AtomicBool::new(false))
                .collect(),
        }
    }

    /// Whether (x, y) is covered.
    pub fn get(&self, x: u32, y: u32) -> bool {
        self.bits[y as usize * self.width as usize + x as usize].load(Ordering::Relaxed)
    }

    /// Coverage of row `y`.
    pub fn row(&self, y: u32) -> impl Iterator<Item = bool> + '_ {
        let w = self.width as usize;
        self.bits[y as usize * w..(y as usize + 1) * w]
            .iter()
            .map(|b| b.load(Ordering::Relaxed))
    }

    /// Draws each task's elements, centred on uniformly random wall pixels.
    /// Returns how many arcs, clumps and hairs were drawn.
    pub(crate) fn place(
        &self,
        region: &Region,
        tasks: &[Task],
        looks: &Looks,
        seed: u64,
        progress: &Progress,
    ) -> Result<[u64; 3]> {
        let (w, h) = (self.width as i64, self.height as i64);
        tasks
            .par_iter()
            .map(|t| {
                progress.check()?;
                let mut rng = random::rng(seed, Stream::DustGranules, t.day as u64, t.chunk);
                let mut plot = |x: i64, y: i64| {
                    if x >= 0 && y >= 0 && x < w && y < h {
                        // Santos eq. (6): b = 1 where an element lies.
                        self.bits[(y * w + x) as usize].store(true, Ordering::Relaxed);
                    }
                };
                let mut counts = [0u64; 3];
                for _ in 0..t.count {
                    let (x, y) = region.sample(&mut rng);
                    let shape = element(x as f32 + 0.5, y as f32 + 0.5, looks, &mut rng, &mut plot);
                    counts[shape as usize] += 1;
                }
                Ok(counts)
            })
            .try_reduce(
                || [0; 3],
                |a, b| Ok([a[0] + b[0], a[1] + b[1], a[2] + b[2]]),
            )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Plain reference: the pixels of a curve are 8-connected when every
    /// plotted pixel (after the first) touches the previous one.
    fn chain_is_connected(pixels: &[(i64, i64)]) -> bool {
        pixels
            .windows(2)
            .all(|p| (p[0].0 - p[1].0).abs() <= 1 && (p[0].1 - p[1].1).abs() <= 1)
    }

    #[test]
    fn hairs_and_arcs_have_no_gaps() {
        use proptest::prelude::*;
        proptest!(|(c in proptest::array::uniform6(-40.0f32..40.0), r in 1.0f32..30.0, phi in 0.1f32..std::f32::consts::TAU)| {
            let mut px = Vec::new();
            hair([(c[0], c[1]), (c[2], c[3]), (c[4], c[5])], &mut |x, y| px.push((x, y)));
            prop_assert!(chain_is_connected(&px), "{px:?}");
            let mut px = Vec::new();
            arc(c[0], c[1], r, c[2], phi, &mut |x, y| px.push((x, y)));
            prop_assert!(chain_is_connected(&px));
        });
    }

    #[test]
    fn fast_floor_matches_floor() {
        for v in [
            -2.5f32,
            -2.0,
            -1.0e-7,
            0.0,
            0.3,
            1.0,
            7.999,
            -7.999,
            1.0e6 + 0.5,
        ] {
            assert_eq!(floor(v), v.floor() as i64, "{v}");
        }
    }

    #[test]
    fn arcs_follow_algorithm_1() {
        // The recurrence stays on the circle: every point within a pixel of
        // radius r around the centre, the last one at angle start + phi.
        let (r, start, phi) = (20.0f32, 0.3f32, 3.0f32);
        let mut px = Vec::new();
        arc(50.0, 50.0, r, start, phi, &mut |x, y| px.push((x, y)));
        assert_eq!(px.len(), (std::f32::consts::TAU * r).ceil() as usize + 1);
        for &(x, y) in &px {
            let d = ((x as f32 + 0.5 - 50.0).powi(2) + (y as f32 + 0.5 - 50.0).powi(2)).sqrt();
            assert!((d - r).abs() < 1.0, "{d}");
        }
        let end = start + phi;
        let want = (floor(50.0 + r * end.sin()), floor(50.0 + r * end.cos()));
        let last = *px.last().unwrap();
        assert!((last.0 - want.0).abs() <= 1 && (last.1 - want.1).abs() <= 1);
    }

    #[test]
    fn shapes_follow_their_shares() {
        let p = DustParams {
            arc_share: 0.0,
            clump_share: 1.0,
            hair_share: 3.0,
            ..DustParams::default()
        };
        let looks = Looks::new(&p);
        assert_eq!(looks.shape(0.0), Shape::Clump);
        assert_eq!(looks.shape(0.2), Shape::Clump);
        assert_eq!(looks.shape(0.3), Shape::Hair);
    }

    #[test]
    fn elements_stay_within_their_size() {
        let looks = Looks::new(&DustParams {
            granule_size: 14.0,
            ..DustParams::default()
        });
        let mut rng = random::rng(3, Stream::DustGranules, 0, 0);
        for _ in 0..500 {
            element(100.0, 100.0, &looks, &mut rng, &mut |x, y| {
                assert!((x - 100).abs() <= 8 && (y - 100).abs() <= 8, "({x}, {y})");
            });
        }
    }
}
