//! The wall: luminance height field B, absorbed water w and deposited dirt D
//! on the simulation grid, with roughness (Chang eq. 1) and moisture
//! diffusion (eqs. 9-10).
//!
//! Arrays are padded by one pixel on every side. Padding is never part of the
//! region, so droplets stop there and stencils need no bounds checks.
//!
//! Storage is column-major: water runs down, so a droplet's path walks
//! through memory in order and each cache line serves many steps. The
//! diffusion stencil is symmetric, so it runs over columns as it would over
//! rows.
//!
//! The grid is larger than the caches, so passes over it are few: per-pixel
//! updates that follow a diffusion run on each finished [`Column`] while it
//! is still in cache (see [`Wall::diffuse`]).

use rayon::prelude::*;

use crate::effects::roughness;
use crate::field::RowMajor;

/// Wall state on the padded simulation grid.
#[derive(Debug, Clone)]
pub struct Wall {
    /// Padded width (grid width + 2).
    pub cols: usize,
    /// Padded height (grid height + 2); also the index step from x to x + 1.
    pub rows: usize,
    /// 1.0 inside the region, 0.0 outside (and on the padding).
    pub inside: Vec<f32>,
    /// 1 + the number of region pixels among the 8 neighbours (the pixel
    /// itself plus those it sends water to); 0 outside the region.
    kept: Vec<f32>,
    /// Per column: every pixel but the padding is in the region.
    whole: Vec<bool>,
    /// Luminance height field B in 0..255.
    pub b: Vec<f32>,
    /// Absorbed water w.
    pub w: Vec<f32>,
    /// Deposited dirt D.
    pub d: Vec<f32>,
    /// Dirt as it would be without the current rainfall's droplets: set at
    /// the start of a rainfall, then diffused and topped up like D. D minus
    /// this is what the droplets moved.
    pub baseline: Vec<f32>,
    /// Dirt carried over into the current rainfall (eqs. 13-14), returned
    /// to the wall over its diffusion rounds.
    pub carry: Vec<f32>,
}

/// One column of the wall's per-pixel state (storage order), handed to the
/// per-pixel passes of [`Wall::columns`] and [`Wall::diffuse`], with the
/// column of an optional unpadded output grid.
#[derive(Debug)]
pub struct Column<'a> {
    /// Padded column index.
    pub x: usize,
    /// [`Wall::inside`].
    pub inside: &'a [f32],
    /// [`Wall::w`].
    pub w: &'a mut [f32],
    /// [`Wall::d`].
    pub d: &'a mut [f32],
    /// [`Wall::baseline`].
    pub baseline: &'a mut [f32],
    /// [`Wall::carry`].
    pub carry: &'a mut [f32],
    /// The column (without padding) of the pass's output grid, column-major;
    /// empty when the pass has none.
    pub output: &'a mut [f32],
}

/// The columns of the wall one droplet queue may touch: water `w` and dirt
/// `d` for storage indices `first..first + w.len()`, and the height field
/// and region of the whole wall.
pub struct Patch<'a> {
    /// Height field B of the whole padded wall, column-major.
    pub b: &'a [f32],
    /// 1 inside the region, per padded pixel.
    pub inside: &'a [f32],
    /// Padded rows: the index step from one column to the next.
    pub rows: usize,
    /// Storage index of the patch's first pixel.
    pub first: usize,
    /// Water w of the patch's columns.
    pub w: &'a mut [f32],
    /// Dirt D of the patch's columns.
    pub d: &'a mut [f32],
}

