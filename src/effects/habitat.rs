//! Where a wall stays wet, on the simulation grid: the places moss, algae
//! and lichen grow and dust is left alone (`how-facades-age.md`, "Living
//! growth" and "Near the ground"). Each map is 0..1 per grid cell.
//!
//! - the **splash zone**: the foot of a wall that stands on the ground
//!   (the site's ground line), wettest at the bottom;
//! - **ledge tops**: a band above each ledge's drip line (sill tops,
//!   copings, cornice tops), where water stands;
//! - **joints and cracks**: dark valleys of the photo's luminance;
//! - **shelter**: the wall under a projecting ledge, shaded and never
//!   washed (the site's rain shelter).

use rayon::prelude::*;

use super::Context;
use crate::field::RowMajor;

/// Width of the valleys taken for joints and cracks, metres (a mortar joint
/// is about 1 cm).
const JOINT_M: f32 = 0.015;

/// A valley starts to count as a joint this much darker than its
/// surroundings (as a share of their luminance): the grain of render or
/// stone is not a joint.
const JOINT_START: f32 = 0.1;

/// ... and counts fully this much further down.
const JOINT_DEPTH: f32 = 0.15;

/// A map on the grid from a function of the photo point at each cell's
/// centre.
pub fn on_grid(ctx: &Context, f: impl Fn(f32, f32) -> f32 + Sync) -> RowMajor<f32> {
    let (w, h) = (ctx.grid.width, ctx.grid.height);
    let mut out = RowMajor::filled(w, h, 0.0);
    out.data_mut()
        .par_chunks_mut(w)
        .enumerate()
        .for_each(|(gy, row)| {
            for (gx, v) in row.iter_mut().enumerate() {
                let (x, y) = ctx.grid.to_photo(gx as f32 + 0.5, gy as f32 + 0.5);
                *v = f(x, y);
            }
        });
    out
}

/// The splash zone: 1 at the foot of the wall, falling to 0 at `height_m`
/// above the ground; 0 where the photo shows no ground under the wall.
pub fn splash(ctx: &Context, height_m: f32) -> RowMajor<f32> {
    let reach = ctx.photo_px(height_m).max(1.0);
    on_grid(ctx, |x, y| {
        let Some(g) = ctx.site.ground_at(x.max(0.0) as u32) else {
            return 0.0;
        };
        let above = g - y;
        if above < -reach * 0.1 || above > reach {
            return 0.0;
        }
        1.0 - (above.max(0.0) / reach).powi(2)
    })
}

/// Ledge tops: a band `depth_m` deep above each ledge's drip line, as
/// strong as the ledge's confidence.
pub fn ledge_tops(ctx: &Context, depth_m: f32) -> RowMajor<f32> {
    let depth = ctx.photo_px(depth_m).max(1.0);
    // A ledge counts as much as the analysis is sure of it (1 for the
    // demo's own): a shutter's edge taken for a sill grows little.
    let lines: Vec<(&Vec<[f32; 2]>, f32)> = ctx
        .site
        .ledges
        .iter()
        .map(|l| (&l.polyline, l.confidence.clamp(0.0, 1.0)))
        .collect();
    on_grid(ctx, |x, y| {
        lines
            .iter()
            .filter_map(|(line, sure)| row_at(line, x).map(|row| (row, *sure)))
            .map(|(row, sure)| {
                let above = row - y;
                if (0.0..=depth).contains(&above) {
                    sure
                } else {
                    0.0
                }
            })
            .fold(0.0, f32::max)
    })
}

