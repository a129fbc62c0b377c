//! Editing tools as plain functions on buffers: brush and eraser dabs,
//! rectangle and polygon fills, the colour wand, and ledge detection. The
//! canvas turns pointer input into calls of these; tests call them directly.

use eframe::egui;

use std::collections::VecDeque;

use image::{DynamicImage, GrayImage, RgbImage};
use serde::{Deserialize, Serialize};

use crate::grid::WALL;
use crate::photo::Photo;
use crate::preset::SourceLine;

/// A box of pixels, exclusive end.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PixelRect {
    /// Left.
    pub x0: u32,
    /// Top.
    pub y0: u32,
    /// Right, exclusive.
    pub x1: u32,
    /// Bottom, exclusive.
    pub y1: u32,
}

impl PixelRect {
    /// The whole of a `w` x `h` image.
    pub fn full(w: u32, h: u32) -> PixelRect {
        PixelRect {
            x0: 0,
            y0: 0,
            x1: w,
            y1: h,
        }
    }

    /// The pixels touched by the continuous box `[x0, x1) x [y0, y1)`,
    /// clipped to a `w` x `h` image; `None` if nothing is left.
    pub fn around(x0: f32, y0: f32, x1: f32, y1: f32, w: u32, h: u32) -> Option<PixelRect> {
        let c = |v: f32, max: u32| v.clamp(0.0, max as f32) as u32;
        let r = PixelRect {
            x0: c(x0.floor(), w),
            y0: c(y0.floor(), h),
            x1: c(x1.ceil(), w),
            y1: c(y1.ceil(), h),
        };
        (r.x1 > r.x0 && r.y1 > r.y0).then_some(r)
    }

    /// Width.
    pub fn width(&self) -> u32 {
        self.x1 - self.x0
    }

    /// Height.
    pub fn height(&self) -> u32 {
        self.y1 - self.y0
    }

    /// The smallest box holding both.
    pub fn union(&self, o: &PixelRect) -> PixelRect {
        PixelRect {
            x0: self.x0.min(o.x0),
            y0: self.y0.min(o.y0),
            x1: self.x1.max(o.x1),
            y1: self.y1.max(o.y1),
        }
    }
}

/// The tools of the canvas.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Tool {
    /// Drag to pan (also: middle button, or hold Space).
    Pan,
    /// Paint wall.
    Brush,
    /// Erase wall.
    Eraser,
    /// Drag a rectangle.
    Rectangle,
    /// Click polygon corners; double-click, Enter or click the first corner to close.
    Lasso,
    /// Click a colour: the connected area of similar colour.
    Wand,
    /// Click points of a new source line; double-click or Enter to finish.
    Line,
    /// Drag line points, drag a line to move it, Delete to remove the selected one.
    EditLines,
    /// Drag the four corners of the perspective quad.
    Quad,
}

impl Tool {
    /// All tools, in toolbar order.
    pub const ALL: [Tool; 9] = [
        Tool::Pan,
        Tool::Brush,
        Tool::Eraser,
        Tool::Rectangle,
        Tool::Lasso,
        Tool::Wand,
        Tool::Line,
        Tool::EditLines,
        Tool::Quad,
    ];

