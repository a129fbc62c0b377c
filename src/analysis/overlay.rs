//! The overlay: the photo with what grime saw drawn on it, readable at a
//! glance. Wall tinted blue, other classes in their colours and named,
//! ledges drawn in their kind's colour and named.

use image::{Rgb, RgbImage};

use super::wall::Class;
use super::{Analysis, LedgeKind};
use crate::photo::Photo;

fn class_colour(c: Class) -> [f32; 3] {
    match c {
        Class::Wall => [40.0, 140.0, 255.0],
        Class::Sky => [255.0, 255.0, 255.0],
        Class::Vegetation => [40.0, 200.0, 40.0],
        Class::Glass => [160.0, 40.0, 200.0],
        Class::Ground => [230.0, 140.0, 30.0],
        Class::Thing => [255.0, 40.0, 160.0],
    }
}

fn ledge_colour(k: LedgeKind) -> Rgb<u8> {
    Rgb(match k {
        LedgeKind::Sill => [255, 230, 0],
        LedgeKind::Cornice => [255, 60, 60],
        LedgeKind::Coping => [255, 120, 200],
        LedgeKind::WindowHead => [0, 230, 230],
        LedgeKind::Balcony => [255, 150, 0],
        LedgeKind::StringCourse => [255, 255, 255],
        LedgeKind::RoofLine => [255, 0, 255],
    })
}

/// Draws the overlay at the photo's size.
pub fn draw(a: &Analysis, photo: &Photo) -> RgbImage {
    let mut img = photo.image().to_rgb8();
    let (w, h) = img.dimensions();
    for (x, y, p) in img.enumerate_pixels_mut() {
        let m = a.matte.get_pixel(x, y)[0] as f32 / 255.0;
        let c = a.class_at(x, y);
        let other = if c == Class::Wall { Class::Sky } else { c };
        let (wc, oc) = (class_colour(Class::Wall), class_colour(other));
        for k in 0..3 {
            let tint = 0.3 * m * wc[k] + 0.5 * (1.0 - m) * oc[k];
            let keep = 1.0 - 0.3 * m - 0.5 * (1.0 - m);
            p[k] = (p[k] as f32 * keep + tint).round().clamp(0.0, 255.0) as u8;
        }
    }
    let px = (w.max(h) / 500).max(1);
    for c in [
        Class::Sky,
        Class::Vegetation,
        Class::Glass,
        Class::Ground,
        Class::Thing,
    ] {
        if let Some((cx, cy)) = centroid(a, c) {
            text(&mut img, cx, cy, c.label(), px, Rgb([0, 0, 0]));
        }
    }
    for l in &a.ledges {
        let col = ledge_colour(l.kind);
        for s in l.polyline.windows(2) {
            line(&mut img, s[0], s[1], px.max(2), col);
        }
        let p = l.polyline[0];
        let y = (p[1] as i64 - 9 * px as i64).max(0) as u32;
        text(&mut img, p[0].max(0.0) as u32, y, l.kind.label(), px, col);
    }
    img
}

/// Centre (photo pixels) of the class's pixels, if it covers at least 0.5%.
fn centroid(a: &Analysis, c: Class) -> Option<(u32, u32)> {
    let w = a.analysis_width as usize;
    let (mut sx, mut sy, mut n) = (0f64, 0f64, 0usize);
    for (i, &k) in a.classes.iter().enumerate() {
        if k == c {
            sx += (i % w) as f64;
            sy += (i / w) as f64;
            n += 1;
        }
    }
    (n as f32 > 0.005 * a.classes.len() as f32).then(|| {
        let s = a.width as f64 / w as f64;
        ((sx / n as f64 * s) as u32, (sy / n as f64 * s) as u32)
    })
}

fn line(img: &mut RgbImage, a: [f32; 2], b: [f32; 2], t: u32, c: Rgb<u8>) {
    let (w, h) = img.dimensions();
    let n = ((b[0] - a[0]).abs().max((b[1] - a[1]).abs()).ceil() as usize).max(1);
    for i in 0..=n {
        let f = i as f32 / n as f32;
        let (x, y) = (a[0] + (b[0] - a[0]) * f, a[1] + (b[1] - a[1]) * f);
        for dy in 0..t {
            let (xx, yy) = (x as i64, y as i64 + dy as i64 - t as i64 / 2);
            if xx >= 0 && yy >= 0 && (xx as u32) < w && (yy as u32) < h {
                img.put_pixel(xx as u32, yy as u32, c);
            }
        }
    }
}

/// 5x7 capitals, one byte per row, low 5 bits, leftmost pixel = bit 4.
const FONT: [[u8; 7]; 26] = [
    [14, 17, 17, 31, 17, 17, 17],
    [30, 17, 17, 30, 17, 17, 30],
    [14, 17, 16, 16, 16, 17, 14],
    [30, 17, 17, 17, 17, 17, 30],
    [31, 16, 16, 30, 16, 16, 31],
    [31, 16, 16, 30, 16, 16, 16],
    [14, 17, 16, 23, 17, 17, 15],
    [17, 17, 17, 31, 17, 17, 17],
    [14, 4, 4, 4, 4, 4, 14],
    [7, 2, 2, 2, 2, 18, 12],
    [17, 18, 20, 24, 20, 18, 17],
    [16, 16, 16, 16, 16, 16, 31],
    [17, 27, 21, 21, 17, 17, 17],
    [17, 17, 25, 21, 19, 17, 17],
    [14, 17, 17, 17, 17, 17, 14],
    [30, 17, 17, 30, 16, 16, 16],
    [14, 17, 17, 17, 21, 18, 13],
    [30, 17, 17, 30, 20, 18, 17],
    [15, 16, 16, 14, 1, 1, 30],
    [31, 4, 4, 4, 4, 4, 4],
    [17, 17, 17, 17, 17, 17, 14],
    [17, 17, 17, 17, 17, 10, 4],
    [17, 17, 17, 21, 21, 21, 10],
    [17, 17, 10, 4, 10, 17, 17],
    [17, 17, 10, 4, 4, 4, 4],
    [31, 1, 2, 4, 8, 16, 31],
];

/// Writes `s` (letters and spaces) at (x, y) with `px`-sized dots on a
/// contrasting box.
fn text(img: &mut RgbImage, x: u32, y: u32, s: &str, px: u32, c: Rgb<u8>) {
    let (w, h) = img.dimensions();
    let bg = if c.0.iter().map(|&v| v as u32).sum::<u32>() > 300 {
        Rgb([0, 0, 0])
    } else {
        Rgb([255, 255, 255])
    };
    let tw = s.len() as u32 * 6 * px + px;
    for yy in y..(y + 9 * px).min(h) {
        for xx in x..(x + tw).min(w) {
            img.put_pixel(xx, yy, bg);
        }
    }
    for (k, ch) in s.bytes().enumerate() {
        let Some(g) = ch
            .to_ascii_uppercase()
            .checked_sub(b'A')
            .and_then(|i| FONT.get(i as usize))
        else {
            continue;
        };
        for (row, bits) in g.iter().enumerate() {
            for col in 0..5 {
                if bits >> (4 - col) & 1 == 1 {
                    let ox = x + px + (k as u32 * 6 + col) * px;
                    let oy = y + px + row as u32 * px;
                    for dy in 0..px {
                        for dx in 0..px {
                            if ox + dx < w && oy + dy < h {
                                img.put_pixel(ox + dx, oy + dy, c);
                            }
                        }
                    }
                }
            }
        }
    }
}
