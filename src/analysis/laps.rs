//! Laps: a traced line that is only one period of a lapped or coursed
//! surface (clapboard laps, brick or stone courses, panel joints, a
//! shutter's slats) is no ledge. Each lap sheds its water onto the next
//! over its whole width, so no streak starts at any one of them
//! (`how-facades-age.md`: streaks start where a projection concentrates
//! the run-off); blind review 28 caught p1010713's clapboard laps traced
//! as short "window heads" and string courses, each dripping mid-wall.
//!
//! The test looks at the wall itself, not at the other lines traced
//! (`courses.rs` stacks lines; with laps 3 px apart at analysis size most
//! laps are never traced, or are suppressed as too close, so no stack
//! forms). Along the line, in chunks of [`CHUNK`] columns, the luma
//! profile across it (rows following the line's slant, averaged over the
//! chunk's columns) is cut into the rows above and the rows below the
//! line. A half is *periodic* when its autocorrelation, after the mean
//! and linear trend are taken out, dips below [`TROUGH`] and then peaks
//! over [`PERIODIC`] at a lag of [`MIN_PERIOD`] to [`MAX_PERIOD`] pixels
//! (the laps' spacing; the half spans at least two periods). A chunk is a
//! lap's when both halves are periodic with about the same period (the
//! pattern covers the stretch on both sides: a sill has its window above,
//! a cornice its frieze, the lowest board the trim below it) and the
//! line's own step does not stand out of the laps' steps (at most
//! [`STANDS_OUT`] times their mean: a real drip cap or sill on siding has
//! a lit top and a deeper shadow). The line is a lap when at least
//! [`LAPPED_SHARE`] of its chunks are.

use super::features::Features;
use super::ledges::Fit;

/// Shortest lap spacing looked for, in analysis pixels: laps 3 px apart
/// (p1010713 at 683 px wide: the autocorrelation peaks at lag 3, 0.8).
const MIN_PERIOD: usize = 2;
/// Longest lap spacing looked for, in analysis pixels: clapboard 0.1-0.2 m,
/// brick courses 75 mm, stone courses up to 0.4 m, at 1-4 cm a pixel; a
/// storey (2.5-3.5 m) is ten times that.
const MAX_PERIOD: usize = 16;
/// Rows on each side of the line whose profile is tested: two periods of
/// the longest spacing.
const REACH: usize = 2 * MAX_PERIOD;
/// Rows on each side of the line tested first: four periods of laps 3 px
/// apart, before a window's casing or a trim board comes in reach
/// (p1010713: laps beside a window's head, 20 rows above it).
const NEAR: usize = 12;
/// Columns averaged into one profile (a short stretch, so a slant error
/// of the line does not smear laps a few pixels apart).
const CHUNK: usize = 8;
/// Autocorrelation at the laps' spacing over which a half is periodic.
/// Measured on CMP (sill + cornice found, floor 4614; strict / lenient
/// precision), with the laps dropped before the course check: 0.5: 4620,
/// 0.349 / 0.630; 0.35: 4614, 0.350 / 0.633.
const PERIODIC: f32 = 0.5;
/// Autocorrelation the half must first dip under (an oscillation, not a
/// smooth shading, whose correlation stays high at every lag).
const TROUGH: f32 = -0.2;
/// Luma spread (standard deviation, 0..1) under which a half is plain
/// wall, not laps (JPEG noise correlates by chance).
const MIN_SPREAD: f32 = 0.01;
/// Largest ratio between the two halves' periods.
const SAME_PERIOD: f32 = 1.34;
/// A line whose step is over this many times the laps' mean step stands
/// out of them: a ledge on the siding, kept (a sill's lit top over its
/// shadow steps 0.6 of the luma, clapboard laps 0.1-0.3). Measured on CMP
/// as merged (laps dropped after the course check): 2: 4618, 0.350 /
/// 0.632; 2.5: 4618, 0.350 / 0.633; 3: 4619, 0.351 / 0.635 (from 4616,
/// 0.347 / 0.627 without the test).
const STANDS_OUT: f32 = 3.0;
/// Share of a line's chunks that must be laps for the line to be one
/// (0.34 with the laps dropped before the course check: 4614, 0.350 /
/// 0.634; with 3 for [`STANDS_OUT`] and 0.35 for [`PERIODIC`] too:
/// 4592, under the floor).
const LAPPED_SHARE: f32 = 0.5;

