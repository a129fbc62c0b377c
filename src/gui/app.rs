//! The application: document, runtime handles and the frame loop.
//!
//! Each frame: take the workers' results, draw the panels and canvas (which
//! emit [`Command`]s), apply the commands in one place (undo steps, mask
//! refresh), then decide whether the preview needs a new simulation, only a
//! re-composite, or nothing.

use eframe::egui;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use egui::{
    Color32, ColorImage, Key, KeyboardShortcut, Modifiers, RichText, TextureHandle, TextureOptions,
    Ui,
};
use image::{GrayImage, RgbImage};

use crate::demo;
use crate::io;
use crate::photo::Photo;
use crate::pipeline::Scene;
use crate::preset::{self, Preset};

use super::canvas::{Canvas, CanvasInput};
use super::command::{Command, MaskShape, PromptKind};
use super::history::{Edit, History, MaskPatch, Touched};
use super::panels::{self, LayerRow};
use super::render::{
    self, ExportJob, Exported, PROXY_PIXELS, Preview, PreviewJob, Previewer, Proxy,
};
use super::state::{Document, ImageSource, LayerSetting};
use super::tools::{self, MaskMode, PixelRect, Tool, ToolSettings};
use super::worker::{Repaint, Worker};

/// How the app starts.
#[derive(Debug, Clone)]
pub struct AppOptions {
    /// A photo or project (`.json`) to open.
    pub image: Option<PathBuf>,
    /// A built-in sample to open instead.
    pub demo: Option<String>,
    /// The starting preset.
    pub preset: Preset,
    /// Save a screenshot of the window here, then quit.
    pub screenshot: Option<PathBuf>,
    /// Quit (or take the screenshot) after this many frames, once the
    /// preview is ready.
    pub quit_after_frames: Option<u64>,
    /// Pixels of the preview proxy.
    pub proxy_pixels: u64,
}

impl Default for AppOptions {
    fn default() -> Self {
        AppOptions {
            image: None,
            demo: None,
            preset: Preset::default(),
            screenshot: None,
            quit_after_frames: None,
            proxy_pixels: PROXY_PIXELS,
        }
    }
}

/// How a scripted run (`--screenshot`, `--quit-after-frames`) ended.
pub type Outcome = Arc<Mutex<Option<Result<(), String>>>>;

struct Automation {
    screenshot: Option<PathBuf>,
    after: u64,
    frames: u64,
    started: Instant,
    requested: bool,
    shot: Arc<Mutex<Option<Arc<ColorImage>>>>,
    outcome: Outcome,
}

/// The open photo and everything derived from it.
struct Loaded {
    doc: Document,
    photo: Arc<Photo>,
    proxy: Proxy,
    /// 8-bit RGB of the photo for the wand, made on first use.
    rgb: Option<RgbImage>,
    /// Bumped whenever the photo, mask, lines or quad change.
    rev: u64,
    /// The mask when the current brush stroke began.
    stroke_before: Option<GrayImage>,
}

struct Running {
    rev: u64,
    preset: Preset,
    layers: BTreeMap<String, LayerSetting>,
}

struct PreviewState {
    worker: Worker<PreviewJob, Preview>,
    current: Option<Preview>,
    /// Inputs of the last finished simulation: revision, preset (without
    /// source lines) and whether it failed.
    sim_rev: u64,
    sim_preset: Preset,
    sim_failed: bool,
    /// The preset and layer settings `current` is styled with.
    styled: Option<(Preset, BTreeMap<String, LayerSetting>)>,
    running: Option<Running>,
    /// `current` is the quick pass of the running job; its full pass follows.
    shown_quick: bool,
    dirty: bool,
    /// When the change the preview is catching up with was made.
    changed_at: Option<Instant>,
    /// The same, once the quick pass showed, until the full pass does.
    refine_from: Option<Instant>,
    /// Change-to-preview time of the last update (the quick pass for a new
    /// simulation), ms.
    latency_ms: Option<f64>,
    /// Change-to-refined-preview time of the last simulation, ms.
    refined_ms: Option<f64>,
    /// Simulation time of the last preview, ms.
    sim_ms: Option<f64>,
}

struct ExportState {
    worker: Worker<ExportJob, Exported>,
    running: Option<PathBuf>,
    last: Option<Result<Exported, String>>,
}

struct Prompt {
    kind: PromptKind,
    text: String,
    focus: bool,
}

struct Message {
    text: String,
    error: bool,
}

#[derive(Default)]
struct Textures {
    original: Option<TextureHandle>,
    preview: Option<TextureHandle>,
    overlay: Option<TextureHandle>,
}

/// The grime GUI.
pub struct GrimeApp {
    /// The context, known from the first frame on.
    ctx: egui::Context,
    /// Where the workers send repaint requests (the context, once known).
    repaint_to: Arc<Mutex<Option<egui::Context>>>,
    loaded: Option<Loaded>,
    history: History,
    tools: ToolSettings,
    canvas: Canvas,
    preview: PreviewState,
    export: ExportState,
    textures: Textures,
    message: Option<Message>,
    prompt: Option<Prompt>,
    show_original: bool,
    show_mask: bool,
    queue: Vec<Command>,
    automation: Option<Automation>,
    proxy_pixels: u64,
    default_preset: Preset,
}

