//! The "Say how old" box: a sentence in grime's adverb language
//! ([`crate::say`]) that fills the sliders. What it set is listed under it,
//! so the user sees the sentence as preset fields.

use eframe::egui;
use egui::{Id, Ui};

use crate::preset::Preset;

use super::command::Command;

/// The text box, its Apply button and what the last sentence set.
pub fn panel(ui: &mut Ui, preset: &Preset, out: &mut Vec<Command>) {
    let text_id = Id::unique("say text");
    let said_id = Id::unique("say result");
    let mut text: String = ui
        .data_mut(|d| d.get_temp::<String>(text_id))
        .unwrap_or_else(|| preset.say.clone());
    let mut apply = false;
    ui.horizontal(|ui| {
        let label = ui.label("Say how old");
        let edit = ui
            .add(
                egui::TextEdit::singleline(&mut text)
                    .hint_text("very rusty near the railings, slightly scratched")
                    .desired_width(ui.available_width() - 60.0),
            )
            .labelled_by(label.id)
            .on_hover_text(
                "Say how old: [adverb] effect [near the place], ... \
                 Adverbs set coverage: slightly 0.05, partially 0.1, somewhat 0.2, (none) 0.25, \
                 moderately 0.35, very 0.55, extremely 0.75, completely 1. Same as --say.",
            );
        apply = edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
        apply |= ui
            .button("Say it")
            .on_hover_text("Set the sliders the sentence names")
            .clicked();
    });
    ui.data_mut(|d| d.insert_temp(text_id, text.clone()));
    if apply {
        let lines = match crate::say::parse(&text) {
            Ok(said) => {
                for (path, value) in &said.set {
                    out.push(Command::SetParam {
                        path: path.clone(),
                        value: value.clone(),
                        merge: false,
                    });
                }
                out.push(Command::SetParam {
                    path: "say".into(),
                    value: toml::Value::String(text.clone()).to_string(),
                    merge: false,
                });
                let mut lines: Vec<String> =
                    said.set.iter().map(|(p, v)| format!("{p} = {v}")).collect();
                lines.extend(said.notes);
                lines
            }
            Err(e) => vec![e.to_string()],
        };
        ui.data_mut(|d| d.insert_temp(said_id, lines));
    }
    if let Some(lines) = ui.data_mut(|d| d.get_temp::<Vec<String>>(said_id)) {
        for line in lines {
            ui.weak(line);
        }
    }
}
