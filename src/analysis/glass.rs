//! Window glass: the panes of a window are darker than the wall around
//! them (the room behind is unlit, the glass reflects the darker street),
//! and a window is a compact, nearly rectangular opening of a window's
//! size. Its frame and glazing bars, lighter than the panes, split it into
//! panes; a closing (a dilation then an erosion, over a few analysis
//! pixels) joins them again, so the whole window is found, bars included.
//! Windows come in rows and columns: a dark blob with no other like it in
//! its row or its column is kept only when it is nearly a full rectangle
//! (a lone shop window or window band); a lone ragged one is more often a
//! shadow, a doorway, a dark sign or a car than a window.
//! Glass is measured against the labelled windows by `scene_eval` (its
//! "glass recall / precision" line).

use rayon::prelude::*;

pub(crate) mod frames;
mod grid;

use super::features::{Features, box_mean, texture_radius};
use super::neighbours;
use super::wall::Class;

/// Glass is darker than this share of the wall's luma around it (CMP base,
/// glass recall / precision against the labelled windows: 0.62 gave
/// 0.105 / 0.511, 0.7 0.126 / 0.510, 0.75 0.137 / 0.513 with sill recall
/// 0.810, 0.811, 0.809).
const DARK: f32 = 0.7;

/// Glass is smoother than this (mean luma gradient).
const SMOOTH: f32 = 0.08;

/// The wall's luma around a pixel is averaged over a box this share of the
/// long side across (a facade's lit and shaded parts differ).
const WALL_AROUND: f32 = 0.05;

/// Mullions and glazing bars up to twice this share of the long side wide
/// (plus the texture's window on each side) are closed over, side to side.
const BARS: f32 = 0.003;

/// Up and down, only transoms up to twice this many analysis pixels are
/// closed over: a sill between a window and the sill's shadow is thicker
/// and stays wall (closing as far as side to side lost sills: CMP sill
/// recall 0.804 against 0.810 at 2 px; 3 px gave 0.809).
const TRANSOMS: usize = 2;

/// A window covers between these shares of the photo.
const AREA: (f32, f32) = (0.0004, 0.06);

/// A window fills at least this share of its bounding box.
const FILL: f32 = 0.45;

/// A window's height over its width lies in this range.
const ASPECT: (f32, f32) = (0.2, 8.0);

/// A window with no other in its row or column is kept when it fills more
/// than this share of its bounding box (LabelMeFacade train, wall IoU /
/// glass recall / precision: every lone one dropped 0.732 / 0.042 / 0.245,
/// kept over 0.7 0.730 / 0.054 / 0.228, over 0.8 0.732 / 0.050 / 0.246;
/// all kept, as before, 0.722 / 0.086 / 0.166).
const LONE_FILL: f32 = 0.8;

/// Two windows share a row (a column) when their spans up and down (side
/// to side) have this share of the longer span in common (0.5 on
/// LabelMeFacade train: 0.731 / 0.056 / 0.226 against 0.6's figures above).
const ALIGN: f32 = 0.6;

/// ... and their widths (heights) differ by less than this factor (3:
/// 0.731 / 0.053 / 0.231).
const LIKE: f32 = 2.0;

/// Finds the windows among the wall pixels of `class` and calls them glass.
pub fn find(f: &Features, class: &mut [Class]) {
    let (w, h) = (f.w, f.h);
    let n = w * h;
    if class.par_iter().filter(|&&c| c == Class::Wall).count() < n / 10 {
        return;
    }
    let wall: Vec<f32> = class
        .par_iter()
        .map(|&c| (c == Class::Wall) as u8 as f32)
        .collect();
    // The wall's luma around each pixel, the darks left out (the windows
    // would darken their own surroundings): the mean over the wall, then
    // again over the wall not darker than that mean allows.
    let r = ((w.max(h) as f32 * WALL_AROUND) as usize).max(1);
    let lit = around(f, &wall, r);
    let wall: Vec<f32> = (0..n)
        .into_par_iter()
        .map(|i| (wall[i] > 0.0 && f.luma[i] >= DARK * lit[i]) as u8 as f32)
        .collect();
    let lit = around(f, &wall, r);
    let found: Vec<(Vec<usize>, Bbox)> = windows(f, class, &lit)
        .into_iter()
        .map(|m| {
            let b = bbox(&m, w);
            (m, b)
        })
        .filter(|(m, b)| is_window(b, m.len(), w, h))
        .collect();
    for (k, (members, b)) in found.iter().enumerate() {
        let (bw, bh) = ((b.2 - b.0 + 1) as f32, (b.3 - b.1 + 1) as f32);
        let rectangle = members.len() as f32 > LONE_FILL * bw * bh;
        if rectangle
            || found
                .iter()
                .enumerate()
                .any(|(j, (_, s))| j != k && aligned(b, s))
        {
            mark(members, w, class);
        }
    }
}

