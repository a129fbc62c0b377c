//! The year caption of a time-lapse frame: "N years" in a 5x7 pixel font,
//! white on a dark box in the bottom-left corner.

use image::RgbaImage;

/// 5x7 glyphs, one row per byte, the low 5 bits from left to right.
fn glyph(c: char) -> [u8; 7] {
    match c {
        '0' => [14, 17, 19, 21, 25, 17, 14],
        '1' => [4, 12, 4, 4, 4, 4, 14],
        '2' => [14, 17, 1, 2, 4, 8, 31],
        '3' => [30, 1, 1, 14, 1, 1, 30],
        '4' => [2, 6, 10, 18, 31, 2, 2],
        '5' => [31, 16, 30, 1, 1, 17, 14],
        '6' => [6, 8, 16, 30, 17, 17, 14],
        '7' => [31, 1, 2, 4, 8, 8, 8],
        '8' => [14, 17, 17, 14, 17, 17, 14],
        '9' => [14, 17, 17, 15, 1, 2, 12],
        'y' => [0, 0, 17, 17, 15, 1, 14],
        'e' => [0, 0, 14, 17, 31, 16, 14],
        'a' => [0, 0, 14, 1, 15, 17, 15],
        'r' => [0, 0, 22, 25, 16, 16, 16],
        's' => [0, 0, 15, 16, 14, 1, 30],
        _ => [0; 7],
    }
}

/// The caption's text.
pub fn text(years: u32) -> String {
    match years {
        1 => "1 year".into(),
        n => format!("{n} years"),
    }
}

/// Draws `years`' caption onto `img`, scaled to its size.
pub fn draw(img: &mut RgbaImage, years: u32) {
    let text = text(years);
    let (w, h) = img.dimensions();
    let scale = (w.min(h) / 160).max(1);
    let (cell, pad) = (6 * scale, 3 * scale);
    let box_w = (text.len() as u32 * cell + 2 * pad - scale).min(w);
    let box_h = (7 * scale + 2 * pad).min(h);
    let (x0, y0) = (pad.min(w - box_w), h - box_h - pad.min(h - box_h));
    for y in y0..y0 + box_h {
        for x in x0..x0 + box_w {
            let p = img.get_pixel_mut(x, y);
            for c in &mut p.0[..3] {
                *c /= 3;
            }
            p.0[3] = p.0[3].max(170);
        }
    }
    for (i, c) in text.chars().enumerate() {
        for (row, bits) in glyph(c).iter().enumerate() {
            for col in 0..5u32 {
                if bits >> (4 - col) & 1 == 0 {
                    continue;
                }
                let gx = x0 + pad + i as u32 * cell + col * scale;
                let gy = y0 + pad + row as u32 * scale;
                for y in gy..(gy + scale).min(h) {
                    for x in gx..(gx + scale).min(w) {
                        img.put_pixel(x, y, image::Rgba([255, 255, 255, 255]));
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_caption_lands_in_the_bottom_left_corner() {
        let mut img = RgbaImage::from_pixel(320, 200, image::Rgba([90, 90, 90, 255]));
        draw(&mut img, 30);
        let white = |x0: u32, x1: u32, y0: u32, y1: u32| {
            (y0..y1).any(|y| (x0..x1).any(|x| img.get_pixel(x, y).0 == [255; 4]))
        };
        assert!(white(0, 160, 150, 200), "text at the bottom left");
        assert!(!white(0, 320, 0, 100), "nothing at the top");
        assert_eq!(text(1), "1 year");
    }

    #[test]
    fn a_tiny_frame_does_not_panic() {
        let mut img = RgbaImage::new(4, 3);
        draw(&mut img, 120);
    }
}
