//! The roof line: where the wall meets the sky. Rain leaves a roof at its
//! eaves, so the line runs along the lower edge of the eave's tiles,
//! fascia or coping, and not up a gable's slope.

use super::features::{Features, l1};
use super::wall::Class;
use super::{Ledge, LedgeKind};

/// Where wall lies just under sky: runs of columns, sampled every few
/// pixels, as polylines along the eave's lower edge ([`eave`]).
pub(super) fn roof_line(f: &Features, class: &[Class]) -> Vec<Ledge> {
    let (w, h) = (f.w, f.h);
    let top: Vec<Option<usize>> = (0..w)
        .map(|x| (1..h).find(|&y| under_sky(f, class, x, y)))
        .collect();
    let lamps = super::lamps::lit(f, class);
    let mut out = Vec::new();
    let mut x = 0;
    let step = (w / 64).max(2);
    while x < w {
        if top[x].is_none() {
            x += 1;
            continue;
        }
        let start = x;
        while x < w
            && top[x].is_some()
            && (x == start
                || matches!((top[x], top[x - 1]), (Some(a), Some(b)) if a.abs_diff(b) <= h / 50 + 1))
        {
            x += 1;
        }
        if x - start >= w / 20 {
            let mut columns: Vec<usize> = (start..x).step_by(step).collect();
            columns.push(x - 1);
            let rows: Vec<f32> = columns
                .iter()
                .map(|&c| eave(f, c, top[c].unwrap_or(0)))
                .collect();
            // A median of three: one column's tile or gutter bracket does
            // not kink the line.
            let mut pts: Vec<[f32; 2]> = columns
                .iter()
                .enumerate()
                .map(|(i, &c)| {
                    let mut near = [
                        rows[i.saturating_sub(1)],
                        rows[i],
                        rows[(i + 1).min(rows.len() - 1)],
                    ];
                    near.sort_by(f32::total_cmp);
                    [c as f32, near[1]]
                })
                .collect();
            if let Some(last) = pts.last_mut() {
                last[0] = x as f32;
            }
            for eave in eaves(pts, (w / 20) as f32) {
                let span = eave[eave.len() - 1][0] - eave[0][0];
                let line = Ledge {
                    kind: LedgeKind::RoofLine,
                    polyline: eave,
                    confidence: (span / w as f32).sqrt().min(1.0),
                };
                out.extend(off_lamps(&line, &lamps, step, w, h));
            }
        }
    }
    out
}

/// The deepest rim of vegetation between the sky and a wall's top, as a
/// share of the height, that the roof line looks through [choice: 1/200,
/// 2-3 rows at 512 (clean33's rule, BENCHMARKS.md thirty-second pass): the
/// sky's edge against dark tiles or a stone coping blends to a colour the
/// classes take for leaves (img_2329: a one- or two-row rim over most of a
/// roof's length broke its roof line into pieces under the least run, and
/// the roof lines of img_2343, IMG_4180 and IMG_7253 were all lost so); a
/// tree in front of the wall top is deeper].
const RIM: f32 = 1.0 / 200.0;
/// Through a rim, the wall's top must not be greener than red by more
/// than this (0..1) [choice: 0.02. Under the rims LabelMeFacade's village
/// photos show, tiles, copings and render run from g - r = -0.11 to
/// +0.02; a hillside or a tree crown taken for wall under the rim (its
/// leaves' edge against the sky) +0.03 to +0.06: streaks on a hill].
const RIM_GREEN: f32 = 0.02;

/// True when row `y` of column `x` is wall whose top meets the sky: right
/// under it, or under a rim of vegetation at most [`RIM`] deep when the
/// wall there is not green ([`RIM_GREEN`]).
fn under_sky(f: &Features, class: &[Class], x: usize, y: usize) -> bool {
    let w = f.w;
    if class[y * w + x] != Class::Wall {
        return false;
    }
    let rim = ((RIM * f.h as f32).round() as usize).max(1);
    let above = (1..=(rim + 1).min(y)).find(|&d| class[(y - d) * w + x] != Class::Vegetation);
    match above {
        Some(1) => class[(y - 1) * w + x] == Class::Sky,
        Some(d) if class[(y - d) * w + x] == Class::Sky => {
            let [r, g, _] = f.rgb_at(y * w + x);
            let rows = y..(y + 3).min(f.h);
            let n = rows.len().max(1) as f32;
            let mut top = [0.0f32; 3];
            for v in rows {
                let c = f.rgb_at(v * w + x);
                (0..3).for_each(|k| top[k] += c[k] / n);
            }
            g - r <= RIM_GREEN && l1(f.rgb_at((y - d) * w + x), top) >= RIM_STEP
        }
        _ => false,
    }
}