/// A bounding box: x0, y0, x1, y1 (inclusive).
type Bbox = (usize, usize, usize, usize);

fn bbox(members: &[usize], w: usize) -> Bbox {
    let (mut x0, mut y0, mut x1, mut y1) = (usize::MAX, usize::MAX, 0, 0);
    for &i in members {
        let (x, y) = (i % w, i / w);
        (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
    }
    (x0, y0, x1, y1)
}

/// Share of the longer of two intervals that they have in common.
fn overlap(a0: usize, a1: usize, b0: usize, b1: usize) -> f32 {
    let common = (a1.min(b1) + 1).saturating_sub(a0.max(b0)) as f32;
    common / ((a1 - a0).max(b1 - b0) + 1) as f32
}

/// True when `b` lies in the row or the column of the window `s`, and is
/// of a like size.
fn aligned(b: &Bbox, s: &Bbox) -> bool {
    let (bw, bh) = ((b.2 - b.0 + 1) as f32, (b.3 - b.1 + 1) as f32);
    let (sw, sh) = ((s.2 - s.0 + 1) as f32, (s.3 - s.1 + 1) as f32);
    let like = |a: f32, b: f32| a < LIKE * b && b < LIKE * a;
    (overlap(b.1, b.3, s.1, s.3) >= ALIGN && like(bw, sw))
        || (overlap(b.0, b.2, s.0, s.2) >= ALIGN && like(bh, sh))
}

/// The components of the smooth wall darker than the lit wall around,
/// closed over glazing bars.
fn windows(f: &Features, class: &[Class], lit: &[f32]) -> Vec<Vec<usize>> {
    let (w, h) = (f.w, f.h);
    let n = w * h;
    let dark: Vec<bool> = (0..n)
        .into_par_iter()
        .map(|i| class[i] == Class::Wall && f.luma[i] < DARK * lit[i] && f.texture[i] < SMOOTH)
        .collect();
    // The bars, and the textured margin the smoothness leaves on each side.
    let bars = ((w.max(h) as f32 * BARS).round() as usize).max(1);
    let margin = texture_radius(w, h) + 1;
    let closed = close(&dark, w, bars + margin, TRANSOMS);
    let cand: Vec<bool> = closed
        .par_iter()
        .zip(class.par_iter())
        .map(|(&c, &k)| c && k == Class::Wall)
        .collect();
    components(&cand, w, h)
}

/// Calls the window's pixels, holes filled, glass where they are wall.
fn mark(members: &[usize], w: usize, class: &mut [Class]) {
    for i in filled(members, w) {
        if class[i] == Class::Wall {
            class[i] = Class::Glass;
        }
    }
}

/// Mean luma of the pixels of `mask` (0/1) within about `r` of each
/// pixel; infinite where there are none (nothing is darker than that).
/// Summed over blocks of a quarter of `r` (the mean over so wide a box
/// changes slowly), each pixel taking its block's value.
fn around(f: &Features, mask: &[f32], r: usize) -> Vec<f32> {
    let (w, h) = (f.w, f.h);
    let s = (r / 4).max(1);
    let (cw, ch) = (w.div_ceil(s), h.div_ceil(s));
    let mut sums = vec![[0f32; 2]; cw * ch];
    sums.par_chunks_mut(cw).enumerate().for_each(|(cy, row)| {
        for y in cy * s..((cy + 1) * s).min(h) {
            let (luma, mask) = (&f.luma[y * w..(y + 1) * w], &mask[y * w..(y + 1) * w]);
            for (acc, (l, m)) in row.iter_mut().zip(luma.chunks(s).zip(mask.chunks(s))) {
                for (l, m) in l.iter().zip(m) {
                    acc[0] += l * m;
                    acc[1] += m;
                }
            }
        }
    });
    let plane = |k: usize| sums.iter().map(|v| v[k]).collect::<Vec<f32>>();
    let (sum, count) = rayon::join(
        || box_mean(&plane(0), cw, ch, r / s),
        || box_mean(&plane(1), cw, ch, r / s),
    );
    let mut out = vec![0f32; w * h];
    out.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
        let c0 = y / s * cw;
        for (c, px) in row.chunks_mut(s).enumerate() {
            let (sum, count) = (sum[c0 + c], count[c0 + c]);
            px.fill(if count > 0.0 {
                sum / count
            } else {
                f32::INFINITY
            });
        }
    });
    out
}

