//! Ledges: long, near-horizontal luma edges that turn from bright above to
//! dark below (the lit top and shadowed underside of a projecting ledge),
//! traced column by column so that perspective slants and small gaps are
//! followed, fitted with least-squares lines, then named by what is above
//! and below them (glass above: sill; glass below, or a dark that goes on
//! below instead of a thin shadow band: window head; long near the wall top:
//! cornice or coping). The roof line is [`roof`]'s.

use super::features::{Features, box_mean};
use super::ledge_kinds::{
    a_line_on_one_surface, crosses_a_frame, glass_below, kind_of, recovery, tops_a_window,
};
use super::silhouette;
use super::wall::Class;
use super::{Ledge, LedgeKind, courses, laps, roof, slants};

/// Edges weaker than this (luma step over two rows, 0..1) are ignored
/// (0.06 before the storey check below: on CMP 0.045 finds 2% more
/// labelled sills and cornices; the check takes most of the noise back).
const MIN_STEP: f32 = 0.045;
/// A ledge shorter than this share of the width, weaker than
/// [`ALONE_CONFIDENCE`], with no other ledge one storey above or below
/// it, is facade texture, not a ledge (see [`alone`]).
const ALONE_SPAN: f32 = 0.06;
/// See [`ALONE_SPAN`].
const ALONE_CONFIDENCE: f32 = 0.5;
/// Steepest slant followed (dy/dx): 45 degrees (the sills of a wall seen
/// in perspective; 0.25 before).
const MAX_SLOPE: f32 = 1.0;
/// In a street scene, a ledge less than this share of the height above
/// the ground is taken to be on a parked car (see [`on_a_car`]). Over the
/// ledges LabelMeFacade labels a car under, the median lies 0.10 of the
/// height above the ground found below it (quartiles 0.05 / 0.17), the
/// others 0.33 (0.19 / 0.50). Measured (ledge length on cars, train /
/// held out; CMP sill + cornice recall): none 0.077 / 0.085, 4623; 0.06
/// 0.066 / 0.075, 4622; 0.1 0.058 / 0.068, 4621; 0.15 0.052 / 0.061,
/// 4617 (0.1 takes 0.6 as much ledge length off the wall as off cars,
/// road and trees on train, 0.45 held out).
const CAR_HEIGHT: f32 = 0.1;
/// A ledge longer than this share of the width is not on a car: 90% of
/// the ledges on LabelMeFacade's cars are under 0.13 of the width. Without
/// it the rule took the long heads and string courses at the foot of
/// CMP facades whose rectified border reads as ground (b0178, b0191):
/// recall 4623 -> 4605 at [`CAR_HEIGHT`] 0.1, with it 4621.
const CAR_LENGTH: f32 = 0.2;
/// A ledge (not a window head) whose luma profile across it does not come
/// back at all below its shadow (see [`recovery`]: a change of paint,
/// siding or material, not a projecting ledge) is dropped. Measured on CMP
/// (sill + cornice recall, floor 4614; strict / lenient precision from
/// 4625, 0.343 / 0.624): under 0.3: 4535, 0.354 / 0.631; under 0.1: 4601,
/// 0.350 / 0.630; under 0: 4616, 0.347 / 0.627; under -0.15: 4620, 0.345
/// / 0.626.
const STEP_DROP: f32 = 0.0;
/// Under this recovery a ledge's confidence falls in proportion (the
/// rain shows its streaks in proportion, `rain.sure_at`), window heads
/// over glass or standing on jambs excepted: the dark of an opening goes
/// on. Blind review 27 called img_0847 fake for streaks from a siding
/// colour change (a window head by its dark that goes on, recovery 0.11);
/// the porch roofs and balconies there recover 0.26 to 1.2.
const STEP_SURE: f32 = 0.3;
/// At most this many ledges are returned (the most confident).
const MAX_LEDGES: usize = 120;

/// A traced chain's least-squares sums.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Fit {
    n: f32,
    sx: f32,
    sy: f32,
    sxx: f32,
    sxy: f32,
    syy: f32,
    strength: f32,
    pub(super) x0: f32,
    pub(super) x1: f32,
}

