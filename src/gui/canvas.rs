//! The canvas: the photo (or its aged preview) with zoom and pan, the mask
//! overlay, source lines and quad, and the pointer gestures of every tool.
//! It turns input into [`Command`]s; it changes nothing itself.

use eframe::egui;

use egui::{
    Color32, Key, PointerButton, Pos2, Rect, Sense, Shape, Stroke, TextureHandle, Ui, Vec2, pos2,
    vec2,
};

use crate::perspective::{self, Quad};
use crate::preset::SourceLine;

use super::command::{Command, MaskShape};
use super::tools::{Tool, ToolSettings};

/// Zoom and pan: screen points per photo pixel, and where the photo's
/// origin sits relative to the canvas's top-left corner.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    /// Screen points per photo pixel.
    pub zoom: f32,
    /// Offset of the photo's origin from the canvas's corner, points.
    pub offset: Vec2,
    /// Fit the photo to the canvas on the next frame.
    pub needs_fit: bool,
}

impl Default for View {
    fn default() -> Self {
        View {
            zoom: 1.0,
            offset: Vec2::ZERO,
            needs_fit: true,
        }
    }
}

impl View {
    /// Photo point to screen.
    pub fn to_screen(&self, rect: Rect, p: [f32; 2]) -> Pos2 {
        rect.min + self.offset + vec2(p[0], p[1]) * self.zoom
    }

    /// Screen point to photo.
    pub fn to_photo(&self, rect: Rect, pos: Pos2) -> [f32; 2] {
        let v = (pos - rect.min - self.offset) / self.zoom;
        [v.x, v.y]
    }

    /// Fits a `size` photo into `rect` with a small margin.
    pub fn fit(&mut self, rect: Rect, size: [f32; 2]) {
        let z = (rect.width() / size[0]).min(rect.height() / size[1]) * 0.97;
        self.zoom = z.max(1e-3);
        self.offset = (rect.size() - vec2(size[0], size[1]) * self.zoom) / 2.0;
        self.needs_fit = false;
    }

    /// Zooms by `factor` keeping the photo point under `pos` in place.
    pub fn zoom_at(&mut self, rect: Rect, pos: Pos2, factor: f32) {
        let p = self.to_photo(rect, pos);
        self.zoom = (self.zoom * factor).clamp(0.01, 64.0);
        self.offset = pos - rect.min - vec2(p[0], p[1]) * self.zoom;
    }
}

/// A gesture in progress.
#[derive(Debug, Clone, Default)]
enum Gesture {
    #[default]
    Idle,
    Stroke {
        last: [f32; 2],
    },
    Rect {
        start: [f32; 2],
    },
    Lasso {
        pts: Vec<[f32; 2]>,
        freehand: bool,
    },
    Line {
        pts: Vec<[f32; 2]>,
    },
    Vertex {
        line: usize,
        idx: usize,
        before: Vec<SourceLine>,
        current: Vec<SourceLine>,
    },
    MoveLine {
        line: usize,
        grab: [f32; 2],
        before: Vec<SourceLine>,
        current: Vec<SourceLine>,
    },
    Corner {
        i: usize,
        before: Option<Quad>,
        current: Quad,
    },
    NewQuad {
        start: [f32; 2],
    },
}

/// What the canvas draws.
pub struct CanvasInput<'a> {
    /// The picture (preview or original), photo-sized on screen.
    pub image: Option<&'a TextureHandle>,
    /// The tinted mask overlay.
    pub overlay: Option<&'a TextureHandle>,
    /// Overlay opacity, 0..1.
    pub overlay_alpha: f32,
    /// Photo size in pixels.
    pub size: Option<[f32; 2]>,
    /// Source lines, photo pixels.
    pub lines: &'a [SourceLine],
    /// Perspective quad.
    pub quad: Option<&'a Quad>,
    /// Tool options.
    pub tools: &'a ToolSettings,
}

/// The canvas's own state (view and the gesture in progress).
#[derive(Debug, Default)]
pub struct Canvas {
    /// Zoom and pan.
    pub view: View,
    gesture: Gesture,
    /// The line the Edit-lines tool selected.
    pub selected_line: Option<usize>,
    /// Photo point under the pointer, for the status bar.
    pub hover: Option<[f32; 2]>,
}