/// Through a rim, the sky above it and the wall's top below it (its first
/// three rows) differ in colour by at least this (L1 over RGB, 0..3)
/// [choice: 0.4. A rim the classes call vegetation is the blend of the sky
/// with a top of another colour: dark tiles or a stone coping under a grey
/// or blue sky, 0.5-0.8 on IMG_4180's eaves; img_2343's tower, a pale grey
/// upper band of its wall taken for sky over yellow paint, differs by
/// 0.25, and the roof line traced through its one-row rim laid a
/// hard-edged brown blot on the plain wall (blind review p75)].
const RIM_STEP: f32 = 0.4;

/// How far above a projecting ledge (cornice, coping, balcony) a roof line
/// sheds into it, as a share of the height [choice: 0.05. The water off a
/// parapet's top runs down its face and leaves the wall at the cornice's
/// drip; traced as two sources, the roof line's plumes were cut by the
/// ledge a few rows below and left a zig-zag of stained triangles between
/// the two lines (IMG_8456: a parapet 20 rows, 0.04 of the height, over
/// its cornice; blind review p75)].
const SHEDS_INTO: f32 = 0.05;

/// How far above a long ledge of any kind but a sill a roof line sheds
/// into it, as a share of the height [choice: 0.1. A pitched roof seen
/// from the street shows its tiles between the sky and the eave's lower
/// edge; the ledge finder finds that edge (often as a window head, one
/// long line), and the roof line on the tiles' upper edge is no wall's
/// top: traced, its water clouded the tiles and the wall as one surface
/// (IMG_8498: tiles 0.08 of the height deep; blind reviews p77 and p78)]
/// ...
const ROOF_DEPTH: f32 = 0.1;
/// ... when that ledge spans at least this share of the width
/// [choice: 0.1, longer than one window's head].
const EAVE_SPAN: f32 = 0.1;

/// `ledges` with each roof line's points that have a projecting ledge
/// (cornice, coping or balcony) less than [`SHEDS_INTO`] of the height
/// `h` below them, or a long ledge other than a sill less than
/// [`ROOF_DEPTH`] below them (an eave under its roof's tiles), taken off:
/// the lower line is where the water leaves the wall. What is left of a
/// roof line stays where it runs at least a twentieth of the width `w`.
pub(super) fn shed_into_ledges(ledges: Vec<Ledge>, w: usize, h: usize) -> Vec<Ledge> {
    let (depth, roof) = (SHEDS_INTO * h as f32, ROOF_DEPTH * h as f32);
    // The ledge a roof line's point at (x, y) sheds into, if any.
    let into = |x: f32, y: f32| {
        ledges.iter().position(|l| {
            let (a, b) = (l.polyline[0][0], l.polyline[l.polyline.len() - 1][0]);
            let reach = match l.kind {
                LedgeKind::RoofLine | LedgeKind::Sill => 0.0,
                _ if (a - b).abs() >= EAVE_SPAN * w as f32 => roof,
                LedgeKind::Cornice | LedgeKind::Coping | LedgeKind::Balcony => depth,
                _ => 0.0,
            };
            let below = super::courses::y_at(l, x) - y;
            reach > 0.0 && (a.min(b)..=a.max(b)).contains(&x) && (0.0..=reach).contains(&below)
        })
    };
    // A ledge that takes a roof's water is where that water leaves the
    // wall: as sure a source as the roof line was, and a window head or
    // course doing so is the roof's eave (the rain sheds it as one; as a
    // window head it shed as a window's twin, 0.8-2.9 levels on
    // IMG_8498's face under its eave against 3.4-4.0 with twins off).
    let mut eave: Vec<Option<f32>> = vec![None; ledges.len()];
    for l in ledges.iter().filter(|l| l.kind == LedgeKind::RoofLine) {
        for p in &l.polyline {
            if let Some(i) = into(p[0], p[1]) {
                eave[i] = Some(eave[i].unwrap_or(0.0).max(l.confidence));
            }
        }
    }
    let mut out = Vec::new();
    for (l, eave) in ledges.iter().zip(eave) {
        match (l.kind, eave) {
            (LedgeKind::RoofLine, _) => out.extend(split(l, w, |p| into(p[0], p[1]).is_some())),
            (_, None) => out.push(l.clone()),
            (kind, Some(roof)) => out.push(Ledge {
                kind: match kind {
                    LedgeKind::WindowHead | LedgeKind::StringCourse => LedgeKind::RoofLine,
                    kind => kind,
                },
                confidence: l.confidence.max(roof),
                ..l.clone()
            }),
        }
    }
    out
}