/// Morphological closing of `mask` by a box `rx` across and `ry` up and
/// down: a dilation, then an erosion (the dilation of the complement).
fn close(mask: &[bool], w: usize, rx: usize, ry: usize) -> Vec<bool> {
    let dilate = |m: &[bool]| spread_cols(&spread_rows(m, w, rx), w, ry);
    let holes: Vec<bool> = dilate(mask).par_iter().map(|&v| !v).collect();
    dilate(&holes).par_iter().map(|&v| !v).collect()
}

/// Sets each pixel within `r` of a set pixel of its row (`w` wide).
fn spread_rows(mask: &[bool], w: usize, r: usize) -> Vec<bool> {
    let mut out = vec![false; mask.len()];
    out.par_chunks_mut(w)
        .zip(mask.par_chunks(w))
        .for_each(|(out, row)| {
            let mut count = vec![0u32; w + 1];
            for (x, &v) in row.iter().enumerate() {
                count[x + 1] = count[x] + v as u32;
            }
            for (x, o) in out.iter_mut().enumerate() {
                *o = count[(x + r + 1).min(w)] > count[x.saturating_sub(r)];
            }
        });
    out
}

/// Sets each pixel within `r` rows of a set pixel of its column (`w` wide).
fn spread_cols(mask: &[bool], w: usize, r: usize) -> Vec<bool> {
    let h = mask.len() / w.max(1);
    let mut out = vec![false; mask.len()];
    out.par_chunks_mut(w).enumerate().for_each(|(y, out)| {
        for yy in y.saturating_sub(r)..(y + r + 1).min(h) {
            for (o, &v) in out.iter_mut().zip(&mask[yy * w..(yy + 1) * w]) {
                *o |= v;
            }
        }
    });
    out
}

/// The 4-connected components of `mask`, each as its pixel indices, in
/// raster order of their first pixel.
pub(super) fn components(mask: &[bool], w: usize, h: usize) -> Vec<Vec<usize>> {
    components_joined(mask, w, h, |_, _| true)
}

/// [`components`] where two neighbours of `mask` join only when
/// `joins(i, j)` (e.g. their colours are close).
pub(super) fn components_joined(
    mask: &[bool],
    w: usize,
    h: usize,
    joins: impl Fn(usize, usize) -> bool,
) -> Vec<Vec<usize>> {
    let mut seen = vec![false; w * h];
    let mut out = Vec::new();
    for start in 0..w * h {
        if !mask[start] || seen[start] {
            continue;
        }
        seen[start] = true;
        let mut members = vec![start];
        let mut k = 0;
        while k < members.len() {
            let i = members[k];
            k += 1;
            neighbours(i, w, h).for_each(|j| {
                if mask[j] && !seen[j] && joins(i, j) {
                    seen[j] = true;
                    members.push(j);
                }
            });
        }
        out.push(members);
    }
    out
}

