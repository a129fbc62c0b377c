//! The roof line: where the wall meets the sky. Rain leaves a roof at its
//! eaves, so the line runs along the lower edge of the eave's tiles,
//! fascia or coping, and not up a gable's slope.

use super::features::{Features, l1};
use super::wall::Class;
use super::{Ledge, LedgeKind};

/// Where wall lies just under sky: runs of columns, sampled every few
/// pixels, as polylines along the eave's lower edge ([`eave`]).
pub(super) fn roof_line(f: &Features, class: &[Class]) -> Vec<Ledge> {
    let (w, h) = (f.w, f.h);
    let top: Vec<Option<usize>> = (0..w)
        .map(|x| {
            (1..h)
                .find(|&y| class[y * w + x] == Class::Wall && class[(y - 1) * w + x] == Class::Sky)
        })
        .collect();
    let mut out = Vec::new();
    let mut x = 0;
    let step = (w / 64).max(2);
    while x < w {
        if top[x].is_none() {
            x += 1;
            continue;
        }
        let start = x;
        while x < w
            && top[x].is_some()
            && (x == start
                || matches!((top[x], top[x - 1]), (Some(a), Some(b)) if a.abs_diff(b) <= h / 50 + 1))
        {
            x += 1;
        }
        if x - start >= w / 20 {
            let mut columns: Vec<usize> = (start..x).step_by(step).collect();
            columns.push(x - 1);
            let rows: Vec<f32> = columns
                .iter()
                .map(|&c| eave(f, c, top[c].unwrap_or(0)))
                .collect();
            // A median of three: one column's tile or gutter bracket does
            // not kink the line.
            let mut pts: Vec<[f32; 2]> = columns
                .iter()
                .enumerate()
                .map(|(i, &c)| {
                    let mut near = [
                        rows[i.saturating_sub(1)],
                        rows[i],
                        rows[(i + 1).min(rows.len() - 1)],
                    ];
                    near.sort_by(f32::total_cmp);
                    [c as f32, near[1]]
                })
                .collect();
            if let Some(last) = pts.last_mut() {
                last[0] = x as f32;
            }
            for eave in eaves(pts, (w / 20) as f32) {
                let span = eave[eave.len() - 1][0] - eave[0][0];
                out.push(Ledge {
                    kind: LedgeKind::RoofLine,
                    polyline: eave,
                    confidence: (span / w as f32).sqrt().min(1.0),
                });
            }
        }
    }
    out
}

/// The steepest a roof line runs, rows per column [choice: 0.7, about 35
/// degrees: rain leaves a pitched roof at its eaves, not along its verges
/// (`how-facades-age.md`, "Where water goes"), so the sky's edge up a
/// gable's slope sheds nothing down the gable (LabelMeFacade IMG_6469: a
/// roof line traced up the slope of the gable in front at 58 degrees laid
/// a stain on its brick that stopped on a level line); an eave seen in a
/// street photo's perspective stays under it].
const PITCH: f32 = 0.7;

/// The stretches of a roof line's points `pts` that are not on a slope
/// (two or more successive steps steeper than [`PITCH`]; one steep step
/// is a jog of the eave, a gutter bracket or a chimney's foot, and stays)
/// and at least `least` columns long.
fn eaves(pts: Vec<[f32; 2]>, least: f32) -> Vec<Vec<[f32; 2]>> {
    let steep: Vec<bool> = pts
        .windows(2)
        .map(|s| (s[1][1] - s[0][1]).abs() > PITCH * (s[1][0] - s[0][0]).abs().max(1.0))
        .collect();
    let slope = |i: usize| {
        steep[i] && (i > 0 && steep[i - 1] || steep.get(i + 1).copied().unwrap_or(false))
    };
    let mut out: Vec<Vec<[f32; 2]>> = Vec::new();
    let mut run: Vec<[f32; 2]> = Vec::new();
    let mut close = |run: &mut Vec<[f32; 2]>| {
        if run.len() >= 2 && run[run.len() - 1][0] - run[0][0] >= least {
            out.push(std::mem::take(run));
        }
        run.clear();
    };
    for (i, p) in pts.iter().enumerate() {
        if i > 0 && slope(i - 1) {
            close(&mut run);
        }
        run.push(*p);
    }
    close(&mut run);
    out
}

/// How far below the sky an eave, fascia or coping reaches, as a share of
/// the height [choice: an eave band 0.2-0.4 m deep is 1-3% of the height of
/// a photo showing three to six storeys].
const EAVE_DEPTH: f32 = 0.03;
/// A colour step (L1, means of the two rows above and below) that ends an
/// eave [choice: roof tiles over render step by about 1; a plain wall's
/// texture by under 0.1].
const EAVE_STEP: f32 = 0.25;