impl Wall {
    /// A dry, clean wall on the grid of `luma` and `region` (the same size).
    pub fn new(luma: &RowMajor<f32>, region: &RowMajor<bool>) -> Wall {
        debug_assert!(luma.same_size(region));
        let (width, height) = (luma.width(), luma.height());
        let (luma, region) = (luma.data(), region.data());
        let cols = width + 2;
        let rows = height + 2;
        let n = cols * rows;
        let mut inside = vec![0.0; n];
        let mut b = vec![0.0; n];
        b.par_chunks_mut(rows)
            .zip(inside.par_chunks_mut(rows))
            .enumerate()
            .for_each(|(x, (b, inside))| {
                // Padding replicates the edge (eq. 1 "clamp the index").
                let sx = x.clamp(1, width) - 1;
                let interior = (1..=width).contains(&x);
                for (y, (b, inside)) in b.iter_mut().zip(inside).enumerate() {
                    let sy = y.clamp(1, height) - 1;
                    *b = luma[sy * width + sx];
                    if interior && (1..=height).contains(&y) && region[sy * width + sx] {
                        *inside = 1.0;
                    }
                }
            });
        let mut kept = vec![0.0; n];
        kept[rows..(cols - 1) * rows]
            .par_chunks_mut(rows)
            .enumerate()
            .for_each(|(k, kept)| {
                let x = k + 1;
                for (y, kept) in kept.iter_mut().enumerate().take(rows - 1).skip(1) {
                    if inside[x * rows + y] == 0.0 {
                        continue;
                    }
                    let mut count = 1.0;
                    for (dx, dy) in NEIGHBOURS {
                        let (nx, ny) = ((x as isize + dx) as usize, (y as isize + dy) as usize);
                        count += inside[nx * rows + ny];
                    }
                    *kept = count;
                }
            });
        let whole = kept
            .chunks(rows)
            .map(|column| column[1..rows - 1].iter().all(|&k| k > 0.0))
            .collect();
        Wall {
            cols,
            rows,
            inside,
            kept,
            whole,
            b,
            w: vec![0.0; n],
            d: vec![0.0; n],
            baseline: vec![0.0; n],
            carry: vec![0.0; n],
        }
    }

    /// Index of padded pixel (x, y).
    #[inline]
    pub fn idx(&self, x: usize, y: usize) -> usize {
        x * self.rows + y
    }

    /// Roughness (M_x, M_y) at padded pixel index `i` (Chang eq. 1).
    #[inline]
    pub fn roughness(&self, i: usize) -> (f32, f32) {
        roughness::at(&self.b, i, self.rows, 1)
    }

    /// The wall cut at padded columns `bounds` (ascending, from 0 to
    /// [`Wall::cols`]) into patches droplets can run in side by side.
    pub fn patches(&mut self, bounds: &[usize]) -> Vec<Patch<'_>> {
        let rows = self.rows;
        let (mut w, mut d) = (&mut self.w[..], &mut self.d[..]);
        bounds
            .windows(2)
            .map(|pair| {
                let len = (pair[1] - pair[0]) * rows;
                let (patch_w, rest_w) = std::mem::take(&mut w).split_at_mut(len);
                let (patch_d, rest_d) = std::mem::take(&mut d).split_at_mut(len);
                (w, d) = (rest_w, rest_d);
                Patch {
                    b: &self.b,
                    inside: &self.inside,
                    rows,
                    first: pair[0] * rows,
                    w: patch_w,
                    d: patch_d,
                }
            })
            .collect()
    }

    /// Total water in the wall.
    pub fn total_water(&self) -> f64 {
        self.w.par_iter().map(|&v| v as f64).sum()
    }

    /// Total dirt on the wall.
    pub fn total_dirt(&self) -> f64 {
        self.d.par_iter().map(|&v| v as f64).sum()
    }

    /// Runs `f` on every column inside the padding, in parallel; returns its
    /// results in column order. `output`, if given, is an unpadded grid in
    /// column-major order whose columns the passes receive.
    pub fn columns<R, F>(&mut self, output: Option<&mut [f32]>, f: F) -> Vec<R>
    where
        R: Send,
        F: Fn(Column) -> R + Sync,
    {
        self.fields().chunks(output, |chunk| chunk.columns(&f))
    }

    /// Runs `iterations` relaxation sweeps of Chang eqs. (9-10): each region
    /// pixel sends `tau` of its water to each of its region neighbours (8 at
    /// most) and receives the same from them. Dirt, and the dirt
    /// [`Wall::baseline`], follow with rate `tau * coupling`. All are conserved
    /// exactly up to rounding, and stay non-negative for `tau <= 1/8`.
    ///
    /// Then `finish` runs on each finished column, as in [`Wall::columns`]
    /// (with `output`), while the column is still in cache.
    ///
    /// Temporal blocking: each chunk of columns is computed through all
    /// iterations from a slightly wider window of input columns, in buffers
    /// that stay in cache, so each field crosses memory once per call, not
    /// once per iteration. The result is identical to sweeping the whole
    /// field each time.
    pub fn diffuse<R, F>(
        &mut self,
        tau: f32,
        coupling: f32,
        iterations: u32,
        output: Option<&mut [f32]>,
        finish: F,
    ) -> Vec<R>
    where
        R: Send,
        F: Fn(Column) -> R + Sync,
    {
        if iterations == 0 {
            return self.columns(output, finish);
        }
        let sweep = Sweep {
            kept: &self.kept,
            whole: &self.whole,
            stride: self.rows,
            iterations: iterations as usize,
        };
        // Each chunk reads the lines around it as they were before any chunk
        // wrote its own.
        let [w_halos, d_halos, b_halos] =
            [&self.w, &self.d, &self.baseline].map(|field| sweep.halos(field));
        let tau_d = tau * coupling;
        let fields = Fields {
            rows: self.rows,
            w: &mut self.w,
            d: &mut self.d,
            baseline: &mut self.baseline,
            carry: &mut self.carry,
            inside: &self.inside,
        };
        fields.chunks(output, |chunk| {
            let (a, c) = (chunk.first, (chunk.first - 1) / CHUNK);
            let mut buffers = Vec::new();
            sweep.run(chunk.w, &w_halos[c], tau, a, &mut buffers);
            sweep.run(chunk.d, &d_halos[c], tau_d, a, &mut buffers);
            sweep.run(chunk.baseline, &b_halos[c], tau_d, a, &mut buffers);
            chunk.columns(&finish)
        })
    }

    /// The per-pixel fields the column passes work on.
    fn fields(&mut self) -> Fields<'_> {
        Fields {
            rows: self.rows,
            w: &mut self.w,
            d: &mut self.d,
            baseline: &mut self.baseline,
            carry: &mut self.carry,
            inside: &self.inside,
        }
    }
}