    /// Button label.
    pub fn label(self) -> &'static str {
        match self {
            Tool::Pan => "Pan",
            Tool::Brush => "Brush",
            Tool::Eraser => "Eraser",
            Tool::Rectangle => "Rectangle",
            Tool::Lasso => "Lasso",
            Tool::Wand => "Wand",
            Tool::Line => "Line",
            Tool::EditLines => "Edit lines",
            Tool::Quad => "Quad",
        }
    }

    /// Keyboard shortcut.
    pub fn key(self) -> egui::Key {
        use egui::Key;
        match self {
            Tool::Pan => Key::H,
            Tool::Brush => Key::B,
            Tool::Eraser => Key::E,
            Tool::Rectangle => Key::R,
            Tool::Lasso => Key::L,
            Tool::Wand => Key::W,
            Tool::Line => Key::N,
            Tool::EditLines => Key::V,
            Tool::Quad => Key::Q,
        }
    }

    /// What the tool does, for its tooltip.
    pub fn help(self) -> &'static str {
        match self {
            Tool::Pan => "Drag to pan. Wheel zooms; middle-drag or Space+drag pans with any tool.",
            Tool::Brush => "Paint the wall region. [ and ] change the size.",
            Tool::Eraser => "Erase from the wall region. [ and ] change the size.",
            Tool::Rectangle => "Drag a rectangle to add to (or subtract from) the wall region.",
            Tool::Lasso => {
                "Click polygon corners (or drag freehand); double-click, Enter or click the first corner to close. Esc cancels."
            }
            Tool::Wand => {
                "Click a colour: the connected area of similar colour joins (or leaves) the wall region."
            }
            Tool::Line => {
                "Click the points of a source line where water drips from (sill, cornice); double-click or Enter finishes, Shift keeps it level, Esc cancels."
            }
            Tool::EditLines => {
                "Drag a point to move it, drag a line to move the whole line; Delete removes the selected line."
            }
            Tool::Quad => {
                "Drag on the image to place a perspective quad on the wall, then drag its corners onto a rectangle of the wall."
            }
        }
    }

    /// True for tools that edit the mask.
    pub fn edits_mask(self) -> bool {
        matches!(
            self,
            Tool::Brush | Tool::Eraser | Tool::Rectangle | Tool::Lasso | Tool::Wand
        )
    }
}

/// Whether a shape adds to or subtracts from the region.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum MaskMode {
    /// Add wall.
    Add,
    /// Remove wall.
    Subtract,
}

/// Tool options.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ToolSettings {
    /// The active tool.
    pub tool: Tool,
    /// Brush diameter, photo pixels.
    pub brush_size: f32,
    /// Brush hardness 0..1 (1 = hard edge).
    pub hardness: f32,
    /// Wand tolerance, 0..255 per channel.
    pub tolerance: f32,
    /// Add or subtract for rectangle, lasso and wand.
    pub mode: MaskMode,
}

impl Default for ToolSettings {
    fn default() -> Self {
        ToolSettings {
            tool: Tool::Pan,
            brush_size: 60.0,
            hardness: 0.7,
            tolerance: 24.0,
            mode: MaskMode::Add,
        }
    }
}

/// One round brush dab at `c` (photo pixels). The brush adds wall
/// (`max`), the eraser removes it (`min`); `hardness` is the flat part of
/// the radius. Returns the box it touched.
pub fn dab(
    mask: &mut GrayImage,
    c: [f32; 2],
    radius: f32,
    hardness: f32,
    erase: bool,
) -> Option<PixelRect> {
    let r = radius.max(0.5);
    let (w, h) = mask.dimensions();
    let rect = PixelRect::around(c[0] - r, c[1] - r, c[0] + r, c[1] + r, w, h)?;
    let hard = hardness.clamp(0.0, 1.0);
    for y in rect.y0..rect.y1 {
        for x in rect.x0..rect.x1 {
            let d = ((x as f32 + 0.5 - c[0]).powi(2) + (y as f32 + 0.5 - c[1]).powi(2)).sqrt() / r;
            if d >= 1.0 {
                continue;
            }
            let v = if d <= hard || hard >= 1.0 {
                1.0
            } else {
                let t = 1.0 - (d - hard) / (1.0 - hard);
                t * t * (3.0 - 2.0 * t)
            };
            let px = &mut mask.get_pixel_mut(x, y)[0];
            let v = (v * 255.0).round() as u8;
            *px = if erase {
                (*px).min(255 - v)
            } else {
                (*px).max(v)
            };
        }
    }
    Some(rect)
}