impl Fit {
    fn add(&mut self, x: f32, y: f32, s: f32) {
        if self.n == 0.0 {
            self.x0 = x;
            self.x1 = x;
        }
        self.n += 1.0;
        self.sx += x;
        self.sy += y;
        self.sxx += x * x;
        self.sxy += x * y;
        self.syy += y * y;
        self.strength += s;
        self.x0 = self.x0.min(x);
        self.x1 = self.x1.max(x);
    }

    fn merge(&mut self, o: &Fit) {
        self.n += o.n;
        self.sx += o.sx;
        self.sy += o.sy;
        self.sxx += o.sxx;
        self.sxy += o.sxy;
        self.syy += o.syy;
        self.strength += o.strength;
        self.x0 = self.x0.min(o.x0);
        self.x1 = self.x1.max(o.x1);
    }

    /// (intercept, slope) of y = a + b x.
    fn line(&self) -> (f32, f32) {
        let d = self.n * self.sxx - self.sx * self.sx;
        if d.abs() < 1e-6 {
            return (self.sy / self.n, 0.0);
        }
        let b = (self.n * self.sxy - self.sx * self.sy) / d;
        ((self.sy - b * self.sx) / self.n, b)
    }

    pub(super) fn y_at(&self, x: f32) -> f32 {
        let (a, b) = self.line();
        a + b * x
    }

    /// Root-mean-square distance of the points from the line.
    fn rms(&self) -> f32 {
        let (a, b) = self.line();
        let sse = self.syy - 2.0 * a * self.sy - 2.0 * b * self.sxy
            + self.n * a * a
            + 2.0 * a * b * self.sx
            + b * b * self.sxx;
        (sse.max(0.0) / self.n).sqrt()
    }

    pub(super) fn span(&self) -> f32 {
        self.x1 - self.x0 + 1.0
    }

    /// The length along the line (a sill seen in perspective is longer
    /// than its span across the photo).
    fn length(&self) -> f32 {
        self.span() * (1.0 + self.line().1.powi(2)).sqrt()
    }
}

