//! The wall: luminance height field B, absorbed water w and deposited dirt D
//! on the simulation grid, with roughness (Chang eq. 1) and moisture
//! diffusion (eqs. 9-10).
//!
//! Arrays are padded by one pixel on every side. Padding is never part of the
//! region, so droplets stop there and stencils need no bounds checks.

use rayon::prelude::*;

/// Wall state on the padded simulation grid.
#[derive(Debug, Clone)]
pub struct Wall {
    /// Padded width (grid width + 2).
    pub stride: usize,
    /// Padded height (grid height + 2).
    pub rows: usize,
    /// 1.0 inside the region, 0.0 outside (and on the padding).
    pub inside: Vec<f32>,
    /// Number of region pixels among the 8 neighbours.
    neighbours: Vec<f32>,
    /// Luminance height field B in 0..255.
    pub b: Vec<f32>,
    /// Absorbed water w.
    pub w: Vec<f32>,
    /// Deposited dirt D.
    pub d: Vec<f32>,
    scratch_w: Vec<f32>,
    scratch_d: Vec<f32>,
}

impl Wall {
    /// A dry, clean wall of `width` x `height` grid pixels.
    /// `luma` and `region` are row-major, unpadded.
    pub fn new(width: usize, height: usize, luma: &[f32], region: &[bool]) -> Wall {
        let stride = width + 2;
        let rows = height + 2;
        let n = stride * rows;
        let mut inside = vec![0.0; n];
        let mut b = vec![0.0; n];
        for y in 0..rows {
            // Padding replicates the edge (eq. 1 "clamp the index").
            let sy = y.clamp(1, height) - 1;
            for x in 0..stride {
                let sx = x.clamp(1, width) - 1;
                b[y * stride + x] = luma[sy * width + sx];
                if (1..=height).contains(&y) && (1..=width).contains(&x) && region[sy * width + sx] {
                    inside[y * stride + x] = 1.0;
                }
            }
        }
        let mut neighbours = vec![0.0; n];
        for y in 1..rows - 1 {
            for x in 1..stride - 1 {
                let mut count = 0.0;
                for (dx, dy) in NEIGHBOURS {
                    count += inside[(y as isize + dy) as usize * stride + (x as isize + dx) as usize];
                }
                neighbours[y * stride + x] = count;
            }
        }
        Wall {
            stride,
            rows,
            inside,
            neighbours,
            b,
            w: vec![0.0; n],
            d: vec![0.0; n],
            scratch_w: vec![0.0; n],
            scratch_d: vec![0.0; n],
        }
    }

    /// Index of padded pixel (x, y).
    #[inline]
    pub fn idx(&self, x: usize, y: usize) -> usize {
        y * self.stride + x
    }

    /// Roughness (M_x, M_y) at padded pixel index `i` (Chang eq. 1).
    #[inline]
    pub fn roughness(&self, i: usize) -> (f32, f32) {
        let b = &self.b;
        // Chang eq. (1): M_x = |B(x,y) - (B(x+1,y) + B(x-1,y))/2| / 255
        let mx = (b[i] - 0.5 * (b[i + 1] + b[i - 1])).abs() / 255.0;
        // Chang eq. (1): M_y = |B(x,y) - B(x,y+1)| / 255
        let my = (b[i] - b[i + self.stride]).abs() / 255.0;
        (mx, my)
    }

    /// Total water in the wall.
    pub fn total_water(&self) -> f64 {
        self.w.par_iter().map(|&v| v as f64).sum()
    }

    /// Total dirt on the wall.
    pub fn total_dirt(&self) -> f64 {
        self.d.par_iter().map(|&v| v as f64).sum()
    }

    /// Runs `iterations` relaxation sweeps of Chang eqs. (9-10): each region
    /// pixel sends `tau` of its water to each of its region neighbours (8 at
    /// most) and receives the same from them. Dirt follows with rate
    /// `tau * coupling`. Both are conserved exactly up to rounding, and stay
    /// non-negative for `tau <= 1/8`.
    pub fn diffuse(&mut self, tau: f32, coupling: f32, iterations: u32) {
        let tau_d = tau * coupling;
        for _ in 0..iterations {
            relax(
                &self.w,
                &mut self.scratch_w,
                &self.inside,
                &self.neighbours,
                self.stride,
                tau,
            );
            std::mem::swap(&mut self.w, &mut self.scratch_w);
            if tau_d > 0.0 {
                relax(
                    &self.d,
                    &mut self.scratch_d,
                    &self.inside,
                    &self.neighbours,
                    self.stride,
                    tau_d,
                );
                std::mem::swap(&mut self.d, &mut self.scratch_d);
            }
        }
    }

    /// Applies the same dirt diffusion as [`Wall::diffuse`] to another field
    /// (a baseline that tells diffusion's share of a change from droplets').
    pub fn diffuse_like_dirt(&self, field: &mut Vec<f32>, scratch: &mut Vec<f32>, tau: f32, coupling: f32, iterations: u32) {
        let tau_d = tau * coupling;
        if tau_d <= 0.0 {
            return;
        }
        scratch.resize(field.len(), 0.0);
        for _ in 0..iterations {
            relax(field, scratch, &self.inside, &self.neighbours, self.stride, tau_d);
            std::mem::swap(field, scratch);
        }
    }

    /// Evaporation (the I_sun term of eq. 6) over the whole wall.
    pub fn evaporate(&mut self, amount: f32) {
        if amount > 0.0 {
            self.w.par_iter_mut().for_each(|w| *w = (*w - amount).max(0.0));
        }
    }
}