/// Dabs from `a` to `b`, spaced a quarter radius apart.
pub fn stroke(
    mask: &mut GrayImage,
    a: [f32; 2],
    b: [f32; 2],
    radius: f32,
    hardness: f32,
    erase: bool,
) -> Option<PixelRect> {
    let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
    let steps = (len / (radius * 0.25).max(0.5)).ceil().max(1.0) as usize;
    let mut out: Option<PixelRect> = None;
    for i in 0..=steps {
        let t = i as f32 / steps as f32;
        let p = [a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t];
        if let Some(r) = dab(mask, p, radius, hardness, erase) {
            out = Some(out.map_or(r, |o| o.union(&r)));
        }
    }
    out
}

fn set(px: &mut u8, mode: MaskMode) {
    *px = match mode {
        MaskMode::Add => 255,
        MaskMode::Subtract => 0,
    };
}

/// Fills the pixels whose centres lie in the box between corners `a` and `b`.
pub fn fill_rect(
    mask: &mut GrayImage,
    a: [f32; 2],
    b: [f32; 2],
    mode: MaskMode,
) -> Option<PixelRect> {
    let (w, h) = mask.dimensions();
    let (x0, x1) = (a[0].min(b[0]), a[0].max(b[0]));
    let (y0, y1) = (a[1].min(b[1]), a[1].max(b[1]));
    // Pixels whose centre v + 0.5 lies in [lo, hi).
    let span = |lo: f32, hi: f32, max: u32| {
        let c = |v: f32| (v - 0.5).ceil().clamp(0.0, max as f32) as u32;
        (c(lo), c(hi))
    };
    let ((xa, xb), (ya, yb)) = (span(x0, x1, w), span(y0, y1, h));
    if xb <= xa || yb <= ya {
        return None;
    }
    let rect = PixelRect {
        x0: xa,
        y0: ya,
        x1: xb,
        y1: yb,
    };
    for y in rect.y0..rect.y1 {
        for x in rect.x0..rect.x1 {
            set(&mut mask.get_pixel_mut(x, y)[0], mode);
        }
    }
    Some(rect)
}

/// Fills a polygon (even-odd rule, pixel centres).
pub fn fill_polygon(mask: &mut GrayImage, pts: &[[f32; 2]], mode: MaskMode) -> Option<PixelRect> {
    if pts.len() < 3 {
        return None;
    }
    let (w, h) = mask.dimensions();
    let (mut x0, mut y0, mut x1, mut y1) = (f32::MAX, f32::MAX, f32::MIN, f32::MIN);
    for p in pts {
        x0 = x0.min(p[0]);
        y0 = y0.min(p[1]);
        x1 = x1.max(p[0]);
        y1 = y1.max(p[1]);
    }
    let bbox = PixelRect::around(x0, y0, x1, y1, w, h)?;
    let mut touched: Option<PixelRect> = None;
    let mut xs = Vec::new();
    for y in bbox.y0..bbox.y1 {
        let cy = y as f32 + 0.5;
        xs.clear();
        for i in 0..pts.len() {
            let (a, b) = (pts[i], pts[(i + 1) % pts.len()]);
            if (a[1] <= cy) != (b[1] <= cy) {
                xs.push(a[0] + (cy - a[1]) / (b[1] - a[1]) * (b[0] - a[0]));
            }
        }
        xs.sort_by(f32::total_cmp);
        for pair in xs.chunks_exact(2) {
            // Pixels whose centre x + 0.5 lies in [pair[0], pair[1]).
            let xa = (pair[0] - 0.5).ceil().clamp(0.0, w as f32) as u32;
            let xb = (pair[1] - 0.5).ceil().clamp(0.0, w as f32) as u32;
            for x in xa..xb {
                set(&mut mask.get_pixel_mut(x, y)[0], mode);
            }
            if xb > xa {
                let r = PixelRect {
                    x0: xa,
                    y0: y,
                    x1: xb,
                    y1: y + 1,
                };
                touched = Some(touched.map_or(r, |t| t.union(&r)));
            }
        }
    }
    touched
}

