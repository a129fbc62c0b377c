//! One run's rain read on another grid: a time-lapse's frames drawn at a
//! smaller size than the photo take the full-size run's rain, each of their
//! grid's cells reading the cell of the run's grid under it (nearest), so
//! the rain is simulated once and the frames show the output's streaks.

use std::sync::Arc;

use rayon::prelude::*;

use super::{Kept, RainLayer, RainOutput};
use crate::field::{Field, Order};
use crate::grid::Grid;

/// A run's rain and the walls it kept, on the run's grid.
#[derive(Debug, Clone)]
pub struct GivenRain {
    /// The rain after the last rainfall.
    pub out: Arc<RainOutput>,
    /// The walls kept after some of the rainfalls.
    pub kept: Vec<Arc<Kept>>,
    /// The run's grid.
    pub grid: Grid,
    /// The run's photo size.
    pub photo: (u32, u32),
}

/// For each cell of a grid, the cell of another under it.
struct Regrid {
    cols: Vec<usize>,
    rows: Vec<usize>,
}

impl Regrid {
    /// From `from` (on a `from_photo`-sized photo) to `to` (on `to_photo`).
    fn new(from: &Grid, from_photo: (u32, u32), to: &Grid, to_photo: (u32, u32)) -> Regrid {
        let (sx, sy) = (
            to_photo.0 as f32 / from_photo.0.max(1) as f32,
            to_photo.1 as f32 / from_photo.1.max(1) as f32,
        );
        let cols = (0..to.width)
            .map(|g| {
                let (px, _) = to.to_photo(g as f32 + 0.5, 0.5);
                let (fx, _) = from.to_grid(px / sx, 0.0);
                (fx.max(0.0) as usize).min(from.width - 1)
            })
            .collect();
        let rows = (0..to.height)
            .map(|g| {
                let (_, py) = to.to_photo(0.5, g as f32 + 0.5);
                let (_, fy) = from.to_grid(0.0, py / sy);
                (fy.max(0.0) as usize).min(from.height - 1)
            })
            .collect();
        Regrid { cols, rows }
    }

    /// `f` read on the other grid, its storage lines in parallel.
    fn field<O: Order>(&self, f: &Field<f32, O>) -> Field<f32, O> {
        let (w, h) = (self.cols.len(), self.rows.len());
        let (fw, fh, src) = (f.width(), f.height(), f.data());
        // Along a line, x runs in row-major storage and y in column-major.
        let x_runs = O::index(w, h, 1, 0) == 1;
        let mut data = vec![0.0; w * h];
        data.par_chunks_mut(O::line(w, h).max(1))
            .enumerate()
            .for_each(|(line, out)| {
                for (k, o) in out.iter_mut().enumerate() {
                    let (x, y) = if x_runs { (k, line) } else { (line, k) };
                    *o = src[O::index(fw, fh, self.cols[x], self.rows[y])];
                }
            });
        Field::new(w, h, data)
    }
}

impl GivenRain {
    /// The rain and kept walls on `grid` (of a `photo`-sized photo, the
    /// run's scaled). Droplet paths are left out (they are the run's).
    pub fn on(&self, grid: &Grid, photo: (u32, u32)) -> (Arc<RainOutput>, Vec<Arc<Kept>>) {
        let map = Regrid::new(&self.grid, self.photo, grid, photo);
        let o = &self.out;
        let out = RainOutput {
            layers: o
                .layers
                .par_iter()
                .map(|l| RainLayer {
                    deposit: map.field(&l.deposit),
                    stats: l.stats.clone(),
                    paths: Vec::new(),
                })
                .collect(),
            water: map.field(&o.water),
            dirt: map.field(&o.dirt),
            roughness_y: map.field(&o.roughness_y),
            washed: o.washed.as_ref().map(|w| map.field(w)),
        };
        let kept = self
            .kept
            .par_iter()
            .map(|k| {
                Arc::new(Kept {
                    rainfalls: k.rainfalls,
                    water: map.field(&k.water),
                    dirt: map.field(&k.dirt),
                    roughness_y: map.field(&k.roughness_y),
                    washed: k.washed.as_ref().map(|w| map.field(w)),
                })
            })
            .collect();
        (Arc::new(out), kept)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::RowMajor;

    #[test]
    fn each_cell_reads_the_cell_under_it() {
        // A 400 x 200 photo's grid at 100 x 50, read on the photo halved
        // (200 x 100, its own grid): cell (x, y) lies on (x / 2, y / 2).
        let from = Grid::new(400, 200, None, 100).unwrap();
        let to = Grid::new(200, 100, None, 0).unwrap();
        let map = Regrid::new(&from, (400, 200), &to, (200, 100));
        let f = RowMajor::from_fn(100, 50, |x, y| (y * 100 + x) as f32);
        let g = map.field(&f);
        assert_eq!((g.width(), g.height()), (200, 100));
        let c = map.field(&crate::field::ColumnMajor::from_fn(100, 50, |x, y| {
            f.get(x, y)
        }));
        for (x, y) in [(0, 0), (7, 3), (199, 99), (120, 41)] {
            assert_eq!(g.get(x, y), f.get(x / 2, y / 2), "({x}, {y})");
            assert_eq!(c.get(x, y), g.get(x, y), "column-major ({x}, {y})");
        }
    }
}