/// How far below a roof line a lit lamp takes its point off, as a share
/// of the height [choice: 0.25, the reach of a roof line's plume on a
/// photo of a few storeys; IMG_8365's lamp lies 0.17 of the height under
/// the church's eave] ...
const LAMP_REACH: f32 = 0.25;
/// ... and at least this far [choice: 0.05: what is clipped white right
/// under the line is the eave's own sunlit edge or fascia (IMG_4180's
/// white parapet top, 5 rows under its line), not a lamp hung on the
/// wall].
const LAMP_CLEAR: f32 = 0.05;

/// Roof line `l` without its points over a lit lamp (one of `lamps`, see
/// [`super::lamps`]) between [`LAMP_CLEAR`] and [`LAMP_REACH`] below it,
/// within half a point's spacing `step` of its columns.
fn off_lamps(l: &Ledge, lamps: &[[usize; 3]], step: usize, w: usize, h: usize) -> Vec<Ledge> {
    let (clear, reach) = (LAMP_CLEAR * h as f32, LAMP_REACH * h as f32);
    let near = (step / 2 + 1) as f32;
    split(l, w, |p| {
        lamps.iter().any(|&[x0, x1, y0]| {
            p[0] + near >= x0 as f32
                && p[0] - near <= x1 as f32
                && (p[1] + clear..=p[1] + reach).contains(&(y0 as f32))
        })
    })
}

/// The pieces of line `l` between its points `drop` takes off, those at
/// least a twentieth of the width `w` long.
fn split(l: &Ledge, w: usize, drop: impl Fn([f32; 2]) -> bool) -> Vec<Ledge> {
    let mut out = Vec::new();
    let mut run: Vec<[f32; 2]> = Vec::new();
    for (i, &p) in l.polyline.iter().enumerate() {
        let dropped = drop(p);
        if !dropped {
            run.push(p);
        }
        if dropped || i + 1 == l.polyline.len() {
            let piece = std::mem::take(&mut run);
            if piece.len() >= 2 && piece[piece.len() - 1][0] - piece[0][0] >= (w / 20) as f32 {
                out.push(Ledge {
                    polyline: piece,
                    ..l.clone()
                });
            }
        }
    }
    out
}

/// The steepest a roof line runs, rows per column [choice: 0.7, about 35
/// degrees: rain leaves a pitched roof at its eaves, not along its verges
/// (`how-facades-age.md`, "Where water goes"), so the sky's edge up a
/// gable's slope sheds nothing down the gable (LabelMeFacade IMG_6469: a
/// roof line traced up the slope of the gable in front at 58 degrees laid
/// a stain on its brick that stopped on a level line); an eave seen in a
/// street photo's perspective stays under it].
const PITCH: f32 = 0.7;

/// The stretches of a roof line's points `pts` that are not on a slope
/// (two or more successive steps steeper than [`PITCH`]; one steep step
/// is a jog of the eave, a gutter bracket or a chimney's foot, and stays)
/// and at least `least` columns long.
fn eaves(pts: Vec<[f32; 2]>, least: f32) -> Vec<Vec<[f32; 2]>> {
    let steep: Vec<bool> = pts
        .windows(2)
        .map(|s| (s[1][1] - s[0][1]).abs() > PITCH * (s[1][0] - s[0][0]).abs().max(1.0))
        .collect();
    let slope = |i: usize| {
        steep[i] && (i > 0 && steep[i - 1] || steep.get(i + 1).copied().unwrap_or(false))
    };
    let mut out: Vec<Vec<[f32; 2]>> = Vec::new();
    let mut run: Vec<[f32; 2]> = Vec::new();
    let mut close = |run: &mut Vec<[f32; 2]>| {
        if run.len() >= 2 && run[run.len() - 1][0] - run[0][0] >= least {
            out.push(std::mem::take(run));
        }
        run.clear();
    };
    for (i, p) in pts.iter().enumerate() {
        if i > 0 && slope(i - 1) {
            close(&mut run);
        }
        run.push(*p);
    }
    close(&mut run);
    out
}

