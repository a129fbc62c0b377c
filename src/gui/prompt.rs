//! The path prompt: a modal with a text field and the system file dialog.
//! Its text is the view's own (what is being typed); a chosen path becomes
//! a [`Command`].

use eframe::egui;

use std::path::PathBuf;

use egui::{Key, RichText, Ui};

use super::command::{Command, PromptKind};

/// An open prompt.
pub struct Prompt {
    kind: PromptKind,
    text: String,
    focus: bool,
    /// Shown when the file dialog gave nothing.
    hint: Option<&'static str>,
}

impl Prompt {
    /// A prompt for `kind`, starting with `text`.
    pub fn new(kind: PromptKind, text: String) -> Prompt {
        Prompt {
            kind,
            text,
            focus: true,
            hint: None,
        }
    }

    /// Draws the modal; returns false once it is closed. A chosen path is
    /// pushed as the kind's command.
    pub fn show(&mut self, ui: &mut Ui, out: &mut Vec<Command>) -> bool {
        let kind = self.kind;
        let mut close = false;
        let mut chosen: Option<PathBuf> = None;
        let modal = egui::Modal::new(egui::Id::unique("path prompt")).show(ui.ctx(), |ui| {
            ui.set_width(520.0);
            ui.heading(kind.title());
            let (name, exts) = kind.filter();
            ui.label(RichText::new(format!("{name}: .{}", exts.join(" ."))).weak());
            ui.horizontal(|ui| {
                let label = ui.label("Path");
                let r = ui
                    .add(
                        egui::TextEdit::singleline(&mut self.text)
                            .desired_width(360.0)
                            .hint_text("/path/to/file"),
                    )
                    .labelled_by(label.id);
                if self.focus {
                    r.request_focus();
                    self.focus = false;
                }
                if r.lost_focus()
                    && ui.input(|i| i.key_pressed(Key::Enter))
                    && !self.text.trim().is_empty()
                {
                    chosen = Some(PathBuf::from(self.text.trim()));
                }
                if ui
                    .button("Browse…")
                    .on_hover_text("The system file dialog (needs xdg-desktop-portal)")
                    .clicked()
                {
                    self.browse(name, exts);
                }
            });
            if let Some(hint) = self.hint {
                ui.label(RichText::new(hint).weak());
            }
            ui.add_space(6.0);
            ui.horizontal(|ui| {
                let ok = ui.add_enabled(
                    !self.text.trim().is_empty(),
                    egui::Button::new(kind.action()),
                );
                if ok.clicked() {
                    chosen = Some(PathBuf::from(self.text.trim()));
                }
                if ui.button("Cancel").clicked() {
                    close = true;
                }
            });
        });
        if let Some(p) = chosen {
            out.push(kind.command(p));
            close = true;
        }
        !(close || modal.should_close())
    }

    /// The system file dialog, starting where the text points.
    fn browse(&mut self, name: &str, exts: &[&str]) {
        let dialog = rfd::FileDialog::new()
            .set_title(self.kind.title())
            .add_filter(name, exts);
        let current = PathBuf::from(self.text.trim());
        let dialog = match (current.parent(), current.file_name()) {
            (Some(dir), Some(file)) if dir.is_dir() => dialog
                .set_directory(dir)
                .set_file_name(file.to_string_lossy()),
            _ => dialog,
        };
        let picked = if self.kind.saves() {
            dialog.save_file()
        } else {
            dialog.pick_file()
        };
        match picked {
            Some(p) => {
                self.text = p.display().to_string();
                self.hint = None;
            }
            None => {
                self.hint = Some(
                    "No file chosen. If no dialog appeared (no xdg-desktop-portal), type the path.",
                )
            }
        }
    }
}
