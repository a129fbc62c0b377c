//! What the UI asks the app to do. Widgets never change the document
//! directly: they push commands, and the app applies them in one place,
//! records undo steps and schedules the preview.

use std::path::{Path, PathBuf};

use crate::perspective::Quad;
use crate::preset::SourceLine;

use super::state::{ImageSource, LayerSetting};
use super::tools::{MaskMode, Tool, ToolSettings};

/// A shape that fills part of the mask.
#[derive(Debug, Clone, PartialEq)]
pub enum MaskShape {
    /// Axis-aligned box between two corners, photo pixels.
    Rect([f32; 2], [f32; 2]),
    /// Closed polygon, photo pixels.
    Polygon(Vec<[f32; 2]>),
    /// Connected area of similar colour around a point.
    Wand([f32; 2]),
}

/// Which file the path prompt asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PromptKind {
    /// A photo to open.
    OpenImage,
    /// A project to open.
    OpenProject,
    /// Where to save the project.
    SaveProject,
    /// A preset TOML to load.
    LoadPreset,
    /// Where to save the preset TOML.
    SavePreset,
    /// Where to export the result (PNG, JPEG, TIFF, WebP, PSD, ORA).
    Export,
    /// Where to export the time-lapse (GIF, animated PNG).
    ExportTimelapse,
}

impl PromptKind {
    /// Window title.
    pub fn title(self) -> &'static str {
        match self {
            PromptKind::OpenImage => "Open image",
            PromptKind::OpenProject => "Open project",
            PromptKind::SaveProject => "Save project",
            PromptKind::LoadPreset => "Load preset",
            PromptKind::SavePreset => "Save preset",
            PromptKind::Export => "Export",
            PromptKind::ExportTimelapse => "Export time-lapse",
        }
    }

    /// Label of the confirming button.
    pub fn action(self) -> &'static str {
        match self {
            PromptKind::OpenImage | PromptKind::OpenProject => "Open",
            PromptKind::SaveProject | PromptKind::SavePreset => "Save",
            PromptKind::LoadPreset => "Load",
            PromptKind::Export | PromptKind::ExportTimelapse => "Export now",
        }
    }

    /// True when the file is written, not read.
    pub fn saves(self) -> bool {
        matches!(
            self,
            PromptKind::SaveProject
                | PromptKind::SavePreset
                | PromptKind::Export
                | PromptKind::ExportTimelapse
        )
    }

    /// File-dialog filter: name and extensions.
    pub fn filter(self) -> (&'static str, &'static [&'static str]) {
        match self {
            PromptKind::OpenImage => ("Images", &["png", "jpg", "jpeg", "tif", "tiff", "webp"]),
            PromptKind::OpenProject | PromptKind::SaveProject => ("grime project", &["json"]),
            PromptKind::LoadPreset | PromptKind::SavePreset => ("Preset", &["toml"]),
            PromptKind::Export => (
                "Image or layered document",
                &["png", "jpg", "tif", "webp", "psd", "ora"],
            ),
            PromptKind::ExportTimelapse => ("Animation", &["gif", "png"]),
        }
    }

    /// The path the prompt suggests for the document from `source`: next
    /// to the photo (or in the working folder), named after it; nothing
    /// for the kinds that open a file.
    pub fn suggest(self, source: Option<&ImageSource>) -> String {
        let cwd = || std::env::current_dir().unwrap_or_default();
        let (dir, stem) = match source {
            Some(ImageSource::File(p)) => (
                p.parent().map(Path::to_path_buf).unwrap_or_default(),
                p.file_stem()
                    .map_or_else(|| "facade".into(), |s| s.to_string_lossy().into_owned()),
            ),
            Some(ImageSource::Demo(n)) => (cwd(), n.clone()),
            None => (cwd(), "facade".into()),
        };
        let file = match self {
            PromptKind::OpenImage | PromptKind::OpenProject | PromptKind::LoadPreset => {
                return String::new();
            }
            PromptKind::SaveProject => format!("{stem}.grime.json"),
            PromptKind::SavePreset => format!("{stem}.toml"),
            PromptKind::Export => format!("{stem}-aged.png"),
            PromptKind::ExportTimelapse => format!("{stem}-ageing.gif"),
        };
        dir.join(file).display().to_string()
    }

    /// The command for a chosen path.
    pub fn command(self, path: PathBuf) -> Command {
        match self {
            PromptKind::OpenImage => Command::OpenImage(path),
            PromptKind::OpenProject => Command::OpenProject(path),
            PromptKind::SaveProject => Command::SaveProject(path),
            PromptKind::LoadPreset => Command::LoadPreset(path),
            PromptKind::SavePreset => Command::SavePreset(path),
            PromptKind::Export => Command::Export(path),
            PromptKind::ExportTimelapse => Command::ExportTimelapse(path),
        }
    }
}