impl GrimeApp {
    /// A new app; it opens what `options` names on its first frame.
    pub fn new(options: AppOptions) -> GrimeApp {
        let repaint_to: Arc<Mutex<Option<egui::Context>>> = Arc::default();
        let repaint: Repaint = {
            let cell = Arc::clone(&repaint_to);
            Arc::new(move || {
                if let Some(ctx) = cell.lock().ok().and_then(|c| c.clone()) {
                    ctx.request_repaint();
                }
            })
        };
        let automation = (options.screenshot.is_some() || options.quit_after_frames.is_some())
            .then(|| Automation {
                screenshot: options.screenshot.clone(),
                after: options.quit_after_frames.unwrap_or(30),
                frames: 0,
                started: Instant::now(),
                requested: false,
                shot: Arc::default(),
                outcome: Arc::default(),
            });
        let mut app = GrimeApp {
            ctx: egui::Context::default(),
            repaint_to,
            loaded: None,
            history: History::default(),
            tools: ToolSettings::default(),
            canvas: Canvas::default(),
            preview: PreviewState {
                worker: {
                    let mut previewer = Previewer::default();
                    Worker::spawn_progressive(
                        "grime-preview",
                        Arc::clone(&repaint),
                        move |job, progress, emit| previewer.run(job, progress, emit),
                    )
                },
                current: None,
                sim_rev: 0,
                sim_preset: Preset::default(),
                sim_failed: false,
                styled: None,
                running: None,
                shown_quick: false,
                dirty: false,
                changed_at: None,
                refine_from: None,
                latency_ms: None,
                refined_ms: None,
                sim_ms: None,
            },
            export: ExportState {
                worker: Worker::spawn("grime-export", repaint, render::export),
                running: None,
                last: None,
            },
            textures: Textures::default(),
            message: None,
            prompt: None,
            show_original: false,
            show_mask: true,
            queue: Vec::new(),
            automation,
            proxy_pixels: options.proxy_pixels.max(1024),
            default_preset: options.preset.clone(),
        };
        if let Some(name) = &options.demo {
            app.queue.push(Command::OpenDemo(name.clone()));
        } else if let Some(path) = &options.image {
            app.queue.push(Command::OpenImage(path.clone()));
        }
        app
    }

    /// The outcome cell of a scripted run, filled when it ends.
    pub fn outcome(&self) -> Option<Outcome> {
        self.automation.as_ref().map(|a| Arc::clone(&a.outcome))
    }

    /// The document, once a photo is open.
    pub fn document(&self) -> Option<&Document> {
        self.loaded.as_ref().map(|l| &l.doc)
    }

    /// The current preview composite (proxy-sized), if one is ready.
    pub fn preview_image(&self) -> Option<&ColorImage> {
        self.preview.current.as_ref().map(|p| &*p.image)
    }

    /// True while the canvas shows the quick pass of a simulation and the
    /// full pass is still running.
    pub fn is_refining(&self) -> bool {
        self.preview.shown_quick && self.preview.running.is_some()
    }

    /// The proxy photo as an image, for comparisons.
    pub fn proxy_image(&self) -> Option<ColorImage> {
        self.loaded
            .as_ref()
            .map(|l| render::to_color_image(l.proxy.photo.image()))
    }

    /// The proxy mask.
    pub fn proxy_mask(&self) -> Option<&GrayImage> {
        self.loaded.as_ref().map(|l| &*l.proxy.mask)
    }

    /// True while a preview or export is computing or pending.
    pub fn is_busy(&self) -> bool {
        self.preview.running.is_some()
            || self.preview.dirty
            || self.export.running.is_some()
            || !self.queue.is_empty()
    }

    /// The message shown in the status bar.
    pub fn message(&self) -> Option<(&str, bool)> {
        self.message.as_ref().map(|m| (m.text.as_str(), m.error))
    }

    /// The last export's result.
    pub fn last_export(&self) -> Option<&Result<Exported, String>> {
        self.export.last.as_ref()
    }

    /// Change-to-preview time of the last preview update, ms (for a new
    /// simulation: until its quick pass showed).
    pub fn preview_latency_ms(&self) -> Option<f64> {
        self.preview.latency_ms
    }

    /// Change-to-refined-preview time of the last simulation, ms.
    pub fn preview_refined_ms(&self) -> Option<f64> {
        self.preview.refined_ms
    }

