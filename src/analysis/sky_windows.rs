//! Pale facades the sky fill took: a white or pale blue front under a
//! blue or white sky whose roof edge is too soft to stop the fill leaves
//! its windows as holes in the sky. Sky around such holes, compact and in
//! groups, is wall again (see [`windows_in_sky`]).

use rayon::prelude::*;

use super::features::{Features, l1};
use super::wall::{CLEAR_BLUE, flood, mean_colour};

/// A window is a hole in the sky (non-sky pixels all around which is sky)
/// of at least this share of the photo's pixels, ... (the four window
/// constants were chosen on LabelMeFacade train's classes, counting the
/// labelled wall and sky pixels the zones would take: area 0.0002 / 0.0003
/// / 0.0006, fill 0.6 / 0.7, one / two / three windows within 1 / 2 / 4
/// sides, zones of 0.5 / 1 / 2 sizes; a lone window, a lamp or a sign,
/// took sky in eight photos)
const WINDOW_AREA: f32 = 0.0003;

/// ... filling at least this share of its bounding box (compact: twigs and
/// wires are not), ...
const WINDOW_FILL: f32 = 0.6;

/// ... with another window within this many times its longer side (windows
/// come in rows and columns; a lamp or a sign alone in the sky does not).
const WINDOW_PAIR: usize = 2;

/// Sky around a window of a group, within this many times its width
/// sideways and its height up and down, may be wall (on LabelMeFacade
/// train's classes, with the clear-blue test: 1 size takes 158 k labelled
/// wall px and 0.4 k sky px, 2 sizes 203 k and 2.9 k).
const WINDOW_WALL: usize = 2;

/// A window's rim: its bounding box grown by this many pixels.
const WINDOW_RIM: usize = 2;

