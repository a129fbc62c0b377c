//! Where a streak can be seen: below its ledge, fading over a fall of a
//! metre or two (`how-facades-age.md`: "narrow at the release point, wider
//! and fainter over a fall of about 0.5 to 2 m").
//!
//! [choice, beyond Chang:] a droplet in Chang's model runs until it dries
//! or leaves the wall, however far that is in metres, so at facade scale a
//! streak would run the whole height of a building. The stain's coverage is
//! multiplied by `exp(-ln 10 (d / fall)^2)`, where d is the distance below
//! the nearest source above in the same column: a tenth of its darkness at
//! `fall`, none above the highest source.

use rayon::prelude::*;

use crate::field::RowMajor;

/// ln 10: the fade reaches a tenth at the fall length.
const LN_10: f32 = std::f32::consts::LN_10;

/// The fade map on a `width` x `height` grid for source polylines (grid
/// coordinates) and, optionally, a top-edge row per column; each source
/// reaches `reach` columns past its ends (water runs off a ledge's ends).
/// `fall` <= 0 gives 1 everywhere below a source.
pub fn fade(
    width: usize,
    height: usize,
    lines: &[Vec<(f32, f32)>],
    top_edge: Option<&[Option<usize>]>,
    fall: f32,
    reach: f32,
) -> RowMajor<f32> {
    // Per column, the rows of the sources crossing it.
    let mut rows: Vec<Vec<f32>> = vec![Vec::new(); width];
    for line in lines.iter().filter(|l| !l.is_empty()) {
        let mut line: Vec<[f32; 2]> = line.iter().map(|&(x, y)| [x, y]).collect();
        line.sort_by(|a, b| a[0].total_cmp(&b[0]));
        let x_lo = line[0][0] - reach;
        let x_hi = line[line.len() - 1][0] + reach;
        let first = x_lo.floor().max(0.0) as usize;
        let last = (x_hi.ceil().max(0.0) as usize).min(width.saturating_sub(1));
        for (x, column) in rows.iter_mut().enumerate().take(last + 1).skip(first) {
            column.push(row_at(&line, x as f32 + 0.5));
        }
    }
    if let Some(edge) = top_edge {
        for (column, row) in rows.iter_mut().zip(edge) {
            if let Some(y) = row {
                column.push(*y as f32);
            }
        }
    }
    rows.iter_mut()
        .for_each(|c| c.sort_by(|a, b| a.total_cmp(b)));
    let mut out = RowMajor::filled(width, height, 0.0);
    out.data_mut()
        .par_chunks_mut(width.max(1))
        .enumerate()
        .for_each(|(y, line)| {
            let y = y as f32 + 0.5;
            for (v, sources) in line.iter_mut().zip(&rows) {
                let above = sources.partition_point(|&s| s <= y);
                if above == 0 {
                    continue;
                }
                let d = y - sources[above - 1];
                *v = if fall > 0.0 {
                    (-LN_10 * (d / fall).powi(2)).exp()
                } else {
                    1.0
                };
            }
        });
    out
}

/// Streaks widen and fade as they fall: `narrow` becomes `narrow` near
/// its source, blending into `wide` (the same stain blurred more) at the
/// fall length, times the fade.
pub fn widen(narrow: &mut RowMajor<f32>, wide: &RowMajor<f32>, fade: &RowMajor<f32>) {
    narrow
        .data_mut()
        .par_iter_mut()
        .zip(wide.data())
        .zip(fade.data())
        .for_each(|((n, w), f)| {
            if *f <= 0.0 {
                *n = 0.0;
                return;
            }
            // How far down the fall: d / fall from f = exp(-ln 10 (d/fall)^2).
            let t = (-f.ln() / LN_10).max(0.0).sqrt().min(1.0);
            *n = (*n + (*w - *n) * t) * f;
        });
}

/// The row at column `x` of a polyline sorted by x, clamped to its ends.
fn row_at(pts: &[[f32; 2]], x: f32) -> f32 {
    let (first, last) = (pts[0], pts[pts.len() - 1]);
    crate::effects::habitat::row_at(pts, x).unwrap_or(match x <= first[0] {
        true => first[1],
        false => last[1],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nothing_above_the_source_and_a_tenth_at_the_fall() {
        let line = vec![(2.0, 10.0), (8.0, 10.0)];
        let f = fade(12, 60, &[line], None, 20.0, 1.0);
        assert_eq!(f.get(5, 5), 0.0, "above the ledge");
        assert!(f.get(5, 10) > 0.99, "just below it");
        assert!((f.get(5, 30) - 0.1).abs() < 0.02, "{}", f.get(5, 30));
        assert_eq!(f.get(11, 30), 0.0, "beside the ledge, past its reach");
        assert!(f.get(8, 30) > 0.05, "within the reach of its end");
    }

    #[test]
    fn a_lower_source_restarts_the_fall() {
        let lines = vec![
            vec![(0.0, 5.0), (10.0, 5.0)],
            vec![(0.0, 40.0), (10.0, 40.0)],
        ];
        let f = fade(10, 60, &lines, None, 10.0, 0.0);
        assert!(f.get(4, 35) < 0.01);
        assert!(f.get(4, 41) > 0.9, "{}", f.get(4, 41));
    }

    #[test]
    fn the_top_edge_is_a_source_per_column() {
        let edge = vec![Some(3), None];
        let f = fade(2, 10, &[], Some(&edge), 0.0, 0.0);
        assert_eq!(f.get(0, 2), 0.0);
        assert_eq!(f.get(0, 5), 1.0);
        assert_eq!(f.get(1, 5), 0.0);
    }
}