/// The wall's per-pixel fields, borrowed apart from the rest of the wall.
struct Fields<'a> {
    rows: usize,
    w: &'a mut [f32],
    d: &'a mut [f32],
    baseline: &'a mut [f32],
    carry: &'a mut [f32],
    inside: &'a [f32],
}

/// [`CHUNK`] columns (fewer at the end) of every per-pixel field, from
/// padded column `first`, with the same columns of an output grid.
struct Chunk<'a> {
    first: usize,
    rows: usize,
    w: &'a mut [f32],
    d: &'a mut [f32],
    baseline: &'a mut [f32],
    carry: &'a mut [f32],
    inside: &'a [f32],
    output: &'a mut [f32],
}

impl Fields<'_> {
    /// Runs `f` on the chunks of columns inside the padding, in parallel;
    /// returns their results in column order.
    fn chunks<R, F>(self, output: Option<&mut [f32]>, f: F) -> Vec<R>
    where
        R: Send,
        F: Fn(Chunk) -> Vec<R> + Sync,
    {
        let rows = self.rows;
        let cols = self.w.len() / rows;
        let body = rows..(cols - 1) * rows;
        let span = CHUNK * rows;
        let results: Vec<Vec<R>> = self.w[body.clone()]
            .par_chunks_mut(span)
            .zip(self.d[body.clone()].par_chunks_mut(span))
            .zip(self.baseline[body.clone()].par_chunks_mut(span))
            .zip(self.carry[body.clone()].par_chunks_mut(span))
            .zip(self.inside[body].par_chunks(span))
            .zip(output_columns(output, cols - 2, rows - 2, CHUNK))
            .enumerate()
            .map(|(c, (((((w, d), baseline), carry), inside), output))| {
                f(Chunk {
                    first: 1 + c * CHUNK,
                    rows,
                    w,
                    d,
                    baseline,
                    carry,
                    inside,
                    output,
                })
            })
            .collect();
        results.into_iter().flatten().collect()
    }
}

impl Chunk<'_> {
    /// `f` on each of the chunk's columns, in order.
    fn columns<R>(self, f: &impl Fn(Column) -> R) -> Vec<R> {
        let rows = self.rows;
        let n = self.w.len() / rows;
        self.w
            .chunks_mut(rows)
            .zip(self.d.chunks_mut(rows))
            .zip(self.baseline.chunks_mut(rows))
            .zip(self.carry.chunks_mut(rows))
            .zip(self.inside.chunks(rows))
            .zip(output_columns(Some(self.output), n, rows - 2, 1))
            .zip(self.first..)
            .map(|((((((w, d), baseline), carry), inside), output), x)| {
                f(Column {
                    x,
                    inside,
                    w,
                    d,
                    baseline,
                    carry,
                    output,
                })
            })
            .collect()
    }
}

