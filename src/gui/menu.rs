//! The menu bar and the window-wide input (shortcuts, dropped files). They
//! read the controller's state and emit [`Command`]s.

use eframe::egui;

use std::path::PathBuf;

use egui::{Key, KeyboardShortcut, Modifiers, RichText, Ui};

use crate::demo;

use super::command::{Command, PromptKind};
use super::controller::{Controller, Loaded};
use super::tools::Tool;

/// Keyboard shortcuts and dropped files. `modal` is true while a dialog
/// has the keyboard.
pub fn global_input(ui: &Ui, ctl: &Controller, modal: bool, out: &mut Vec<Command>) {
    // Drag and drop: images open, presets load, projects open.
    let dropped: Vec<PathBuf> = ui.input(|i| {
        i.raw
            .dropped_files
            .iter()
            .map(|f| f.path().to_path_buf())
            .filter(|p| !p.as_os_str().is_empty())
            .collect()
    });
    for path in dropped {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .unwrap_or_default();
        out.push(match ext.as_str() {
            "toml" => Command::LoadPreset(path),
            "json" => Command::OpenProject(path),
            _ => Command::OpenImage(path),
        });
    }
    if modal {
        return;
    }
    let shortcut = |m: Modifiers, k: Key| KeyboardShortcut::new(m, k);
    let shortcuts = [
        (
            shortcut(Modifiers::COMMAND | Modifiers::SHIFT, Key::Z),
            Command::Redo,
        ),
        (shortcut(Modifiers::COMMAND, Key::Y), Command::Redo),
        (shortcut(Modifiers::COMMAND, Key::Z), Command::Undo),
        (
            shortcut(Modifiers::COMMAND, Key::O),
            Command::Prompt(PromptKind::OpenImage),
        ),
        (
            shortcut(Modifiers::COMMAND, Key::S),
            Command::Prompt(PromptKind::SaveProject),
        ),
        (
            shortcut(Modifiers::COMMAND, Key::E),
            Command::Prompt(PromptKind::Export),
        ),
    ];
    for (sc, cmd) in shortcuts {
        if ui.input_mut(|i| i.consume_shortcut(&sc)) {
            out.push(cmd);
        }
    }
    if ui.ctx().egui_wants_keyboard_input() || !ui.input(|i| i.modifiers.is_none()) {
        return;
    }
    let pressed = |k: Key| ui.input(|i| i.key_pressed(k));
    for t in Tool::ALL {
        if pressed(t.key()) {
            out.push(Command::SetTool(t));
        }
    }
    let mut tools = *ctl.tools();
    if pressed(Key::CloseBracket) {
        tools.brush_size = (tools.brush_size * 1.25).min(2000.0);
    }
    if pressed(Key::OpenBracket) {
        tools.brush_size = (tools.brush_size / 1.25).max(1.0);
    }
    if tools != *ctl.tools() {
        out.push(Command::SetTools(tools));
    }
    if pressed(Key::F) {
        out.push(Command::FitView);
    }
    if pressed(Key::O) {
        out.push(Command::ShowOriginal(!ctl.view().show_original));
    }
}

/// Gives "remove all" style commands their undo record.
pub fn recorded(loaded: Option<&Loaded>, cmd: Command) -> Command {
    let Some(l) = loaded else { return cmd };
    match cmd {
        Command::SetLines {
            lines,
            before: None,
        } => Command::SetLines {
            lines,
            before: Some(l.doc.lines.clone()),
        },
        Command::SetQuad { quad, before: None } => Command::SetQuad {
            quad,
            before: Some(l.doc.quad),
        },
        other => other,
    }
}

/// The menu bar: File, Edit, View, Help.
pub fn bar(ui: &mut Ui, ctl: &Controller, out: &mut Vec<Command>) {
    let has_doc = ctl.loaded().is_some();
    let enabled = |ui: &mut Ui, on: bool, label: &str| ui.add_enabled(on, egui::Button::new(label));
    egui::MenuBar::new().ui(ui, |ui| {
        ui.menu_button("File", |ui| {
            if ui.button("Open image…").clicked() {
                out.push(Command::Prompt(PromptKind::OpenImage));
            }
            for name in demo::NAMES {
                if ui.button(format!("Open sample: {name}")).clicked() {
                    out.push(Command::OpenDemo(name.to_string()));
                }
            }
            ui.separator();
            if ui.button("Open project…").clicked() {
                out.push(Command::Prompt(PromptKind::OpenProject));
            }
            if enabled(ui, has_doc, "Save project…").clicked() {
                out.push(Command::Prompt(PromptKind::SaveProject));
            }
            ui.separator();
            if ui.button("Load preset…").clicked() {
                out.push(Command::Prompt(PromptKind::LoadPreset));
            }
            if ui.button("Save preset…").clicked() {
                out.push(Command::Prompt(PromptKind::SavePreset));
            }
            ui.separator();
            if enabled(ui, has_doc, "Export image…").clicked() {
                out.push(Command::Prompt(PromptKind::Export));
            }
            if enabled(ui, has_doc, "Export time-lapse…").clicked() {
                out.push(Command::Prompt(PromptKind::ExportTimelapse));
            }
            ui.separator();
            if ui.button("Quit").clicked() {
                out.push(Command::Quit);
            }
        });
        ui.menu_button("Edit", |ui| {
            let h = ctl.history();
            let undo = egui::Button::new("Undo").shortcut_text("Ctrl+Z");
            if ui.add_enabled(h.can_undo(), undo).clicked() {
                out.push(Command::Undo);
            }
            let redo = egui::Button::new("Redo").shortcut_text("Ctrl+Shift+Z");
            if ui.add_enabled(h.can_redo(), redo).clicked() {
                out.push(Command::Redo);
            }
            ui.separator();
            let remove_lines = Command::SetLines {
                lines: vec![],
                before: None,
            };
            let remove_quad = Command::SetQuad {
                quad: None,
                before: None,
            };
            for (label, cmd) in [
                ("Invert region", Command::MaskInvert),
                ("Clear region", Command::MaskClear),
                ("Whole image is wall", Command::MaskFill),
                ("Auto region", Command::AutoRegion),
                ("Detect ledges", Command::DetectLedges),
                ("Remove all source lines", remove_lines),
                ("Remove quad", remove_quad),
            ] {
                if enabled(ui, has_doc, label).clicked() {
                    out.push(recorded(ctl.loaded(), cmd));
                }
            }
        });
        ui.menu_button("View", |ui| {
            if ui.button("Fit to window").clicked() {
                out.push(Command::FitView);
            }
            let v = ctl.view();
            let (mut original, mut mask) = (v.show_original, v.show_mask);
            if ui.checkbox(&mut original, "Show original (O)").changed() {
                out.push(Command::ShowOriginal(original));
            }
            if ui.checkbox(&mut mask, "Show region overlay").changed() {
                out.push(Command::ShowMask(mask));
            }
        });
        ui.menu_button("Help", |ui| {
            ui.label(RichText::new("Shortcuts").strong());
            for line in [
                "Wheel: zoom · middle/right drag or Space+drag: pan · F: fit",
                "H pan · B brush · E eraser · R rectangle · L lasso · W wand",
                "N new line · V edit lines · Q quad · [ ] brush size · O original",
                "Enter: finish line/lasso · Esc: cancel · Delete: remove selected line",
                "Ctrl+Z undo · Ctrl+Shift+Z redo · Ctrl+O open · Ctrl+S save project · Ctrl+E export",
            ] {
                ui.label(line);
            }
        });
    });
}