    /// Queues a command as if a widget had emitted it.
    pub fn push(&mut self, cmd: Command) {
        self.queue.push(cmd);
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

    /// Draws one frame into `ui` (the whole window).
    pub fn show(&mut self, ui: &mut Ui) {
        if let Ok(mut cell) = self.repaint_to.lock()
            && cell.is_none()
        {
            self.ctx = ui.ctx().clone();
            *cell = Some(self.ctx.clone());
        }
        self.poll_workers();
        self.global_input(ui);
        let mut out = std::mem::take(&mut self.queue);

        egui::Panel::top("menu").show(ui, |ui| self.top_bar(ui, &mut out));
        egui::Panel::bottom("status").show(ui, |ui| self.status_bar(ui, &mut out));
        egui::Panel::right("params")
            .resizable(true)
            .default_size(340.0)
            .min_size(260.0)
            .show(ui, |ui| self.side_panel(ui, &mut out));
        egui::CentralPanel::no_frame().show(ui, |ui| self.canvas_ui(ui, &mut out));
        self.prompt_ui(ui, &mut out);

        let changed = !out.is_empty();
        for cmd in out {
            self.apply(cmd);
        }
        self.schedule_preview();
        if changed {
            ui.ctx().request_repaint();
        }
        if self.preview.running.is_some() || self.export.running.is_some() {
            // Keeps the spinner turning; results wake the UI themselves.
            ui.ctx().request_repaint_after(Duration::from_millis(100));
        }
        self.automate(ui.ctx());
    }

    fn poll_workers(&mut self) {
        if let Some(done) = self.preview.worker.poll() {
            if done.partial {
                // The quick pass: show it; the running job goes on.
                if let Ok(p) = done.result {
                    self.preview.styled = self
                        .preview
                        .running
                        .as_ref()
                        .map(|r| (r.preset.clone(), r.layers.clone()));
                    self.preview.shown_quick = true;
                    self.set_preview(Some(p), true);
                    // Restyle it if the document moved on by a restyle-only change.
                    self.preview.dirty = true;
                }
                return self.poll_export();
            }
            self.preview.shown_quick = false;
            let running = self.preview.running.take();
            let ok = done.result.is_ok();
            if let Some(r) = &running {
                self.preview.sim_rev = r.rev;
                self.preview.sim_preset = r.preset.clone();
                self.preview.sim_failed = !ok;
            }
            match done.result {
                Ok(p) => {
                    self.preview.styled = running.map(|r| (r.preset, r.layers));
                    self.preview.sim_ms = Some(done.elapsed.as_secs_f64() * 1000.0);
                    self.set_preview(Some(p), true);
                    if self
                        .message
                        .as_ref()
                        .is_some_and(|m| m.error && m.text.starts_with("preview:"))
                    {
                        self.message = None;
                    }
                }
                Err(e) => {
                    self.preview.styled = None;
                    self.set_preview(None, false);
                    self.error(format!("preview: {e}"));
                }
            }
            // The document may have moved on while it ran.
            self.preview.dirty = true;
        }
        self.poll_export();
    }

    fn poll_export(&mut self) {
        if let Some(done) = self.export.worker.poll() {
            self.export.running = None;
            match done.result {
                Ok(e) => {
                    self.info(format!(
                        "Exported {}×{} ({} layers) to {} in {:.1} s",
                        e.width,
                        e.height,
                        e.layers,
                        e.path.display(),
                        done.elapsed.as_secs_f64()
                    ));
                    self.export.last = Some(Ok(e));
                }
                Err(crate::Error::Cancelled) => self.info("Export cancelled"),
                Err(e) => {
                    self.error(format!("export failed: {e}"));
                    self.export.last = Some(Err(e.to_string()));
                }
            }
        }
    }

    /// Shows `p`; `sim` when it comes from the worker (a quick or full pass),
    /// not from a re-composite.
    fn set_preview(&mut self, p: Option<Preview>, sim: bool) {
        let quick = p.as_ref().is_some_and(|p| p.quick);
        match &p {
            // The texture shares the image (no copy).
            Some(p) => match &mut self.textures.preview {
                Some(t) => t.set(Arc::clone(&p.image), TextureOptions::LINEAR),
                None => {
                    self.textures.preview = Some(self.ctx.load_texture(
                        "preview",
                        Arc::clone(&p.image),
                        TextureOptions::LINEAR,
                    ))
                }
            },
            None => self.textures.preview = None,
        }
        self.preview.current = p;
        let ms = |t: Instant| Some(t.elapsed().as_secs_f64() * 1000.0);
        let pv = &mut self.preview;
        let changed = pv.changed_at.take();
        if let Some(t) = changed {
            pv.latency_ms = ms(t);
        }
        if sim && quick {
            if let Some(t) = changed {
                pv.refine_from.get_or_insert(t);
            }
        } else if sim && let Some(t) = pv.refine_from.take().or(changed) {
            pv.refined_ms = ms(t);
        }
    }

    /// Starts a simulation, re-composites, or waits, as the change needs.
    fn schedule_preview(&mut self) {
        if !self.preview.dirty {
            return;
        }
        let Some(l) = &self.loaded else {
            self.preview.dirty = false;
            return;
        };
        if l.stroke_before.is_some() {
            return; // the preview follows when the stroke ends
        }
        self.preview.dirty = false;
        let p = &self.preview;
        let doc = &l.doc;
        let need_sim = match (&p.running, &p.current) {
            (Some(r), _) => r.rev != l.rev || !render::restyles(&r.preset, &doc.preset),
            (None, _) if p.sim_failed => p.sim_rev != l.rev || p.sim_preset != doc.preset,
            (None, Some(_)) => p.sim_rev != l.rev || !render::restyles(&p.sim_preset, &doc.preset),
            (None, None) => true,
        };
        let styled = p
            .styled
            .as_ref()
            .is_some_and(|(sp, sl)| *sp == doc.preset && *sl == doc.layers);
        if need_sim {
            match l
                .proxy
                .job(&doc.run_preset(), doc.quad.as_ref(), &doc.layers)
            {
                Ok(job) => {
                    self.preview.worker.submit(job);
                    self.preview.shown_quick = false;
                    self.preview.refine_from = None;
                    self.preview.running = Some(Running {
                        rev: l.rev,
                        preset: doc.preset.clone(),
                        layers: doc.layers.clone(),
                    });
                }
                Err(e) => self.error(format!("preview: {e}")),
            }
        } else if (self.preview.running.is_none() || self.preview.shown_quick) && !styled {
            // Also while the full pass runs: the quick pass shown follows at
            // once, the full one is restyled when it arrives.
            if let Some(mut cur) = self.preview.current.take() {
                cur.restyle(&doc.preset, &doc.layers);
                self.preview.styled = Some((doc.preset.clone(), doc.layers.clone()));
                self.set_preview(Some(cur), false);
            }
        } else if self.preview.running.is_none() {
            self.preview.changed_at = None;
        }
    }

    fn global_input(&mut self, ui: &Ui) {
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
            self.queue.push(match ext.as_str() {
                "toml" => Command::LoadPreset(path),
                "json" => Command::OpenProject(path),
                _ => Command::OpenImage(path),
            });
        }
        if self.prompt.is_some() {
            return;
        }
        let redo = KeyboardShortcut::new(Modifiers::COMMAND | Modifiers::SHIFT, Key::Z);
        let shortcuts = [
            (redo, Command::Redo),
            (
                KeyboardShortcut::new(Modifiers::COMMAND, Key::Y),
                Command::Redo,
            ),
            (
                KeyboardShortcut::new(Modifiers::COMMAND, Key::Z),
                Command::Undo,
            ),
            (
                KeyboardShortcut::new(Modifiers::COMMAND, Key::O),
                Command::Prompt(PromptKind::OpenImage),
            ),
            (
                KeyboardShortcut::new(Modifiers::COMMAND, Key::S),
                Command::Prompt(PromptKind::SaveProject),
            ),
            (
                KeyboardShortcut::new(Modifiers::COMMAND, Key::E),
                Command::Prompt(PromptKind::Export),
            ),
        ];
        for (sc, cmd) in shortcuts {
            if ui.input_mut(|i| i.consume_shortcut(&sc)) {
                self.queue.push(cmd);
            }
        }
        if ui.ctx().egui_wants_keyboard_input() {
            return;
        }
        let plain = ui.input(|i| i.modifiers.is_none());
        if plain {
            for t in Tool::ALL {
                if ui.input(|i| i.key_pressed(t.key())) {
                    self.queue.push(Command::SetTool(t));
                }
            }
            let (bigger, smaller, fit, orig) = ui.input(|i| {
                (
                    i.key_pressed(Key::CloseBracket),
                    i.key_pressed(Key::OpenBracket),
                    i.key_pressed(Key::F),
                    i.key_pressed(Key::O),
                )
            });
            if bigger {
                self.tools.brush_size = (self.tools.brush_size * 1.25).min(2000.0);
            }
            if smaller {
                self.tools.brush_size = (self.tools.brush_size / 1.25).max(1.0);
            }
            if fit {
                self.queue.push(Command::FitView);
            }
            if orig {
                self.show_original = !self.show_original;
            }
        }
    }

