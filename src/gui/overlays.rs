//! What the canvas draws over the picture: source lines with their drip
//! ticks, the perspective quad with its rectified grid, the brush cursor.

use eframe::egui;

use egui::{Color32, Pos2, Shape, Stroke, vec2};

use crate::perspective::{Quad, Rectifier};
use crate::preset::SourceLine;

/// Source lines.
pub const LINE_COLOR: Color32 = Color32::from_rgb(255, 150, 30);
/// The selected source line.
pub const SELECTED_COLOR: Color32 = Color32::from_rgb(255, 235, 60);
/// The quad.
pub const QUAD_COLOR: Color32 = Color32::from_rgb(230, 60, 230);
/// Mask shapes being drawn.
pub const SHAPE_COLOR: Color32 = Color32::from_rgb(60, 200, 255);

/// Source lines (photo pixels) with drip ticks; `selected` highlighted,
/// point handles on every line with `handles`.
pub fn source_lines(
    painter: &egui::Painter,
    lines: &[SourceLine],
    selected: Option<usize>,
    handles: bool,
    to_screen: impl Fn([f32; 2]) -> Pos2,
) {
    for (i, line) in lines.iter().enumerate() {
        let pts: Vec<Pos2> = line.iter().map(|p| to_screen(*p)).collect();
        let color = if selected == Some(i) {
            SELECTED_COLOR
        } else {
            LINE_COLOR
        };
        painter.add(Shape::line(
            pts.clone(),
            Stroke::new(4.0, Color32::from_black_alpha(140)),
        ));
        painter.add(Shape::line(pts.clone(), Stroke::new(2.0, color)));
        // Drips: short ticks below the line show where water leaves it.
        for pair in pts.windows(2) {
            let len = pair[0].distance(pair[1]);
            let n = (len / 28.0).floor() as usize;
            for k in 1..=n {
                let q = pair[0] + (pair[1] - pair[0]) * (k as f32 / (n + 1) as f32);
                painter.line_segment(
                    [q, q + vec2(0.0, 7.0)],
                    Stroke::new(1.5, color.gamma_multiply(0.8)),
                );
            }
        }
        if handles || selected == Some(i) {
            for p in &pts {
                painter.circle(*p, 4.0, color, Stroke::new(1.0, Color32::BLACK));
            }
        }
    }
}

/// The brush outline at `p`, radius `r` points, with the hard core.
pub fn brush(painter: &egui::Painter, p: Pos2, r: f32, hardness: f32) {
    painter.circle_stroke(p, r, Stroke::new(1.5, Color32::from_black_alpha(160)));
    painter.circle_stroke(p, r, Stroke::new(1.0, Color32::WHITE));
    if hardness < 1.0 {
        painter.circle_stroke(
            p,
            r * hardness,
            Stroke::new(1.0, Color32::from_white_alpha(90)),
        );
    }
}

/// The quad, its rectified grid and (with `handles`) its corner handles.
pub fn quad(
    painter: &egui::Painter,
    q: &Quad,
    to_screen: impl Fn([f32; 2]) -> Pos2,
    handles: bool,
) {
    let pts: Vec<Pos2> = q.iter().map(|p| to_screen(*p)).collect();
    // The rectified grid: lines of constant u and v, so the user sees the
    // wall's verticals as the simulation will.
    if let Ok(r) = Rectifier::new(q, 1 << 20) {
        let (w, h) = (r.width as f32, r.height as f32);
        for k in 1..6 {
            let t = k as f32 / 6.0;
            let a = r.rect_to_photo(w * t, 0.0);
            let b = r.rect_to_photo(w * t, h);
            painter.line_segment(
                [to_screen([a.0, a.1]), to_screen([b.0, b.1])],
                Stroke::new(1.0, QUAD_COLOR.gamma_multiply(0.45)),
            );
            let a = r.rect_to_photo(0.0, h * t);
            let b = r.rect_to_photo(w, h * t);
            painter.line_segment(
                [to_screen([a.0, a.1]), to_screen([b.0, b.1])],
                Stroke::new(1.0, QUAD_COLOR.gamma_multiply(0.25)),
            );
        }
    }
    painter.add(Shape::closed_line(
        pts.clone(),
        Stroke::new(2.0, QUAD_COLOR),
    ));
    if handles {
        for p in pts {
            painter.circle(
                p,
                6.0,
                Color32::from_black_alpha(120),
                Stroke::new(2.0, QUAD_COLOR),
            );
        }
    }
}