/// How far below the sky an eave, fascia or coping reaches, as a share of
/// the height [choice: an eave band 0.2-0.4 m deep is 1-3% of the height of
/// a photo showing three to six storeys].
const EAVE_DEPTH: f32 = 0.03;
/// A colour step (L1, means of the two rows above and below) that ends an
/// eave [choice: roof tiles over render step by about 1; a plain wall's
/// texture by under 0.1].
const EAVE_STEP: f32 = 0.25;

/// The line's row at column `x` under a roof whose wall begins at row
/// `top` under the sky: the lowest strong colour step within
/// [`EAVE_DEPTH`] below it, the lower edge of the tiles, fascia or coping
/// where the wall face begins and water drips off; a row below `top` when
/// there is none. Blind review 18 caught drips that began on the tiles of
/// an eave, darkening them.
fn eave(f: &Features, x: usize, top: usize) -> f32 {
    let (w, h) = (f.w, f.h);
    let depth = ((EAVE_DEPTH * h as f32).round() as usize).max(2);
    let (x0, x1) = (x.saturating_sub(1), (x + 1).min(w - 1));
    let mean = |y0: usize| {
        let mut sum = [0.0f32; 3];
        for y in y0..y0 + 2 {
            for c in x0..=x1 {
                let v = f.rgb_at(y * w + c);
                (0..3).for_each(|k| sum[k] += v[k]);
            }
        }
        sum.map(|v| v / (2 * (x1 - x0 + 1)) as f32)
    };
    let steps: Vec<(usize, f32)> = (top + 2..=(top + depth).min(h.saturating_sub(2)))
        .map(|y| (y, l1(mean(y - 2), mean(y))))
        .collect();
    // The lowest run of strong steps, and its strongest row: the edge
    // itself, not the rows whose means straddle it.
    let Some(last) = steps.iter().rposition(|s| s.1 > EAVE_STEP) else {
        return top as f32 + 1.0;
    };
    let first = steps[..last]
        .iter()
        .rposition(|s| s.1 <= EAVE_STEP)
        .map_or(0, |i| i + 1);
    steps[first..=last]
        .iter()
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map_or(top as f32 + 1.0, |s| s.0 as f32)
}

#[cfg(test)]
mod tests {
    use super::super::synthetic::sky_over_wall;
    use super::*;
    use crate::photo::Photo;

    /// 400 x 400 classes: sky over rows 0..38, a two-row rim the classes
    /// call vegetation (the sky's blend with the wall's top), wall below.
    fn rim_classes() -> Vec<Class> {
        (0..400 * 400)
            .map(|i| match i / 400 {
                0..38 => Class::Sky,
                38..40 => Class::Vegetation,
                _ => Class::Wall,
            })
            .collect()
    }