/// The line's row at column `x` under a roof whose wall begins at row
/// `top` under the sky: the lowest strong colour step within
/// [`EAVE_DEPTH`] below it, the lower edge of the tiles, fascia or coping
/// where the wall face begins and water drips off; a row below `top` when
/// there is none. Blind review 18 caught drips that began on the tiles of
/// an eave, darkening them.
fn eave(f: &Features, x: usize, top: usize) -> f32 {
    let (w, h) = (f.w, f.h);
    let depth = ((EAVE_DEPTH * h as f32).round() as usize).max(2);
    let (x0, x1) = (x.saturating_sub(1), (x + 1).min(w - 1));
    let mean = |y0: usize| {
        let mut sum = [0.0f32; 3];
        for y in y0..y0 + 2 {
            for c in x0..=x1 {
                let v = f.rgb_at(y * w + c);
                (0..3).for_each(|k| sum[k] += v[k]);
            }
        }
        sum.map(|v| v / (2 * (x1 - x0 + 1)) as f32)
    };
    let steps: Vec<(usize, f32)> = (top + 2..=(top + depth).min(h.saturating_sub(2)))
        .map(|y| (y, l1(mean(y - 2), mean(y))))
        .collect();
    // The lowest run of strong steps, and its strongest row: the edge
    // itself, not the rows whose means straddle it.
    let Some(last) = steps.iter().rposition(|s| s.1 > EAVE_STEP) else {
        return top as f32 + 1.0;
    };
    let first = steps[..last]
        .iter()
        .rposition(|s| s.1 <= EAVE_STEP)
        .map_or(0, |i| i + 1);
    steps[first..=last]
        .iter()
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map_or(top as f32 + 1.0, |s| s.0 as f32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::photo::Photo;

    #[test]
    fn a_gables_slope_is_no_roof_line_its_eave_is() {
        // Sky over a wall whose top is level over x < 100 (row 120), then
        // climbs a gable's slope at 60 degrees (1.7 rows per column) to its
        // apex at x = 160, with sky alone beyond.
        let top = |x: u32| match x {
            0..100 => 120,
            100..160 => 120 - ((x - 100) as f32 * 1.7) as u32,
            _ => 200,
        };
        let img = image::RgbImage::from_fn(200, 200, |x, y| match y < top(x) {
            true => image::Rgb([170, 200, 240]),
            false => image::Rgb([235, 165, 95]),
        });
        let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 200);
        let class: Vec<Class> = (0..200 * 200u32)
            .map(|i: u32| match i / 200 < top(i % 200) {
                true => Class::Sky,
                false => Class::Wall,
            })
            .collect();
        let roofs = roof_line(&f, &class);
        assert_eq!(roofs.len(), 1, "{roofs:?}");
        let p = &roofs[0].polyline;
        assert!(p.iter().all(|q| q[0] <= 110.0), "up the slope: {p:?}");
        assert!(p[0][0] <= 5.0 && p[p.len() - 1][0] >= 90.0, "{p:?}");
    }

    #[test]
    fn a_roof_line_runs_under_the_eaves_tiles_a_plain_wall_top_keeps_its_edge() {
        // Sky to row 40 over a 200 x 200 wall; the left half has a row of
        // dark red tiles (rows 40..45) whose lower edge the water drips
        // from; the right half's top has a faint shade step (texture).
        let img = image::RgbImage::from_fn(200, 200, |x, y| match (x, y) {
            (_, 0..40) => image::Rgb([170, 200, 240]),
            (0..100, 40..45) => image::Rgb([140, 60, 30]),
            (100.., 40..44) => image::Rgb([222, 170, 100]),
            _ => image::Rgb([235, 165, 95]),
        });
        let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 200);
        let class: Vec<Class> = (0..200 * 200)
            .map(|i| {
                if i < 40 * 200 {
                    Class::Sky
                } else {
                    Class::Wall
                }
            })
            .collect();
        let roofs = roof_line(&f, &class);
        assert_eq!(roofs.len(), 1, "{roofs:?}");
        let row = |x: f32| {
            let p = &roofs[0].polyline;
            p.iter()
                .min_by(|a, b| (a[0] - x).abs().total_cmp(&(b[0] - x).abs()))
                .unwrap()[1]
        };
        assert!(
            (row(40.0) - 45.0).abs() <= 1.0,
            "under the tiles: {roofs:?}"
        );
        assert!((row(160.0) - 41.0).abs() <= 1.0, "at the sky: {roofs:?}");
    }
}