/// Detects ledges; polylines in analysis pixels. `storey`: the storey
/// height in analysis pixels, if known (short weak ledges must repeat at
/// it).
pub fn detect(f: &Features, class: &[Class], storey: Option<f32>) -> Vec<Ledge> {
    let (w, h) = (f.w, f.h);
    if w < 8 || h < 8 {
        return Vec::new();
    }
    let l = box_mean(&f.luma, w, h, 1);
    let at = |x: usize, y: usize| l[y * w + x];
    let wall = |x: usize, y: usize| class[y * w + x] == Class::Wall;
    // Step down across the row: positive where bright above, dark below.
    let mut step = vec![0f32; w * h];
    for y in 1..h - 1 {
        for x in 0..w {
            step[y * w + x] = at(x, y - 1) - at(x, y + 1);
        }
    }
    let mut edge = vec![false; w * h];
    for y in 2..h - 2 {
        for x in 1..w - 1 {
            let s = step[y * w + x];
            let gx = (at(x + 1, y) - at(x - 1, y)).abs();
            edge[y * w + x] = s > MIN_STEP
                && gx < s
                && s >= step[(y - 1) * w + x]
                && s > step[(y + 1) * w + x]
                && wall(x, (y + 2).min(h - 1))
                && wall(x, y - 2);
        }
    }
    let chains = trace(&edge, &step, w, h);
    let mut lines = join(chains, w);
    // A close-up (all wall) is texture: only long ledges are sources there.
    if class.iter().all(|&c| c == Class::Wall) {
        lines.retain(|fit| fit.span() >= 0.25 * w as f32);
    }
    let lines: Vec<Fit> = suppress(lines, h)
        .into_iter()
        .filter_map(|fit| off_a_silhouette(&l, f, fit))
        .collect();
    // Where steps of the wall's tone start, and how sure they are left.
    let mut doubts = Vec::new();
    // Where lines that are one lap of a lapped wall start (see `laps`).
    let mut lapped = Vec::new();
    let mut out: Vec<Ledge> = lines
        .iter()
        .map(|fit| (fit, kind_of(f, class, fit)))
        // Inside a window: not a ledge. A window head keeps its frame
        // (the surround runs on above it up to the hood; measured on CMP,
        // dropping those loses hoods: recall 0.838 -> 0.786).
        .filter(|&(fit, kind)| kind == LedgeKind::WindowHead || !crosses_a_frame(f, fit))
        // Slanted: a wall seen in perspective, where cables and cracks
        // slant as its sills do; a sill has another surface above.
        .filter(|&(fit, _)| fit.line().1.abs() <= slants::LEVEL || !a_line_on_one_surface(f, fit))
        .map(|(fit, kind)| match kind {
            LedgeKind::WindowHead => (fit, kind),
            _ if tops_a_window(f, fit) => (fit, LedgeKind::WindowHead),
            _ => (fit, kind),
        })
        .filter_map(|(fit, kind)| {
            let (x0, x1) = (fit.x0, fit.x1 + 1.0);
            let strength = fit.strength / fit.n;
            let confidence = ((strength / 0.25).min(1.0)
                * (fit.span() / (0.08 * w as f32)).min(1.0).sqrt())
            .clamp(0.05, 1.0);
            let start = [x0, fit.y_at(x0) + 1.5];
            if laps::is_lap(f, fit) {
                lapped.push(start);
            }
            match recovery(f, fit) {
                Some(r) if kind != LedgeKind::WindowHead && r < STEP_DROP => return None,
                Some(r) if r < STEP_SURE && !opens_below(f, class, fit, kind) => {
                    doubts.push((start, r.max(0.0) / STEP_SURE))
                }
                _ => {}
            }
            Some(Ledge {
                kind,
                polyline: vec![start, [x1, fit.y_at(x1) + 1.5]],
                confidence,
            })
        })
        .collect();
    out.extend(roof::roof_line(f, class));
    out.sort_by(|a, b| b.confidence.total_cmp(&a.confidence));
    // Laps take no place among the ledges kept and support no other line
    // one storey away; they stay only for the course check below.
    let (laps, mut out): (Vec<Ledge>, Vec<Ledge>) = out
        .into_iter()
        .partition(|l| lapped.contains(&l.polyline[0]));
    out.truncate(MAX_LEDGES);
    if let Some(storey) = storey {
        out = without(out, |ls, i| alone(ls, i, storey, w, h));
    }
    let reach = slants::reach(storey.unwrap_or(0.1 * h as f32));
    out = without(out, |ls, i| slants::against_the_slant(ls, i, reach));
    out.extend(laps);
    out.sort_by(|a, b| {
        a.polyline[0][1]
            .total_cmp(&b.polyline[0][1])
            .then(a.polyline[0][0].total_cmp(&b.polyline[0][0]))
    });
    let out = without(out, |ls, i| courses::is_course(ls, i, h as f32));
    let mut out = match super::vehicles::street_top(f, class) {
        Some(top) => without(out, |ls, i| on_a_car(&ls[i], &top, h)),
        None => out,
    };
    // Laps go after the course check, which stacks each line with all
    // traced (a stack of laps dropped before it leaves its laps that the
    // laps test cannot tell, by a trim board or a rail, standing alone).
    out.retain(|l| !lapped.contains(&l.polyline[0]));
    // A step's confidence falls last: the storey and course checks above
    // weigh ledges by the edge alone (lowered before them, CMP recall fell
    // to 4593, under the floor).
    for l in &mut out {
        if let Some(&(_, k)) = doubts.iter().find(|(p, _)| *p == l.polyline[0]) {
            l.confidence = (l.confidence * k).max(0.05);
        }
    }
    roof::shed_into_ledges(out, w, h)
}

/// True when the line is a window head over glass or standing on a
/// window's jambs: the dark below it is an opening's.
fn opens_below(f: &Features, class: &[Class], fit: &Fit, kind: LedgeKind) -> bool {
    kind == LedgeKind::WindowHead && (glass_below(class, f.w, f.h, fit) || tops_a_window(f, fit))
}

