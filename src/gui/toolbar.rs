//! The toolbar under the menu: the tools, Detect ledges, undo and redo,
//! export, and the active tool's options. It reads the controller's state
//! and emits [`Command`]s.

use eframe::egui;

use egui::{RichText, Ui};

use super::command::{Command, PromptKind};
use super::controller::Controller;
use super::menu::recorded;
use super::tools::{MaskMode, Tool};

/// The tool row and the options row. `selected_line` is the canvas's
/// selection (for "Delete line").
pub fn show(ui: &mut Ui, ctl: &Controller, selected_line: Option<usize>, out: &mut Vec<Command>) {
    let has_doc = ctl.loaded().is_some();
    ui.add_space(2.0);
    ui.horizontal_wrapped(|ui| {
        for t in Tool::ALL {
            if matches!(t, Tool::Line | Tool::Quad) {
                ui.separator();
            }
            let r = ui
                .selectable_label(ctl.tools().tool == t, t.label())
                .on_hover_text(format!("{} ({:?})", t.help(), t.key()));
            if r.clicked() {
                out.push(Command::SetTool(t));
            }
        }
        ui.separator();
        let detect = ui
            .add_enabled(has_doc, egui::Button::new("Detect ledges"))
            .on_hover_text(
                "Propose source lines along the ledges grime sees (sills, cornices, roof line) inside the region",
            );
        if detect.clicked() {
            out.push(Command::DetectLedges);
        }
        ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
            let can_export = has_doc && ctl.export_running().is_none();
            let export = ui
                .add_enabled(can_export, egui::Button::new("Export…"))
                .on_hover_text("Full resolution: PNG, JPEG, TIFF, WebP, PSD or ORA (Ctrl+E)");
            if export.clicked() {
                out.push(Command::Prompt(PromptKind::Export));
            }
            let mut original = ctl.view().show_original;
            if ui
                .toggle_value(&mut original, "Original")
                .on_hover_text("Show the photo without weathering (O)")
                .changed()
            {
                out.push(Command::ShowOriginal(original));
            }
            let h = ctl.history();
            let redo = ui.add_enabled(h.can_redo(), egui::Button::new("Redo"));
            if redo.on_hover_text("Ctrl+Shift+Z").clicked() {
                out.push(Command::Redo);
            }
            let undo = ui.add_enabled(h.can_undo(), egui::Button::new("Undo"));
            if undo.on_hover_text("Ctrl+Z").clicked() {
                out.push(Command::Undo);
            }
        });
    });
    ui.horizontal(|ui| options(ui, ctl, selected_line, out));
    ui.add_space(2.0);
}

/// The active tool's options, and the region buttons.
fn options(ui: &mut Ui, ctl: &Controller, selected_line: Option<usize>, out: &mut Vec<Command>) {
    let mut t = *ctl.tools();
    ui.label(RichText::new(t.tool.label()).strong());
    match t.tool {
        Tool::Brush | Tool::Eraser => {
            ui.add(
                egui::Slider::new(&mut t.brush_size, 1.0..=1000.0)
                    .logarithmic(true)
                    .text("Size")
                    .suffix(" px"),
            )
            .on_hover_text("Brush diameter in photo pixels ([ and ])");
            ui.add(egui::Slider::new(&mut t.hardness, 0.0..=1.0).text("Hardness"))
                .on_hover_text("1 = hard edge, 0 = soft");
        }
        Tool::Rectangle | Tool::Lasso | Tool::Wand => {
            ui.radio_value(&mut t.mode, MaskMode::Add, "Add");
            ui.radio_value(&mut t.mode, MaskMode::Subtract, "Subtract");
            if t.tool == Tool::Wand {
                ui.add(egui::Slider::new(&mut t.tolerance, 0.0..=255.0).text("Tolerance"))
                    .on_hover_text(
                        "How far a colour may be from the clicked one, per channel (0-255)",
                    );
            }
        }
        Tool::EditLines => {
            let delete = ui.add_enabled(selected_line.is_some(), egui::Button::new("Delete line"));
            if delete.clicked()
                && let (Some(i), Some(l)) = (selected_line, ctl.loaded())
                && i < l.doc.lines.len()
            {
                let mut lines = l.doc.lines.clone();
                lines.remove(i);
                out.push(Command::SetLines {
                    lines,
                    before: Some(l.doc.lines.clone()),
                });
            }
        }
        Tool::Quad => {
            let has = ctl.loaded().is_some_and(|l| l.doc.quad.is_some());
            if ui
                .add_enabled(has, egui::Button::new("Remove quad"))
                .clicked()
            {
                let remove = Command::SetQuad {
                    quad: None,
                    before: None,
                };
                out.push(recorded(ctl.loaded(), remove));
            }
        }
        Tool::Pan | Tool::Line => {}
    }
    if t != *ctl.tools() {
        out.push(Command::SetTools(t));
    }
    ui.label(RichText::new(t.tool.help()).weak().small());
    ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
        let has = ctl.loaded().is_some();
        let mut mask = ctl.view().show_mask;
        if ui.checkbox(&mut mask, "Show region").changed() {
            out.push(Command::ShowMask(mask));
        }
        for (label, cmd, tip) in [
            ("Fill", Command::MaskFill, "The whole photo is wall"),
            (
                "Clear",
                Command::MaskClear,
                "Empty the region (paint it back with Brush, Rectangle, Lasso or Wand)",
            ),
            ("Invert", Command::MaskInvert, "Swap wall and not-wall"),
            (
                "Auto region",
                Command::AutoRegion,
                "The wall grime sees in the photo (not sky, vegetation, glass, ground); edit it with Brush and Eraser",
            ),
        ] {
            if ui
                .add_enabled(has, egui::Button::new(label))
                .on_hover_text(tip)
                .clicked()
            {
                out.push(cmd);
            }
        }
        ui.label("Region:");
    });
}
