//! Lit lamps before the wall: a street lamp's glass or a lantern glowing
//! at dusk is a small blob near white, far brighter than what is around
//! it. A roof line whose rain falls over one dimmed the lamp (blind review
//! p75: IMG_8365's street lamp before a church portico, 255 -> 206 under
//! a roof line's plume), so the roof line does not run over one
//! ([`super::roof`]).
//!
//! [choice: the lamps are not made a class of their own. Marked
//! [`Class::Thing`] (keeping all grime off them), the same test took
//! 111,000 more labelled wall pixels on LabelMeFacade train (white frames
//! against glass, clipped highlights) and the wall IoU fell 0.759 ->
//! 0.753; as a check under the roof line alone it costs no IoU.]

use super::features::Features;
use super::glass::components;
use super::wall::Class;

/// A lamp's core is at least this bright (luma, 0..1) [choice: 0.96, near
/// clipping: IMG_8365's lamps are 0.98-1.0 at their core; its lit wall
/// beside them 0.85-0.9].
const LIT: f32 = 0.96;

/// The ring around the core is darker than the core by at least this
/// (luma) [choice: 0.15: a lamp glows out of its surround; a sunlit white
/// frame or render clipped in the light is as bright on its wall].
const GLOWS: f32 = 0.15;

/// The core is at most this share of the photo [choice: 0.0005, 175
/// pixels at 683 x 512: a lamp's glass seen from the street; larger
/// clipped blobs are lit walls, boards or sky].
const MAX_AREA: f32 = 0.0005;

/// The ring taken with the core (its glow), pixels at the analysis size.
const HALO: usize = 2;

/// The most of the wall that may be clipped (at [`LIT`]) for its bright
/// blobs to be lamps [choice: 0.001: a photo at dusk, when lamps are lit,
/// has few clipped pixels (IMG_8365: 0.018% of its lower two thirds); a
/// sunlit wall's clipped specks (0.6-3.2% on five sunlit photos of blind
/// review p75) glint in the sun, and taken for lamps they cut IMG_4180's
/// eaves out of its roof line].
const DUSK: f32 = 0.001;

/// The lit lamps (see the module's documentation) in the wall: each as
/// its core's columns and top row, `[x0, x1, y0]`.
pub(super) fn lit(f: &Features, class: &[Class]) -> Vec<[usize; 3]> {
    let (w, h) = (f.w, f.h);
    let bright: Vec<bool> = (0..w * h)
        .map(|i| class[i] == Class::Wall && f.luma[i] >= LIT)
        .collect();
    let wall = class.iter().filter(|c| **c == Class::Wall).count();
    if bright.iter().filter(|b| **b).count() as f32 > DUSK * wall as f32 {
        return Vec::new();
    }
    let max = (MAX_AREA * (w * h) as f32) as usize;
    let mut out = Vec::new();
    for blob in components(&bright, w, h) {
        if blob.len() < 2 || blob.len() > max {
            continue;
        }
        let (mut x0, mut y0, mut x1, mut y1) = (w, h, 0, 0);
        for &i in &blob {
            (x0, x1, y0, y1) = (x0.min(i % w), x1.max(i % w), y0.min(i / w), y1.max(i / w));
        }
        // A lamp is compact: not a thin clipped frame or edge.
        let (bw, bh) = (x1 - x0 + 1, y1 - y0 + 1);
        if bw.max(bh) > 3 * bw.min(bh) {
            continue;
        }
        let (rx0, ry0) = (x0.saturating_sub(HALO), y0.saturating_sub(HALO));
        let (rx1, ry1) = ((x1 + HALO).min(w - 1), (y1 + HALO).min(h - 1));
        let ring: Vec<usize> = (ry0..=ry1)
            .flat_map(|y| (rx0..=rx1).map(move |x| y * w + x))
            .filter(|&i| !bright[i])
            .collect();
        // Set in the wall (not a bright gap at the sky's edge or a frame
        // by its glass) ...
        if ring.is_empty() || ring.iter().any(|&i| class[i] != Class::Wall) {
            continue;
        }
        // ... and glowing out of it.
        let core = blob.iter().map(|&i| f.luma[i]).sum::<f32>() / blob.len() as f32;
        let around = ring.iter().map(|&i| f.luma[i]).sum::<f32>() / ring.len() as f32;
        if core - around >= GLOWS {
            out.push([x0, x1, y0]);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::photo::Photo;

    #[test]
    fn a_lit_lamp_before_the_wall_is_found_a_lit_wall_is_not() {
        // 300 x 200: sky to row 30, a warm wall below; a glowing lamp
        // (5 x 6, near white) at (100, 120) with a dim glow around it;
        // a clipped white frame (1 x 20 at x 200) is none. With the sun
        // on the wall (clipped 3 x 3 specks every 20 pixels: 0.9% of it)
        // no blob is a lamp.
        let lamps = |sunlit: bool| {
            let img = image::RgbImage::from_fn(300, 200, |x, y| match (x, y) {
                (_, 0..30) => image::Rgb([170, 200, 240]),
                (100..105, 120..126) => image::Rgb([255, 252, 240]),
                (97..108, 117..129) => image::Rgb([220, 180, 130]),
                (200, 60..80) => image::Rgb([255, 255, 255]),
                _ if sunlit && x % 20 < 3 && y % 20 < 3 && y > 40 => image::Rgb([255, 255, 255]),
                _ => image::Rgb([190, 150, 110]),
            });
            let f = Features::new(&Photo::new(image::DynamicImage::ImageRgb8(img)), 300);
            let class: Vec<Class> = (0..300 * 200)
                .map(|i| match i / 300 < 30 {
                    true => Class::Sky,
                    false => Class::Wall,
                })
                .collect();
            lit(&f, &class)
        };
        assert_eq!(lamps(false), vec![[100, 104, 120]]);
        assert!(lamps(true).is_empty());
    }
}