/// True when ledge `l` (not a roof line) lies, over at least half its
/// columns, less than [`CAR_HEIGHT`] of the height `h` above the street's
/// top `top` (per column, see [`super::vehicles::street_top`]): where
/// parked cars stand in front of the wall, whose roofs, windscreens and
/// body lines make the same bright-over-dark edges as sills and heads.
fn on_a_car(l: &Ledge, top: &[usize], h: usize) -> bool {
    let band = CAR_HEIGHT * h as f32;
    let ([x0, y0], [x1, y1]) = (l.polyline[0], l.polyline[l.polyline.len() - 1]);
    if l.kind == LedgeKind::RoofLine || x1 <= x0 || x1 - x0 > CAR_LENGTH * top.len() as f32 {
        return false;
    }
    let cols = (x0.max(0.0) as usize..(x1 as usize).min(top.len())).collect::<Vec<_>>();
    let near = cols
        .iter()
        .filter(|&&x| {
            let y = y0 + (y1 - y0) * (x as f32 + 0.5 - x0) / (x1 - x0);
            top[x] as f32 - y < band
        })
        .count();
    2 * near >= cols.len().max(1)
}

/// `ledges` without those `drop` flags, each judged against all of them.
fn without(ledges: Vec<Ledge>, drop: impl Fn(&[Ledge], usize) -> bool) -> Vec<Ledge> {
    let dropped: Vec<bool> = (0..ledges.len()).map(|i| drop(&ledges, i)).collect();
    ledges
        .into_iter()
        .zip(dropped)
        .filter_map(|(l, d)| (!d).then_some(l))
        .collect()
}

/// True when ledge `i` is short (under [`ALONE_SPAN`] of the width `w`),
/// weak (under [`ALONE_CONFIDENCE`]) and alone: no other ledge lies one
/// storey above or below it (within a tenth of the storey or 1.5% of the
/// height `h`) over at least half the shorter one's columns; a ledge
/// slanted (a wall seen in perspective, [`slants`]), long or short, weak
/// or sure, needs another slanted the same way a few storeys above or
/// below ([`slants::storeys_apart`]). Sills,
/// heads and hoods repeat from storey to storey; a stain, a crack or a
/// brick course does not (on CMP, with [`MIN_STEP`] 0.045: recall 0.819 (offline)
/// -> 0.808, precision 0.302 -> 0.325; see BENCHMARKS.md, sixth pass).
fn alone(ledges: &[Ledge], i: usize, storey: f32, w: usize, h: usize) -> bool {
    let l = &ledges[i];
    let ends = |l: &Ledge| (l.polyline[0], l.polyline[l.polyline.len() - 1]);
    let (a, b) = ends(l);
    let oblique = slants::way(l) != 0.0;
    if l.kind == LedgeKind::RoofLine
        || !oblique && (b[0] - a[0] >= ALONE_SPAN * w as f32 || l.confidence >= ALONE_CONFIDENCE)
    {
        return false;
    }
    let y = (a[1] + b[1]) / 2.0;
    let near = (0.1 * storey).max(0.015 * h as f32);
    !ledges.iter().enumerate().any(|(j, o)| {
        let (c, d) = ends(o);
        let overlap = b[0].min(d[0]) - a[0].max(c[0]);
        let yo = (c[1] + d[1]) / 2.0;
        let storeys = if oblique && slants::slope(o) * slants::slope(l) > 0.0 {
            slants::storeys_apart(yo - y, storey)
        } else {
            [-storey, storey]
                .iter()
                .any(|s| (yo - (y + s)).abs() < near)
        };
        j != i && overlap >= 0.5 * (b[0] - a[0]).min(d[0] - c[0]) && storeys
    })
}

/// `fit` with each end taken back off the silhouette of a surface in
/// front slanting in under it ([`silhouette::end_before`]), or None when
/// too little is left (under [`trace`]'s least length).
fn off_a_silhouette(l: &[f32], f: &Features, mut fit: Fit) -> Option<Fit> {
    let p = silhouette::Planes {
        l,
        rgb: &f.rgb,
        w: f.w,
        h: f.h,
    };
    let (x0, x1) = (fit.x0, fit.x1);
    if let Some(x) = silhouette::end_before(&p, x1, fit.y_at(x1), true) {
        fit.x1 = fit.x1.min(x.floor());
    }
    if let Some(x) = silhouette::end_before(&p, x0, fit.y_at(x0), false) {
        fit.x0 = fit.x0.max(x.ceil());
    }
    let trimmed = (fit.x0, fit.x1) != (x0, x1);
    (!trimmed || fit.span() >= (0.03 * f.w as f32).max(8.0)).then_some(fit)
}