/// The pixels of a component with its holes filled (where crossing bars
/// left more than the closing bridges): every pixel of its bounding box
/// not 4-connected to the box's border through pixels outside it.
fn filled(members: &[usize], w: usize) -> Vec<usize> {
    let (mut x0, mut y0, mut x1, mut y1) = (usize::MAX, usize::MAX, 0, 0);
    for &i in members {
        let (x, y) = (i % w, i / w);
        (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
    }
    let (bw, bh) = (x1 - x0 + 1, y1 - y0 + 1);
    let mut inside = vec![false; bw * bh];
    for &i in members {
        inside[(i / w - y0) * bw + i % w - x0] = true;
    }
    let outside: Vec<bool> = inside.iter().map(|&v| !v).collect();
    let border = (0..bw * bh).filter(|&k| {
        let (x, y) = (k % bw, k / bw);
        outside[k] && (x == 0 || y == 0 || x + 1 == bw || y + 1 == bh)
    });
    let open = super::wall::flood(&outside, bw, bh, border.collect(), |_, _| true);
    (0..bw * bh)
        .filter(|&k| !open[k])
        .map(|k| (y0 + k / bw) * w + x0 + k % bw)
        .collect()
}

/// True for a window's size and shape (its bounding box `b`, `area`
/// pixels), not touching the photo's edge.
fn is_window(b: &Bbox, area: usize, w: usize, h: usize) -> bool {
    let &(x0, y0, x1, y1) = b;
    let (bw, bh) = ((x1 - x0 + 1) as f32, (y1 - y0 + 1) as f32);
    let (area, n) = (area as f32, (w * h) as f32);
    area > AREA.0 * n
        && area < AREA.1 * n
        && area > FILL * bw * bh
        && (ASPECT.0..=ASPECT.1).contains(&(bh / bw))
        && x0 > 0
        && y0 > 0
        && x1 + 1 < w
        && y1 + 1 < h
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::photo::Photo;

    /// A wall (luma 0.7, 300 x 240) with one window at x 40..80, y 30..90:
    /// four dark panes (0.2) split by a light cross of glazing bars 2 px
    /// wide; under it a sill 6 px thick (0.9) and the sill's shadow (0.3).
    fn window_with_bars() -> Features {
        let img = image::RgbImage::from_fn(300, 240, |x, y| {
            let v = match (x, y) {
                (59..61, 30..90) | (40..80, 59..61) => 0.7,
                (40..80, 30..90) => 0.2,
                (36..84, 90..96) => 0.9,
                (36..84, 96..100) => 0.3,
                _ => 0.7,
            };
            image::Rgb([(v * 255.0) as u8; 3])
        });
        Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 300)
    }

    #[test]
    fn a_window_with_glazing_bars_is_one_pane_of_glass() {
        let f = window_with_bars();
        let mut class = vec![Class::Wall; f.w * f.h];
        find(&f, &mut class);
        let at = |x: usize, y: usize| class[y * f.w + x];
        assert_eq!(at(50, 40), Class::Glass);
        assert_eq!(at(70, 80), Class::Glass);
        // The bars between the panes are part of the window.
        assert_eq!(at(60, 40), Class::Glass);
        // The wall around it is not, nor the sill under it.
        assert_eq!(at(60, 93), Class::Wall);
        assert_eq!(at(20, 20), Class::Wall);
        assert_eq!(at(100, 60), Class::Wall);
        assert_eq!(at(60, 100), Class::Wall);
    }

    /// A wall (luma 0.7, 300 x 240) with a dark (0.2), ragged blob at each
    /// of `xs`, y 60..120: 40 wide, its upper right quarter wall, so it
    /// fills three quarters of its bounding box.
    fn ragged_blobs(xs: &[u32]) -> Features {
        let img = image::RgbImage::from_fn(300, 240, |x, y| {
            let dark = xs.iter().any(|&x0| {
                (x0..x0 + 40).contains(&x) && (60..120).contains(&y) && !(x >= x0 + 20 && y < 90)
            });
            image::Rgb([if dark { 51 } else { 178 }; 3])
        });
        Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 300)
    }

    #[test]
    fn ragged_windows_in_a_row_are_glass() {
        let f = ragged_blobs(&[40, 130, 220]);
        let mut class = vec![Class::Wall; f.w * f.h];
        find(&f, &mut class);
        let at = |x: usize, y: usize| class[y * f.w + x];
        for x0 in [40, 130, 220] {
            assert_eq!(at(x0 + 10, 100), Class::Glass);
        }
        assert_eq!(at(100, 100), Class::Wall);
    }

    #[test]
    fn a_lone_ragged_dark_patch_is_wall() {
        // The same blob alone, in no row or column of windows: a shadow
        // or a dark sign, not a window.
        let f = ragged_blobs(&[130]);
        let mut class = vec![Class::Wall; f.w * f.h];
        find(&f, &mut class);
        assert_eq!(class[100 * f.w + 140], Class::Wall);
        // One of a different size in its row does not make it a window.
        let img = image::RgbImage::from_fn(300, 240, |x, y| {
            let blob = (130..170).contains(&x) && (60..120).contains(&y) && !(x >= 150 && y < 90);
            let small = (40..50).contains(&x) && (80..110).contains(&y);
            image::Rgb([if blob || small { 51 } else { 178 }; 3])
        });
        let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 300);
        let mut class = vec![Class::Wall; f.w * f.h];
        find(&f, &mut class);
        assert_eq!(class[100 * f.w + 140], Class::Wall);
    }
}