    #[test]
    fn a_gables_slope_is_no_roof_line_its_eave_is() {
        // Sky over a wall whose top is level over x < 100 (row 120), then
        // climbs a gable's slope at 60 degrees (1.7 rows per column) to its
        // apex at x = 160, with sky alone beyond.
        let top = |x: u32| match x {
            0..100 => 120,
            100..160 => 120 - ((x - 100) as f32 * 1.7) as u32,
            _ => 200,
        };
        let img = image::RgbImage::from_fn(200, 200, |x, y| match y < top(x) {
            true => image::Rgb([170, 200, 240]),
            false => image::Rgb([235, 165, 95]),
        });
        let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 200);
        let class: Vec<Class> = (0..200 * 200u32)
            .map(|i: u32| match i / 200 < top(i % 200) {
                true => Class::Sky,
                false => Class::Wall,
            })
            .collect();
        let roofs = roof_line(&f, &class);
        assert_eq!(roofs.len(), 1, "{roofs:?}");
        let p = &roofs[0].polyline;
        assert!(p.iter().all(|q| q[0] <= 110.0), "up the slope: {p:?}");
        assert!(p[0][0] <= 5.0 && p[p.len() - 1][0] >= 90.0, "{p:?}");
    }

    #[test]
    fn a_roof_line_runs_under_the_eaves_tiles_a_plain_wall_top_keeps_its_edge() {
        // Sky to row 40 over a 200 x 200 wall; the left half has a row of
        // dark red tiles (rows 40..45) whose lower edge the water drips
        // from; the right half's top has a faint shade step (texture).
        let img = image::RgbImage::from_fn(200, 200, |x, y| match (x, y) {
            (_, 0..40) => image::Rgb([170, 200, 240]),
            (0..100, 40..45) => image::Rgb([140, 60, 30]),
            (100.., 40..44) => image::Rgb([222, 170, 100]),
            _ => image::Rgb([235, 165, 95]),
        });
        let (f, class) = sky_over_wall(img, 40);
        let roofs = roof_line(&f, &class);
        assert_eq!(roofs.len(), 1, "{roofs:?}");
        let row = |x: f32| {
            let p = &roofs[0].polyline;
            p.iter()
                .min_by(|a, b| (a[0] - x).abs().total_cmp(&(b[0] - x).abs()))
                .unwrap()[1]
        };
        assert!(
            (row(40.0) - 45.0).abs() <= 1.0,
            "under the tiles: {roofs:?}"
        );
        assert!((row(160.0) - 41.0).abs() <= 1.0, "at the sky: {roofs:?}");
    }

    #[test]
    fn a_roof_line_looks_through_a_thin_rim_of_leaves_not_onto_a_green_hill() {
        // Sky to row 38 over a 400 x 400 scene; rows 38..40 the sky's
        // edge, taken for vegetation (img_2329's eaves). The left half is
        // a stone wall with a coping of dark tiles (rows 40..45); the right
        // half a green hillside the classes took for wall.
        let img = image::RgbImage::from_fn(400, 400, |x, y| match (x, y) {
            (_, 0..38) => image::Rgb([170, 200, 240]),
            (_, 38..40) => image::Rgb([110, 130, 120]),
            (0..200, 40..45) => image::Rgb([90, 60, 45]),
            (0..200, _) => image::Rgb([150, 140, 125]),
            _ => image::Rgb([80, 100, 90]),
        });
        let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 400);
        let class = rim_classes();
        let roofs = roof_line(&f, &class);
        assert_eq!(roofs.len(), 1, "one roof line, the wall's: {roofs:?}");
        let p = &roofs[0].polyline;
        let (x0, x1) = (p[0][0], p[p.len() - 1][0]);
        assert!(x0 <= 5.0 && (190.0..=210.0).contains(&x1), "{roofs:?}");
        assert!(
            p.iter().all(|q| (43.0..=46.0).contains(&q[1])),
            "under the tiles: {roofs:?}"
        );
    }

    #[test]
    fn no_roof_line_through_a_rim_between_two_paints_of_one_wall() {
        // img_2343's tower: a pale grey upper band the classes took for
        // sky (rows 0..38) over yellow paint, a one-row rim between them
        // called vegetation; the colours differ by 0.25 (L1), no sky over
        // tiles.
        let img = image::RgbImage::from_fn(400, 400, |_, y| match y {
            0..38 => image::Rgb([195, 190, 185]),
            38..40 => image::Rgb([192, 178, 165]),
            _ => image::Rgb([193, 167, 146]),
        });
        let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 400);
        let class = rim_classes();
        assert!(roof_line(&f, &class).is_empty());
    }

    #[test]
    fn a_roof_line_over_a_cornice_a_few_rows_below_sheds_into_it() {
        // 400 x 400: a roof line at row 60 over x 0..400; a cornice 15
        // rows below it (0.0375 of the height) over x 100..300 and a sill
        // as close over x 320..360 (not projecting: both stay there).
        let line = |kind, x0: f32, x1: f32, y: f32| Ledge {
            kind,
            polyline: (0..=((x1 - x0) / 10.0) as usize)
                .map(|k| [x0 + 10.0 * k as f32, y])
                .collect(),
            confidence: 0.5,
        };
        let ledges = vec![
            line(LedgeKind::RoofLine, 0.0, 400.0, 60.0),
            line(LedgeKind::Cornice, 100.0, 300.0, 75.0),
            line(LedgeKind::Sill, 320.0, 360.0, 72.0),
        ];
        let out = shed_into_ledges(ledges, 400, 400);
        let roofs: Vec<(f32, f32)> = out
            .iter()
            .filter(|l| l.kind == LedgeKind::RoofLine)
            .map(|l| (l.polyline[0][0], l.polyline[l.polyline.len() - 1][0]))
            .collect();
        assert_eq!(roofs, vec![(0.0, 90.0), (310.0, 400.0)], "{out:?}");
        assert_eq!(out.len(), 4, "the cornice and sill kept: {out:?}");
    }

    #[test]
    fn a_roof_line_on_a_pitched_roofs_tiles_sheds_into_its_eave() {
        // 400 x 400: a roof line at row 40 over x 0..400 (the tiles' upper
        // edge); 32 rows below (0.08 of the height) the eave's lower edge,
        // found as a window head, over x 200..380; a window head as far
        // below over x 40..70 (one window's: too short) and a sill over
        // x 100..180: neither takes the roof line's water.
        let line = |kind, x0: f32, x1: f32, y: f32| Ledge {
            kind,
            polyline: vec![[x0, y], [x1, y]],
            confidence: 0.2,
        };
        let roof = Ledge {
            polyline: (0..=40).map(|k| [10.0 * k as f32, 40.0]).collect(),
            confidence: 0.9,
            ..line(LedgeKind::RoofLine, 0.0, 400.0, 40.0)
        };
        let ledges = vec![
            roof,
            line(LedgeKind::WindowHead, 200.0, 380.0, 72.0),
            line(LedgeKind::WindowHead, 40.0, 70.0, 72.0),
            line(LedgeKind::Sill, 100.0, 180.0, 72.0),
        ];
        let out = shed_into_ledges(ledges, 400, 400);
        let seen: Vec<(LedgeKind, f32, f32, f32)> = out
            .iter()
            .map(|l| {
                let (a, b) = (l.polyline[0][0], l.polyline[l.polyline.len() - 1][0]);
                (l.kind, a, b, l.confidence)
            })
            .collect();
        // The roof line is left where no eave is under it (what is left
        // past the eave, x 390..400, is under a twentieth of the width);
        // the eave takes the roof's water as a roof line, with its
        // sureness; the short head and the sill are as they were.
        use LedgeKind::*;
        assert_eq!(
            seen,
            vec![
                (RoofLine, 0.0, 190.0, 0.9),
                (RoofLine, 200.0, 380.0, 0.9),
                (WindowHead, 40.0, 70.0, 0.2),
                (Sill, 100.0, 180.0, 0.2)
            ]
        );
    }

    #[test]
    fn a_roof_line_does_not_run_over_a_lit_lamp_below_it() {
        // IMG_8365: sky to row 40 over a 400 x 400 wall; a lamp glowing
        // (6 x 6, near white, a dim ring) 60 rows under the eave at
        // x 200..206; a clipped white fascia right under the eave at
        // x 300..306 (rows 42..46) is the eave's, no lamp.
        let img = image::RgbImage::from_fn(400, 400, |x, y| match (x, y) {
            (_, 0..40) => image::Rgb([170, 200, 240]),
            (200..206, 100..106) => image::Rgb([255, 252, 240]),
            (197..209, 97..109) => image::Rgb([200, 170, 130]),
            (300..306, 42..46) => image::Rgb([255, 255, 255]),
            _ => image::Rgb([170, 140, 110]),
        });
        let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 400);
        let class: Vec<Class> = (0..400 * 400)
            .map(|i| match i / 400 < 40 {
                true => Class::Sky,
                false => Class::Wall,
            })
            .collect();
        let roofs = roof_line(&f, &class);
        let spans: Vec<(f32, f32)> = roofs
            .iter()
            .map(|l| (l.polyline[0][0], l.polyline[l.polyline.len() - 1][0]))
            .collect();
        assert_eq!(spans.len(), 2, "{roofs:?}");
        assert!(
            spans[0].0 <= 5.0 && (185.0..200.0).contains(&spans[0].1),
            "{spans:?}"
        );
        assert!(
            (206.0..220.0).contains(&spans[1].0) && spans[1].1 >= 395.0,
            "{spans:?}"
        );
    }
}
