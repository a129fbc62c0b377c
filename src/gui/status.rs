//! The status bar: preview and export progress, timings, the message, and
//! where the pointer is. It reads the controller's state and emits
//! [`Command`]s.

use eframe::egui;

use egui::{Color32, RichText, Ui};

use super::canvas::Canvas;
use super::command::Command;
use super::controller::Controller;

/// The status bar.
pub fn show(ui: &mut Ui, ctl: &Controller, canvas: &Canvas, out: &mut Vec<Command>) {
    ui.horizontal(|ui| {
        let pv = ctl.preview();
        if pv.is_running() {
            let s = pv.status();
            ui.spinner();
            // The quick pass is shown while the full one runs.
            let (label, tip) = if pv.is_refining() {
                (
                    "refining…",
                    "A quick pass on a coarse grid is shown; the full detail follows",
                )
            } else {
                ("preview", "Computing the preview")
            };
            ui.add(
                egui::ProgressBar::new(s.fraction)
                    .desired_width(160.0)
                    .text(format!("{label}: {}", s.stage)),
            )
            .on_hover_text(tip);
            if pv.is_refining()
                && let Some(ms) = pv.latency_ms()
            {
                ui.weak(format!("preview {ms:.0} ms"));
            }
        } else if let Some(ms) = pv.latency_ms().or(pv.sim_ms()) {
            let text = match pv.refined_ms() {
                Some(r) if r > ms + 1.0 => format!("preview {ms:.0} ms · refined {r:.0} ms"),
                _ => format!("preview {ms:.0} ms"),
            };
            ui.weak(text)
                .on_hover_text("Change to preview: the quick pass, then the full detail (refined)");
        }
        if let Some((path, s)) = ctl.export_running() {
            ui.separator();
            ui.spinner();
            let name = path
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            ui.add(
                egui::ProgressBar::new(s.fraction)
                    .desired_width(200.0)
                    .text(format!("export {name}: {}", s.stage)),
            );
            if ui.small_button("Cancel export").clicked() {
                out.push(Command::CancelExport);
            }
        }
        if let Some(m) = ctl.message() {
            ui.separator();
            let text = RichText::new(&m.text);
            let text = if m.error {
                text.color(Color32::from_rgb(255, 110, 100))
            } else {
                text
            };
            ui.label(text);
            if ui.small_button("×").on_hover_text("Dismiss").clicked() {
                out.push(Command::DismissMessage);
            }
        }
        ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
            let Some(l) = ctl.loaded() else { return };
            if let Some(p) = canvas.hover {
                ui.weak(format!("{:.0}, {:.0}", p[0], p[1]));
            }
            ui.weak(format!("zoom {:.0}%", canvas.view.zoom * 100.0));
            let (pw, ph) = (l.proxy.photo.width(), l.proxy.photo.height());
            ui.weak(format!(
                "{} · {}×{} (preview {}×{})",
                l.doc.source.display_name(),
                l.photo.width(),
                l.photo.height(),
                pw,
                ph
            ));
        });
    });
}
