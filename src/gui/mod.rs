//! `grime gui`: retouch a facade interactively.
//!
//! The GUI is a thin front end over the same pipeline as the CLI
//! ([`crate::perspective::pipeline_with_quad`], i.e. [`crate::pipeline::run`]).
//! Its parts:
//!
//! - [`state`]: the document (image, mask, source lines, quad, preset,
//!   layer settings) and the project file. Plain data.
//! - [`command`]: what widgets ask for. Widgets emit commands; [`app`]
//!   applies them in one place and records [`history`] steps.
//! - [`worker`]: background threads with cancellation; a newer job cancels
//!   an older one and stale results are dropped. A job may hand over an
//!   early result (the preview's quick pass) before its final one.
//! - [`render`]: the jobs: the ~1 MP preview (a quick pass on a coarse grid,
//!   then the full pass; re-composite-only updates) and the full-resolution
//!   export.
//! - [`canvas`], [`tools`], [`panels`]: the canvas and its tools, and the
//!   parameter, time and layer panels.

pub mod app;
pub mod automation;
pub mod canvas;
pub mod command;
pub mod controller;
pub mod files;
pub mod history;
pub mod menu;
pub mod panels;
pub mod preview;
pub mod prompt;
pub mod proxy;
pub mod render;
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