/// `output` (an unpadded column-major grid of `cols` columns of `height`)
/// cut into pieces of `per` columns, or as many empty pieces without one
/// (`None` or empty).
fn output_columns(
    output: Option<&mut [f32]>,
    cols: usize,
    height: usize,
    per: usize,
) -> Vec<&mut [f32]> {
    match output {
        Some(out) if !out.is_empty() => out.chunks_mut(per * height).collect(),
        _ => (0..cols.div_ceil(per))
            .map(|_| <&mut [f32]>::default())
            .collect(),
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

/// Columns per work item of [`Wall::diffuse`]: small enough that a chunk's
/// intermediate iterations and its three finished fields stay in cache.
const CHUNK: usize = 32;

/// `iterations` sweeps of eqs. (9-10) over one field, using that fields are
/// zero outside the region: `w'_p = w_p + tau * (sum of 8 neighbours - n_p
/// w_p)` for p in the region. `stride` is the length of a contiguous line (a
/// column here); the stencil is symmetric, so which axis is contiguous does
/// not matter.
struct Sweep<'a> {
    kept: &'a [f32],
    whole: &'a [bool],
    stride: usize,
    iterations: usize,
}

/// The lines a chunk of [`Sweep::run`] reads beyond its own: before and
/// after it.
type Halo = (Vec<f32>, Vec<f32>);

impl Sweep<'_> {
    /// The lines of the window around chunk `a..b` outside it.
    fn window(&self, a: usize) -> (usize, usize, usize) {
        let lines = self.kept.len() / self.stride;
        let b = (a + CHUNK).min(lines - 1);
        (
            a.saturating_sub(self.iterations),
            b,
            (b + self.iterations).min(lines),
        )
    }

    /// Every chunk's [`Halo`] in `field`.
    fn halos(&self, field: &[f32]) -> Vec<Halo> {
        let lines = self.kept.len() / self.stride;
        (1..lines - 1)
            .step_by(CHUNK)
            .map(|a| {
                let (lo, b, hi) = self.window(a);
                let s = self.stride;
                (field[lo * s..a * s].to_vec(), field[b * s..hi * s].to_vec())
            })
            .collect()
    }

    /// The sweeps of the chunk `lines` (its lines, from line `a`), in place,
    /// with its `halo`.
    fn run(&self, lines: &mut [f32], halo: &Halo, tau: f32, a: usize, buffers: &mut Vec<f32>) {
        let (stride, iterations) = (self.stride, self.iterations);
        let (lo, b, hi) = self.window(a);
        let span = (hi - lo) * stride;
        buffers.clear();
        buffers.extend_from_slice(&halo.0);
        buffers.extend_from_slice(lines);
        buffers.extend_from_slice(&halo.1);
        buffers.resize(2 * span, 0.0);
        let (mut prev, mut next) = buffers.split_at_mut(span);
        let mut sums = Vec::with_capacity(stride);
        let last_line = self.kept.len() / stride - 1;
        for k in 1..=iterations {
            let reach = iterations - k;
            let first = a.saturating_sub(reach).max(1);
            let last = (b + reach).min(last_line);
            for j in first..last {
                let kept = &self.kept[j * stride..(j + 1) * stride];
                let window = &prev[(j - 1 - lo) * stride..(j + 2 - lo) * stride];
                let dst = if k == iterations {
                    &mut lines[(j - a) * stride..(j - a + 1) * stride]
                } else {
                    &mut next[(j - lo) * stride..(j - lo + 1) * stride]
                };
                relax_line(window, kept, self.whole[j], dst, tau, &mut sums);
            }
            std::mem::swap(&mut prev, &mut next);
        }
    }
}

