//! The controller: the document, its history and the workers, changed only
//! by [`Command`]s ([`Controller::apply`]). No egui in here: what the view
//! must do afterwards (new textures, a prompt, fit the view) is left in
//! [`ViewRequests`] for the frame loop. File I/O runs on the file thread
//! ([`Files`]), simulations on the preview and export workers.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use image::{GrayImage, RgbImage};

use crate::analysis::Analysis;
use crate::photo::Photo;
use crate::pipeline::Site;
use crate::preset::{self, Preset};

use super::analyser::{self, Analyser, Finished, Want};
use super::command::{Command, MaskShape, PromptKind};
use super::exporter::Exporter;
use super::files::{FileDone, FileJob, Files};
use super::history::{Edit, History, MaskPatch, Touched};
use super::preview::{Polled, Scheduler};
use super::proxy::Proxy;
use super::render::Exported;
use super::state::Document;
use super::tools::{self, PixelRect, Tool, ToolSettings};
use super::worker::{Repaint, Status};

/// The open photo and everything derived from it.
pub struct Loaded {
    /// The document.
    pub doc: Document,
    /// The full-size photo.
    pub photo: Arc<Photo>,
    /// The preview proxy.
    pub proxy: Proxy,
    /// The files behind the document, which no export may overwrite.
    pub from: Vec<PathBuf>,
    /// 8-bit RGB of the photo for the wand, made on first use.
    rgb: Option<RgbImage>,
    /// Bumped whenever the photo, mask, lines or quad change.
    pub rev: u64,
    /// The mask when the current brush stroke began.
    stroke_before: Option<GrayImage>,
    /// The scene analysis of the photo, once "Auto region" or "Detect
    /// ledges" asked for it.
    analysis: Option<Arc<Analysis>>,
}

impl Loaded {
    /// The building the scene analysis saw at the photo's size (scale,
    /// ground, ledges, shelter), once "Auto region" or "Detect ledges" ran:
    /// what an export runs with, as `grime run` does with an analysed photo.
    pub fn site(&self) -> Option<Site> {
        self.analysis.as_deref().map(Site::seen)
    }

    /// True during a brush or eraser stroke.
    pub fn stroking(&self) -> bool {
        self.stroke_before.is_some()
    }
}

/// A line in the status bar.
#[derive(Debug, Clone, PartialEq)]
pub struct Message {
    /// The text.
    pub text: String,
    /// Shown as an error.
    pub error: bool,
}

/// What the view shows besides the document.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewOptions {
    /// The photo without weathering.
    pub show_original: bool,
    /// The region overlay.
    pub show_mask: bool,
}

/// What the frame loop must do for the view after commands were applied.
#[derive(Debug, Default)]
pub struct ViewRequests {
    /// A new document is open: new textures, a fresh canvas.
    pub opened: bool,
    /// Proxy pixels of the mask that changed (for the overlay).
    pub mask_rects: Vec<PixelRect>,
    /// Ask for a path, with a suggestion.
    pub prompt: Option<(PromptKind, String)>,
    /// Fit the photo to the canvas.
    pub fit_view: bool,
    /// Drop the canvas gesture in progress.
    pub reset_gesture: bool,
    /// Lines were removed: drop the line selection.
    pub deselect_line: bool,
    /// Close the window.
    pub quit: bool,
}

/// The application's state and its workers.
pub struct Controller {
    loaded: Option<Loaded>,
    history: History,
    tools: ToolSettings,
    view: ViewOptions,
    preview: Scheduler,
    export: Exporter,
    files: Files,
    analyser: Analyser,
    message: Option<Message>,
    requests: ViewRequests,
    proxy_pixels: u64,
    default_preset: Preset,
}

impl Controller {
    /// A controller with its workers; they call `repaint` when they have
    /// something to show.
    pub fn new(preset: Preset, proxy_pixels: u64, repaint: Repaint) -> Controller {
        Controller {
            loaded: None,
            history: History::default(),
            tools: ToolSettings::default(),
            view: ViewOptions {
                show_original: false,
                show_mask: true,
            },
            preview: Scheduler::new(Arc::clone(&repaint)),
            export: Exporter::new(Arc::clone(&repaint)),
            files: Files::spawn(Arc::clone(&repaint)),
            analyser: Analyser::new(repaint),
            message: None,
            requests: ViewRequests::default(),
            proxy_pixels: proxy_pixels.max(1024),
            default_preset: preset,
        }
    }