/// A pale facade the sky fill took (a white or pale blue front under a blue
/// or white sky, its roof edge too soft to stop the fill): its windows are
/// left as holes in the sky, compact and in groups, which a real sky does
/// not have (measured on LabelMeFacade train, IoU / sky spill / wall
/// called sky: none 0.708 / 0.057 / 0.042; the clear-blue test alone 0.722
/// / 0.061 / 0.025; the nearer colour alone 0.718 / 0.068; both 0.720 /
/// 0.058 / 0.029). The sky around such windows is wall unless it is
/// clear blue ([`CLEAR_BLUE`]) or nearer the colour of the rest of the sky
/// than that of the windows' rims.
pub(super) fn windows_in_sky(f: &Features, sky: &mut [bool]) {
    let (w, h) = (f.w, f.h);
    if w < 3 || h < 3 || !sky.contains(&true) {
        return;
    }
    // Holes lie within the sky's bounds: what is not sky there and reaches
    // their border reaches the photo's border (what lies outside them is
    // not sky), so it is no hole. The bounds are cropped out.
    let rows: Vec<Option<(usize, usize)>> = sky
        .par_chunks(w)
        .map(|row| Some((row.iter().position(|&s| s)?, row.iter().rposition(|&s| s)?)))
        .collect();
    let y0 = rows.iter().position(Option::is_some).unwrap_or(0);
    let y1 = rows.iter().rposition(Option::is_some).unwrap_or(0);
    let x0 = rows.iter().flatten().map(|r| r.0).min().unwrap_or(0);
    let x1 = rows.iter().flatten().map(|r| r.1).max().unwrap_or(0);
    let (cw, ch) = (x1 - x0 + 1, y1 - y0 + 1);
    if cw < 3 || ch < 3 {
        return;
    }
    let not_sky: Vec<bool> = (0..cw * ch)
        .into_par_iter()
        .map(|i| !sky[(y0 + i / cw) * w + x0 + i % cw])
        .collect();
    let border: Vec<usize> = (0..cw)
        .flat_map(|x| [x, (ch - 1) * cw + x])
        .chain((1..ch - 1).flat_map(|y| [y * cw, y * cw + cw - 1]))
        .collect();
    let mut seen = flood(&not_sky, cw, ch, border, |_, _| true);
    // Each hole's area and bounding box (x0, y0, x1, y1) in the photo.
    let mut holes: Vec<(usize, [usize; 4])> = Vec::new();
    let mut stack: Vec<(usize, usize)> = Vec::new();
    for start in 0..cw * ch {
        if !not_sky[start] || seen[start] {
            continue;
        }
        seen[start] = true;
        stack.push((start % cw, start / cw));
        let (mut area, mut bbox) = (0, [cw, ch, 0, 0]);
        while let Some((x, y)) = stack.pop() {
            area += 1;
            bbox = [
                bbox[0].min(x),
                bbox[1].min(y),
                bbox[2].max(x),
                bbox[3].max(y),
            ];
            // Holes do not touch the border: every neighbour exists.
            for (nx, ny) in [(x - 1, y), (x + 1, y), (x, y - 1), (x, y + 1)] {
                let j = ny * cw + nx;
                if not_sky[j] && !seen[j] {
                    seen[j] = true;
                    stack.push((nx, ny));
                }
            }
        }
        let [a, b, c, d] = bbox;
        holes.push((area, [a + x0, b + y0, c + x0, d + y0]));
    }
    let windows: Vec<[usize; 4]> = holes
        .into_iter()
        .filter(|&(area, [x0, y0, x1, y1])| {
            let (bw, bh) = (x1 - x0 + 1, y1 - y0 + 1);
            area as f32 >= WINDOW_AREA * (w * h) as f32
                && area as f32 >= WINDOW_FILL * (bw * bh) as f32
                && bw.min(bh) >= 3
        })
        .map(|(_, bbox)| bbox)
        .collect();
    let grown = |[x0, y0, x1, y1]: [usize; 4], gx: usize, gy: usize| {
        [
            x0.saturating_sub(gx),
            y0.saturating_sub(gy),
            (x1 + gx).min(w - 1),
            (y1 + gy).min(h - 1),
        ]
    };
    let overlap =
        |a: [usize; 4], b: [usize; 4]| a[0] <= b[2] && b[0] <= a[2] && a[1] <= b[3] && b[1] <= a[3];
    // Windows in a group, then their zones and rims (the wall just around
    // each window, which the fill took as sky).
    let grouped: Vec<[usize; 4]> = windows
        .iter()
        .enumerate()
        .filter(|&(i, &b)| {
            let reach = WINDOW_PAIR * (b[2] - b[0] + 1).max(b[3] - b[1] + 1);
            let near = grown(b, reach, reach);
            windows
                .iter()
                .enumerate()
                .any(|(j, &o)| j != i && overlap(near, o))
        })
        .map(|(_, &b)| b)
        .collect();
    if grouped.is_empty() {
        return;
    }
    let (mut zone, mut rims) = (vec![false; w * h], vec![false; w * h]);
    let mark = |set: &mut [bool], [x0, y0, x1, y1]: [usize; 4]| {
        for y in y0..=y1 {
            set[y * w + x0..=y * w + x1].fill(true);
        }
    };
    for b in grouped {
        let (bw, bh) = (b[2] - b[0] + 1, b[3] - b[1] + 1);
        mark(&mut zone, grown(b, WINDOW_WALL * bw, WINDOW_WALL * bh));
        mark(&mut rims, grown(b, WINDOW_RIM, WINDOW_RIM));
    }
    let in_rims: Vec<bool> = (0..w * h)
        .into_par_iter()
        .map(|i| sky[i] && rims[i])
        .collect();
    let rim_count = in_rims.par_iter().filter(|&&r| r).count();
    if rim_count == 0 {
        return;
    }
    let outside: Vec<bool> = (0..w * h)
        .into_par_iter()
        .map(|i| sky[i] && !zone[i])
        .collect();
    let outside_count = outside.par_iter().filter(|&&o| o).count();
    let wall = mean_colour(f, &in_rims, rim_count);
    let open = (outside_count > 0).then(|| mean_colour(f, &outside, outside_count));
    sky.par_iter_mut().enumerate().for_each(|(i, s)| {
        if *s && zone[i] {
            let p = f.rgb_at(i);
            *s = p[2] - p[0] > CLEAR_BLUE || open.is_some_and(|open| l1(p, open) <= l1(p, wall));
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::wall::sky;
    use crate::analysis::wall::tests::brick;
    use crate::photo::Photo;

    #[test]
    fn a_pale_front_the_sky_took_is_wall_around_its_windows() {
        // A pale blue sky (not clear blue) down to row 100 over a pale
        // blue-grey front a soft step away, so the fill takes it; the front
        // has three rows of six dark windows, 16 x 24 pixels.
        let (w, h) = (400u32, 300u32);
        let window = |x: u32, y: u32| {
            (x + 20) % 60 < 16 && x < 360 && y >= 130 && (y - 130) % 60 < 24 && y < 274
        };
        let img = image::RgbImage::from_fn(w, h, |x, y| {
            image::Rgb(if y < 100 {
                [196, 210, 236]
            } else if window(x, y) {
                [60, 60, 70]
            } else {
                [200, 211, 230]
            })
        });
        let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 400);
        let mut sky = sky(&f);
        windows_in_sky(&f, &mut sky);
        let front: Vec<usize> = (110..290)
            .flat_map(|y| (20..380).map(move |x| (x, y)))
            .filter(|&(x, y)| !window(x, y))
            .map(|(x, y)| (y * 400 + x) as usize)
            .collect();
        let taken = front.iter().filter(|&&i| sky[i]).count();
        assert!(
            taken * 10 < front.len(),
            "{taken} of {} are sky",
            front.len()
        );
        // The sky above, within reach of the top windows too, stays sky.
        let above = &sky[10 * 400..98 * 400];
        let kept = above.iter().filter(|&&s| s).count();
        assert!(kept * 100 > above.len() * 98, "{kept} of {}", above.len());
    }

    #[test]
    fn the_sky_around_a_lone_lamp_stays_sky() {
        // A sky paling towards the horizon (not clear blue) over a brick
        // wall; one dark lamp, 16 x 24 pixels, hangs low in it: a hole as
        // compact as a window, but alone.
        let (w, h) = (400u32, 300u32);
        let lamp = |x: u32, y: u32| (190..206).contains(&x) && (150..174).contains(&y);
        let img = image::RgbImage::from_fn(w, h, |x, y| {
            let t = y.min(200) as f32 / 200.0;
            let sky = [170.0 + 45.0 * t, 190.0 + 32.0 * t, 230.0 + 2.0 * t].map(|v| v as u8);
            image::Rgb(if y >= 200 {
                brick(y)
            } else if lamp(x, y) {
                [40, 40, 45]
            } else {
                sky
            })
        });
        let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 400);
        let mut sky = sky(&f);
        windows_in_sky(&f, &mut sky);
        let around: Vec<usize> = (110..196)
            .flat_map(|y| (150..250).map(move |x| (x, y)))
            .filter(|&(x, y)| !lamp(x, y))
            .map(|(x, y)| (y * 400 + x) as usize)
            .collect();
        let kept = around.iter().filter(|&&i| sky[i]).count();
        assert!(kept * 100 > around.len() * 95, "{kept} of {}", around.len());
    }
}
