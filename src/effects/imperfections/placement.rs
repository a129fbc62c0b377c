//! Becket & Badler's placement rules in image space: each rule is a
//! distance (photo pixels) from a feature of the wall (its edges, top,
//! foot, sills, railings, a point), turned into a weight by the rule's band.
//!
//! A pixel's weight is 1 within `band` of the feature, falls to 0 at
//! 1.5 `band`, and is 0 off the wall. The placement area, over which
//! coverage is measured, is the pixels of weight at least 0.5.

use rayon::prelude::*;

use crate::analysis::LedgeKind;
use crate::effects::Context;
use crate::preset::{Place, Placement};

/// Weight of the placement area's boundary.
pub const AREA: f32 = 0.5;

/// A placement rule on the photo.
#[derive(Debug, Clone)]
pub struct Placed {
    /// Photo width and height.
    pub width: usize,
    /// Photo height.
    pub height: usize,
    /// Distance to the feature, photo pixels (infinite where it has none).
    pub distance: Vec<f32>,
    /// Weight per pixel, row-major, 0 off the wall.
    pub weight: Vec<f32>,
    /// Pixels of weight at least [`AREA`].
    pub area: u64,
    /// The band in photo pixels.
    pub band: f32,
    /// The rule used ("railings" falls back when the photo has none).
    pub used: String,
}

impl Placed {
    /// Whether pixel `i` is in the placement area.
    pub fn in_area(&self, i: usize) -> bool {
        self.weight[i] >= AREA
    }
}

/// The weight of a pixel at distance `d` from the feature, band `b`.
pub fn falloff(d: f32, b: f32) -> f32 {
    if d <= b {
        1.0
    } else {
        (1.0 - (d - b) / (0.5 * b)).max(0.0)
    }
}

/// The placement rule `place` on `ctx`'s photo.
pub fn place(ctx: &Context, place: Place) -> Placed {
    let (w, h) = ctx.size();
    let (w, h) = (w as usize, h as usize);
    let band = ctx.photo_px(place.band).max(1.0);
    let wall: Vec<bool> = (0..h)
        .into_par_iter()
        .flat_map_iter(|y| {
            let row = ctx.wall.mask_row(y as u32);
            (0..w).map(move |x| row.is_none_or(|r| r[x] >= crate::grid::WALL))
        })
        .collect();
    let mut used = format!("{:?}", place.placement).to_lowercase();
    let distance = match place.placement {
        Placement::Everywhere => vec![0.0; w * h],
        Placement::Edges => {
            // The frame is an edge too.
            let mut seeds = wall.iter().map(|&b| !b).collect::<Vec<_>>();
            for x in 0..w {
                seeds[x] = true;
                seeds[(h - 1) * w + x] = true;
            }
            for y in 0..h {
                seeds[y * w] = true;
                seeds[y * w + w - 1] = true;
            }
            chamfer(&seeds, w, h)
        }
        Placement::Top | Placement::Bottom | Placement::Ground => {
            columns(ctx, &wall, w, h, place.placement)
        }
        Placement::Sills => {
            let sills = ledges(ctx, &[LedgeKind::Sill]);
            if sills.is_empty() {
                used = "sills (none found: the wall's foot)".into();
                columns(ctx, &wall, w, h, Placement::Ground)
            } else {
                below(&sills, w, h, band)
            }
        }
        Placement::Railings => {
            let mut lines = ledges(ctx, &[LedgeKind::Balcony]);
            if lines.is_empty() {
                lines = ledges(ctx, &[LedgeKind::Sill]);
                used = "railings (none found: the sills' flashings)".into();
            }
            if lines.is_empty() {
                lines = ctx.site.ledges.iter().map(|l| l.polyline.clone()).collect();
                used = "railings (none found: every ledge)".into();
            }
            if lines.is_empty() {
                let edges = Place {
                    placement: Placement::Edges,
                    ..place
                };
                return Placed {
                    used: "railings (no ledges: the edges)".into(),
                    ..self::place(ctx, edges)
                };
            }
            let mut seeds = vec![false; w * h];
            for line in &lines {
                raster(line, w, h, &mut seeds);
            }
            chamfer(&seeds, w, h)
        }
        Placement::Point => {
            let [px, py] = place.around;
            (0..w * h)
                .map(|i| ((i % w) as f32 + 0.5 - px).hypot((i / w) as f32 + 0.5 - py))
                .collect()
        }
        Placement::Area => (0..w * h)
            .map(|i| {
                let inside = inside(place.area, (i % w) as f32 + 0.5, (i / w) as f32 + 0.5);
                if inside { 0.0 } else { f32::INFINITY }
            })
            .collect(),
    };
    let weight: Vec<f32> = distance
        .par_iter()
        .zip(&wall)
        .map(|(&d, &on)| if on { falloff(d, band) } else { 0.0 })
        .collect();
    let area = weight.iter().filter(|&&v| v >= AREA).count() as u64;
    Placed {
        width: w,
        height: h,
        distance,
        weight,
        area,
        band,
        used,
    }
}

/// Polylines of the site's ledges of these kinds.
fn ledges(ctx: &Context, kinds: &[LedgeKind]) -> Vec<Vec<[f32; 2]>> {
    ctx.site
        .ledges
        .iter()
        .filter(|l| kinds.contains(&l.kind))
        .map(|l| l.polyline.clone())
        .collect()
}