    /// The open document and its runtime data.
    pub fn loaded(&self) -> Option<&Loaded> {
        self.loaded.as_ref()
    }

    /// The undo history.
    pub fn history(&self) -> &History {
        &self.history
    }

    /// The tool options.
    pub fn tools(&self) -> &ToolSettings {
        &self.tools
    }

    /// What the view shows.
    pub fn view(&self) -> ViewOptions {
        self.view
    }

    /// The preview scheduler.
    pub fn preview(&self) -> &Scheduler {
        &self.preview
    }

    /// The preview scheduler, for the view to take fresh previews.
    pub fn preview_mut(&mut self) -> &mut Scheduler {
        &mut self.preview
    }

    /// The status bar message.
    pub fn message(&self) -> Option<&Message> {
        self.message.as_ref()
    }

    /// The file being exported and the export's progress.
    pub fn export_running(&self) -> Option<(&Path, Status)> {
        self.export.running()
    }

    /// The last export's result.
    pub fn last_export(&self) -> Option<&Result<Exported, String>> {
        self.export.last()
    }

    /// True while a preview, export, file operation or analysis is running
    /// or pending.
    pub fn is_busy(&self) -> bool {
        self.is_working() || self.preview.is_busy()
    }

    /// True while a worker runs (the view keeps its spinner turning).
    pub fn is_working(&self) -> bool {
        self.preview.is_running()
            || self.export.running().is_some()
            || self.files.is_busy()
            || self.analyser.is_busy()
    }

    /// What the view must do; taking it clears it.
    pub fn take_requests(&mut self) -> ViewRequests {
        std::mem::take(&mut self.requests)
    }

    fn info(&mut self, text: impl Into<String>) {
        self.message = Some(Message {
            text: text.into(),
            error: false,
        });
    }

    fn error(&mut self, text: impl Into<String>) {
        self.message = Some(Message {
            text: text.into(),
            error: true,
        });
    }

    /// Takes the workers' results.
    pub fn poll(&mut self) {
        match self.preview.poll() {
            Polled::Failed(e) => self.error(e),
            Polled::Shown => {
                if self
                    .message
                    .as_ref()
                    .is_some_and(|m| m.error && m.text.starts_with("preview:"))
                {
                    self.message = None;
                }
            }
            Polled::Nothing => {}
        }
        match self.export.poll() {
            Some(Ok(note)) => self.info(note),
            Some(Err(e)) => self.error(e),
            None => {}
        }
        for done in self.files.poll() {
            match done {
                Ok(FileDone::Opened {
                    doc,
                    photo,
                    from,
                    note,
                }) => {
                    self.open(*doc, photo, from);
                    self.info(note);
                }
                Ok(FileDone::Preset(p, path)) => {
                    self.set_preset(*p, "preset file");
                    self.info(format!("Loaded preset {}", path.display()));
                }
                Ok(FileDone::Saved(note)) => self.info(note),
                Err(e) => self.error(e),
            }
        }
        if let Some(done) = self.analyser.poll() {
            self.analysed(done);
        }
    }

    /// Starts a simulation, re-composites, or waits, as the last changes need.
    pub fn schedule_preview(&mut self) {
        if let Err(e) = self.preview.schedule(self.loaded.as_ref()) {
            self.error(e);
        }
    }

    fn file(&mut self, job: FileJob) {
        if let Err(e) = self.files.submit(job) {
            self.error(e);
        }
    }

    fn open(&mut self, doc: Document, photo: Photo, from: Vec<PathBuf>) {
        let photo = Arc::new(photo);
        let proxy = Proxy::new(&photo, &doc.mask, self.proxy_pixels);
        self.preview.reset();
        let rev = self.loaded.as_ref().map_or(1, |l| l.rev + 1);
        self.loaded = Some(Loaded {
            doc,
            photo,
            proxy,
            from,
            rgb: None,
            rev,
            stroke_before: None,
            analysis: None,
        });
        self.analyser.reset();
        self.history.clear();
        self.requests.opened = true;
        self.requests.mask_rects.clear();
    }

