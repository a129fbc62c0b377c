//! Metres per pixel from what the building shows: the spacing of storeys
//! (3.1 m apart: the period of the rows of window jambs, checked against
//! the rows of glass, else rows of glass, sills or window heads), else the
//! windows' height
//! (1.4 m), else the user's wall width, else a 10 m wide wall
//! (how-facades-age.md, "Scale anchors"). A wall width given by the user
//! wins over every estimate.

use rayon::prelude::*;

use super::features::Features;
use super::wall::Class;
use super::{Ledge, LedgeKind, Scale, ScaleSource};

/// Storey height assumed, metres (the spec's 2.7 to 3.5 m).
pub const STOREY_M: f32 = 3.1;
/// Window height assumed, metres (the spec's 1.2 to 1.6 m).
pub const WINDOW_M: f32 = 1.4;
/// Wall width assumed when nothing else is known, metres.
pub const DEFAULT_WIDTH_M: f32 = 10.0;

/// Estimates the scale; `ledges` in photo pixels, `storey` from
/// [`JambPeriods::checked`] and `glass_rows` from [`glass_rows`], both in
/// analysis pixels.
pub fn estimate(
    f: &Features,
    class: &[Class],
    ledges: &[Ledge],
    storey: Option<f32>,
    glass_rows: Option<f32>,
    wall_width_m: Option<f32>,
) -> Scale {
    let (w, h) = (f.w, f.h);
    let wall_cols = (0..w)
        .filter(|&x| (0..h).any(|y| class[y * w + x] == Class::Wall))
        .count()
        .max(1) as f32
        * f.sx;
    if let Some(m) = wall_width_m.filter(|m| m.is_finite() && *m > 0.0) {
        return Scale {
            metres_per_pixel: m / wall_cols,
            source: ScaleSource::UserWidth,
        };
    }
    if let Some(storey) = storey.or(glass_rows) {
        return Scale {
            metres_per_pixel: STOREY_M / (storey * f.sy),
            source: ScaleSource::StoreyHeight,
        };
    }
    for kind in [LedgeKind::WindowHead, LedgeKind::Sill] {
        let ys: Vec<f32> = ledges
            .iter()
            .filter(|l| l.kind == kind)
            .map(|l| (l.polyline[0][1] + l.polyline[l.polyline.len() - 1][1]) / 2.0)
            .collect();
        if let Some(storey) = storey_px(ys, f.h as f32 * f.sy) {
            return Scale {
                metres_per_pixel: STOREY_M / storey,
                source: ScaleSource::StoreyHeight,
            };
        }
    }
    if let Some(px) = window_height_px(class, w, h) {
        return Scale {
            metres_per_pixel: WINDOW_M / (px * f.sy),
            source: ScaleSource::WindowSize,
        };
    }
    Scale {
        metres_per_pixel: DEFAULT_WIDTH_M / wall_cols,
        source: ScaleSource::Default,
    }
}

/// The spacing of the rows of windows (analysis pixels) from the tops of
/// the glass blobs.
pub fn glass_rows(f: &Features, class: &[Class]) -> Option<f32> {
    let (w, h) = (f.w, f.h);
    let glass: Vec<u8> = class.iter().map(|&c| (c == Class::Glass) as u8).collect();
    let tops: Vec<f32> = super::eval::components(&glass, w, h, &[1], (w * h) / 5000)
        .iter()
        .map(|b| b.y0)
        .collect();
    storey_px(tops, h as f32)
}

/// How many times the larger of two lengths is the smaller.
fn factor(a: f32, b: f32) -> f32 {
    a.max(b) / a.min(b).max(f32::MIN_POSITIVE)
}

/// The typical spacing of rows among `ys` (photo pixels): rows are runs of
/// values within 1.5% of the height; the median gap between neighbouring
/// rows, when there are at least three rows.
pub fn storey_px(mut ys: Vec<f32>, height: f32) -> Option<f32> {
    ys.sort_by(f32::total_cmp);
    let tol = 0.015 * height;
    let mut rows: Vec<(f32, usize)> = Vec::new();
    for y in ys {
        match rows.last_mut() {
            Some((m, n)) if y - *m / *n as f32 <= tol => {
                *m += y;
                *n += 1;
            }
            _ => rows.push((y, 1)),
        }
    }
    let rows: Vec<f32> = rows.iter().map(|(m, n)| m / *n as f32).collect();
    if rows.len() < 3 {
        return None;
    }
    let mut gaps: Vec<f32> = rows
        .windows(2)
        .map(|r| r[1] - r[0])
        .filter(|g| *g > 0.05 * height)
        .collect();
    if gaps.len() < 2 {
        return None;
    }
    gaps.sort_by(f32::total_cmp);
    Some(gaps[gaps.len() / 2])
}