/// Distance from the wall's top or bottom in each column, or from the
/// ground line where the site knows it.
fn columns(ctx: &Context, wall: &[bool], w: usize, h: usize, which: Placement) -> Vec<f32> {
    let mut out = vec![f32::INFINITY; w * h];
    for x in 0..w {
        let top = (0..h).find(|&y| wall[y * w + x]);
        let bottom = (0..h).rev().find(|&y| wall[y * w + x]);
        let (Some(top), Some(bottom)) = (top, bottom) else {
            continue;
        };
        for y in 0..h {
            out[y * w + x] = match which {
                Placement::Top => y as f32 - top as f32,
                Placement::Ground => ctx
                    .site
                    .ground_at(x as u32)
                    .map_or(bottom as f32 - y as f32, |g| g - 1.0 - y as f32),
                _ => bottom as f32 - y as f32,
            }
            .max(0.0);
        }
    }
    out
}

/// Distance below each polyline; beside its ends the distance grows with
/// twice the distance past the end (so the area tapers off instead of
/// ending in a vertical cut), and it is infinite above the line.
fn below(lines: &[Vec<[f32; 2]>], w: usize, h: usize, band: f32) -> Vec<f32> {
    let mut out = vec![f32::INFINITY; w * h];
    for line in lines {
        let (lo, hi) = line
            .iter()
            .fold((f32::MAX, f32::MIN), |(a, b), p| (a.min(p[0]), b.max(p[0])));
        let a = (lo - band).max(0.0) as usize;
        let b = ((hi + band).ceil() as usize).min(w);
        for x in a..b {
            let xc = x as f32 + 0.5;
            let past = (lo - xc).max(xc - hi).max(0.0);
            let yl = line_y(line, xc.clamp(lo, hi));
            for y in (yl.max(0.0) as usize)..h {
                let d = (y as f32 + 0.5 - yl).max(0.0) + 2.0 * past;
                let o = &mut out[y * w + x];
                *o = o.min(d);
            }
        }
    }
    out
}

/// The polyline's row at column `x` (within its span).
fn line_y(line: &[[f32; 2]], x: f32) -> f32 {
    for seg in line.windows(2) {
        let ([x0, y0], [x1, y1]) = (seg[0], seg[1]);
        if (x0.min(x1)..=x0.max(x1)).contains(&x) {
            let t = if x1 != x0 { (x - x0) / (x1 - x0) } else { 0.0 };
            return y0 + (y1 - y0) * t;
        }
    }
    line.first().map_or(0.0, |p| p[1])
}

/// Marks the pixels a polyline passes through.
fn raster(line: &[[f32; 2]], w: usize, h: usize, seeds: &mut [bool]) {
    for seg in line.windows(2) {
        let ([x0, y0], [x1, y1]) = (seg[0], seg[1]);
        let steps = ((x1 - x0).abs().max((y1 - y0).abs()) * 2.0).ceil().max(1.0) as usize;
        for k in 0..=steps {
            let t = k as f32 / steps as f32;
            let (x, y) = (x0 + (x1 - x0) * t, y0 + (y1 - y0) * t);
            if x >= 0.0 && y >= 0.0 && (x as usize) < w && (y as usize) < h {
                seeds[y as usize * w + x as usize] = true;
            }
        }
    }
}

/// Even-odd test of (x, y) against a polygon.
fn inside(poly: &[[f32; 2]], x: f32, y: f32) -> bool {
    let mut c = false;
    let n = poly.len();
    for i in 0..n {
        let ([xi, yi], [xj, yj]) = (poly[i], poly[(i + n - 1) % n]);
        if (yi > y) != (yj > y) && x < (xj - xi) * (y - yi) / (yj - yi) + xi {
            c = !c;
        }
    }
    c
}

/// Chamfer distance (1, √2) to the nearest seed, two passes.
pub fn chamfer(seeds: &[bool], w: usize, h: usize) -> Vec<f32> {
    const D: f32 = std::f32::consts::SQRT_2;
    let mut d: Vec<f32> = seeds
        .iter()
        .map(|&s| if s { 0.0 } else { f32::INFINITY })
        .collect();
    for y in 0..h {
        for x in 0..w {
            let i = y * w + x;
            let mut v = d[i];
            if x > 0 {
                v = v.min(d[i - 1] + 1.0);
            }
            if y > 0 {
                v = v.min(d[i - w] + 1.0);
                if x > 0 {
                    v = v.min(d[i - w - 1] + D);
                }
                if x + 1 < w {
                    v = v.min(d[i - w + 1] + D);
                }
            }
            d[i] = v;
        }
    }
    for y in (0..h).rev() {
        for x in (0..w).rev() {
            let i = y * w + x;
            let mut v = d[i];
            if x + 1 < w {
                v = v.min(d[i + 1] + 1.0);
            }
            if y + 1 < h {
                v = v.min(d[i + w] + 1.0);
                if x + 1 < w {
                    v = v.min(d[i + w + 1] + D);
                }
                if x > 0 {
                    v = v.min(d[i + w - 1] + D);
                }
            }
            d[i] = v;
        }
    }
    d
}
