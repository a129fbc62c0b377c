//! Ledge detection: source lines proposed from a photo, where water would
//! drip from (the shadowed underside of a sill or cornice).

use image::{DynamicImage, GrayImage};

use crate::grid::WALL;
use crate::photo::Photo;
use crate::preset::SourceLine;

/// Proposes source lines from strong horizontal edges where the image turns
/// from bright above to dark below (the shadowed underside of a sill or
/// cornice), inside the wall region. Returns level lines in photo pixels,
/// just below each edge, top to bottom.
///
/// ```
/// let d = grime::demo::facade(480, 360);
/// let lines = grime::ledges::detect(&d.photo, d.region.as_ref());
/// assert!(lines.len() >= 5);
/// ```
pub fn detect(photo: &Photo, mask: Option<&GrayImage>) -> Vec<SourceLine> {
    let (w, h) = (photo.width(), photo.height());
    if w < 8 || h < 8 {
        return Vec::new();
    }
    // Analyse at most ~1000 px on the long side: ledges are large features.
    let s = (1000.0 / w.max(h) as f32).min(1.0);
    let (aw, ah) = (
        ((w as f32 * s).round() as u32).max(8),
        ((h as f32 * s).round() as u32).max(8),
    );
    let luma = DynamicImage::ImageLuma8(photo.image().to_luma8())
        .resize_exact(aw, ah, image::imageops::FilterType::Triangle)
        .to_luma32f();
    let l = imageproc::filter::gaussian_blur_f32(&luma, 1.0);
    let at = |x: u32, y: u32| l.get_pixel(x, y)[0] * 255.0;
    let gy = |x: u32, y: u32| at(x, y + 1) - at(x, y - 1);
    let in_region = |x: u32, y: u32| {
        mask.is_none_or(|m| {
            let (px, py) = (((x as f32 + 0.5) / s) as u32, ((y as f32 + 0.5) / s) as u32);
            m.get_pixel(px.min(w - 1), py.min(h - 1))[0] >= WALL
        })
    };
    const T: f32 = 25.0;
    let min_len = (aw as f32 * 0.03).max(10.0) as u32;
    // Edge pixels: bright above, dark below, a local extreme across rows.
    let mut edge = vec![false; (aw * ah) as usize];
    for y in 2..ah - 2 {
        for x in 1..aw - 1 {
            let g = gy(x, y);
            let gx = at(x + 1, y) - at(x - 1, y);
            edge[(y * aw + x) as usize] = g < -T
                && gx.abs() < 0.5 * g.abs()
                && g <= gy(x, y - 1)
                && g <= gy(x, y + 1)
                && in_region(x, (y + 2).min(ah - 1));
        }
    }
    // Row runs, tolerating a row of jitter and gaps of a few pixels:
    // (y, x0, x1, edge pixels on the row itself).
    let is_edge = |x: u32, y: u32| edge[(y * aw + x) as usize];
    let mut runs: Vec<(u32, u32, u32, u32)> = Vec::new();
    for y in 3..ah - 3 {
        let mut start: Option<u32> = None;
        let (mut last, mut own) = (0, 0);
        let close = |start: Option<u32>, last: u32, own: u32, runs: &mut Vec<_>| {
            if let Some(s0) = start
                && last + 1 - s0 >= min_len
                && own * 2 >= last + 1 - s0
            {
                runs.push((y, s0, last + 1, own));
            }
        };
        for x in 1..aw - 1 {
            if is_edge(x, y) || is_edge(x, y - 1) || is_edge(x, y + 1) {
                if start.is_none() || x > last + 4 {
                    close(start, last, own, &mut runs);
                    start = Some(x);
                    own = 0;
                }
                last = x;
                own += is_edge(x, y) as u32;
            }
        }
        close(start, last, own, &mut runs);
    }
    // Merge runs on neighbouring rows that overlap or nearly touch: one
    // ledge. Groups: (sum of y weighted by own pixels, own pixels, x0, x1, last y).
    let mut groups: Vec<(f32, u32, u32, u32, u32)> = Vec::new();
    for (y, x0, x1, own) in runs {
        let hit = groups
            .iter()
            .position(|g| y - g.4 <= 2 && x0 <= g.3 + 4 && x1 + 4 >= g.2);
        match hit {
            Some(i) => {
                let g = &mut groups[i];
                g.0 += y as f32 * own as f32;
                g.1 += own;
                g.2 = g.2.min(x0);
                g.3 = g.3.max(x1);
                g.4 = y;
            }
            None => groups.push((y as f32 * own as f32, own, x0, x1, y)),
        }
    }
    let mut lines: Vec<SourceLine> = groups
        .into_iter()
        .filter(|g| g.1 > 0)
        .map(|(sum, n, x0, x1, _)| {
            let y = (sum / n as f32 + 1.5) / s;
            vec![[x0 as f32 / s, y], [x1 as f32 / s, y]]
        })
        .collect();
    lines.sort_by(|a, b| {
        a[0][1]
            .total_cmp(&b[0][1])
            .then(a[0][0].total_cmp(&b[0][0]))
    });
    lines.truncate(100);
    lines
}

/// The lines of `found` that repeat none of `existing`: a found line
/// repeats one when it overlaps it horizontally and lies within `tolerance`
/// pixels of its mean height. Found lines are level (see [`detect`]).
///
/// ```
/// let old = vec![vec![[0.0, 10.0], [50.0, 10.0]]];
/// let found = vec![vec![[5.0, 12.0], [40.0, 12.0]], vec![[5.0, 40.0], [40.0, 40.0]]];
/// assert_eq!(grime::ledges::not_in(&old, found, 6.0).len(), 1);
/// ```
pub fn not_in(
    existing: &[SourceLine],
    found: impl IntoIterator<Item = SourceLine>,
    tolerance: f32,
) -> Vec<SourceLine> {
    let mut kept: Vec<SourceLine> = Vec::new();
    for line in found {
        let (Some(first), Some(last)) = (line.first(), line.last()) else {
            continue;
        };
        let (y, x0, x1) = (first[1], first[0], last[0]);
        let repeats = existing.iter().chain(&kept).any(|o| {
            let oy = o.iter().map(|p| p[1]).sum::<f32>() / o.len().max(1) as f32;
            let (ox0, ox1) = o
                .iter()
                .fold((f32::MAX, f32::MIN), |(a, b), p| (a.min(p[0]), b.max(p[0])));
            (y - oy).abs() < tolerance && x0 < ox1 && x1 > ox0
        });
        if !repeats {
            kept.push(line);
        }
    }
    kept
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ledges_of_the_sample_facade_are_found() {
        let (w, h) = (480, 360);
        let d = crate::demo::facade(w, h);
        let l = crate::demo::layout(w, h);
        let found = detect(&d.photo, d.region.as_ref());
        let near = |y: f32, x0: u32, x1: u32| {
            found.iter().any(|line| {
                (line[0][1] - y).abs() <= 3.0 && line[0][0] < x1 as f32 && line[1][0] > x0 as f32
            })
        };
        for s in &l.sills {
            assert!(
                near(s.3 as f32 + 1.0, s.0, s.2),
                "sill {s:?} not in {found:?}"
            );
        }
        assert!(
            near(l.cornice.1 as f32 + 1.0, 0, w),
            "cornice not in {found:?}"
        );
        assert!(
            found.len() <= 2 * (l.sills.len() + 1),
            "too many: {found:?}"
        );
    }
}