/// A row counts in the jambs' profile when at least this share of it is
/// not sky.
const PROFILE_ROW: f32 = 0.25;
/// The storey is the shortest period whose autocorrelation is at least
/// this share of the strongest (measured on CMP's first half and checked
/// on its second: 0.4 to 0.8 all within 0.02 of the share within 1.5x).
const PERIOD_SHARE: f32 = 0.6;
/// Periods weaker than this normalised autocorrelation are not trusted.
const MIN_PERIOD_AC: f32 = 0.1;
/// The shortest storey, a share of the height.
const MIN_STOREY: f32 = 0.06;
// Measured on CMP base (378 photos), the share of scale estimates within
// 1.5x of the labels' storey (`scene_eval cmp`; 0.794 before these rules).

/// A period repeats at least this many times in the height, ...
/// [choice: 2 (as before) 0.807, 2.5 0.836, 3 0.852, 3.5 0.849; of the 35
/// photos whose period was longer than a third of the height, it was the
/// storey on 12]
const MIN_REPEATS: usize = 3;
/// ... or, seen only twice (a photo of two or three storeys), has at
/// least this autocorrelation [choice: on the 12 photos above 0.38-0.84,
/// on the 23 others 0.10-0.37, or 0.40-0.71 with a shorter period that
/// is the storey; at 0.3 0.852, 0.4 0.852, 0.5 0.849, never 0.833].
const TWICE_AC: f32 = 0.4;
/// The glass rows' spacing and the jambs' period disagree beyond this
/// factor [choice: 1.5 0.852, 2 0.833, no check 0.828] ...
const DISAGREE: f32 = 1.5;
/// ... then the strongest period within this factor of the glass rows'
/// spacing [choice: 1.15 0.849, 1.25 0.852, 1.5 0.841], ...
const AGREE: f32 = 1.25;
/// ... at least this share of the strongest [choice: 0.3 0.852, 0.5
/// 0.844] ...
const AGREEING_SHARE: f32 = 0.3;
/// ... and at least this share of the height [choice: 0.04 0.852, 0.06
/// 0.847] is the storey.
const MIN_AGREEING_STOREY: f32 = 0.04;

/// The periods of the facade's rows of windows: the mean horizontal luma
/// step (vertical edges: window jambs, frames, mullions) along each row
/// below the sky is high across a row of windows and low on the wall
/// between, a square wave whose period is the storey. Holds the peaks of
/// its autocorrelation (lag in analysis pixels, normalised value), the
/// shortest lag first, between 4% of the height and half of it.
#[derive(Debug, Clone)]
pub struct JambPeriods {
    peaks: Vec<(usize, f32)>,
    h: usize,
}

impl JambPeriods {
    /// The storey height (analysis pixels): the autocorrelation's first
    /// peak from 6% to a third of the height that reaches 0.6 of the
    /// strongest there, else the first longer one that is strong on its
    /// own ([`TWICE_AC`]) [choice: rather than the spacing of glass
    /// blobs, which splits at transoms and misses curtained panes; on CMP
    /// within 1.5x of the labels' storey for 0.71 of the photos against
    /// 0.56; a photo taken at a slant smears the rows]. None when no row
    /// profile or no periodic peak.
    pub fn storey(&self) -> Option<f32> {
        let lo = ((MIN_STOREY * self.h as f32) as usize).max(2);
        let hi = self.h / MIN_REPEATS;
        let peaks = || self.peaks.iter().filter(|p| p.0 >= lo && p.0 <= hi);
        let best = peaks().map(|p| p.1).fold(0f32, f32::max);
        let short = peaks().find(|p| best >= MIN_PERIOD_AC && p.1 >= PERIOD_SHARE * best);
        short
            .or_else(|| self.peaks.iter().find(|p| p.0 > hi && p.1 >= TWICE_AC))
            .map(|p| p.0 as f32)
    }

    /// The storey (analysis pixels): [`Self::storey`], unless the glass
    /// rows' spacing `glass_rows` disagrees with it and a weaker period
    /// agrees with the glass (see [`Self::agreeing`]).
    pub fn checked(&self, glass_rows: Option<f32>) -> Option<f32> {
        let storey = self.storey()?;
        Some(match glass_rows {
            Some(g) if factor(storey, g) > DISAGREE => self.agreeing(g).unwrap_or(storey),
            _ => storey,
        })
    }

    /// The strongest period within [`AGREE`] of `spacing` (analysis
    /// pixels) that reaches [`AGREEING_SHARE`] of the strongest: when two
    /// independent cues agree on a weaker period, it is the storey and the
    /// stronger one a harmonic (two storeys alike, or a mezzanine).
    fn agreeing(&self, spacing: f32) -> Option<f32> {
        let lo = MIN_AGREEING_STOREY * self.h as f32;
        let hi = self.h / MIN_REPEATS;
        let peaks = || self.peaks.iter().filter(|p| p.0 as f32 >= lo && p.0 <= hi);
        let best = peaks().map(|p| p.1).fold(0f32, f32::max);
        if best < MIN_PERIOD_AC {
            return None;
        }
        peaks()
            .filter(|p| p.1 >= AGREEING_SHARE * best && factor(p.0 as f32, spacing) <= AGREE)
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map(|p| p.0 as f32)
    }
}