/// Eqs. (9-10) for one line; `src` holds the line before, the line and the
/// line after, `kept` is [`Wall::kept`] for the line (`whole` when all of it
/// but the padding is in the region), `sums` a buffer.
#[inline]
fn relax_line(
    src: &[f32],
    kept: &[f32],
    whole: bool,
    out: &mut [f32],
    tau: f32,
    sums: &mut Vec<f32>,
) {
    let stride = kept.len();
    let (up, mid, down) = (&src[..stride], &src[stride..2 * stride], &src[2 * stride..]);
    // The 3x3 sum as three sums across the lines, added along the line.
    sums.clear();
    sums.extend(up.iter().zip(mid).zip(down).map(|((u, m), d)| u + m + d));
    out[0] = 0.0;
    out[stride - 1] = 0.0;
    // Equal-length slices let the compiler drop bounds checks and vectorise.
    let n = stride - 2;
    let (kept, out, c) = (&kept[1..=n], &mut out[1..=n], &mid[1..=n]);
    let (s0, s1, s2) = (&sums[..n], &sums[1..=n], &sums[2..]);
    // Chang eqs. (9-10): send tau*w to each region neighbour, receive
    // theirs: w + tau (sum of the 8 - n w) = w + tau (s9 - (1 + n) w).
    let relaxed = |i: usize| c[i] + tau * ((s0[i] + s1[i] + s2[i]) - kept[i] * c[i]);
    if whole {
        for (i, out) in out.iter_mut().enumerate() {
            *out = relaxed(i);
        }
    } else {
        for (i, out) in out.iter_mut().enumerate() {
            *out = if kept[i] == 0.0 { 0.0 } else { relaxed(i) };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn wall(width: usize, height: usize, region: &[bool]) -> Wall {
        Wall::new(
            &RowMajor::filled(width, height, 128.0),
            &RowMajor::new(width, height, region.to_vec()),
        )
    }

    /// Slow, obvious eqs. (9-10): every pixel sends tau*w to each region neighbour.
    fn reference_sweep(wl: &Wall, tau: f32) -> Vec<f32> {
        let (w, inside) = (&wl.w, &wl.inside);
        let mut out = w.to_vec();
        for y in 1..wl.rows - 1 {
            for x in 1..wl.cols - 1 {
                let p = wl.idx(x, y);
                if inside[p] == 0.0 {
                    continue;
                }
                for (dx, dy) in NEIGHBOURS {
                    let q = wl.idx((x as isize + dx) as usize, (y as isize + dy) as usize);
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
            let want = reference_sweep(&wl, tau);
            wl.diffuse(tau, 0.0, 1, None, |_| ());
            for (a, b) in wl.w.iter().zip(&want) {
                prop_assert!((a - b).abs() < 1e-4, "{a} vs {b}");
                prop_assert!(*a >= 0.0);
            }
            prop_assert!((wl.total_water() - before).abs() < 1e-3 * (1.0 + before));
        }
    }

    #[test]
    fn blocked_sweeps_equal_repeated_single_sweeps() {
        // Wider than several chunks, with an irregular region.
        let (width, height) = (150, 9);
        let region: Vec<bool> = (0..width * height).map(|i| (i * 7919) % 11 != 0).collect();
        let mut a = wall(width, height, &region);
        for (i, (w, ins)) in a.w.iter_mut().zip(&a.inside).enumerate() {
            *w = ins * ((i * 37) % 101) as f32;
        }
        a.d.clone_from(&a.w);
        let mut b = a.clone();
        a.diffuse(0.11, 0.5, 5, None, |_| ());
        for _ in 0..5 {
            b.diffuse(0.11, 0.5, 1, None, |_| ());
        }
        for (x, y) in a.w.iter().zip(&b.w).chain(a.d.iter().zip(&b.d)) {
            assert!((x - y).abs() < 1e-4, "{x} vs {y}");
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
        wl.diffuse(0.125, 0.5, 200, None, |_| ());
        assert!(
            (wl.total_water() - 100.0).abs() < 1e-2,
            "{}",
            wl.total_water()
        );
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
    fn roughness_is_eq1_with_the_edge_clamped_by_the_padding() {
        let luma = RowMajor::new(3, 2, vec![10.0, 20.0, 60.0, 10.0, 30.0, 70.0]);
        let wl = Wall::new(&luma, &RowMajor::filled(3, 2, true));
        let (mx, my) = wl.roughness(wl.idx(2, 1));
        assert!((mx - (20.0f32 - 35.0).abs() / 255.0).abs() < 1e-6);
        assert!((my - 10.0 / 255.0).abs() < 1e-6);
        // The edge clamps: B(x+1) at the right edge is B itself.
        let (mx, _) = wl.roughness(wl.idx(3, 1));
        assert!((mx - (60.0f32 - 40.0).abs() / 255.0).abs() < 1e-6);
    }
}