/// Follows edge pixels left to right, one row of jitter per column and
/// gaps of up to 3 columns; keeps straight, long, level-ish chains.
fn trace(edge: &[bool], step: &[f32], w: usize, h: usize) -> Vec<Fit> {
    let min_len = (0.03 * w as f32).max(8.0);
    let mut used = vec![false; w * h];
    let mut out = Vec::new();
    for x in 0..w {
        for y in 0..h {
            let i = y * w + x;
            if !edge[i] || used[i] {
                continue;
            }
            let mut fit = Fit::default();
            let (mut cx, mut cy) = (x, y);
            used[i] = true;
            fit.add(cx as f32, cy as f32, step[i]);
            'follow: loop {
                for dx in 1..=3 {
                    let nx = cx + dx;
                    if nx >= w {
                        break 'follow;
                    }
                    for dy in [0i64, -1, 1] {
                        let ny = cy as i64 + dy;
                        if ny < 0 || ny >= h as i64 {
                            continue;
                        }
                        let j = ny as usize * w + nx;
                        if edge[j] && !used[j] {
                            used[j] = true;
                            (cx, cy) = (nx, ny as usize);
                            fit.add(cx as f32, cy as f32, step[j]);
                            continue 'follow;
                        }
                    }
                }
                break;
            }
            if fit.length() >= min_len
                && fit.n >= 0.6 * fit.span()
                && fit.line().1.abs() <= MAX_SLOPE
                && fit.rms() <= 1.5
            {
                out.push(fit);
            }
        }
    }
    out
}

/// Joins chains that continue one another across a small gap (a cornice
/// broken by a drainpipe), but not separate sills of neighbouring windows.
fn join(mut chains: Vec<Fit>, w: usize) -> Vec<Fit> {
    chains.sort_by(|a, b| a.x0.total_cmp(&b.x0));
    let gap = (0.01 * w as f32).max(3.0);
    let mut out: Vec<Fit> = Vec::new();
    for c in chains {
        let hit = out.iter_mut().find(|o| {
            c.x0 > o.x1 - 2.0
                && c.x0 - o.x1 <= gap
                && (o.y_at(c.x0) - c.y_at(c.x0)).abs() <= 1.5
                && (o.y_at(o.x1) - c.y_at(o.x1)).abs() <= 1.5
        });
        match hit {
            Some(o) => o.merge(&c),
            None => out.push(c),
        }
    }
    out
}

/// Of parallel lines closer than 2% of the height that overlap over half
/// the shorter one (the slats of a shutter, the steps of a moulding), keeps
/// the strongest.
fn suppress(mut lines: Vec<Fit>, h: usize) -> Vec<Fit> {
    let weight = |f: &Fit| f.strength;
    lines.sort_by(|a, b| weight(b).total_cmp(&weight(a)).then(a.x0.total_cmp(&b.x0)));
    let near = 0.02 * h as f32;
    let mut kept: Vec<Fit> = Vec::new();
    for l in lines {
        let clash = kept.iter().any(|k| {
            let overlap = l.x1.min(k.x1) - l.x0.max(k.x0);
            let xm = (l.x0.max(k.x0) + l.x1.min(k.x1)) / 2.0;
            overlap > 0.5 * l.span().min(k.span()) && (l.y_at(xm) - k.y_at(xm)).abs() < near
        });
        if !clash {
            kept.push(l);
        }
    }
    kept
}

#[cfg(test)]
mod tests {
    use super::super::synthetic::sky_over_wall;
    use super::*;
    use crate::photo::Photo;