    /// The mask changed inside `rect` (photo pixels): update the proxy there.
    fn mask_changed(&mut self, rect: PixelRect) {
        let Some(l) = &mut self.loaded else { return };
        if let Some(r) = l.proxy.update_mask(&l.doc.mask, rect) {
            self.requests.mask_rects.push(r);
        }
    }

    /// The photo, mask, lines or quad changed.
    fn bump(&mut self) {
        if let Some(l) = &mut self.loaded {
            l.rev += 1;
        }
        self.preview.touch();
    }

    /// Applies a mask operation as one undo step.
    fn mask_op(&mut self, op: impl FnOnce(&mut GrayImage, &Loaded) -> Option<PixelRect>) {
        let Some(l) = &mut self.loaded else { return };
        let before = l.doc.mask.clone();
        let mut mask = std::mem::take(&mut l.doc.mask);
        let touched = op(&mut mask, l);
        l.doc.mask = mask;
        if touched.is_none() {
            return;
        }
        if let Some(patch) = MaskPatch::diff(&before, &l.doc.mask) {
            let rect = patch.rect;
            self.history.push(Edit::Mask(patch), false);
            self.mask_changed(rect);
            self.bump();
        }
    }

    fn current_preset(&self) -> Preset {
        let mut p = self
            .loaded
            .as_ref()
            .map_or_else(|| self.default_preset.clone(), |l| l.doc.preset.clone());
        p.rain.source_lines.clear();
        p
    }

