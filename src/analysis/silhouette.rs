//! Where a ledge runs into the silhouette of a building in front.
//!
//! Where a building stands in front of another, a ledge of the one behind
//! ends at the front one's edge; when that edge slants in under the ledge
//! (a gable's slope), the rain run from the ledge's last columns falls on
//! the front building and is cut there on a vertical (LabelMeFacade
//! IMG_6469: a cornice behind a gable, a block of stain on the gable's
//! brick, named by three blind critics; `how-facades-age.md`: a streak
//! runs down the face it leaves, never across onto another). The rule
//! first measured (BENCHMARKS.md, thirtieth pass, helper cross31) took a
//! straight, leaning luma edge through the ledge's end for a silhouette;
//! it also cut ledges at tree branches, a fire escape's stringer, a
//! downpipe's bracket and the edges of CMP's black and grey fill round a
//! rectified facade. [choice: an edge is a silhouette only where it also
//! parts two surfaces: (1) the strips either side of it under the ledge
//! differ in colour ([`CHROMA`]; another building's brick or render, while
//! a branch, a stringer or a bracket has the same wall on both sides),
//! (2) the far side is textured ([`TEXTURE`]; a front building is a
//! surface, a rectification fill is flat), and (3) the ledge's own step
//! does not carry on past the edge ([`CARRY`]; a head goes on behind a
//! branch or a stringer, not onto the front building).]

/// How far above and below a ledge's end a silhouette must run, and how
/// far below it the end is taken back to, as a share of the height: about
/// the first storey's worth of rain run under a cornice (IMG_6469: 33 of
/// 683 rows to the head below).
const RUN: f32 = 0.05;
/// Least inward lean (columns per row) of a silhouette under a ledge's
/// end; plumb edges leaning in the photo's perspective stay under it
/// (jambs, pipes and building sides leave no wedge). At most 1.
const LEAN: f32 = 0.2;
/// Least horizontal luma step of a silhouette's pixel (the ledges'
/// `MIN_STEP` / 1.5).
const EDGE: f32 = 0.03;
/// The strips either side of a silhouette, columns from it: clear of the
/// edge's own blur and of a thin thing's width (a stringer, a branch).
const STRIP: std::ops::RangeInclusive<i64> = 4..=12;
/// Least difference of the two strips' mean chromaticity (r, g, b over
/// their sum; sum of the three absolute differences) [choice: 0.045: on
/// IMG_6469's gable 0.056 and 0.083, at two depth steps on davis 0.080
/// and 0.104; a branch over a head 0.007 and 0.027, a downpipe's bracket
/// 0.023, a grey fill's border on CMP 0.017 to 0.037].
const CHROMA: f32 = 0.045;
/// Least mean luma gradient (|dx| + |dy|, 3x3-smoothed luma) on the far
/// strip [choice: 0.006: IMG_6469's gable brick 0.013, CMP's black fill
/// 0.002 to 0.003].
const TEXTURE: f32 = 0.006;
/// The ledge carries on past the edge when the step across its row just
/// beyond the edge has its sign and at least this share of its size on
/// its last columns [choice: 0.5: a fire escape's stringer on CMP 0.89, a
/// branch over a head 1.9; IMG_6469's gable 0.01 to 0.04].
const CARRY: f32 = 0.5;

/// An image to measure: smoothed luma `l` and the `rgb` planes, `w` x `h`.
pub(super) struct Planes<'a> {
    pub(super) l: &'a [f32],
    pub(super) rgb: &'a [Vec<f32>; 3],
    pub(super) w: usize,
    pub(super) h: usize,
}

impl Planes<'_> {
    fn idx(&self, x: i64, y: i64) -> Option<usize> {
        let inside = x >= 0 && y >= 0 && (x as usize) < self.w && (y as usize) < self.h;
        inside.then(|| y as usize * self.w + x as usize)
    }

    /// Horizontal luma step at (x, y), 0 off the image.
    fn gx(&self, x: i64, y: i64) -> f32 {
        match (self.idx(x - 1, y), self.idx(x + 1, y)) {
            (Some(a), Some(b)) => (self.l[b] - self.l[a]).abs(),
            _ => 0.0,
        }
    }

    /// Vertical luma step (below minus above, 2 rows each way) at (x, y).
    fn gy(&self, x: i64, y: i64) -> Option<f32> {
        Some(self.l[self.idx(x, y + 2)?] - self.l[self.idx(x, y - 2)?])
    }
}

/// A straight line x = `mx` + `lean` (y - `my`).
#[derive(Clone, Copy, Debug)]
struct Line {
    mx: f32,
    my: f32,
    lean: f32,
}