/// The row profile's periods (see [`JambPeriods`]); none when under a
/// quarter of the rows are facade.
pub fn jamb_periods(f: &Features, class: &[Class]) -> JambPeriods {
    let (w, h) = (f.w, f.h);
    let none = JambPeriods {
        peaks: Vec::new(),
        h,
    };
    if w < 3 || h < 20 {
        return none;
    }
    // Trees, cars and glass in front of the facade still show its rows
    // (counting only wall and glass measured 0.689 on CMP, against 0.711).
    let facade = |c: Class| c != Class::Sky;
    let rows: Vec<Option<f32>> = (0..h)
        .into_par_iter()
        .map(|y| {
            let (mut s, mut n) = (0f32, 0usize);
            for x in 1..w - 1 {
                if facade(class[y * w + x]) {
                    s += (f.luma[y * w + x + 1] - f.luma[y * w + x - 1]).abs();
                    n += 1;
                }
            }
            (n as f32 >= PROFILE_ROW * w as f32).then(|| s / n as f32)
        })
        .collect();
    let valid: Vec<f32> = rows.iter().flatten().copied().collect();
    if valid.len() < h / 4 {
        return none;
    }
    let mean = valid.iter().sum::<f32>() / valid.len() as f32;
    // Rows that are not facade sit at the mean: they add nothing.
    let p: Vec<f32> = rows.iter().map(|r| r.map_or(0.0, |v| v - mean)).collect();
    let energy = p.iter().map(|v| v * v).sum::<f32>() / h as f32;
    if energy <= 1e-12 {
        return none;
    }
    let ac = |lag: usize| {
        let s: f32 = p[..h - lag].iter().zip(&p[lag..]).map(|(a, b)| a * b).sum();
        s / (h - lag) as f32 / energy
    };
    let (lo, hi) = (((MIN_AGREEING_STOREY * h as f32) as usize).max(2), h / 2);
    let acs: Vec<f32> = (lo - 1..=hi + 1).map(ac).collect();
    let peaks = (1..acs.len() - 1)
        .filter(|&i| acs[i] > 0.0 && acs[i] >= acs[i - 1] && acs[i] >= acs[i + 1])
        .map(|i| (lo - 1 + i, acs[i]))
        .collect();
    JambPeriods { peaks, h }
}

/// Median height (analysis pixels) of the glass blobs.
fn window_height_px(class: &[Class], w: usize, h: usize) -> Option<f32> {
    let mut heights = Vec::new();
    for x in (0..w).step_by((w / 64).max(1)) {
        let mut run = 0;
        for y in 0..h {
            if class[y * w + x] == Class::Glass {
                run += 1;
            } else if run > 0 {
                heights.push(run as f32);
                run = 0;
            }
        }
    }
    if heights.len() < 3 {
        return None;
    }
    heights.sort_by(f32::total_cmp);
    Some(heights[heights.len() / 2])
}