/// True when the traced line `fit` is one lap of a lapped or coursed
/// surface (see the module's text).
pub(super) fn is_lap(f: &Features, fit: &Fit) -> bool {
    let (x0, x1) = (fit.x0.max(0.0) as usize, (fit.x1 as usize).min(f.w - 1));
    if x1 < x0 + CHUNK / 2 {
        return false;
    }
    let chunks: Vec<(usize, usize)> = (x0..=x1)
        .step_by(CHUNK)
        .map(|c| (c, (c + CHUNK).min(x1 + 1)))
        .filter(|&(c, end)| end - c >= CHUNK / 2)
        .collect();
    let need = LAPPED_SHARE * chunks.len() as f32;
    // Chunk by chunk, until the answer is sure either way.
    let mut laps = 0usize;
    for (k, &(c, end)) in chunks.iter().enumerate() {
        laps += profile(f, fit, c, end).is_some_and(|p| lap_chunk(&p)) as usize;
        if laps as f32 >= need {
            return true;
        }
        if ((laps + chunks.len() - k - 1) as f32) < need {
            return false;
        }
    }
    false
}

/// The mean luma over columns `c0..c1` at each row offset `-REACH..=REACH`
/// from the line (rounded to its row at each column); `None` when a row
/// leaves the photo.
fn profile(f: &Features, fit: &Fit, c0: usize, c1: usize) -> Option<Vec<f32>> {
    let mut p = vec![0f32; 2 * REACH + 1];
    for x in c0..c1 {
        let y = fit.y_at(x as f32).round() as isize;
        if y - (REACH as isize) < 0 || y + REACH as isize >= f.h as isize {
            return None;
        }
        for (k, v) in p.iter_mut().enumerate() {
            *v += f.luma[(y + k as isize - REACH as isize) as usize * f.w + x];
        }
    }
    let n = (c1 - c0) as f32;
    p.iter_mut().for_each(|v| *v /= n);
    Some(p)
}

/// True when the profile (centred on the line) is laps on both sides and
/// the line's own step does not stand out of theirs.
fn lap_chunk(p: &[f32]) -> bool {
    // Above: the rows down to two above the line; below: from two below.
    let Some(b) = side(p, Side::Below) else {
        return false;
    };
    let Some(a) = side(p, Side::Above) else {
        return false;
    };
    if a.max(b) as f32 > SAME_PERIOD * a.min(b) as f32 {
        return false;
    }
    // The step over two rows (bright above, dark below), as the tracer
    // measures it; the line's is the largest within a row of it.
    let step = |i: usize| p[i - 1] - p[i + 1];
    let own = (REACH - 1..=REACH + 1).map(step).fold(f32::MIN, f32::max);
    // The laps' steps: each positive local peak away from the line.
    let peaks: Vec<f32> = (2..p.len() - 2)
        .filter(|&i| i.abs_diff(REACH) >= 2)
        .map(|i| (step(i), step(i - 1), step(i + 1)))
        .filter(|&(s, l, r)| s > 0.0 && s >= l && s > r)
        .map(|(s, _, _)| s)
        .collect();
    if peaks.is_empty() {
        return false;
    }
    let mean = peaks.iter().sum::<f32>() / peaks.len() as f32;
    own <= STANDS_OUT * mean
}

/// Which side of the line.
#[derive(Clone, Copy)]
enum Side {
    Above,
    Below,
}

/// The laps' period on one side of the line: in the [`NEAR`] rows nearest
/// to it (close laps near a window or a trim board), else in all
/// [`REACH`] - 1 (wider laps); the two rows at the line left out.
fn side(p: &[f32], s: Side) -> Option<usize> {
    [NEAR, REACH - 1].into_iter().find_map(|n| match s {
        Side::Above => period(&p[REACH - 1 - n..REACH - 1]),
        Side::Below => period(&p[REACH + 2..REACH + 2 + n]),
    })
}