/// The connected (4-neighbour) area around `seed` whose colour is within
/// `tolerance` of the seed's in every channel joins (or leaves) the region.
pub fn wand(
    rgb: &RgbImage,
    mask: &mut GrayImage,
    seed: [f32; 2],
    tolerance: f32,
    mode: MaskMode,
) -> Option<PixelRect> {
    let (w, h) = rgb.dimensions();
    if mask.dimensions() != (w, h) || !(seed[0] >= 0.0 && seed[1] >= 0.0) {
        return None;
    }
    let (sx, sy) = (seed[0] as u32, seed[1] as u32);
    if sx >= w || sy >= h {
        return None;
    }
    let raw = rgb.as_raw();
    let target = rgb.get_pixel(sx, sy).0;
    let tol = tolerance.clamp(0.0, 255.0);
    let similar =
        |i: usize| (0..3).all(|c| (raw[i * 3 + c] as f32 - target[c] as f32).abs() <= tol);
    let mut seen = vec![false; (w * h) as usize];
    let mut queue = VecDeque::from([(sx, sy)]);
    seen[(sy * w + sx) as usize] = true;
    let mut rect = PixelRect {
        x0: sx,
        y0: sy,
        x1: sx + 1,
        y1: sy + 1,
    };
    let m: &mut [u8] = mask;
    while let Some((x, y)) = queue.pop_front() {
        set(&mut m[(y * w + x) as usize], mode);
        rect = rect.union(&PixelRect {
            x0: x,
            y0: y,
            x1: x + 1,
            y1: y + 1,
        });
        let mut visit = |nx: u32, ny: u32| {
            let i = (ny * w + nx) as usize;
            if !seen[i] && similar(i) {
                seen[i] = true;
                queue.push_back((nx, ny));
            }
        };
        if x > 0 {
            visit(x - 1, y);
        }
        if x + 1 < w {
            visit(x + 1, y);
        }
        if y > 0 {
            visit(x, y - 1);
        }
        if y + 1 < h {
            visit(x, y + 1);
        }
    }
    Some(rect)
}

/// Inverts the region.
pub fn invert(mask: &mut GrayImage) -> PixelRect {
    mask.iter_mut().for_each(|p| *p = 255 - *p);
    PixelRect::full(mask.width(), mask.height())
}

/// Sets the whole region to `value` (0 = clear, 255 = all wall).
pub fn fill_all(mask: &mut GrayImage, value: u8) -> PixelRect {
    mask.iter_mut().for_each(|p| *p = value);
    PixelRect::full(mask.width(), mask.height())
}

