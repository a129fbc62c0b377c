//! Metres per pixel from what the building shows: the spacing of storeys
//! (rows of sills or window heads, 3.1 m apart), else the windows' height
//! (1.4 m), else the user's wall width, else a 10 m wide wall
//! (how-facades-age.md, "Scale anchors"). A wall width given by the user
//! wins over every estimate.

use super::features::Features;
use super::wall::Class;
use super::{Ledge, LedgeKind, Scale, ScaleSource};

/// Storey height assumed, metres (the spec's 2.7 to 3.5 m).
pub const STOREY_M: f32 = 3.1;
/// Window height assumed, metres (the spec's 1.2 to 1.6 m).
pub const WINDOW_M: f32 = 1.4;
/// Wall width assumed when nothing else is known, metres.
pub const DEFAULT_WIDTH_M: f32 = 10.0;

/// Estimates the scale; `ledges` in photo pixels.
pub fn estimate(
    f: &Features,
    class: &[Class],
    ledges: &[Ledge],
    wall_width_m: Option<f32>,
) -> Scale {
    let (w, h) = (f.w, f.h);
    let wall_cols = (0..w)
        .filter(|&x| (0..h).any(|y| class[y * w + x] == Class::Wall))
        .count()
        .max(1) as f32
        * f.sx;
    if let Some(m) = wall_width_m.filter(|m| m.is_finite() && *m > 0.0) {
        return Scale {
            metres_per_pixel: m / wall_cols,
            source: ScaleSource::UserWidth,
        };
    }
    // Rows of windows: the tops of the glass blobs.
    let glass: Vec<u8> = class.iter().map(|&c| (c == Class::Glass) as u8).collect();
    let tops: Vec<f32> = super::eval::components(&glass, w, h, &[1], (w * h) / 5000)
        .iter()
        .map(|b| b.y0 * f.sy)
        .collect();
    if let Some(storey) = storey_px(tops, h as f32 * f.sy) {
        return Scale {
            metres_per_pixel: STOREY_M / storey,
            source: ScaleSource::StoreyHeight,
        };
    }
    for kind in [LedgeKind::WindowHead, LedgeKind::Sill] {
        let ys: Vec<f32> = ledges
            .iter()
            .filter(|l| l.kind == kind)
            .map(|l| (l.polyline[0][1] + l.polyline[l.polyline.len() - 1][1]) / 2.0)
            .collect();
        if let Some(storey) = storey_px(ys, f.h as f32 * f.sy) {
            return Scale {
                metres_per_pixel: STOREY_M / storey,
                source: ScaleSource::StoreyHeight,
            };
        }
    }
    if let Some(px) = window_height_px(class, w, h) {
        return Scale {
            metres_per_pixel: WINDOW_M / (px * f.sy),
            source: ScaleSource::WindowSize,
        };
    }
    Scale {
        metres_per_pixel: DEFAULT_WIDTH_M / wall_cols,
        source: ScaleSource::Default,
    }
}

/// The typical spacing of rows among `ys` (photo pixels): rows are runs of
/// values within 1.5% of the height; the median gap between neighbouring
/// rows, when there are at least three rows.
pub fn storey_px(mut ys: Vec<f32>, height: f32) -> Option<f32> {
    ys.sort_by(f32::total_cmp);
    let tol = 0.015 * height;
    let mut rows: Vec<(f32, usize)> = Vec::new();
    for y in ys {
        match rows.last_mut() {
            Some((m, n)) if y - *m / *n as f32 <= tol => {
                *m += y;
                *n += 1;
            }
            _ => rows.push((y, 1)),
        }
    }
    let rows: Vec<f32> = rows.iter().map(|(m, n)| m / *n as f32).collect();
    if rows.len() < 3 {
        return None;
    }
    let mut gaps: Vec<f32> = rows
        .windows(2)
        .map(|r| r[1] - r[0])
        .filter(|g| *g > 0.05 * height)
        .collect();
    if gaps.len() < 2 {
        return None;
    }
    gaps.sort_by(f32::total_cmp);
    Some(gaps[gaps.len() / 2])
}

/// Median height (analysis pixels) of the glass blobs.
fn window_height_px(class: &[Class], w: usize, h: usize) -> Option<f32> {
    let mut heights = Vec::new();
    for x in (0..w).step_by((w / 64).max(1)) {
        let mut run = 0;
        for y in 0..h {
            if class[y * w + x] == Class::Glass {
                run += 1;
            } else if run > 0 {
                heights.push(run as f32);
                run = 0;
            }
        }
    }
    if heights.len() < 3 {
        return None;
    }
    heights.sort_by(f32::total_cmp);
    Some(heights[heights.len() / 2])
}

/// Parses a length in metres as the user writes it: `14m`, `14 m`, `14`,
/// `1400cm`.
///
/// # Errors
/// [`crate::Error::OutOfRange`] when it is not a positive length.
pub fn parse_metres(s: &str) -> crate::Result<f32> {
    let t = s.trim().to_ascii_lowercase();
    let (num, factor) = if let Some(n) = t.strip_suffix("cm") {
        (n, 0.01)
    } else if let Some(n) = t.strip_suffix("mm") {
        (n, 0.001)
    } else if let Some(n) = t.strip_suffix('m') {
        (n, 1.0)
    } else {
        (t.as_str(), 1.0)
    };
    match num.trim().parse::<f32>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v * factor),
        _ => Err(crate::Error::OutOfRange {
            field: "wall width".into(),
            value: s.to_string(),
            range: "a positive length such as 14m or 1400cm".into(),
        }),
    }
}