/// Parses a length in metres as the user writes it: `14m`, `14 m`, `14`,
/// `1400cm`.
///
/// # Errors
/// [`crate::Error::OutOfRange`] when it is not a positive length.
pub fn parse_metres(s: &str) -> crate::Result<f32> {
    let t = s.trim().to_ascii_lowercase();
    let (num, factor) = if let Some(n) = t.strip_suffix("cm") {
        (n, 0.01)
    } else if let Some(n) = t.strip_suffix("mm") {
        (n, 0.001)
    } else if let Some(n) = t.strip_suffix('m') {
        (n, 1.0)
    } else {
        (t.as_str(), 1.0)
    };
    match num.trim().parse::<f32>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v * factor),
        _ => Err(crate::Error::OutOfRange {
            field: "wall width".into(),
            value: s.to_string(),
            range: "a positive length such as 14m or 1400cm".into(),
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::photo::Photo;

    #[test]
    fn the_storey_is_the_period_of_the_window_rows_not_of_their_panes() {
        // Plaster 0.75 under a strip of sky; four storeys of 100 px from
        // y 40, each with five windows 60 px tall whose two panes (dark
        // 0.2) are parted by a white transom at 35% of the height: the
        // panes' tops come in pairs 21 px apart.
        let (w, h, storey) = (400u32, 440u32, 100u32);
        let img = image::RgbImage::from_fn(w, h, |x, y| {
            if y < 40 {
                return image::Rgb([120, 170, 235]);
            }
            let (sx, sy) = (x % 80, (y - 40) % storey);
            let v = match (sx, sy) {
                (20..60, 20..80) => {
                    let frame = !(24..56).contains(&sx) || !(24..76).contains(&sy);
                    if frame || (41..45).contains(&sy) {
                        0.95
                    } else {
                        0.2
                    }
                }
                _ => 0.75,
            };
            image::Rgb([(v * 255.0) as u8; 3])
        });
        let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 512);
        let class = super::super::wall::classify(&f);
        let glass = glass_rows(&f, &class);
        let rows = jamb_periods(&f, &class).checked(glass);
        let s = estimate(&f, &class, &[], rows, glass, None);
        let truth = STOREY_M / storey as f32;
        assert_eq!(s.source, ScaleSource::StoreyHeight);
        assert!(
            (s.metres_per_pixel / truth - 1.0).abs() < 0.1,
            "{s:?} against {truth}"
        );
    }

    /// The facade of the test above, `storeys` of 100 px; on every second
    /// storey the wall beside and between the windows is fluted (stripes
    /// 4 px wide, luma 0.75 and 0.68): the jambs' profile then repeats
    /// every two storeys more strongly than every one (autocorrelation
    /// 0.4 at one storey, 0.9 at two).
    fn fluted(storeys: u32) -> (Features, Vec<Class>) {
        let (w, h, storey) = (400u32, 40 + 100 * storeys, 100u32);
        let img = image::RgbImage::from_fn(w, h, |x, y| {
            if y < 40 {
                return image::Rgb([120, 170, 235]);
            }
            let (sx, sy, k) = (x % 80, (y - 40) % storey, (y - 40) / storey);
            let v = match (sx, sy) {
                (20..60, 20..80) => {
                    if !(24..56).contains(&sx) || !(24..76).contains(&sy) {
                        0.95
                    } else {
                        0.2
                    }
                }
                _ if k % 2 == 0 && (x / 4) % 2 == 0 => 0.68,
                _ => 0.75,
            };
            image::Rgb([(v * 255.0) as u8; 3])
        });
        let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 512);
        let class = super::super::wall::classify(&f);
        (f, class)
    }

    /// Whether `storey` (analysis pixels) is within 10% of `px` photo
    /// pixels.
    fn near(f: &Features, storey: Option<f32>, px: f32) -> bool {
        storey.is_some_and(|s| (s * f.sy / px - 1.0).abs() < 0.1)
    }

    #[test]
    fn two_storeys_more_than_a_third_of_the_height_are_not_the_storey() {
        // Five storeys: two of them, 200 px of 540, are seen twice only.
        let (f, class) = fluted(5);
        let periods = jamb_periods(&f, &class);
        assert!(near(&f, periods.storey(), 100.0), "{periods:?}");
    }

    #[test]
    fn the_glass_rows_pick_the_storey_among_the_jambs_periods() {
        // Seven storeys: two of them, 200 px of 740, are seen 3.7 times.
        let (f, class) = fluted(7);
        let periods = jamb_periods(&f, &class);
        let glass = glass_rows(&f, &class);
        let storey = periods.checked(glass);
        assert!(
            near(&f, storey, 100.0),
            "{storey:?} from {periods:?}, glass rows {glass:?}"
        );
        // Without the glass rows the stronger period, two storeys.
        assert!(near(&f, periods.storey(), 200.0), "{periods:?}");
    }

    #[test]
    fn a_weaker_period_agreeing_with_the_glass_rows_wins_a_disagreeing_one_does_not() {
        // Autocorrelation peaks at one storey (100 px, weaker) and two.
        let periods = JambPeriods {
            peaks: vec![(100, 0.35), (200, 0.8)],
            h: 700,
        };
        assert_eq!(periods.storey(), Some(200.0));
        assert_eq!(periods.checked(Some(104.0)), Some(100.0));
        // Glass rows 1.5x off both periods: no period agrees.
        assert_eq!(periods.checked(Some(150.0)), Some(200.0));
        // Glass rows agreeing with the stronger period: no change.
        assert_eq!(periods.checked(Some(190.0)), Some(200.0));
        assert_eq!(periods.checked(None), Some(200.0));
    }

    #[test]
    fn a_period_seen_twice_in_the_height_must_be_strong() {
        // 250 px in 600: more than a third of the height.
        let weak = JambPeriods {
            peaks: vec![(250, 0.3)],
            h: 600,
        };
        assert_eq!(weak.storey(), None);
        let strong = JambPeriods {
            peaks: vec![(250, 0.5)],
            h: 600,
        };
        assert_eq!(strong.storey(), Some(250.0));
        // A shorter period qualifying wins over a strong long one.
        let both = JambPeriods {
            peaks: vec![(150, 0.3), (250, 0.7)],
            h: 600,
        };
        assert_eq!(both.storey(), Some(150.0));
    }
}
