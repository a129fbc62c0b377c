//! The canvas's tools and their options, and the brush and eraser as plain
//! functions on the mask. The mask fills (rectangle, polygon, wand) are in
//! [`crate::masks`], ledge detection in [`crate::ledges`].

use eframe::egui;

use image::GrayImage;
use serde::{Deserialize, Serialize};

pub use crate::masks::{Mode as MaskMode, PixelRect};

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
                crate::random::smoothstep(t)
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

#[cfg(test)]
mod tests {
    use super::*;

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
}