    #[test]
    fn an_edge_between_a_windows_jambs_is_no_ledge_its_sill_is() {
        // Wall 0.7; a window (glass 0.2, white jambs at x 60..64 and
        // 136..140) with a meeting rail at y 136..140 over a short lower
        // pane; below it the bottom rail, a sill wider than the window and
        // its shadow ending at y 161.
        let img = image::RgbImage::from_fn(200, 200, |x, y| {
            let v = match (x, y) {
                (60..64 | 136..140, 40..154) => 0.95,
                (64..136, 136..140 | 150..154) => 0.95,
                (64..136, 40..150) => 0.2,
                (50..150, 154..158) => 0.9,
                (50..150, 158..161) => 0.35,
                _ => 0.7,
            };
            image::Rgb([(v * 255.0) as u8; 3])
        });
        let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 200);
        let ledges = detect(&f, &vec![Class::Wall; 200 * 200], None);
        let near = |y0: f32, y1: f32| {
            ledges
                .iter()
                .filter(|l| l.kind != LedgeKind::WindowHead)
                .any(|l| (y0..y1).contains(&l.polyline[0][1]))
        };
        assert!(!near(130.0, 150.0), "the meeting rail: {ledges:?}");
        assert!(near(156.0, 163.0), "the sill: {ledges:?}");
    }

    #[test]
    fn a_line_standing_on_a_windows_jambs_is_its_head_without_jambs_it_is_not() {
        // Wall 0.7; at y 60 a bright-over-dark edge 72 px wide over a
        // dark strip (0.2) six rows deep, then wall-light again: a ledge's
        // shadow band, or, with `jambs` (white, 0.95) running down both
        // sides from the edge and none above it, the top of a window whose
        // blind (as light as the wall) fills the opening under a strip of
        // glass, so the dark does not go on below the edge.
        let kind_at_top = |jambs: bool| {
            let img = image::RgbImage::from_fn(200, 200, |x, y| {
                let v = match (x, y) {
                    (60..64 | 136..140, 60..150) if jambs => 0.95,
                    (64..136, 60..66) => 0.2,
                    _ => 0.7,
                };
                image::Rgb([(v * 255.0) as u8; 3])
            });
            let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 200);
            let ledges = detect(&f, &vec![Class::Wall; 200 * 200], None);
            ledges
                .iter()
                .find(|l| (l.polyline[0][1] - 61.0).abs() < 4.0)
                .map(|l| l.kind)
        };
        assert_eq!(kind_at_top(true), Some(LedgeKind::WindowHead));
        let plain = kind_at_top(false);
        assert!(
            plain.is_some_and(|k| k != LedgeKind::WindowHead),
            "{plain:?}"
        );
    }

    #[test]
    fn a_dark_that_goes_on_below_is_a_window_head_a_thin_shadow_is_not() {
        // Wall 0.7; a ledge whose shadow ends 4 rows down at y 60; the top
        // of a tall opening (too big to be glass) at y 120.
        let img = image::RgbImage::from_fn(200, 200, |x, y| {
            let v = match (x, y) {
                (30..170, 60..64) => 0.3,
                (30..170, 120..190) => 0.2,
                _ => 0.7,
            };
            image::Rgb([(v * 255.0) as u8; 3])
        });
        let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 200);
        let ledges = detect(&f, &vec![Class::Wall; 200 * 200], None);
        let at = |y: f32| {
            ledges
                .iter()
                .find(|l| (l.polyline[0][1] - y).abs() < 4.0)
                .map(|l| l.kind)
        };
        assert!(
            at(61.0).is_some_and(|k| k != LedgeKind::WindowHead),
            "{ledges:?}"
        );
        assert_eq!(at(121.0), Some(LedgeKind::WindowHead), "{ledges:?}");
    }

    #[test]
    fn in_a_street_a_ledge_at_a_cars_height_is_dropped_one_higher_or_longer_stays() {
        // A wall (0.7) down to row 140 over a road with diagonal stripes
        // (seen in perspective); a bright edge over a thin shadow over
        // columns `x0..x1` at rows `y..y + 8`.
        let (w, h) = (240u32, 200u32);
        let found = |(x0, x1): (u32, u32), y: u32| {
            let img = image::RgbImage::from_fn(w, h, |x, yy| {
                let v = match (x0..x1).contains(&x) {
                    _ if yy >= 140 => {
                        if (x + yy) % 8 < 4 {
                            0.45
                        } else {
                            0.38
                        }
                    }
                    true if (y..y + 4).contains(&yy) => 0.9,
                    true if (y + 4..y + 8).contains(&yy) => 0.35,
                    _ => 0.7,
                };
                image::Rgb([(v * 255.0) as u8; 3])
            });
            let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), w);
            let class: Vec<Class> = (0..(w * h) as usize)
                .map(|i| {
                    if i >= 140 * w as usize {
                        Class::Ground
                    } else {
                        Class::Wall
                    }
                })
                .collect();
            let ledges = detect(&f, &class, None);
            ledges
                .iter()
                .any(|l| (l.polyline[0][1] - (y + 4) as f32).abs() < 4.0)
        };
        // 10 rows above the road (0.05 of the height), 40 columns long.
        assert!(!found((90, 130), 126), "a ledge on a car");
        assert!(found((90, 130), 60), "the same ledge high on the wall");
        assert!(found((10, 230), 126), "a ledge longer than a car");
    }

    #[test]
    fn a_short_weak_edge_alone_is_texture_sills_one_storey_apart_are_ledges() {
        // Wall 0.7; three storeys of 100 px, each with a sill (0.9 over a
        // shadow 0.45) under the same window columns; between the first two
        // a faint, short stain edge (0.78 over 0.66) that nothing repeats.
        let img = image::RgbImage::from_fn(400, 340, |x, y| {
            let v = match (x, y % 100, y) {
                (170..190, _, 100..104) => 0.78,
                (170..190, _, 104..108) => 0.66,
                (60..110 | 260..310, 60..64, ..300) => 0.9,
                (60..110 | 260..310, 64..68, ..300) => 0.45,
                _ => 0.7,
            };
            image::Rgb([(v * 255.0) as u8; 3])
        });
        // Sky along the top: not a close-up, where only long ledges count.
        let (f, class) = sky_over_wall(img, 30);
        let stain = |ls: &[Ledge]| {
            ls.iter()
                .any(|l| (l.polyline[0][1] - 105.0).abs() < 4.0 && l.polyline[0][0] > 150.0)
        };
        let sills = |ls: &[Ledge]| {
            ls.iter()
                .filter(|l| {
                    let y = l.polyline[0][1] % 100.0;
                    l.polyline[0][0] < 120.0 && (y - 65.0).abs() < 4.0
                })
                .count()
        };
        let unknown = detect(&f, &class, None);
        assert!(
            stain(&unknown),
            "without a storey the stain stays: {unknown:?}"
        );
        let known = detect(&f, &class, Some(100.0));
        assert!(!stain(&known), "{known:?}");
        assert_eq!(sills(&known), 3, "{known:?}");
    }

    #[test]
    fn a_step_of_the_walls_tone_is_no_ledge_a_shadow_band_that_ends_is() {
        // Wall 0.7 over 400 x 400. A ledge's 4-row shadow at y 100; a
        // dark band 18 rows tall at y 180 (darkening downward: it does not
        // come back within 8 texture radii, yet ends before a window
        // head's reach); a step to 0.55 at y 280 that goes on to the foot,
        // wall to wall (a siding colour change: a window head by its dark,
        // with no glass and no jambs).
        let img = image::RgbImage::from_fn(400, 400, |x, y| {
            let v = match (x, y) {
                (60..340, 100..104) => 0.35,
                (60..340, 180..198) => 0.4 - 0.002 * (y - 180) as f32,
                (_, 280..) => 0.55,
                _ => 0.7,
            };
            image::Rgb([(v * 255.0) as u8; 3])
        });
        let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 400);
        let ledges = detect(&f, &vec![Class::Wall; 400 * 400], None);
        let at = |y: f32| {
            ledges
                .iter()
                .find(|l| (l.polyline[0][1] - y).abs() < 4.0)
                .map(|l| (l.kind, l.confidence))
        };
        assert!(at(101.0).is_some_and(|(_, c)| c > 0.5), "{ledges:?}");
        assert_eq!(at(181.0), None, "{ledges:?}");
        let step = at(281.0);
        assert!(
            step.is_some_and(|(k, c)| k == LedgeKind::WindowHead && c < 0.1),
            "{ledges:?}"
        );
    }
}