impl Line {
    fn x_at(&self, y: f32) -> f32 {
        self.mx + self.lean * (y - self.my)
    }
}

/// The column the ledge's end at column `end` (its line at row `y`, the
/// right end when `right`) is taken back to: where the silhouette of a
/// surface in front slanting in under it lies [`RUN`] of the height below
/// the ledge; None when no such silhouette runs through the end.
pub(super) fn end_before(p: &Planes, end: f32, y: f32, right: bool) -> Option<f32> {
    let rows = (RUN * p.h as f32).ceil() as i64;
    let row = y.round() as i64;
    let line = edge_through(p, end.round() as i64, row, rows, right)?;
    let out = if right { 1 } else { -1 };
    (two_surfaces(p, &line, row, rows, out) && !carries_on(p, &line, end, row, out))
        .then(|| line.x_at((row + rows) as f32))
}

/// The straight edge through the ledge's end (found 3 rows under its
/// line, where the ledge's own step does not hide it), held over 80% of
/// the `rows` above and below it, within 1 px (rms) of one line leaning
/// inward by [`LEAN`] to 1 column per row.
fn edge_through(p: &Planes, end: i64, row: i64, rows: i64, right: bool) -> Option<Line> {
    let y0 = row + 3;
    let x0 = (end - 3..=end + 3)
        .max_by(|&a, &b| p.gx(a, y0).total_cmp(&p.gx(b, y0)))
        .filter(|&x| p.gx(x, y0) >= EDGE)?;
    let mut pts = follow(p, x0, y0, -1, rows + 3)?;
    pts.extend(follow(p, x0, y0, 1, rows - 3)?);
    let n = pts.len() as f32;
    let (my, mx) = pts
        .iter()
        .fold((0.0, 0.0), |a, q| (a.0 + q.0 / n, a.1 + q.1 / n));
    let (vyy, vyx) = pts.iter().fold((0.0, 0.0), |a, q| {
        (a.0 + (q.0 - my).powi(2), a.1 + (q.0 - my) * (q.1 - mx))
    });
    if vyy <= 0.0 {
        return None;
    }
    let line = Line {
        mx,
        my,
        lean: vyx / vyy,
    };
    let spread = pts
        .iter()
        .map(|q| (q.1 - line.x_at(q.0)).powi(2))
        .sum::<f32>()
        / n;
    let inward = if right { -line.lean } else { line.lean };
    ((LEAN..=1.0).contains(&inward) && spread <= 1.0).then_some(line)
}

/// Follows the strongest step row by row (one column of drift per row,
/// one more per row missed, up to 3) from (`x0`, `y0`) towards `dir` for
/// `n` rows: the (row, column) points held, when they are 80% of them.
fn follow(p: &Planes, x0: i64, y0: i64, dir: i64, n: i64) -> Option<Vec<(f32, f32)>> {
    let (mut cx, mut missed, mut held) = (x0, 0, Vec::new());
    for k in 1..=n {
        let (y, r) = (y0 + dir * k, 1 + missed.min(2));
        let best = (cx - r..=cx + r)
            .max_by(|&a, &b| p.gx(a, y).total_cmp(&p.gx(b, y)))
            .filter(|&x| p.gx(x, y) >= EDGE);
        match best {
            Some(x) => {
                (cx, missed) = (x, 0);
                held.push((y as f32, x as f32));
            }
            None => missed += 1,
        }
    }
    (held.len() as f32 >= 0.8 * n.max(1) as f32).then_some(held)
}

/// Whether the strips either side of `line` under the ledge (from 2 rows
/// under `row` to `rows` under it) are two surfaces: their colours differ by
/// [`CHROMA`] and the far one (towards `out`) has [`TEXTURE`].
fn two_surfaces(p: &Planes, line: &Line, row: i64, rows: i64, out: i64) -> bool {
    // Per side: summed chromaticity, summed gradient, count.
    let mut sides = [([0f32; 3], 0f32, 0f32); 2];
    for y in row + 2..row + rows {
        let xs = line.x_at(y as f32);
        for d in STRIP {
            for (side, s) in [(0, out), (1, -out)] {
                let x = (xs + (s * d) as f32).round() as i64;
                let Some(i) = p.idx(x, y) else { continue };
                let c = [p.rgb[0][i], p.rgb[1][i], p.rgb[2][i]];
                let sum = (c[0] + c[1] + c[2]).max(1e-3);
                let g = p.gx(x, y)
                    + match (p.idx(x, y - 1), p.idx(x, y + 1)) {
                        (Some(a), Some(b)) => (p.l[b] - p.l[a]).abs(),
                        _ => 0.0,
                    };
                let acc = &mut sides[side];
                (0..3).for_each(|k| acc.0[k] += c[k] / sum);
                acc.1 += g;
                acc.2 += 1.0;
            }
        }
    }
    let [far, near] = sides;
    if far.2 == 0.0 || near.2 == 0.0 {
        return false;
    }
    let chroma: f32 = (0..3)
        .map(|k| (far.0[k] / far.2 - near.0[k] / near.2).abs())
        .sum();
    chroma >= CHROMA && far.1 / far.2 >= TEXTURE
}