    /// Applies one command.
    pub fn apply(&mut self, cmd: Command) {
        match cmd {
            Command::Prompt(kind) => {
                let source = self.loaded.as_ref().map(|l| &l.doc.source);
                self.requests.prompt = Some((kind, kind.suggest(source)));
            }
            Command::OpenImage(path) => {
                if path
                    .extension()
                    .is_some_and(|e| e.eq_ignore_ascii_case("json"))
                {
                    return self.apply(Command::OpenProject(path));
                }
                let preset = self.current_preset();
                self.file(FileJob::OpenImage(path, preset));
            }
            Command::OpenDemo(name) => {
                let preset = self.current_preset();
                self.file(FileJob::OpenDemo(name, preset));
            }
            Command::OpenProject(path) => self.file(FileJob::OpenProject(path)),
            Command::SaveProject(path) => {
                let Some(l) = &self.loaded else { return };
                let doc = Box::new(l.doc.clone());
                self.file(FileJob::SaveProject(doc, path));
            }
            Command::LoadPreset(path) => self.file(FileJob::LoadPreset(path)),
            Command::BuiltinPreset(name) => match preset::builtin(&name) {
                Ok(mut p) => {
                    if let Some(l) = &self.loaded {
                        p.seed = l.doc.preset.seed;
                    }
                    self.set_preset(p, "built-in preset");
                    self.info(format!("Preset: {name}"));
                }
                Err(e) => self.error(e.to_string()),
            },
            Command::SavePreset(path) => {
                let text = self.loaded.as_ref().map_or_else(
                    || self.default_preset.to_commented_toml(),
                    |l| l.doc.preset_toml(),
                );
                self.file(FileJob::SavePreset(text, path));
            }
            Command::Export(path) => self.start_export(path, false),
            Command::ExportTimelapse(path) => self.start_export(path, true),
            Command::ShowAge(years) => self.preview.show_age(years),
            Command::PlayAges(on) => self.preview.play(on),
            Command::CancelExport => {
                self.export.cancel();
                self.info("Export cancelled");
            }
            Command::StrokeBegin => {
                if let Some(l) = &mut self.loaded {
                    l.stroke_before = Some(l.doc.mask.clone());
                }
            }
            Command::StrokeTo { from, to, erase } => {
                let (size, hard) = (self.tools.brush_size, self.tools.hardness);
                let Some(l) = &mut self.loaded else { return };
                if let Some(r) = tools::stroke(&mut l.doc.mask, from, to, size / 2.0, hard, erase) {
                    self.mask_changed(r);
                }
            }
            Command::StrokeEnd => {
                let Some(l) = &mut self.loaded else { return };
                if let Some(before) = l.stroke_before.take()
                    && let Some(patch) = MaskPatch::diff(&before, &l.doc.mask)
                {
                    self.history.push(Edit::Mask(patch), false);
                    self.bump();
                }
            }
            Command::MaskShape(shape, mode) => {
                let tol = self.tools.tolerance;
                if let (MaskShape::Wand(_), Some(l)) = (&shape, &mut self.loaded)
                    && l.rgb.is_none()
                {
                    l.rgb = Some(l.photo.image().to_rgb8());
                }
                self.mask_op(|mask, l| match &shape {
                    MaskShape::Rect(a, b) => crate::masks::fill_rect(mask, *a, *b, mode),
                    MaskShape::Polygon(pts) => crate::masks::fill_polygon(mask, pts, mode),
                    MaskShape::Wand(p) => l
                        .rgb
                        .as_ref()
                        .and_then(|rgb| crate::masks::wand(rgb, mask, *p, tol, mode)),
                });
            }
            Command::MaskInvert => self.mask_op(|m, _| Some(crate::masks::invert(m))),
            Command::MaskClear => self.mask_op(|m, _| Some(crate::masks::fill_all(m, 0))),
            Command::MaskFill => self.mask_op(|m, _| Some(crate::masks::fill_all(m, 255))),
            Command::SetLines { lines, before } => {
                let Some(l) = &mut self.loaded else { return };
                if let Some(before) = before {
                    self.history.push(
                        Edit::Lines {
                            before,
                            after: lines.clone(),
                        },
                        false,
                    );
                }
                if lines.len() < l.doc.lines.len() {
                    self.requests.deselect_line = true;
                }
                l.doc.lines = lines;
                self.bump();
            }
            Command::AutoRegion => self.with_analysis(Want::Region),
            Command::DetectLedges => self.with_analysis(Want::Ledges),
            Command::SetQuad { quad, before } => {
                if let Some(q) = &quad
                    && let Err(e) = crate::perspective::validate(q)
                {
                    return self.error(e.to_string());
                }
                let Some(l) = &mut self.loaded else { return };
                if let Some(before) = before {
                    self.history.push(
                        Edit::Quad {
                            before,
                            after: quad,
                        },
                        false,
                    );
                }
                l.doc.quad = quad;
                self.bump();
            }
            Command::SetParam { path, value, merge } => {
                let Some(l) = &mut self.loaded else { return };
                let mut p = l.doc.preset.clone();
                // The clock's fields set the effects' counts (crate::clock).
                let mut set = p.set(&format!("{path}={value}"));
                if set.is_ok() && path.starts_with("age.") {
                    set = crate::clock::resolve(&p, crate::clock::Pins::none()).map(|r| p = r);
                }
                match set {
                    Ok(()) => {
                        p.rain.source_lines.clear();
                        if p != l.doc.preset {
                            let before = std::mem::replace(&mut l.doc.preset, p.clone());
                            self.history.push(
                                Edit::Preset {
                                    key: path,
                                    before: Box::new(before),
                                    after: Box::new(p),
                                },
                                merge,
                            );
                            self.preview.touch();
                        }
                    }
                    Err(e) => self.error(e.to_string()),
                }
            }
            Command::SetLayer { name, setting } => {
                let Some(l) = &mut self.loaded else { return };
                l.doc.layers.insert(name, setting);
                self.preview.touch();
            }
            Command::ResetLayers => {
                let Some(l) = &mut self.loaded else { return };
                l.doc.layers.clear();
                self.preview.touch();
            }
            Command::Undo | Command::Redo => self.undo_redo(cmd == Command::Undo),
            Command::SetTool(t) => {
                self.tools.tool = t;
                self.requests.reset_gesture = true;
            }
            Command::SetTools(t) => self.tools = t,
            Command::ShowOriginal(on) => self.view.show_original = on,
            Command::ShowMask(on) => self.view.show_mask = on,
            Command::DismissMessage => self.message = None,
            Command::FitView => self.requests.fit_view = true,
            Command::Quit => self.requests.quit = true,
        }
    }