/// The 8-neighbourhood.
pub const NEIGHBOURS: [(isize, isize); 8] = [
    (-1, -1),
    (0, -1),
    (1, -1),
    (-1, 0),
    (1, 0),
    (-1, 1),
    (0, 1),
    (1, 1),
];

/// One sweep of eqs. (9-10), using that fields are zero outside the region:
/// `w'_p = w_p + tau * (sum of 8 neighbours - n_p * w_p)` for p in the region.
fn relax(src: &[f32], dst: &mut [f32], inside: &[f32], neighbours: &[f32], stride: usize, tau: f32) {
    let rows = src.len() / stride;
    dst[..stride].fill(0.0);
    dst[(rows - 1) * stride..].fill(0.0);
    dst[stride..(rows - 1) * stride]
        .par_chunks_mut(stride)
        .enumerate()
        .for_each(|(r, out)| {
            let y = r + 1;
            let up = &src[(y - 1) * stride..y * stride];
            let mid = &src[y * stride..(y + 1) * stride];
            let down = &src[(y + 1) * stride..(y + 2) * stride];
            let ins = &inside[y * stride..(y + 1) * stride];
            let nb = &neighbours[y * stride..(y + 1) * stride];
            out[0] = 0.0;
            out[stride - 1] = 0.0;
            for x in 1..stride - 1 {
                let s9 = up[x - 1] + up[x] + up[x + 1] + mid[x - 1] + mid[x] + mid[x + 1]
                    + down[x - 1]
                    + down[x]
                    + down[x + 1];
                let c = mid[x];
                // Chang eqs. (9-10): send tau*w to each neighbour, receive theirs.
                out[x] = ins[x] * (c + tau * (s9 - c - nb[x] * c));
            }
        });
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn wall(width: usize, height: usize, region: &[bool]) -> Wall {
        Wall::new(width, height, &vec![128.0; width * height], region)
    }

    /// Slow, obvious eqs. (9-10): every pixel sends tau*w to each region neighbour.
    fn reference_sweep(w: &[f32], inside: &[f32], stride: usize, tau: f32) -> Vec<f32> {
        let rows = w.len() / stride;
        let mut out = w.to_vec();
        for y in 1..rows - 1 {
            for x in 1..stride - 1 {
                let p = y * stride + x;
                if inside[p] == 0.0 {
                    continue;
                }
                for (dx, dy) in NEIGHBOURS {
                    let q = (y as isize + dy) as usize * stride + (x as isize + dx) as usize;
                    if inside[q] == 1.0 {
                        let sent = tau * w[p]; // eq. (9)
                        out[q] += sent;
                        out[p] -= sent; // eq. (10)
                    }
                }
            }
        }
        out
    }

    proptest! {
        #[test]
        fn sweep_matches_reference_and_conserves(
            water in proptest::collection::vec(0.0f32..10.0, 6 * 5),
            region in proptest::collection::vec(any::<bool>(), 6 * 5),
            tau in 0.0f32..=0.125,
        ) {
            let mut wl = wall(6, 5, &region);
            for y in 0..5 {
                for x in 0..6 {
                    let i = wl.idx(x + 1, y + 1);
                    wl.w[i] = if region[y * 6 + x] { water[y * 6 + x] } else { 0.0 };
                }
            }
            let before = wl.total_water();
            let want = reference_sweep(&wl.w, &wl.inside, wl.stride, tau);
            wl.diffuse(tau, 0.0, 1);
            for (a, b) in wl.w.iter().zip(&want) {
                prop_assert!((a - b).abs() < 1e-4, "{a} vs {b}");
                prop_assert!(*a >= 0.0);
            }
            prop_assert!((wl.total_water() - before).abs() < 1e-3 * (1.0 + before));
        }
    }

    #[test]
    fn diffusion_conserves_water_and_dirt_over_many_sweeps() {
        let (width, height) = (40, 30);
        let region: Vec<bool> = (0..width * height).map(|i| (i % width) > 5).collect();
        let mut wl = wall(width, height, &region);
        let i = wl.idx(20, 15);
        wl.w[i] = 100.0;
        wl.d[i] = 50.0;
        wl.diffuse(0.125, 0.5, 200);
        assert!((wl.total_water() - 100.0).abs() < 1e-2, "{}", wl.total_water());
        assert!((wl.total_dirt() - 50.0).abs() < 1e-2, "{}", wl.total_dirt());
        assert!(wl.w.iter().all(|&v| v >= 0.0));
        // Nothing leaks outside the region.
        for y in 1..=height {
            for x in 1..=6 {
                assert_eq!(wl.w[wl.idx(x, y)], 0.0);
            }
        }
        // Dirt spreads less than water with coupling 0.5.
        assert!(wl.d[i] / 50.0 > wl.w[i] / 100.0);
    }

    #[test]
    fn roughness_matches_eq1() {
        let luma = [10.0, 20.0, 60.0, 10.0, 30.0, 70.0];
        let wl = Wall::new(3, 2, &luma, &[true; 6]);
        let (mx, my) = wl.roughness(wl.idx(2, 1));
        assert!((mx - (20.0f32 - 35.0).abs() / 255.0).abs() < 1e-6);
        assert!((my - 10.0 / 255.0).abs() < 1e-6);
        // The edge clamps: B(x+1) at the right edge is B itself.
        let (mx, _) = wl.roughness(wl.idx(3, 1));
        assert!((mx - (60.0f32 - 40.0).abs() / 255.0).abs() < 1e-6);
    }
}