    fn top_bar(&mut self, ui: &mut Ui, out: &mut Vec<Command>) {
        let has_doc = self.loaded.is_some();
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
                if ui.add_enabled(has_doc, egui::Button::new("Save project…")).clicked() {
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
                if ui.add_enabled(has_doc, egui::Button::new("Export image…")).clicked() {
                    out.push(Command::Prompt(PromptKind::Export));
                }
                ui.separator();
                if ui.button("Quit").clicked() {
                    out.push(Command::Quit);
                }
            });
            ui.menu_button("Edit", |ui| {
                if ui.add_enabled(self.history.can_undo(), egui::Button::new("Undo").shortcut_text("Ctrl+Z")).clicked() {
                    out.push(Command::Undo);
                }
                if ui.add_enabled(self.history.can_redo(), egui::Button::new("Redo").shortcut_text("Ctrl+Shift+Z")).clicked() {
                    out.push(Command::Redo);
                }
                ui.separator();
                for (label, cmd) in [
                    ("Invert region", Command::MaskInvert),
                    ("Clear region", Command::MaskClear),
                    ("Whole image is wall", Command::MaskFill),
                    ("Detect ledges", Command::DetectLedges),
                    ("Remove all source lines", Command::SetLines { lines: vec![], before: None }),
                    ("Remove quad", Command::SetQuad { quad: None, before: None }),
                ] {
                    if ui.add_enabled(has_doc, egui::Button::new(label)).clicked() {
                        out.push(self.recorded(cmd));
                    }
                }
            });
            ui.menu_button("View", |ui| {
                if ui.button("Fit to window").clicked() {
                    out.push(Command::FitView);
                }
                ui.checkbox(&mut self.show_original, "Show original (O)");
                ui.checkbox(&mut self.show_mask, "Show region overlay");
            });
            ui.menu_button("Help", |ui| {
                ui.label(RichText::new("Shortcuts").strong());
                ui.label("Wheel: zoom · middle/right drag or Space+drag: pan · F: fit");
                ui.label("H pan · B brush · E eraser · R rectangle · L lasso · W wand");
                ui.label("N new line · V edit lines · Q quad · [ ] brush size · O original");
                ui.label("Enter: finish line/lasso · Esc: cancel · Delete: remove selected line");
                ui.label("Ctrl+Z undo · Ctrl+Shift+Z redo · Ctrl+O open · Ctrl+S save project · Ctrl+E export");
            });
        });
        ui.add_space(2.0);
        ui.horizontal_wrapped(|ui| {
            for t in Tool::ALL {
                if matches!(t, Tool::Line | Tool::Quad) {
                    ui.separator();
                }
                let r = ui
                    .selectable_label(self.tools.tool == t, t.label())
                    .on_hover_text(format!("{} ({:?})", t.help(), t.key()));
                if r.clicked() {
                    out.push(Command::SetTool(t));
                }
            }
            ui.separator();
            if ui.add_enabled(has_doc, egui::Button::new("Detect ledges")).on_hover_text("Propose source lines along strong horizontal edges (sills, cornices) inside the region").clicked() {
                out.push(Command::DetectLedges);
            }
            ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                if ui.add_enabled(has_doc && self.export.running.is_none(), egui::Button::new("Export…")).on_hover_text("Full resolution: PNG, JPEG, TIFF, WebP, PSD or ORA (Ctrl+E)").clicked() {
                    out.push(Command::Prompt(PromptKind::Export));
                }
                ui.toggle_value(&mut self.show_original, "Original").on_hover_text("Show the photo without weathering (O)");
                if ui.add_enabled(self.history.can_redo(), egui::Button::new("Redo")).on_hover_text("Ctrl+Shift+Z").clicked() {
                    out.push(Command::Redo);
                }
                if ui.add_enabled(self.history.can_undo(), egui::Button::new("Undo")).on_hover_text("Ctrl+Z").clicked() {
                    out.push(Command::Undo);
                }
            });
        });
        ui.horizontal(|ui| self.tool_options(ui, out));
        ui.add_space(2.0);
    }

    /// Gives "remove all" style menu commands their undo record.
    fn recorded(&self, cmd: Command) -> Command {
        let Some(l) = &self.loaded else { return cmd };
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

    fn tool_options(&mut self, ui: &mut Ui, out: &mut Vec<Command>) {
        let t = &mut self.tools;
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
                let selected = self.canvas.selected_line;
                if ui
                    .add_enabled(selected.is_some(), egui::Button::new("Delete line"))
                    .clicked()
                    && let (Some(i), Some(l)) = (selected, &self.loaded)
                {
                    let mut lines = l.doc.lines.clone();
                    if i < lines.len() {
                        lines.remove(i);
                        out.push(Command::SetLines {
                            lines,
                            before: Some(l.doc.lines.clone()),
                        });
                    }
                    self.canvas.selected_line = None;
                }
            }
            Tool::Quad => {
                let has = self.loaded.as_ref().is_some_and(|l| l.doc.quad.is_some());
                if ui
                    .add_enabled(has, egui::Button::new("Remove quad"))
                    .clicked()
                {
                    out.push(self.recorded(Command::SetQuad {
                        quad: None,
                        before: None,
                    }));
                }
            }
            Tool::Pan | Tool::Line => {}
        }
        ui.label(RichText::new(self.tools.tool.help()).weak().small());
        ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
            let has = self.loaded.is_some();
            ui.checkbox(&mut self.show_mask, "Show region");
            for (label, cmd, tip) in [
                ("Fill", Command::MaskFill, "The whole photo is wall"),
                (
                    "Clear",
                    Command::MaskClear,
                    "Empty the region (paint it back with Brush, Rectangle, Lasso or Wand)",
                ),
                ("Invert", Command::MaskInvert, "Swap wall and not-wall"),
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

    fn side_panel(&mut self, ui: &mut Ui, out: &mut Vec<Command>) {
        let Some(l) = &self.loaded else {
            ui.add_space(8.0);
            ui.heading("grime");
            ui.label("Ages photos of buildings: rain streaks, moss and dust as layers.");
            ui.add_space(8.0);
            if ui.button("Try the sample facade").clicked() {
                out.push(Command::OpenDemo("facade".into()));
            }
            ui.add_space(4.0);
            ui.label("Or open a photo (File > Open image, Ctrl+O), or drop one onto the window.");
            return;
        };
        let preset = &l.doc.preset;
        egui::ScrollArea::vertical()
            .auto_shrink([false, false])
            .show(ui, |ui| {
                ui.add_space(4.0);
                ui.heading("Time");
                panels::time(ui, preset, out);
                ui.separator();
                ui.heading("Layers");
                let rows: Vec<LayerRow> =
                    self.preview.current.as_ref().map_or_else(Vec::new, |p| {
                        p.stack
                            .layers
                            .iter()
                            .map(|layer| LayerRow {
                                name: layer.name.clone(),
                                opacity: layer.opacity,
                                visible: layer.visible,
                                setting: l.doc.layers.get(&layer.name).copied().unwrap_or_default(),
                            })
                            .collect()
                    });
                panels::layers(ui, &rows, out);
                ui.separator();
                ui.horizontal(|ui| {
                    ui.heading("Parameters");
                    ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                        if ui
                            .button("Save…")
                            .on_hover_text(
                                "Save the preset as commented TOML (same as the CLI's --preset)",
                            )
                            .clicked()
                        {
                            out.push(Command::Prompt(PromptKind::SavePreset));
                        }
                        if ui
                            .button("Load…")
                            .on_hover_text("Load a preset TOML")
                            .clicked()
                        {
                            out.push(Command::Prompt(PromptKind::LoadPreset));
                        }
                        egui::ComboBox::from_id_salt("builtin")
                            .selected_text("Preset")
                            .show_ui(ui, |ui| {
                                for (name, about) in preset::BUILTIN {
                                    if ui
                                        .selectable_label(false, *name)
                                        .on_hover_text(*about)
                                        .clicked()
                                    {
                                        out.push(Command::BuiltinPreset(name.to_string()));
                                    }
                                }
                            })
                            .response
                            .on_hover_text("Built-in presets");
                    });
                });
                panels::seed(ui, preset, out);
                panels::parameters(ui, preset, out);
            });
    }

    fn status_bar(&mut self, ui: &mut Ui, out: &mut Vec<Command>) {
        ui.horizontal(|ui| {
            if self.preview.running.is_some() {
                let s = self.preview.worker.status();
                ui.spinner();
                // The quick pass is shown while the full one runs.
                let (label, tip) = if self.is_refining() {
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
                if self.is_refining()
                    && let Some(ms) = self.preview.latency_ms
                {
                    ui.weak(format!("preview {ms:.0} ms"));
                }
            } else if let Some(ms) = self.preview.latency_ms.or(self.preview.sim_ms) {
                let text = match self.preview.refined_ms {
                    Some(r) if r > ms + 1.0 => format!("preview {ms:.0} ms · refined {r:.0} ms"),
                    _ => format!("preview {ms:.0} ms"),
                };
                ui.weak(text).on_hover_text(
                    "Change to preview: the quick pass, then the full detail (refined)",
                );
            }
            if let Some(path) = &self.export.running {
                let s = self.export.worker.status();
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
            if let Some(m) = &self.message {
                ui.separator();
                let text = RichText::new(&m.text);
                let text = if m.error {
                    text.color(Color32::from_rgb(255, 110, 100))
                } else {
                    text
                };
                ui.label(text);
                if ui.small_button("×").on_hover_text("Dismiss").clicked() {
                    self.message = None;
                }
            }
            ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                if let Some(l) = &self.loaded {
                    if let Some(p) = self.canvas.hover {
                        ui.weak(format!("{:.0}, {:.0}", p[0], p[1]));
                    }
                    ui.weak(format!("zoom {:.0}%", self.canvas.view.zoom * 100.0));
                    let (pw, ph) = (l.proxy.photo.width(), l.proxy.photo.height());
                    ui.weak(format!(
                        "{} · {}×{} (preview {}×{})",
                        l.doc.source.display_name(),
                        l.photo.width(),
                        l.photo.height(),
                        pw,
                        ph
                    ));
                }
            });
        });
    }

    fn canvas_ui(&mut self, ui: &mut Ui, out: &mut Vec<Command>) {
        let image = if self.show_original {
            self.textures.original.as_ref()
        } else {
            self.textures
                .preview
                .as_ref()
                .or(self.textures.original.as_ref())
        };
        let overlay_alpha = match (self.show_mask, self.tools.tool.edits_mask()) {
            (false, _) => 0.0,
            (true, true) => 0.55,
            (true, false) => 0.1,
        };
        let l = self.loaded.as_ref();
        let input = CanvasInput {
            image,
            overlay: self.textures.overlay.as_ref(),
            overlay_alpha,
            size: l.map(|l| [l.photo.width() as f32, l.photo.height() as f32]),
            lines: l.map_or(&[], |l| &l.doc.lines),
            quad: l.and_then(|l| l.doc.quad.as_ref()),
            tools: &self.tools,
        };
        self.canvas.show(ui, input, out);
    }

    fn prompt_ui(&mut self, ui: &mut Ui, out: &mut Vec<Command>) {
        let Some(prompt) = &mut self.prompt else {
            return;
        };
        let kind = prompt.kind;
        let mut close = false;
        let mut chosen: Option<PathBuf> = None;
        let mut browse_failed = false;
        let modal = egui::Modal::new(egui::Id::unique("path prompt")).show(ui.ctx(), |ui| {
            ui.set_width(520.0);
            ui.heading(kind.title());
            let (name, exts) = kind.filter();
            ui.label(RichText::new(format!("{name}: .{}", exts.join(" ."))).weak());
            ui.horizontal(|ui| {
                let label = ui.label("Path");
                let r = ui
                    .add(
                        egui::TextEdit::singleline(&mut prompt.text)
                            .desired_width(360.0)
                            .hint_text("/path/to/file"),
                    )
                    .labelled_by(label.id);
                if prompt.focus {
                    r.request_focus();
                    prompt.focus = false;
                }
                if r.lost_focus()
                    && ui.input(|i| i.key_pressed(Key::Enter))
                    && !prompt.text.trim().is_empty()
                {
                    chosen = Some(PathBuf::from(prompt.text.trim()));
                }
                if ui
                    .button("Browse…")
                    .on_hover_text("The system file dialog (needs xdg-desktop-portal)")
                    .clicked()
                {
                    let dialog = rfd::FileDialog::new()
                        .set_title(kind.title())
                        .add_filter(name, exts);
                    let current = PathBuf::from(prompt.text.trim());
                    let dialog = match (current.parent(), current.file_name()) {
                        (Some(dir), Some(file)) if dir.is_dir() => dialog
                            .set_directory(dir)
                            .set_file_name(file.to_string_lossy()),
                        _ => dialog,
                    };
                    let picked = if kind.saves() {
                        dialog.save_file()
                    } else {
                        dialog.pick_file()
                    };
                    match picked {
                        Some(p) => prompt.text = p.display().to_string(),
                        None => browse_failed = true,
                    }
                }
            });
            ui.add_space(6.0);
            ui.horizontal(|ui| {
                let ok = ui.add_enabled(
                    !prompt.text.trim().is_empty(),
                    egui::Button::new(kind.action()),
                );
                if ok.clicked() {
                    chosen = Some(PathBuf::from(prompt.text.trim()));
                }
                if ui.button("Cancel").clicked() {
                    close = true;
                }
            });
        });
        if browse_failed {
            self.info(
                "No file chosen. If no dialog appeared (no xdg-desktop-portal), type the path.",
            );
        }
        if let Some(p) = chosen {
            out.push(kind.command(p));
            close = true;
        }
        if close || modal.should_close() {
            self.prompt = None;
        }
    }

    /// Scripted runs: count frames, take the screenshot once the preview is
    /// ready, then close.
    fn automate(&mut self, ctx: &egui::Context) {
        let busy = self.is_busy();
        let Some(a) = &mut self.automation else {
            return;
        };
        a.frames += 1;
        ctx.request_repaint_after(Duration::from_millis(16));
        let ready =
            (a.frames >= a.after && !busy) || a.started.elapsed() > Duration::from_secs(100);
        match &a.screenshot {
            Some(path) => {
                if ready && !a.requested {
                    a.requested = true;
                    let slot = Arc::clone(&a.shot);
                    ctx.request_screenshot(move |img| {
                        if let Ok(mut s) = slot.lock() {
                            *s = Some(img);
                        }
                    });
                }
                let shot = a.shot.lock().ok().and_then(|mut s| s.take());
                if let Some(img) = shot {
                    let result = save_screenshot(&img, path);
                    if let Ok(mut o) = a.outcome.lock() {
                        *o = Some(result);
                    }
                    ctx.send_viewport_cmd(egui::ViewportCommand::Close);
                }
            }
            None if ready => {
                if let Ok(mut o) = a.outcome.lock() {
                    *o = Some(Ok(()));
                }
                ctx.send_viewport_cmd(egui::ViewportCommand::Close);
            }
            None => {}
        }
    }

    fn open(&mut self, doc: Document, photo: Photo) {
        let photo = Arc::new(photo);
        let proxy = Proxy::new(&photo, &doc.mask, self.proxy_pixels);
        self.textures.original = Some(self.ctx.load_texture(
            "original",
            render::to_color_image(proxy.photo.image()),
            TextureOptions::LINEAR,
        ));
        let overlay = overlay_image(
            &proxy.mask,
            PixelRect::full(proxy.mask.width(), proxy.mask.height()),
        );
        self.textures.overlay = Some(self.ctx.load_texture(
            "overlay",
            overlay,
            TextureOptions::LINEAR,
        ));
        self.textures.preview = None;
        self.preview.current = None;
        self.preview.styled = None;
        self.preview.sim_failed = false;
        self.preview.worker.cancel();
        self.preview.running = None;
        self.preview.shown_quick = false;
        self.preview.dirty = true;
        self.preview.changed_at = Some(Instant::now());
        let rev = self.loaded.as_ref().map_or(1, |l| l.rev + 1);
        self.info(format!(
            "Opened {} ({}×{})",
            doc.source.display_name(),
            photo.width(),
            photo.height()
        ));
        self.loaded = Some(Loaded {
            doc,
            photo,
            proxy,
            rgb: None,
            rev,
            stroke_before: None,
        });
        self.history.clear();
        self.canvas = Canvas::default();
    }

    /// The mask changed inside `rect` (photo pixels): update the proxy and
    /// the overlay texture there.
    fn mask_changed(&mut self, rect: PixelRect) {
        let Some(l) = &mut self.loaded else { return };
        if let Some(r) = l.proxy.update_mask(&l.doc.mask, rect)
            && let Some(tex) = &mut self.textures.overlay
        {
            tex.set_partial(
                [r.x0 as usize, r.y0 as usize],
                overlay_image(&l.proxy.mask, r),
                TextureOptions::LINEAR,
            );
        }
    }

    fn bump(&mut self) {
        if let Some(l) = &mut self.loaded {
            l.rev += 1;
        }
        self.preview.dirty = true;
        self.preview.changed_at.get_or_insert_with(Instant::now);
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

    /// Applies one command.
    pub fn apply(&mut self, cmd: Command) {
        match cmd {
            Command::Prompt(kind) => {
                let text = self.suggest_path(kind);
                self.prompt = Some(Prompt {
                    kind,
                    text,
                    focus: true,
                });
            }
            Command::OpenImage(path) => {
                if path
                    .extension()
                    .is_some_and(|e| e.eq_ignore_ascii_case("json"))
                {
                    return self.apply(Command::OpenProject(path));
                }
                match io::load_photo(&path) {
                    Ok(photo) => {
                        let mut preset = self.current_preset();
                        preset.rain.source_lines.clear();
                        let doc = Document::new(
                            ImageSource::File(path),
                            photo.width(),
                            photo.height(),
                            preset,
                        );
                        self.open(doc, photo);
                    }
                    Err(e) => self.error(format!("cannot open image: {e}")),
                }
            }
            Command::OpenDemo(name) => match demo::load(&name) {
                Ok(d) => {
                    let mut preset = self.current_preset();
                    preset.rain.source_lines.clear();
                    let mut doc = Document::new(
                        ImageSource::Demo(name),
                        d.photo.width(),
                        d.photo.height(),
                        preset,
                    );
                    if let Some(r) = d.region {
                        doc.mask = r;
                    }
                    doc.lines = d.source_lines;
                    self.open(doc, d.photo);
                }
                Err(e) => self.error(e.to_string()),
            },
            Command::OpenProject(path) => match Document::load_project(&path) {
                Ok((doc, photo)) => {
                    self.open(doc, photo);
                    self.info(format!("Opened project {}", path.display()));
                }
                Err(e) => self.error(format!("cannot open project: {e}")),
            },
            Command::SaveProject(path) => {
                let Some(l) = &self.loaded else { return };
                match l.doc.save_project(&path) {
                    Ok(()) => self.info(format!("Saved project {}", path.display())),
                    Err(e) => self.error(format!("cannot save project: {e}")),
                }
            }
            Command::LoadPreset(path) => {
                let loaded = std::fs::read_to_string(&path)
                    .map_err(|e| crate::Error::io(&path, e).to_string())
                    .and_then(|t| {
                        Preset::from_toml(&t).map_err(|e| format!("{}: {e}", path.display()))
                    });
                match loaded {
                    Ok(p) => {
                        self.set_preset(p, "preset file");
                        self.info(format!("Loaded preset {}", path.display()));
                    }
                    Err(e) => self.error(format!("cannot load preset: {e}")),
                }
            }
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
                let r = io::write_atomic(&path, |out| {
                    std::io::Write::write_all(out, text.as_bytes())
                        .map_err(|e| crate::Error::io(&path, e))
                });
                match r {
                    Ok(()) => self.info(format!("Saved preset {}", path.display())),
                    Err(e) => self.error(format!("cannot save preset: {e}")),
                }
            }
            Command::Export(path) => self.start_export(path),
            Command::CancelExport => {
                self.export.worker.cancel();
                self.export.running = None;
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
                l.doc.lines = lines;
                if self
                    .canvas
                    .selected_line
                    .is_some_and(|i| i >= l.doc.lines.len())
                {
                    self.canvas.selected_line = None;
                }
                self.bump();
            }
            Command::DetectLedges => {
                let Some(l) = &self.loaded else { return };
                let found = crate::ledges::detect(&l.proxy.photo, Some(&l.proxy.mask));
                let (sx, sy) = (l.proxy.sx, l.proxy.sy);
                let mut lines = l.doc.lines.clone();
                let mut added = 0;
                for line in found {
                    let line: Vec<[f32; 2]> = line.iter().map(|p| [p[0] / sx, p[1] / sy]).collect();
                    let dup = lines.iter().any(|o| {
                        let (y, oy) = (
                            line[0][1],
                            o.iter().map(|p| p[1]).sum::<f32>() / o.len().max(1) as f32,
                        );
                        let (x0, x1) = (line[0][0], line[line.len() - 1][0]);
                        let (ox0, ox1) = o
                            .iter()
                            .fold((f32::MAX, f32::MIN), |(a, b), p| (a.min(p[0]), b.max(p[0])));
                        (y - oy).abs() < 6.0 / sy && x0 < ox1 && x1 > ox0
                    });
                    if !dup {
                        lines.push(line);
                        added += 1;
                    }
                }
                if added > 0 {
                    let before = l.doc.lines.clone();
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
                match p.set(&format!("{path}={value}")) {
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
                            self.preview.dirty = true;
                            self.preview.changed_at.get_or_insert_with(Instant::now);
                        }
                    }
                    Err(e) => self.error(e.to_string()),
                }
            }
            Command::SetLayer { name, setting } => {
                let Some(l) = &mut self.loaded else { return };
                l.doc.layers.insert(name, setting);
                self.preview.dirty = true;
                self.preview.changed_at.get_or_insert_with(Instant::now);
            }
            Command::ResetLayers => {
                let Some(l) = &mut self.loaded else { return };
                l.doc.layers.clear();
                self.preview.dirty = true;
            }
            Command::Undo | Command::Redo => {
                let Some(l) = &mut self.loaded else { return };
                let touched = if cmd == Command::Undo {
                    self.history.undo(&mut l.doc)
                } else {
                    self.history.redo(&mut l.doc)
                };
                self.canvas.reset_gesture();
                match touched {
                    Some(Touched::Mask(r)) => {
                        self.mask_changed(r);
                        self.bump();
                    }
                    Some(Touched::Lines | Touched::Quad) => self.bump(),
                    Some(Touched::Preset) => {
                        self.preview.dirty = true;
                        self.preview.changed_at.get_or_insert_with(Instant::now);
                    }
                    None => self.info(if cmd == Command::Undo {
                        "Nothing to undo"
                    } else {
                        "Nothing to redo"
                    }),
                }
            }
            Command::SetTool(t) => {
                self.tools.tool = t;
                self.canvas.reset_gesture();
            }
            Command::FitView => self.canvas.view.needs_fit = true,
            Command::Quit => self.ctx.send_viewport_cmd(egui::ViewportCommand::Close),
        }
    }

    fn current_preset(&self) -> Preset {
        self.loaded
            .as_ref()
            .map_or_else(|| self.default_preset.clone(), |l| l.doc.preset.clone())
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
        self.preview.dirty = true;
        self.preview.changed_at.get_or_insert_with(Instant::now);
        if !lines.is_empty() {
            let before = l.doc.lines.clone();
            self.apply(Command::SetLines {
                lines,
                before: Some(before),
            });
        }
    }

    fn start_export(&mut self, path: PathBuf) {
        let Some(l) = &self.loaded else {
            return self.error("nothing to export: open an image first");
        };
        let from = match &l.doc.source {
            ImageSource::File(p) => vec![p.clone()],
            ImageSource::Demo(_) => Vec::new(),
        };
        let scene = Scene::shared(Arc::clone(&l.photo), Some(Arc::new(l.doc.mask.clone())))
            .and_then(|s| s.with_quad(l.doc.quad));
        let scene = match scene {
            Ok(s) => s,
            Err(e) => return self.error(format!("cannot export: {e}")),
        };
        let job = ExportJob {
            scene,
            from,
            preset: l.doc.run_preset(),
            layers: l.doc.layers.clone(),
            path: path.clone(),
        };
        self.export.worker.submit(job);
        self.export.running = Some(path.clone());
        self.info(format!("Exporting {} at full resolution…", path.display()));
    }

    fn suggest_path(&self, kind: PromptKind) -> String {
        let (dir, stem) = match self.loaded.as_ref().map(|l| &l.doc.source) {
            Some(ImageSource::File(p)) => (
                p.parent().map(Path::to_path_buf).unwrap_or_default(),
                p.file_stem()
                    .map_or_else(|| "facade".into(), |s| s.to_string_lossy().into_owned()),
            ),
            Some(ImageSource::Demo(n)) => (std::env::current_dir().unwrap_or_default(), n.clone()),
            None => (std::env::current_dir().unwrap_or_default(), "facade".into()),
        };
        let file = match kind {
            PromptKind::OpenImage | PromptKind::OpenProject | PromptKind::LoadPreset => {
                return String::new();
            }
            PromptKind::SaveProject => format!("{stem}.grime.json"),
            PromptKind::SavePreset => format!("{stem}.toml"),
            PromptKind::Export => format!("{stem}-aged.png"),
        };
        dir.join(file).display().to_string()
    }
}

