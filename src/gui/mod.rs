//! `grime gui`: retouch a facade interactively.
//!
//! The GUI is a thin front end over the same core as the CLI: previews go
//! through [`crate::pipeline::run_cached`], exports through
//! [`crate::age::age_adjusted`] (whose guard is the one overwrite check).
//! It is laid out in rooms, in the manner of egui_demo_app:
//!
//! - [`app`]: the frame loop, wiring only (the `eframe::App`).
//! - [`controller`]: applies [`command::Command`]s to the document, records
//!   [`history`] steps and drives the workers; no egui inside. File I/O
//!   runs on the file thread ([`files`]), simulations on [`worker`]s.
//! - [`preview`]: the preview scheduler (simulate, re-composite, or wait).
//! - [`exporter`]: the export worker, its progress and last result.
//! - [`render`] and [`proxy`]: the jobs the workers run, on a ~1 MP proxy
//!   (a quick pass on a coarse grid, then the full pass) and at full size.
//! - The views, which read state and emit commands: [`menu`], [`toolbar`],
//!   [`panels`] (the side panel), [`status`], [`prompt`], and the
//!   [`canvas`] with its [`tools`] and [`overlays`].
//! - [`state`]: the document and the project file, plain data.
//! - [`automation`]: scripted runs (`--screenshot`, `--quit-after-frames`).

pub mod ages;
pub mod analyser;
pub mod app;
pub mod automation;
pub mod canvas;
pub mod command;
pub mod controller;
pub mod exporter;
pub mod fields;
pub mod files;
pub mod history;
pub mod menu;
pub mod overlays;
pub mod panels;
pub mod preview;
pub mod prompt;
pub mod proxy;
pub mod render;
pub mod say;
pub mod state;
pub mod status;
pub mod toolbar;
pub mod tools;
pub mod worker;

pub use app::{AppOptions, GrimeApp};
/// The egui version the GUI is built with (for tests and embedding).
pub use eframe::egui;

/// Opens the window and runs until it is closed.
///
/// # Errors
/// When the window cannot be created (no display, no OpenGL), or a scripted
/// run (`--screenshot`) failed, e.g. because the screenshot was blank.
pub fn launch(options: AppOptions) -> Result<(), String> {
    let automated = options.screenshot.is_some() || options.quit_after_frames.is_some();
    let native = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title("grime")
            .with_app_id("grime")
            .with_inner_size([1280.0, 800.0])
            .with_min_inner_size([720.0, 480.0])
            .with_drag_and_drop(true),
        persist_window: !automated,
        ..Default::default()
    };
    let outcome: std::sync::Arc<std::sync::Mutex<Option<app::Outcome>>> = Default::default();
    let slot = std::sync::Arc::clone(&outcome);
    eframe::run_native(
        "grime",
        native,
        Box::new(move |cc| {
            let app = GrimeApp::new(options);
            cc.egui_ctx.request_repaint();
            if let Ok(mut s) = slot.lock() {
                *s = app.outcome();
            }
            Ok(Box::new(app))
        }),
    )
    .map_err(|e| format!("cannot open the window: {e}"))?;
    let cell = outcome.lock().ok().and_then(|s| s.clone());
    match cell {
        None => Ok(()),
        Some(cell) => cell
            .lock()
            .ok()
            .and_then(|o| o.clone())
            .unwrap_or_else(|| Err("the window closed before the scripted run finished".into())),
    }
}