/// Everything the UI can ask for.
#[derive(Debug, Clone, PartialEq)]
pub enum Command {
    /// Ask for a path (text field plus the system file dialog).
    Prompt(PromptKind),
    /// Open a photo.
    OpenImage(PathBuf),
    /// Open a built-in sample.
    OpenDemo(String),
    /// Open a project file.
    OpenProject(PathBuf),
    /// Save the project.
    SaveProject(PathBuf),
    /// Load a preset TOML (same format as the CLI's `--preset`).
    LoadPreset(PathBuf),
    /// Use a built-in preset.
    BuiltinPreset(String),
    /// Save the preset as commented TOML.
    SavePreset(PathBuf),
    /// Export at full resolution.
    Export(PathBuf),
    /// Export the time-lapse (year 0 to the preset's age) at full resolution.
    ExportTimelapse(PathBuf),
    /// Stop a running export.
    CancelExport,
    /// Show the preview at this age (years); `None` = the preset's age. No
    /// simulation: the frames of the last one are shown.
    ShowAge(Option<u32>),
    /// Start or stop playing the ages.
    PlayAges(bool),
    /// A brush or eraser stroke starts.
    StrokeBegin,
    /// The stroke continues from one photo point to the next.
    StrokeTo {
        /// From.
        from: [f32; 2],
        /// To.
        to: [f32; 2],
        /// Eraser instead of brush.
        erase: bool,
    },
    /// The stroke ends (one undo step).
    StrokeEnd,
    /// Fill a shape.
    MaskShape(MaskShape, MaskMode),
    /// Invert the region.
    MaskInvert,
    /// Empty the region.
    MaskClear,
    /// Make the whole photo wall.
    MaskFill,
    /// Fill the region with the wall the scene analysis finds (one undo step).
    AutoRegion,
    /// Replace the source lines; with `before`, as one undo step from
    /// `before` (the end of a drag), without, live while dragging.
    SetLines {
        /// The new lines.
        lines: Vec<SourceLine>,
        /// The lines before the gesture, to record an undo step.
        before: Option<Vec<SourceLine>>,
    },
    /// Propose source lines from the ledges the scene analysis finds inside
    /// the region (adds to the lines).
    DetectLedges,
    /// Replace the quad; `before` as for [`Command::SetLines`].
    SetQuad {
        /// The new quad.
        quad: Option<Quad>,
        /// The quad before the gesture, to record an undo step.
        before: Option<Option<Quad>>,
    },
    /// Set one preset field, `path=value` as in `--set`.
    SetParam {
        /// Dotted path, e.g. `rain.k_a`.
        path: String,
        /// TOML literal.
        value: String,
        /// Merge with the previous step of the same field (dragging).
        merge: bool,
    },
    /// Layer visibility and opacity.
    SetLayer {
        /// Layer name.
        name: String,
        /// The setting.
        setting: LayerSetting,
    },
    /// Forget all layer settings.
    ResetLayers,
    /// Undo.
    Undo,
    /// Redo.
    Redo,
    /// Choose a tool.
    SetTool(Tool),
    /// Tool options (brush size and hardness, wand tolerance, add or
    /// subtract).
    SetTools(ToolSettings),
    /// Show the photo without weathering.
    ShowOriginal(bool),
    /// Show the region overlay.
    ShowMask(bool),
    /// Hide the status bar message.
    DismissMessage,
    /// Fit the image to the canvas.
    FitView,
    /// Close the window.
    Quit,
}