/// The lag (in [`MIN_PERIOD`]..=[`MAX_PERIOD`], at most half the
/// samples) at which the detrended samples' autocorrelation, after dipping
/// under [`TROUGH`], first peaks over [`PERIODIC`]; `None` when it does
/// not (no laps).
fn period(s: &[f32]) -> Option<usize> {
    let d = detrend(s);
    let var = d.iter().map(|v| v * v).sum::<f32>() / d.len() as f32;
    if var.sqrt() < MIN_SPREAD {
        return None;
    }
    let max_lag = MAX_PERIOD.min(d.len() / 2);
    // Pearson correlation of the samples with themselves `k` later.
    let r: Vec<f32> = (0..=max_lag + 1).map(|k| correlation(&d, k)).collect();
    let mut dipped = false;
    for k in 1..=max_lag {
        dipped |= r[k] < TROUGH;
        if dipped && k >= MIN_PERIOD && r[k] > PERIODIC && r[k] >= r[k - 1] && r[k] >= r[k + 1] {
            return Some(k);
        }
    }
    None
}

/// The samples less their least-squares line.
fn detrend(s: &[f32]) -> Vec<f32> {
    let n = s.len() as f32;
    let mx = (n - 1.0) / 2.0;
    let my = s.iter().sum::<f32>() / n;
    let (mut sxy, mut sxx) = (0f32, 0f32);
    for (i, &v) in s.iter().enumerate() {
        let dx = i as f32 - mx;
        sxy += dx * (v - my);
        sxx += dx * dx;
    }
    let b = if sxx > 0.0 { sxy / sxx } else { 0.0 };
    s.iter()
        .enumerate()
        .map(|(i, &v)| v - my - b * (i as f32 - mx))
        .collect()
}