/// Proposes source lines from strong horizontal edges where the image turns
/// from bright above to dark below (the shadowed underside of a sill or
/// cornice), inside the wall region. Returns level lines in photo pixels,
/// just below each edge, top to bottom.
///
/// ```
/// let d = grime::demo::facade(480, 360);
/// let lines = grime::gui::tools::detect_ledges(&d.photo, d.region.as_ref());
/// assert!(lines.len() >= 5);
/// ```
pub fn detect_ledges(photo: &Photo, mask: Option<&GrayImage>) -> Vec<SourceLine> {
    let (w, h) = (photo.width(), photo.height());
    if w < 8 || h < 8 {
        return Vec::new();
    }
    // Analyse at most ~1000 px on the long side: ledges are large features.
    let s = (1000.0 / w.max(h) as f32).min(1.0);
    let (aw, ah) = (
        ((w as f32 * s).round() as u32).max(8),
        ((h as f32 * s).round() as u32).max(8),
    );
    let luma = DynamicImage::ImageLuma8(photo.image().to_luma8())
        .resize_exact(aw, ah, image::imageops::FilterType::Triangle)
        .to_luma32f();
    let l = imageproc::filter::gaussian_blur_f32(&luma, 1.0);
    let at = |x: u32, y: u32| l.get_pixel(x, y)[0] * 255.0;
    let gy = |x: u32, y: u32| at(x, y + 1) - at(x, y - 1);
    let in_region = |x: u32, y: u32| {
        mask.is_none_or(|m| {
            let (px, py) = (((x as f32 + 0.5) / s) as u32, ((y as f32 + 0.5) / s) as u32);
            m.get_pixel(px.min(w - 1), py.min(h - 1))[0] >= WALL
        })
    };
    const T: f32 = 25.0;
    let min_len = (aw as f32 * 0.03).max(10.0) as u32;
    // Edge pixels: bright above, dark below, a local extreme across rows.
    let mut edge = vec![false; (aw * ah) as usize];
    for y in 2..ah - 2 {
        for x in 1..aw - 1 {
            let g = gy(x, y);
            let gx = at(x + 1, y) - at(x - 1, y);
            edge[(y * aw + x) as usize] = g < -T
                && gx.abs() < 0.5 * g.abs()
                && g <= gy(x, y - 1)
                && g <= gy(x, y + 1)
                && in_region(x, (y + 2).min(ah - 1));
        }
    }
    // Row runs, tolerating a row of jitter and gaps of a few pixels:
    // (y, x0, x1, edge pixels on the row itself).
    let is_edge = |x: u32, y: u32| edge[(y * aw + x) as usize];
    let mut runs: Vec<(u32, u32, u32, u32)> = Vec::new();
    for y in 3..ah - 3 {
        let mut start: Option<u32> = None;
        let (mut last, mut own) = (0, 0);
        let close = |start: Option<u32>, last: u32, own: u32, runs: &mut Vec<_>| {
            if let Some(s0) = start
                && last + 1 - s0 >= min_len
                && own * 2 >= last + 1 - s0
            {
                runs.push((y, s0, last + 1, own));
            }
        };
        for x in 1..aw - 1 {
            if is_edge(x, y) || is_edge(x, y - 1) || is_edge(x, y + 1) {
                if start.is_none() || x > last + 4 {
                    close(start, last, own, &mut runs);
                    start = Some(x);
                    own = 0;
                }
                last = x;
                own += is_edge(x, y) as u32;
            }
        }
        close(start, last, own, &mut runs);
    }
    // Merge runs on neighbouring rows that overlap or nearly touch: one
    // ledge. Groups: (sum of y weighted by own pixels, own pixels, x0, x1, last y).
    let mut groups: Vec<(f32, u32, u32, u32, u32)> = Vec::new();
    for (y, x0, x1, own) in runs {
        let hit = groups
            .iter()
            .position(|g| y - g.4 <= 2 && x0 <= g.3 + 4 && x1 + 4 >= g.2);
        match hit {
            Some(i) => {
                let g = &mut groups[i];
                g.0 += y as f32 * own as f32;
                g.1 += own;
                g.2 = g.2.min(x0);
                g.3 = g.3.max(x1);
                g.4 = y;
            }
            None => groups.push((y as f32 * own as f32, own, x0, x1, y)),
        }
    }
    let mut lines: Vec<SourceLine> = groups
        .into_iter()
        .filter(|g| g.1 > 0)
        .map(|(sum, n, x0, x1, _)| {
            let y = (sum / n as f32 + 1.5) / s;
            vec![[x0 as f32 / s, y], [x1 as f32 / s, y]]
        })
        .collect();
    lines.sort_by(|a, b| {
        a[0][1]
            .total_cmp(&b[0][1])
            .then(a[0][0].total_cmp(&b[0][0]))
    });
    lines.truncate(100);
    lines
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::Luma;

    #[test]
    fn brush_paints_and_eraser_erases_a_disc() {
        let mut m = GrayImage::new(40, 40);
        let r = dab(&mut m, [20.0, 20.0], 5.0, 1.0, false).unwrap();
        assert_eq!(m.get_pixel(20, 20)[0], 255);
        assert_eq!(m.get_pixel(20, 27)[0], 0);
        assert!(r.x0 >= 14 && r.x1 <= 26);
        dab(&mut m, [20.0, 20.0], 2.0, 1.0, true);
        assert_eq!(m.get_pixel(20, 20)[0], 0);
        assert_eq!(m.get_pixel(23, 20)[0], 255);
        let mut soft = GrayImage::new(40, 40);
        dab(&mut soft, [20.0, 20.0], 10.0, 0.0, false);
        let edge = soft.get_pixel(27, 20)[0];
        assert!(edge > 0 && edge < 255, "soft edge {edge}");
    }

    #[test]
    fn stroke_is_gap_free() {
        let mut m = GrayImage::new(100, 20);
        stroke(&mut m, [5.0, 10.0], [95.0, 10.0], 3.0, 1.0, false);
        assert!((5..95).all(|x| m.get_pixel(x, 10)[0] == 255));
    }

    #[test]
    fn rect_polygon_and_wand_fill_what_they_should() {
        let mut m = GrayImage::new(20, 20);
        let r = fill_rect(&mut m, [12.0, 15.0], [2.0, 5.0], MaskMode::Add).unwrap();
        assert_eq!(
            r,
            PixelRect {
                x0: 2,
                y0: 5,
                x1: 12,
                y1: 15
            }
        );
        assert_eq!(m.iter().filter(|&&v| v == 255).count(), 100);
        let mut p = GrayImage::new(20, 20);
        fill_polygon(
            &mut p,
            &[[2.0, 2.0], [12.0, 2.0], [12.0, 12.0], [2.0, 12.0]],
            MaskMode::Add,
        )
        .unwrap();
        assert_eq!(p.iter().filter(|&&v| v == 255).count(), 100);
        fill_polygon(
            &mut p,
            &[[2.0, 2.0], [12.0, 2.0], [2.0, 12.0]],
            MaskMode::Subtract,
        );
        assert_eq!(p.get_pixel(3, 3)[0], 0);
        assert_eq!(p.get_pixel(11, 11)[0], 255);

        let rgb = RgbImage::from_fn(20, 20, |x, _| {
            if x < 8 {
                image::Rgb([200, 10, 10])
            } else {
                image::Rgb([10, 10, 200])
            }
        });
        let mut w = GrayImage::new(20, 20);
        let r = wand(&rgb, &mut w, [3.0, 3.0], 10.0, MaskMode::Add).unwrap();
        assert_eq!(
            r,
            PixelRect {
                x0: 0,
                y0: 0,
                x1: 8,
                y1: 20
            }
        );
        assert_eq!(w.iter().filter(|&&v| v == 255).count(), 160);
        assert!(wand(&rgb, &mut w, [-3.0, 3.0], 10.0, MaskMode::Add).is_none());
    }

    #[test]
    fn invert_and_clear() {
        let mut m = GrayImage::from_pixel(4, 4, Luma([255]));
        m.put_pixel(0, 0, Luma([0]));
        invert(&mut m);
        assert_eq!(m.get_pixel(0, 0)[0], 255);
        assert_eq!(m.get_pixel(1, 0)[0], 0);
        fill_all(&mut m, 0);
        assert!(m.iter().all(|&v| v == 0));
    }

    #[test]
    fn ledges_of_the_sample_facade_are_found() {
        let (w, h) = (480, 360);
        let d = crate::demo::facade(w, h);
        let l = crate::demo::layout(w, h);
        let found = detect_ledges(&d.photo, d.region.as_ref());
        let near = |y: f32, x0: u32, x1: u32| {
            found.iter().any(|line| {
                (line[0][1] - y).abs() <= 3.0 && line[0][0] < x1 as f32 && line[1][0] > x0 as f32
            })
        };
        for s in &l.sills {
            assert!(
                near(s.3 as f32 + 1.0, s.0, s.2),
                "sill {s:?} not in {found:?}"
            );
        }
        assert!(
            near(l.cornice.1 as f32 + 1.0, 0, w),
            "cornice not in {found:?}"
        );
        assert!(
            found.len() <= 2 * (l.sills.len() + 1),
            "too many: {found:?}"
        );
    }
}