/// The tinted region overlay for `rect` of the proxy mask.
fn overlay_image(mask: &GrayImage, r: PixelRect) -> ColorImage {
    let mut pixels = Vec::with_capacity((r.width() * r.height()) as usize);
    for y in r.y0..r.y1 {
        for x in r.x0..r.x1 {
            let m = mask.get_pixel(x, y)[0] as f32 / 255.0;
            pixels.push(Color32::from_rgba_unmultiplied(
                40,
                170,
                255,
                (m * 150.0) as u8,
            ));
        }
    }
    ColorImage::new([r.width() as usize, r.height() as usize], pixels)
}

/// Saves a window screenshot as PNG and refuses a blank one.
fn save_screenshot(img: &ColorImage, path: &Path) -> Result<(), String> {
    let [w, h] = img.size;
    let rgb = RgbImage::from_fn(w as u32, h as u32, |x, y| {
        let c = img.pixels[y as usize * w + x as usize];
        image::Rgb([c.r(), c.g(), c.b()])
    });
    io::save_image(&image::DynamicImage::ImageRgb8(rgb.clone()), None, path)
        .map_err(|e| e.to_string())?;
    check_not_blank(&rgb).map_err(|e| format!("{}: {e}", path.display()))
}

/// Errors when an image is (nearly) one colour.
pub fn check_not_blank(img: &RgbImage) -> Result<(), String> {
    let mut colors = std::collections::HashSet::new();
    let (mut lo, mut hi) = (255u8, 0u8);
    for p in img.pixels().step_by(7) {
        let l = ((p[0] as u32 * 299 + p[1] as u32 * 587 + p[2] as u32 * 114) / 1000) as u8;
        lo = lo.min(l);
        hi = hi.max(l);
        if colors.len() < 1000 {
            colors.insert(p.0);
        }
    }
    if img.width() == 0 || hi.saturating_sub(lo) < 16 || colors.len() < 32 {
        return Err(format!(
            "the screenshot is blank ({} colours, luma {lo}..{hi})",
            colors.len()
        ));
    }
    Ok(())
}