use super::overlays::{self, LINE_COLOR, QUAD_COLOR, SHAPE_COLOR};

/// Pick distance for points and lines, screen points.
const PICK: f32 = 9.0;

fn dist_to_segment(p: Pos2, a: Pos2, b: Pos2) -> f32 {
    let ab = b - a;
    let t = ((p - a).dot(ab) / ab.length_sq().max(1e-6)).clamp(0.0, 1.0);
    (a + ab * t).distance(p)
}

impl Canvas {
    /// Forgets any gesture in progress (a new document, undo, ...).
    pub fn reset_gesture(&mut self) {
        self.gesture = Gesture::Idle;
    }

    /// True while a gesture is in progress.
    pub fn is_busy(&self) -> bool {
        !matches!(self.gesture, Gesture::Idle)
    }

    /// Draws the canvas and turns input into commands.
    pub fn show(&mut self, ui: &mut Ui, input: CanvasInput, out: &mut Vec<Command>) {
        let (rect, resp) = ui.allocate_exact_size(ui.available_size(), Sense::click_and_drag());
        resp.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Canvas, true, "Canvas"));
        let painter = ui.painter_at(rect);
        painter.rect_filled(rect, 0.0, Color32::from_gray(24));
        let Some(size) = input.size else {
            painter.text(
                rect.center(),
                egui::Align2::CENTER_CENTER,
                "Open a photo of a facade (File > Open image, Ctrl+O),\ndrop one here, or try File > Open sample.",
                egui::FontId::proportional(16.0),
                Color32::from_gray(170),
            );
            return;
        };
        if self.view.needs_fit {
            self.view.fit(rect, size);
        }
        let view = self.view;

        // Zoom (wheel, pinch, Ctrl+wheel) about the pointer.
        if resp.hovered() {
            let (scroll, zoom, pointer) = ui.input(|i| {
                (
                    i.smooth_scroll_delta.y,
                    i.zoom_delta(),
                    i.pointer.hover_pos(),
                )
            });
            let factor = zoom * (scroll * 0.002).exp();
            if let Some(p) = pointer
                && (factor - 1.0).abs() > 1e-4
            {
                self.view.zoom_at(rect, p, factor);
            }
        }
        // Pan: middle or right drag, Space + drag, or the Pan tool.
        let space = ui.input(|i| i.key_down(Key::Space)) && !ui.ctx().egui_wants_keyboard_input();
        let tool = input.tools.tool;
        let pan_primary = tool == Tool::Pan || space;
        if resp.dragged_by(PointerButton::Middle)
            || resp.dragged_by(PointerButton::Secondary)
            || (pan_primary && resp.dragged_by(PointerButton::Primary))
        {
            self.view.offset += resp.drag_delta();
        }

        let img_rect = Rect::from_min_size(
            view.to_screen(rect, [0.0, 0.0]),
            vec2(size[0], size[1]) * view.zoom,
        );
        let uv = Rect::from_min_max(pos2(0.0, 0.0), pos2(1.0, 1.0));
        painter.rect_filled(img_rect.expand(1.0), 0.0, Color32::from_gray(8));
        if let Some(tex) = input.image {
            painter.image(tex.id(), img_rect, uv, Color32::WHITE);
        }
        if let Some(tex) = input.overlay
            && input.overlay_alpha > 0.0
        {
            painter.image(
                tex.id(),
                img_rect,
                uv,
                Color32::from_white_alpha((input.overlay_alpha * 255.0) as u8),
            );
        }

        let pointer = resp.hover_pos().or_else(|| resp.interact_pointer_pos());
        self.hover = pointer.map(|p| view.to_photo(rect, p));
        let (pressed, down, shift) = ui.input(|i| {
            (
                i.pointer.primary_pressed(),
                i.pointer.primary_down(),
                i.modifiers.shift,
            )
        });
        let pressed_here = pressed && resp.hovered() && !pan_primary;
        let keys = !ui.ctx().egui_wants_keyboard_input();
        let key = |k: Key| keys && ui.input(|i| i.key_pressed(k));
        let p_photo = pointer.map(|p| view.to_photo(rect, p));

        if !pan_primary && let Some(p) = p_photo {
            self.gesture_input(&resp, rect, p, pressed_here, down, shift, &input, out);
        } else if !down {
            self.finish_drag(out);
        }
        if key(Key::Escape) {
            self.gesture = Gesture::Idle;
        }
        self.key_input(&key, &input, out);

        // Overlays: lines, quad, gesture previews, brush cursor.
        let to_screen = |p: [f32; 2]| view.to_screen(rect, p);
        let shown_lines: &[SourceLine] = match &self.gesture {
            Gesture::Vertex { current, .. } | Gesture::MoveLine { current, .. } => current,
            _ => input.lines,
        };
        let handles = tool == Tool::EditLines;
        overlays::source_lines(
            &painter,
            shown_lines,
            self.selected_line,
            handles,
            to_screen,
        );
        let quad = match &self.gesture {
            Gesture::Corner { current, .. } => Some(*current),
            _ => input.quad.copied(),
        };
        if let Some(q) = quad {
            overlays::quad(&painter, &q, to_screen, tool == Tool::Quad);
        }
        match &self.gesture {
            Gesture::Rect { start } | Gesture::NewQuad { start } => {
                let color = if matches!(self.gesture, Gesture::NewQuad { .. }) {
                    QUAD_COLOR
                } else {
                    SHAPE_COLOR
                };
                if let Some(p) = p_photo {
                    let r = Rect::from_two_pos(to_screen(*start), to_screen(p));
                    painter.rect_stroke(r, 0.0, Stroke::new(1.5, color), egui::StrokeKind::Middle);
                }
            }
            Gesture::Lasso { pts, .. } | Gesture::Line { pts } => {
                let color = if matches!(self.gesture, Gesture::Line { .. }) {
                    LINE_COLOR
                } else {
                    SHAPE_COLOR
                };
                let mut screen: Vec<Pos2> = pts.iter().map(|p| to_screen(*p)).collect();
                if let Some(p) = pointer {
                    screen.push(p);
                }
                painter.add(Shape::line(screen, Stroke::new(1.5, color)));
                for p in pts {
                    painter.circle_filled(to_screen(*p), 3.0, color);
                }
            }
            _ => {}
        }
        if matches!(tool, Tool::Brush | Tool::Eraser)
            && !pan_primary
            && let Some(p) = resp.hover_pos()
        {
            let r = input.tools.brush_size / 2.0 * view.zoom;
            overlays::brush(&painter, p, r, input.tools.hardness);
        }
        let cursor = if pan_primary {
            if resp.dragged() {
                egui::CursorIcon::Grabbing
            } else {
                egui::CursorIcon::Grab
            }
        } else if matches!(tool, Tool::Brush | Tool::Eraser) {
            egui::CursorIcon::None
        } else {
            egui::CursorIcon::Crosshair
        };
        if resp.hovered() {
            ui.ctx().set_cursor_icon(cursor);
        }
    }

    /// Ends a move/drag gesture when the button is up (e.g. released
    /// outside the canvas).
    fn finish_drag(&mut self, out: &mut Vec<Command>) {
        match std::mem::take(&mut self.gesture) {
            Gesture::Stroke { .. } => out.push(Command::StrokeEnd),
            Gesture::Vertex {
                before, current, ..
            }
            | Gesture::MoveLine {
                before, current, ..
            } if before != current => {
                out.push(Command::SetLines {
                    lines: current,
                    before: Some(before),
                });
            }
            Gesture::Corner {
                before, current, ..
            } if before != Some(current) => {
                out.push(Command::SetQuad {
                    quad: Some(current),
                    before: Some(before),
                });
            }
            keep @ (Gesture::Lasso {
                freehand: false, ..
            }
            | Gesture::Line { .. }) => self.gesture = keep,
            _ => {}
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn gesture_input(
        &mut self,
        resp: &egui::Response,
        rect: Rect,
        p: [f32; 2],
        pressed: bool,
        down: bool,
        shift: bool,
        input: &CanvasInput,
        out: &mut Vec<Command>,
    ) {
        let view = self.view;
        let settings = input.tools;
        let near = |a: [f32; 2], b: [f32; 2]| {
            view.to_screen(rect, a).distance(view.to_screen(rect, b)) < PICK
        };
        match (settings.tool, &mut self.gesture) {
            (Tool::Brush | Tool::Eraser, Gesture::Idle) if pressed => {
                let erase = settings.tool == Tool::Eraser;
                out.push(Command::StrokeBegin);
                out.push(Command::StrokeTo {
                    from: p,
                    to: p,
                    erase,
                });
                self.gesture = Gesture::Stroke { last: p };
            }
            (Tool::Brush | Tool::Eraser, Gesture::Stroke { last }) if down && *last != p => {
                out.push(Command::StrokeTo {
                    from: *last,
                    to: p,
                    erase: settings.tool == Tool::Eraser,
                });
                *last = p;
            }
            (Tool::Brush | Tool::Eraser, Gesture::Stroke { .. }) if down => {}
            (Tool::Rectangle, Gesture::Idle) if pressed => {
                self.gesture = Gesture::Rect { start: p }
            }
            (Tool::Rectangle, Gesture::Rect { start }) if !down => {
                let start = *start;
                self.gesture = Gesture::Idle;
                out.push(Command::MaskShape(MaskShape::Rect(start, p), settings.mode));
            }
            (Tool::Lasso, Gesture::Idle) if pressed => {
                self.gesture = Gesture::Lasso {
                    pts: vec![p],
                    freehand: false,
                }
            }
            (Tool::Lasso, Gesture::Lasso { pts, freehand }) => {
                if down && resp.dragged_by(PointerButton::Primary) {
                    // Dragging draws freehand; it closes on release.
                    if pts.len() == 1 || *freehand {
                        *freehand = true;
                        if pts.last().is_none_or(|l| {
                            !near(*l, p)
                                || view.to_screen(rect, *l).distance(view.to_screen(rect, p)) > 3.0
                        }) {
                            pts.push(p);
                        }
                    }
                } else if *freehand && !down {
                    let pts = std::mem::take(pts);
                    self.gesture = Gesture::Idle;
                    if pts.len() >= 3 {
                        out.push(Command::MaskShape(MaskShape::Polygon(pts), settings.mode));
                    }
                } else if resp.clicked() || pressed {
                    let closes = pts.len() >= 3 && near(pts[0], p);
                    if closes || (resp.double_clicked() && pts.len() >= 3) {
                        let pts = std::mem::take(pts);
                        self.gesture = Gesture::Idle;
                        out.push(Command::MaskShape(MaskShape::Polygon(pts), settings.mode));
                    } else if pressed && pts.last().is_none_or(|l| !near(*l, p)) {
                        pts.push(p);
                    }
                }
            }
            (Tool::Wand, Gesture::Idle) if resp.clicked() => {
                out.push(Command::MaskShape(MaskShape::Wand(p), settings.mode));
            }
            (Tool::Line, Gesture::Idle) if pressed => self.gesture = Gesture::Line { pts: vec![p] },
            (Tool::Line, Gesture::Line { pts }) => {
                let mut q = p;
                if shift && let Some(l) = pts.last() {
                    q[1] = l[1];
                }
                if pressed && pts.last().is_none_or(|l| !near(*l, q)) {
                    pts.push(q);
                }
                if resp.double_clicked() && pts.len() >= 2 {
                    let new = std::mem::take(pts);
                    self.gesture = Gesture::Idle;
                    let mut lines = input.lines.to_vec();
                    lines.push(new);
                    out.push(Command::SetLines {
                        lines,
                        before: Some(input.lines.to_vec()),
                    });
                }
            }
            (Tool::EditLines, Gesture::Idle) if pressed => {
                let vertex = input.lines.iter().enumerate().find_map(|(li, line)| {
                    line.iter().position(|q| near(*q, p)).map(|idx| (li, idx))
                });
                let screen = |q: [f32; 2]| view.to_screen(rect, q);
                let segment = input.lines.iter().position(|line| {
                    line.windows(2)
                        .any(|s| dist_to_segment(screen(p), screen(s[0]), screen(s[1])) < PICK)
                });
                if let Some((line, idx)) = vertex {
                    self.selected_line = Some(line);
                    self.gesture = Gesture::Vertex {
                        line,
                        idx,
                        before: input.lines.to_vec(),
                        current: input.lines.to_vec(),
                    };
                } else if let Some(line) = segment {
                    self.selected_line = Some(line);
                    self.gesture = Gesture::MoveLine {
                        line,
                        grab: p,
                        before: input.lines.to_vec(),
                        current: input.lines.to_vec(),
                    };
                } else {
                    self.selected_line = None;
                }
            }
            (
                Tool::EditLines,
                Gesture::Vertex {
                    line, idx, current, ..
                },
            ) if down => {
                if let Some(v) = current.get_mut(*line).and_then(|l| l.get_mut(*idx)) {
                    *v = p;
                }
            }
            (
                Tool::EditLines,
                Gesture::MoveLine {
                    line,
                    grab,
                    before,
                    current,
                },
            ) if down => {
                let (dx, dy) = (p[0] - grab[0], p[1] - grab[1]);
                if let (Some(src), Some(dst)) = (before.get(*line), current.get_mut(*line)) {
                    for (d, s) in dst.iter_mut().zip(src) {
                        *d = [s[0] + dx, s[1] + dy];
                    }
                }
            }
            (Tool::Quad, Gesture::Idle) if pressed => {
                let corner = input.quad.and_then(|q| q.iter().position(|c| near(*c, p)));
                match (input.quad, corner) {
                    (Some(q), Some(i)) => {
                        self.gesture = Gesture::Corner {
                            i,
                            before: Some(*q),
                            current: *q,
                        }
                    }
                    _ => self.gesture = Gesture::NewQuad { start: p },
                }
            }
            (Tool::Quad, Gesture::Corner { i, current, .. }) if down => {
                let mut next = *current;
                next[*i] = p;
                // Keep the last valid shape while the pointer crosses over.
                if perspective::validate(&next).is_ok() {
                    *current = next;
                }
            }
            (Tool::Quad, Gesture::NewQuad { start }) if !down => {
                let s = *start;
                self.gesture = Gesture::Idle;
                let (x0, x1) = (s[0].min(p[0]), s[0].max(p[0]));
                let (y0, y1) = (s[1].min(p[1]), s[1].max(p[1]));
                let q = [[x0, y0], [x1, y0], [x1, y1], [x0, y1]];
                if perspective::validate(&q).is_ok()
                    && (x1 - x0) * view.zoom > 8.0
                    && (y1 - y0) * view.zoom > 8.0
                {
                    out.push(Command::SetQuad {
                        quad: Some(q),
                        before: Some(input.quad.copied()),
                    });
                }
            }
            (_, Gesture::Idle) => {}
            (_, _) if !down => self.finish_drag(out),
            _ => {}
        }
    }

    fn key_input(
        &mut self,
        key: &dyn Fn(Key) -> bool,
        input: &CanvasInput,
        out: &mut Vec<Command>,
    ) {
        match &mut self.gesture {
            Gesture::Line { pts } => {
                if key(Key::Enter) && pts.len() >= 2 {
                    let new = std::mem::take(pts);
                    self.gesture = Gesture::Idle;
                    let mut lines = input.lines.to_vec();
                    lines.push(new);
                    out.push(Command::SetLines {
                        lines,
                        before: Some(input.lines.to_vec()),
                    });
                } else if key(Key::Backspace) {
                    pts.pop();
                }
            }
            Gesture::Lasso { pts, .. } => {
                if key(Key::Enter) && pts.len() >= 3 {
                    let pts = std::mem::take(pts);
                    self.gesture = Gesture::Idle;
                    out.push(Command::MaskShape(
                        MaskShape::Polygon(pts),
                        input.tools.mode,
                    ));
                } else if key(Key::Backspace) {
                    pts.pop();
                }
            }
            Gesture::Idle => {
                if let Some(i) = self.selected_line
                    && input.tools.tool == Tool::EditLines
                    && (key(Key::Delete) || key(Key::Backspace))
                    && i < input.lines.len()
                {
                    let mut lines = input.lines.to_vec();
                    lines.remove(i);
                    self.selected_line = None;
                    out.push(Command::SetLines {
                        lines,
                        before: Some(input.lines.to_vec()),
                    });
                }
            }
            _ => {}
        }
    }
}