/// Pearson correlation between `d[..n - k]` and `d[k..]` (0 when either
/// is flat or too short).
fn correlation(d: &[f32], k: usize) -> f32 {
    if k + 2 > d.len() {
        return 0.0;
    }
    let (a, b) = (&d[..d.len() - k], &d[k..]);
    let n = a.len() as f32;
    let (ma, mb) = (a.iter().sum::<f32>() / n, b.iter().sum::<f32>() / n);
    let (mut sab, mut saa, mut sbb) = (0f32, 0f32, 0f32);
    for (&x, &y) in a.iter().zip(b) {
        sab += (x - ma) * (y - mb);
        saa += (x - ma) * (x - ma);
        sbb += (y - mb) * (y - mb);
    }
    if saa <= 0.0 || sbb <= 0.0 {
        0.0
    } else {
        sab / (saa * sbb).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::super::ledges::detect;
    use super::super::wall::Class;
    use super::super::{Ledge, LedgeKind};
    use super::*;
    use crate::photo::Photo;

    const W: u32 = 400;
    const H: u32 = 300;
    /// The siding's rows.
    const SIDING: (f32, f32) = (34.0, 250.0);
    /// The window's columns and rows (casing included).
    const WINDOW: (u32, u32, u32, u32) = (150, 250, 100, 170);

    /// A hash of `k` in 0..1 (shading that does not repeat).
    fn jitter(k: u32) -> f32 {
        let v = k.wrapping_mul(2_654_435_761) ^ (k >> 7).wrapping_mul(40_503);
        (v >> 8) as f32 / (1 << 24) as f32
    }

    /// The luma of a clapboard wall at (x, y): laps 3.4 px apart,
    /// slanting 3% under perspective, each lap's face brightening toward
    /// its lip over a shadow line whose depth varies from lap to lap, lit
    /// more on the right, with pixel noise; under a fascia and over a trim
    /// board. Area-sampled four times per row, as a camera would.
    fn clapboard(x: u32, y: u32) -> f32 {
        let (y0, y1) = SIDING;
        let v = match y {
            30..34 => 0.4,
            20..30 => 0.85,
            _ if (y as f32) < y0 || (y as f32) >= y1 => 0.8,
            _ => {
                let mut s = 0.0;
                for q in 0..4 {
                    let t = (y as f32 + (q as f32 + 0.5) / 4.0 - y0 + 0.03 * x as f32) / 3.4;
                    let (lap, phase) = (t.floor() as u32, t.fract());
                    s += if phase < 0.72 {
                        0.62 + 0.12 * phase
                    } else {
                        0.36 + 0.1 * jitter(lap)
                    };
                }
                s / 4.0
            }
        };
        (v * (0.92 + 0.16 * x as f32 / W as f32) + 0.03 * (jitter(y * W + x) - 0.5)).clamp(0.0, 1.0)
    }

    /// The ledges found on the clapboard wall, with a window and its sill
    /// when `window`: a white casing round glass, the sill wider than it,
    /// lit on top over its shadow.
    fn ledges(window: bool) -> Vec<Ledge> {
        let (wx0, wx1, wy0, wy1) = WINDOW;
        let glass = |x: u32, y: u32| {
            window && (wx0 + 4..wx1 - 4).contains(&x) && (wy0 + 4..wy1 - 4).contains(&y)
        };
        let img = image::RgbImage::from_fn(W, H, |x, y| {
            let v = match (x, y) {
                (0.., 0..20) => return image::Rgb([150, 190, 235]),
                _ if glass(x, y) => 0.2,
                _ if window && (wx0..wx1).contains(&x) && (wy0..wy1).contains(&y) => 0.95,
                _ if window && (wx0 - 10..wx1 + 10).contains(&x) && (wy1..wy1 + 4).contains(&y) => {
                    0.95
                }
                _ if window
                    && (wx0 - 10..wx1 + 10).contains(&x)
                    && (wy1 + 4..wy1 + 8).contains(&y) =>
                {
                    0.3
                }
                _ => clapboard(x, y),
            };
            image::Rgb([(v * 255.0) as u8; 3])
        });
        let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), W);
        let class: Vec<Class> = (0..(W * H))
            .map(|i| match (i % W, i / W) {
                (_, 0..20) => Class::Sky,
                (x, y) if glass(x, y) => Class::Glass,
                _ => Class::Wall,
            })
            .collect();
        detect(&f, &class, None)
    }

    /// The ledges starting inside the siding, away from its top and foot.
    fn on_the_siding(ls: &[Ledge]) -> Vec<&Ledge> {
        ls.iter()
            .filter(|l| l.kind != LedgeKind::RoofLine)
            .filter(|l| {
                let y = l.polyline[0][1];
                y > SIDING.0 + 4.0 && y < SIDING.1 - 4.0
            })
            .collect()
    }

    #[test]
    fn a_clapboard_wall_has_no_ledges_on_its_laps() {
        let ls = ledges(false);
        assert_eq!(on_the_siding(&ls), Vec::<&Ledge>::new(), "{ls:?}");
    }

    #[test]
    fn a_sill_on_the_clapboard_stays_the_laps_round_it_go() {
        let ls = ledges(true);
        let sill = WINDOW.3 as f32 + 4.0;
        let (on, off): (Vec<&Ledge>, Vec<&Ledge>) = on_the_siding(&ls)
            .into_iter()
            .partition(|l| (l.polyline[0][1] - sill).abs() <= 3.0);
        // Laps within [`NEAR`] + 2 rows of the sill's shadow have too few
        // clean laps above them to be told and may stay.
        let reach = sill + 4.0 + (NEAR + 2) as f32;
        let off: Vec<&Ledge> = off
            .into_iter()
            .filter(|l| l.polyline[0][1] > reach || l.polyline[0][1] < WINDOW.2 as f32)
            .collect();
        assert!(
            on.iter().any(|l| l.kind == LedgeKind::Sill
                && l.polyline[0][0] <= WINDOW.0 as f32
                && l.polyline[l.polyline.len() - 1][0] >= WINDOW.1 as f32),
            "the sill: {ls:?}"
        );
        assert_eq!(off, Vec::<&Ledge>::new(), "laps: {ls:?}");
    }
}
