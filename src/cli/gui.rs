//! `grime gui`: the interactive editor.

use std::path::PathBuf;

use anyhow::anyhow;
use clap::Args;
use grime::gui::{self, AppOptions};

use super::common::PresetFlags;

/// Open the interactive editor: mark the wall, draw source lines, tune the
/// parameters and watch the wall age; export PNG, PSD or ORA.
///
/// Mouse: wheel zooms, middle/right drag or Space+drag pans. Tools: H pan,
/// B brush, E eraser, R rectangle, L lasso, W wand, N line, V edit lines,
/// Q quad. Ctrl+Z / Ctrl+Shift+Z undo and redo.
#[derive(Debug, Args)]
pub struct GuiArgs {
    /// A photo (PNG, JPEG, TIFF, WebP) or a project file (.json) to open.
    #[arg(conflicts_with = "demo")]
    image: Option<PathBuf>,
    /// Open an embedded sample: `facade` (default) or `brick`.
    #[arg(long, value_name = "NAME", num_args = 0..=1, default_missing_value = "facade")]
    demo: Option<String>,
    #[command(flatten)]
    preset: PresetFlags,
    /// Save a PNG screenshot of the window once the preview is ready, then
    /// quit; fails if the screenshot is blank (for CI and docs).
    #[arg(long, value_name = "FILE")]
    screenshot: Option<PathBuf>,
    /// Quit after N frames (at least; with --screenshot, once the preview
    /// is ready).
    #[arg(long, value_name = "N")]
    quit_after_frames: Option<u64>,
}

pub fn run(args: GuiArgs) -> anyhow::Result<()> {
    let (preset, _) = args.preset.resolve()?;
    gui::launch(AppOptions {
        image: args.image,
        demo: args.demo,
        preset,
        screenshot: args.screenshot,
        quit_after_frames: args.quit_after_frames,
        ..AppOptions::default()
    })
    .map_err(|e| anyhow!(e))
}
