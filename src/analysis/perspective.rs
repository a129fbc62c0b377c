//! How a part of the photo lies in perspective, from its luma gradients:
//! the edges of a road seen along a street converge to its vanishing
//! point and run oblique ([`oblique`]); its texture is magnified toward
//! the camera ([`nearer_smoother`]). A facade seen square on has neither.

use rayon::prelude::*;

use super::features::Features;

/// The share of `part`'s luma gradient energy that runs oblique,
/// sum 2 |gx gy| / sum (gx^2 + gy^2): 0 for edges that run level or
/// upright, 1 for edges at 45 degrees, 2 / pi for isotropic noise.
pub(super) fn oblique(f: &Features, part: &[bool]) -> f32 {
    let (a, b) = (1..f.h.saturating_sub(1))
        .into_par_iter()
        .map(|y| {
            row_sums(f, part, y, |gx, gy| {
                (2.0 * (gx * gy).abs(), gx * gx + gy * gy)
            })
        })
        .reduce(|| (0.0, 0.0), |p, q| (p.0 + q.0, p.1 + q.1));
    if b > 0.0 { (a / b) as f32 } else { 0.0 }
}

/// Over `part`'s pixels in row `y` (not the first or last row), the sums of
/// `term` of the luma's central differences (gx, gy).
fn row_sums(
    f: &Features,
    part: &[bool],
    y: usize,
    term: impl Fn(f32, f32) -> (f32, f32),
) -> (f64, f64) {
    let (w, l) = (f.w, &f.luma);
    let (mut a, mut b) = (0f64, 0f64);
    for x in 1..w.saturating_sub(1) {
        let i = y * w + x;
        if part[i] {
            let (p, q) = term(l[i + 1] - l[i - 1], l[i + w] - l[i - w]);
            a += p as f64;
            b += q as f64;
        }
    }
    (a, b)
}

/// How much smoother `part` is in its nearer half than in its farther
/// half: the mean squared luma gradient per pixel of `part` in the rows
/// from halfway between row `y0` and the bottom down, over the same in the
/// rows from `y0` to halfway. The texture of a plane seen in perspective
/// (asphalt's grain, paving, shadows) is magnified toward the camera, so
/// its gradients per pixel fall (J. J. Gibson, "The Perception of the
/// Visual World", 1950: the texture gradient); the evenly spaced courses
/// and grooves of a plinth seen square on keep theirs. Infinite when the
/// farther half holds none of `part` or no gradient.
pub(super) fn nearer_smoother(f: &Features, part: &[bool], y0: usize) -> f32 {
    let (h, mid) = (f.h, (y0 + f.h) / 2);
    // Per half: the summed squared gradient and the pixels.
    let energy = |gx: f32, gy: f32| (gx * gx + gy * gy, 1.0);
    let (far, near) = (y0.max(1)..h.saturating_sub(1))
        .into_par_iter()
        .map(|y| {
            let sums = row_sums(f, part, y, energy);
            if y < mid {
                (sums, (0.0, 0.0))
            } else {
                ((0.0, 0.0), sums)
            }
        })
        .reduce(
            || ((0.0, 0.0), (0.0, 0.0)),
            |a, b| {
                (
                    (a.0.0 + b.0.0, a.0.1 + b.0.1),
                    (a.1.0 + b.1.0, a.1.1 + b.1.1),
                )
            },
        );
    if far.0 <= 0.0 {
        return f32::INFINITY;
    }
    ((near.0 / near.1.max(1.0)) / (far.0 / far.1)) as f32
}