/// How far below the nearest deep projection above it (a roof's eave, a
/// cornice, a coping or a balcony: the ledges whose rain shelter reaches
/// far; sills and window heads project a few centimetres) each grid pixel
/// lies, in metres, divided by how far it is within the ledge's span: a
/// pixel `taper_m` or more in from the ledge's ends gets its plain
/// distance; toward an end the distance grows without bound, so a band
/// under the ledge narrows to nothing there. `f32::INFINITY` where no such
/// ledge is above.
pub fn below_projections(ctx: &Context, taper_m: f32) -> RowMajor<f32> {
    use crate::analysis::LedgeKind::{Balcony, Coping, Cornice, RoofLine};
    let per_m = ctx.photo_px(1.0).max(f32::MIN_POSITIVE);
    let taper = (taper_m * per_m).max(1.0);
    let deep: Vec<&Vec<[f32; 2]>> = ctx
        .site
        .ledges
        .iter()
        .filter(|l| matches!(l.kind, RoofLine | Cornice | Coping | Balcony))
        .map(|l| &l.polyline)
        .collect();
    on_grid(ctx, |x, y| {
        deep.iter()
            .filter_map(|line| {
                let row = row_at(line, x)?;
                let (first, last) = (line[0][0], line[line.len() - 1][0]);
                let inside = ((x - first).min(last - x) / taper).clamp(0.0, 1.0);
                let below = (y - row) / per_m;
                (below >= 0.0 && inside > 0.0).then(|| below / inside)
            })
            .fold(f32::INFINITY, f32::min)
    })
}

/// The row of a polyline (left to right) at column `x`, if `x` is within it.
pub(crate) fn row_at(line: &[[f32; 2]], x: f32) -> Option<f32> {
    line.windows(2).find_map(|pair| {
        let (a, b) = (pair[0], pair[1]);
        let (lo, hi) = (a[0].min(b[0]), a[0].max(b[0]));
        (x >= lo && x <= hi).then(|| {
            let t = if hi > lo {
                (x - a[0]) / (b[0] - a[0])
            } else {
                0.0
            };
            a[1] + (b[1] - a[1]) * t
        })
    })
}

/// Joints and cracks: how much darker each cell is than the wall on
/// *both* sides of it, across or along (a valley), as a share of their
/// luminance [choice: darker than the mean around it also took the shaded
/// side of every step, a pilaster's or a reveal's, and grew moss in
/// vertical lines down every shadow edge].
pub fn joints(ctx: &Context) -> RowMajor<f32> {
    let r = (ctx.grid_px(JOINT_M) * 2.0).round().max(1.0) as usize;
    let (w, h) = (ctx.grid.width, ctx.grid.height);
    let (luma, region) = (ctx.luma, ctx.region);
    // The wall's luminance at (x, y), if it is wall.
    let at = |x: usize, y: usize| region.get(x, y).then(|| luma.get(x, y));
    let depth = |l: f32, a: Option<f32>, b: Option<f32>| match (a, b) {
        (Some(a), Some(b)) if a.min(b) > 0.0 => {
            let m = 0.5 * (a + b);
            ((a.min(b) - l) / m - JOINT_START) / JOINT_DEPTH
        }
        _ => 0.0,
    };
    let mut out = RowMajor::filled(w, h, 0.0);
    out.data_mut()
        .par_chunks_mut(w)
        .enumerate()
        .for_each(|(y, row)| {
            for (x, v) in row.iter_mut().enumerate() {
                if !region.get(x, y) {
                    continue;
                }
                let l = luma.get(x, y);
                let across = match x >= r && x + r < w {
                    true => depth(l, at(x - r, y), at(x + r, y)),
                    false => 0.0,
                };
                let along = match y >= r && y + r < h {
                    true => depth(l, at(x, y - r), at(x, y + r)),
                    false => 0.0,
                };
                *v = across.max(along).clamp(0.0, 1.0);
            }
        });
    out
}

/// The rain shelter on the grid.
pub fn shelter(ctx: &Context) -> RowMajor<f32> {
    on_grid(ctx, |x, y| {
        ctx.site.shelter_at(x.max(0.0) as u32, y.max(0.0) as u32)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_polyline_row_is_found_only_within_it() {
        let line = [[10.0, 50.0], [20.0, 60.0]];
        assert_eq!(row_at(&line, 15.0), Some(55.0));
        assert_eq!(row_at(&line, 25.0), None);
    }
}
