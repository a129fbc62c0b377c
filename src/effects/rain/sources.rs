//! Where droplets start: the top edge of the region and user source lines.

/// One water source on the padded grid.
#[derive(Debug, Clone)]
pub enum Source {
    /// The region's top edge: for each grid column, the first region row.
    TopEdge(Vec<(f32, f32)>),
    /// A polyline (a sill or a cornice); droplets start just below it.
    Line {
        /// Vertices, padded grid coordinates.
        points: Vec<(f32, f32)>,
        /// Cumulative length at each vertex.
        lengths: Vec<f32>,
    },
}

impl Source {
    /// A polyline source.
    pub fn line(points: Vec<(f32, f32)>) -> Source {
        let mut lengths = vec![0.0];
        for pair in points.windows(2) {
            let d = ((pair[1].0 - pair[0].0).powi(2) + (pair[1].1 - pair[0].1).powi(2)).sqrt();
            lengths.push(lengths.last().copied().unwrap_or(0.0) + d);
        }
        Source::Line { points, lengths }
    }

    /// Length along which droplets start, in grid pixels.
    pub fn length(&self) -> f32 {
        match self {
            Source::TopEdge(cols) => cols.len() as f32,
            Source::Line { lengths, .. } => lengths.last().copied().unwrap_or(0.0),
        }
    }

    /// The start point at arc length `u` (clamped into the source).
    pub fn point(&self, u: f32) -> (f32, f32) {
        match self {
            Source::TopEdge(cols) => {
                let u = u.clamp(0.0, cols.len() as f32 - 1e-3);
                let (x, y) = cols[u as usize];
                (x + u.fract(), y + 0.5)
            }
            Source::Line { points, lengths } => {
                let total = lengths.last().copied().unwrap_or(0.0);
                let u = u.clamp(0.0, total);
                let k = lengths
                    .partition_point(|&l| l <= u)
                    .clamp(1, points.len() - 1);
                let (a, b) = (points[k - 1], points[k]);
                let seg = (lengths[k] - lengths[k - 1]).max(1e-6);
                let t = ((u - lengths[k - 1]) / seg).clamp(0.0, 1.0);
                // One pixel below the line: water drips off the ledge's lower edge.
                (a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t + 1.0)
            }
        }
    }
}

/// The region's top edge on the padded grid: (x, first region row) per column.
pub fn top_edge(wall: &Wall) -> Vec<(f32, f32)> {
    (1..wall.cols - 1)
        .filter_map(|x| {
            (1..wall.rows - 1)
                .find(|&y| wall.inside[wall.idx(x, y)] > 0.0)
                .map(|y| (x as f32, y as f32))
        })
        .collect()
}

use super::wall::Wall;

/// Picks the source at cumulative-length position `u` in `0..total`.
pub fn pick(sources: &[Source], u: f32) -> (usize, f32) {
    let mut u = u;
    for (i, s) in sources.iter().enumerate() {
        if u < s.length() || i + 1 == sources.len() {
            return (i, u.min(s.length()));
        }
        u -= s.length();
    }
    (0, 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::RowMajor;

    #[test]
    fn line_points_lie_just_below_the_polyline() {
        let s = Source::line(vec![(10.0, 20.0), (30.0, 20.0), (30.0, 40.0)]);
        assert_eq!(s.length(), 40.0);
        assert_eq!(s.point(5.0), (15.0, 21.0));
        assert_eq!(s.point(30.0), (30.0, 31.0));
        assert_eq!(s.point(-3.0), (10.0, 21.0), "clamped to the start");
        assert_eq!(s.point(99.0), (30.0, 41.0), "clamped to the end");
    }

    #[test]
    fn top_edge_follows_the_region() {
        // 3x3 grid; column 1 starts one row lower.
        let region = [true, false, true, true, true, false, false, false, true];
        let wall = Wall::new(
            &RowMajor::filled(3, 3, 0.0),
            &RowMajor::new(3, 3, region.to_vec()),
        );
        assert_eq!(top_edge(&wall), vec![(1.0, 1.0), (2.0, 2.0), (3.0, 1.0)]);
    }

    #[test]
    fn pick_splits_by_length() {
        let s = vec![
            Source::line(vec![(0.0, 0.0), (10.0, 0.0)]),
            Source::line(vec![(0.0, 5.0), (30.0, 5.0)]),
        ];
        assert_eq!(pick(&s, 4.0), (0, 4.0));
        assert_eq!(pick(&s, 12.0), (1, 2.0));
        assert_eq!(pick(&s, 100.0), (1, 30.0));
    }
}