/// Whether the ledge's step across its row (at `row`) carries on past
/// `line`: just beyond it (the strip towards `out`) the step has the sign
/// of the ledge's last columns' and [`CARRY`] of their size.
fn carries_on(p: &Planes, line: &Line, end: f32, row: i64, out: i64) -> bool {
    let mean = |v: Vec<f32>| (!v.is_empty()).then(|| v.iter().sum::<f32>() / v.len() as f32);
    let end = end.round() as i64;
    let xs = line.x_at(row as f32);
    let inner = mean((2..10).filter_map(|k| p.gy(end - out * k, row)).collect());
    let outer = mean(
        STRIP
            .filter_map(|d| p.gy((xs + (out * d) as f32).round() as i64, row))
            .collect(),
    );
    match (inner, outer) {
        (Some(a), Some(b)) => a * b > 0.0 && b.abs() >= CARRY * a.abs(),
        _ => true,
    }
}

#[cfg(test)]
mod tests {
    use super::super::features::Features;
    use super::super::ledges::detect;
    use super::super::wall::Class;
    use crate::photo::Photo;

    /// 300 x 400: a buff render wall with a ledge's 4-row shadow at y 150
    /// from x 20 rightwards, and in front of it, right of an edge through
    /// x 175 at y 150 leaning `lean` columns per row, `front` (the colour
    /// at (x, y)); `bar` draws a 3-column dark bar along that edge instead
    /// (a fire escape's stringer: the wall and the ledge go on past it).
    /// The right end of the ledge `detect` finds near y 151.
    fn right_end(lean: f32, bar: bool, front: impl Fn(u32, u32) -> [f32; 3]) -> Option<f32> {
        let img = image::RgbImage::from_fn(300, 400, |x, y| {
            let edge = 175.0 - lean * (y as f32 - 150.0);
            let render = [0.78, 0.72, 0.6];
            let c = match (x, y) {
                _ if bar && (x as f32 - edge).abs() < 1.5 => [0.1; 3],
                _ if !bar && x as f32 >= edge => front(x, y),
                (20.., 150..154) => render.map(|v| v * 0.5),
                _ => render,
            };
            image::Rgb(c.map(|v| (v * 255.0) as u8))
        });
        let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 400);
        let ledges = detect(&f, &vec![Class::Wall; 300 * 400], None);
        ledges
            .iter()
            .find(|l| (l.polyline[0][1] - 151.0).abs() < 4.0)
            .map(|l| l.polyline[l.polyline.len() - 1][0])
    }

    /// Red brick seen from afar: its colour with a speckle of +-15% per
    /// pixel (a texture without the long joints a lapped wall has).
    fn brick(x: u32, y: u32) -> [f32; 3] {
        let hash = (x.wrapping_mul(73_856_093) ^ y.wrapping_mul(19_349_663)) % 1000;
        let k = 0.85 + 0.3 * hash as f32 / 1000.0;
        [0.55, 0.28, 0.22].map(|v| v * k)
    }

    #[test]
    fn a_ledge_behind_a_gable_ends_where_the_slope_is_below_it() {
        // A gable's slope (0.5 columns per row): 20 rows below the ledge
        // (a twentieth of the height) it is at x 165. Main ran the
        // ledge on to the edge on its own row, x 175.
        let slope = right_end(0.5, false, brick);
        assert!(
            slope.is_some_and(|x| (150.0..=167.0).contains(&x)),
            "{slope:?}"
        );
        let plumb = right_end(0.0, false, brick);
        assert!(plumb.is_some_and(|x| x >= 172.0), "{plumb:?}");
    }

    #[test]
    fn a_stringer_or_a_flat_fill_over_a_ledges_end_leaves_it_whole() {
        // A dark bar along the same slope (the render and the ledge go on
        // past it), and a flat black fill in front (a rectified photo's
        // border): no building in front, nothing taken back.
        let bar = right_end(0.5, true, brick);
        assert!(bar.is_some_and(|x| x >= 172.0), "{bar:?}");
        let fill = right_end(0.5, false, |_, _| [0.0; 3]);
        assert!(fill.is_some_and(|x| x >= 172.0), "{fill:?}");
    }
}