    fn undo_redo(&mut self, undo: bool) {
        let Some(l) = &mut self.loaded else { return };
        let touched = if undo {
            self.history.undo(&mut l.doc)
        } else {
            self.history.redo(&mut l.doc)
        };
        self.requests.reset_gesture = true;
        match touched {
            Some(Touched::Mask(r)) => {
                self.mask_changed(r);
                self.bump();
            }
            Some(Touched::Lines | Touched::Quad) => {
                self.requests.deselect_line = true;
                self.bump();
            }
            Some(Touched::Preset) => self.preview.touch(),
            None => self.info(if undo {
                "Nothing to undo"
            } else {
                "Nothing to redo"
            }),
        }
    }

    /// Does `want` with the photo's analysis, starting it (off the UI
    /// thread) when there is none yet.
    fn with_analysis(&mut self, want: Want) {
        let Some(l) = &self.loaded else { return };
        if let Some(a) = l.analysis.clone() {
            return self.use_analysis(want, &a);
        }
        let name = l.doc.source.display_name();
        self.analyser.start(&l.photo, &name, want);
        self.info("Analysing the photo…");
    }

    /// An analysis finished: keep it with its photo and do what it was for.
    fn analysed(&mut self, done: Finished) {
        let Some(l) = &mut self.loaded else { return };
        if !Arc::ptr_eq(&l.photo, &done.photo) {
            return;
        }
        match done.result {
            Ok(a) => {
                l.analysis = Some(Arc::clone(&a));
                // The preview runs with what was seen (scale, ground,
                // ledges, shelter) from now on, as `grime run` does.
                let (w, h) = (l.proxy.photo.width(), l.proxy.photo.height());
                l.proxy.site = Some(Site::seen_at(&a, w, h));
                self.bump();
                for want in done.wants {
                    self.use_analysis(want, &a);
                }
            }
            Err(e) => self.error(e),
        }
    }

    fn use_analysis(&mut self, want: Want, a: &Analysis) {
        match want {
            Want::Region => self.auto_region(a),
            Want::Ledges => self.detect_ledges(a),
        }
    }

    /// Replaces the region with the analysis's wall matte, one undo step.
    fn auto_region(&mut self, a: &Analysis) {
        self.mask_op(|mask, _| {
            if mask.dimensions() != a.matte.dimensions() {
                return None;
            }
            mask.copy_from_slice(&a.matte);
            Some(PixelRect::full(mask.width(), mask.height()))
        });
        self.info(format!(
            "Auto region: {:.0}% of the photo is wall",
            a.wall_fraction * 100.0
        ));
    }

    /// Adds source lines along the analysis's ledges inside the region,
    /// skipping those that repeat a line already there.
    fn detect_ledges(&mut self, a: &Analysis) {
        let Some(l) = &self.loaded else { return };
        let new = analyser::new_ledges(a, &l.doc.mask, &l.doc.lines, 6.0 / l.proxy.sy);
        let added = new.len();
        if added > 0 {
            let before = l.doc.lines.clone();
            let lines = before.iter().cloned().chain(new).collect();
            self.apply(Command::SetLines {
                lines,
                before: Some(before),
            });
            self.tools.tool = Tool::EditLines;
        }
        self.info(format!(
            "Detect ledges: {added} new source line{}",
            if added == 1 { "" } else { "s" }
        ));
    }

    /// Replaces the preset as one undo step; its source lines (if any)
    /// replace the document's.
    fn set_preset(&mut self, mut p: Preset, key: &str) {
        let lines = std::mem::take(&mut p.rain.source_lines);
        let Some(l) = &mut self.loaded else {
            self.default_preset = p;
            return;
        };
        let before = std::mem::replace(&mut l.doc.preset, p.clone());
        self.history.push(
            Edit::Preset {
                key: key.into(),
                before: Box::new(before),
                after: Box::new(p),
            },
            false,
        );
        self.preview.touch();
        if !lines.is_empty() {
            let before = l.doc.lines.clone();
            self.apply(Command::SetLines {
                lines,
                before: Some(before),
            });
        }
    }

    fn start_export(&mut self, path: PathBuf, timelapse: bool) {
        let Some(l) = &self.loaded else {
            return self.error("nothing to export: open an image first");
        };
        if timelapse && l.doc.preset.age.years.is_none() {
            return self.error("a time-lapse needs an age: set Age (years) first");
        }
        match self.export.start(l, path, timelapse) {
            Ok(note) => self.info(note),
            Err(e) => self.error(e),
        }
    }
}