impl eframe::App for GrimeApp {
    fn ui(&mut self, ui: &mut Ui, _frame: &mut eframe::Frame) {
        self.show(ui);
    }

    fn persist_egui_memory(&self) -> bool {
        // Scripted runs start from the same layout every time.
        self.automation.is_none()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_simulation_shows_a_quick_pass_then_refines() {
        use egui_kittest::Harness;
        let mut h = Harness::builder()
            .with_size(egui::vec2(1280.0, 800.0))
            .build_ui_state(
                |ui, app: &mut GrimeApp| app.show(ui),
                GrimeApp::new(AppOptions {
                    demo: Some("facade".into()),
                    ..AppOptions::default()
                }),
            );
        let step_until =
            |h: &mut Harness<'_, GrimeApp>, what: &str, f: &dyn Fn(&GrimeApp) -> bool| {
                let start = Instant::now();
                while !f(h.state()) {
                    assert!(start.elapsed() < Duration::from_secs(300), "never: {what}");
                    h.step();
                    std::thread::sleep(Duration::from_millis(2));
                }
            };
        step_until(&mut h, "first preview", &|a| {
            a.preview_image().is_some() && !a.is_busy()
        });
        // A simulation parameter: the quick pass shows first (the default
        // preset's full pass takes far longer than a frame).
        h.state_mut().push(Command::SetParam {
            path: "rain.k_a".into(),
            value: "0.7".into(),
            merge: false,
        });
        h.step();
        assert!(h.state().is_busy() && !h.state().is_refining());
        step_until(&mut h, "the quick pass", &|a| a.is_refining());
        let quick = h.state().preview.current.as_ref().unwrap().clone();
        assert!(quick.quick);
        assert_eq!(quick.sim_preset.sim.max_side, render::QUICK_MAX_SIDE);
        // A restyle-only change follows on the quick pass at once.
        h.state_mut().push(Command::SetParam {
            path: "stain.opacity".into(),
            value: "0.3".into(),
            merge: false,
        });
        h.step();
        if h.state().is_refining() {
            assert_ne!(h.state().preview_image().unwrap(), &*quick.image);
        }
        step_until(&mut h, "the full pass", &|a| !a.is_busy());
        let full = h.state().preview.current.as_ref().unwrap();
        assert!(!full.quick);
        assert_eq!(full.sim_preset.rain.k_a, 0.7);
        assert_eq!(full.sim_preset.sim.max_side, Preset::default().sim.max_side);
        // The full pass is the plain run of the document, restyled.
        let l = h.state().loaded.as_ref().unwrap();
        let job = l
            .proxy
            .job(&l.doc.run_preset(), None, &l.doc.layers)
            .unwrap();
        let fresh = render::simulate(job, &crate::progress::Progress::none()).unwrap();
        assert_eq!(full.image, fresh.image);
        let (first, refined) = (
            h.state().preview_latency_ms().unwrap(),
            h.state().preview_refined_ms().unwrap(),
        );
        assert!(refined > first, "{first} ms, then {refined} ms");
    }

    #[test]
    fn blank_screenshots_are_refused() {
        let blank = RgbImage::from_pixel(64, 48, image::Rgb([30, 30, 30]));
        assert!(check_not_blank(&blank).unwrap_err().contains("blank"));
        let d = demo::facade(64, 48);
        assert!(check_not_blank(&d.photo.image().to_rgb8()).is_ok());
    }
}
