//! The frame loop: wiring only. Each frame takes the workers' results
//! ([`Controller::poll`]), draws the views (menu, toolbar, status bar, side
//! panel, canvas, prompt), which read the state and emit [`Command`]s,
//! applies the commands ([`Controller::apply`]), schedules the preview, and
//! brings the textures and canvas in line with what the controller asks
//! ([`super::controller::ViewRequests`]).

use eframe::egui;

use std::path::PathBuf;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use egui::{Color32, ColorImage, TextureHandle, TextureOptions, Ui};
use image::GrayImage;

use crate::preset::Preset;

use super::automation::Automation;
use super::canvas::{Canvas, CanvasInput};
use super::command::Command;
use super::controller::Controller;
use super::prompt::Prompt;
use super::proxy::PROXY_PIXELS;
use super::render::{self, Exported};
use super::state::Document;
use super::tools::PixelRect;
use super::worker::Repaint;
use super::{menu, panels, status, toolbar};

pub use super::automation::Outcome;

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
    ctl: Controller,
    canvas: Canvas,
    prompt: Option<Prompt>,
    textures: Textures,
    queue: Vec<Command>,
    automation: Option<Automation>,
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
            .then(|| {
                let after = options.quit_after_frames.unwrap_or(30);
                Automation::new(options.screenshot.clone(), after)
            });
        let mut queue = Vec::new();
        if let Some(name) = &options.demo {
            queue.push(Command::OpenDemo(name.clone()));
        } else if let Some(path) = &options.image {
            queue.push(Command::OpenImage(path.clone()));
        }
        GrimeApp {
            ctx: egui::Context::default(),
            repaint_to,
            ctl: Controller::new(options.preset, options.proxy_pixels, repaint),
            canvas: Canvas::default(),
            prompt: None,
            textures: Textures::default(),
            queue,
            automation,
        }
    }

    /// The outcome cell of a scripted run, filled when it ends.
    pub fn outcome(&self) -> Option<Outcome> {
        self.automation.as_ref().map(|a| Arc::clone(&a.outcome))
    }

    /// The controller (state and workers), for tests.
    pub fn controller(&self) -> &Controller {
        &self.ctl
    }

    /// The document, once a photo is open.
    pub fn document(&self) -> Option<&Document> {
        self.ctl.loaded().map(|l| &l.doc)
    }

    /// The current preview composite (proxy-sized), if one is ready.
    pub fn preview_image(&self) -> Option<&ColorImage> {
        self.ctl.preview().shown_image().map(|i| &**i)
    }

    /// True while the canvas shows the quick pass of a simulation and the
    /// full pass is still running.
    pub fn is_refining(&self) -> bool {
        self.ctl.preview().is_refining()
    }

    /// The proxy photo as an image, for comparisons.
    pub fn proxy_image(&self) -> Option<ColorImage> {
        self.ctl
            .loaded()
            .map(|l| render::to_color_image(l.proxy.photo.image()))
    }

    /// The proxy mask.
    pub fn proxy_mask(&self) -> Option<&GrayImage> {
        self.ctl.loaded().map(|l| &*l.proxy.mask)
    }

    /// True while a preview, export or file operation is computing or pending.
    pub fn is_busy(&self) -> bool {
        self.ctl.is_busy() || !self.queue.is_empty()
    }

    /// The message shown in the status bar.
    pub fn message(&self) -> Option<(&str, bool)> {
        self.ctl.message().map(|m| (m.text.as_str(), m.error))
    }

    /// The last export's result.
    pub fn last_export(&self) -> Option<&Result<Exported, String>> {
        self.ctl.last_export()
    }

    /// Change-to-preview time of the last preview update, ms (for a new
    /// simulation: until its quick pass showed).
    pub fn preview_latency_ms(&self) -> Option<f64> {
        self.ctl.preview().latency_ms()
    }

    /// Change-to-refined-preview time of the last simulation, ms.
    pub fn preview_refined_ms(&self) -> Option<f64> {
        self.ctl.preview().refined_ms()
    }

    /// Queues a command as if a widget had emitted it.
    pub fn push(&mut self, cmd: Command) {
        self.queue.push(cmd);
    }

    /// Draws one frame into `ui` (the whole window).
    pub fn show(&mut self, ui: &mut Ui) {
        if let Ok(mut cell) = self.repaint_to.lock()
            && cell.is_none()
        {
            self.ctx = ui.ctx().clone();
            *cell = Some(self.ctx.clone());
        }
        self.ctl.poll();
        let mut out = std::mem::take(&mut self.queue);
        menu::global_input(ui, &self.ctl, self.prompt.is_some(), &mut out);

        let ctl = &self.ctl;
        let selected = self.canvas.selected_line;
        egui::Panel::top("menu").show(ui, |ui| {
            menu::bar(ui, ctl, &mut out);
            toolbar::show(ui, ctl, selected, &mut out);
        });
        egui::Panel::bottom("status").show(ui, |ui| status::show(ui, ctl, &self.canvas, &mut out));
        egui::Panel::right("params")
            .resizable(true)
            .default_size(340.0)
            .min_size(260.0)
            .show(ui, |ui| panels::side(ui, ctl, &mut out));
        egui::CentralPanel::no_frame().show(ui, |ui| self.canvas_ui(ui, &mut out));
        if let Some(prompt) = &mut self.prompt
            && !prompt.show(ui, &mut out)
        {
            self.prompt = None;
        }

        let changed = !out.is_empty();
        for cmd in out {
            self.ctl.apply(cmd);
        }
        self.ctl.schedule_preview();
        self.follow_controller();
        if changed {
            ui.ctx().request_repaint();
        }
        if self.ctl.is_working() {
            // Keeps the spinner turning; results wake the UI themselves.
            ui.ctx().request_repaint_after(Duration::from_millis(100));
        }
        let busy = self.is_busy();
        if let Some(a) = &mut self.automation {
            a.step(ui.ctx(), busy);
        }
    }

    fn canvas_ui(&mut self, ui: &mut Ui, out: &mut Vec<Command>) {
        let view = self.ctl.view();
        let image = if view.show_original {
            self.textures.original.as_ref()
        } else {
            self.textures
                .preview
                .as_ref()
                .or(self.textures.original.as_ref())
        };
        let tools = self.ctl.tools();
        let overlay_alpha = match (view.show_mask, tools.tool.edits_mask()) {
            (false, _) => 0.0,
            (true, true) => 0.55,
            (true, false) => 0.1,
        };
        let l = self.ctl.loaded();
        let input = CanvasInput {
            image,
            overlay: self.textures.overlay.as_ref(),
            overlay_alpha,
            size: l.map(|l| [l.photo.width() as f32, l.photo.height() as f32]),
            lines: l.map_or(&[], |l| &l.doc.lines),
            quad: l.and_then(|l| l.doc.quad.as_ref()),
            tools,
        };
        self.canvas.show(ui, input, out);
    }

    /// Textures, canvas and prompt follow what the commands changed.
    fn follow_controller(&mut self) {
        let req = self.ctl.take_requests();
        if req.opened
            && let Some(l) = self.ctl.loaded()
        {
            let original = render::to_color_image(l.proxy.photo.image());
            let (w, h) = l.proxy.mask.dimensions();
            let overlay = overlay_image(&l.proxy.mask, PixelRect::full(w, h));
            let load = |name: &str, img: ColorImage| {
                self.ctx.load_texture(name, img, TextureOptions::LINEAR)
            };
            self.textures = Textures {
                original: Some(load("original", original)),
                preview: None,
                overlay: Some(load("overlay", overlay)),
            };
            self.canvas = Canvas::default();
        }
        if let (Some(l), Some(tex)) = (self.ctl.loaded(), &mut self.textures.overlay) {
            for r in req.mask_rects {
                let patch = overlay_image(&l.proxy.mask, r);
                tex.set_partial(
                    [r.x0 as usize, r.y0 as usize],
                    patch,
                    TextureOptions::LINEAR,
                );
            }
        }
        if self.ctl.preview().is_playing() {
            self.ctl.preview_mut().tick(Duration::from_millis(200));
            self.ctx.request_repaint_after(Duration::from_millis(50));
        }
        if let Some(fresh) = self.ctl.preview_mut().take_fresh() {
            // The texture shares the image (no copy); while scrubbing the
            // ages, the frame's.
            let fresh = fresh.map(|_| ());
            let shown = self.ctl.preview().shown_image().cloned();
            match (fresh.and(shown), &mut self.textures.preview) {
                (Some(image), Some(t)) => t.set(image, TextureOptions::LINEAR),
                (Some(image), None) => {
                    let tex = self
                        .ctx
                        .load_texture("preview", image, TextureOptions::LINEAR);
                    self.textures.preview = Some(tex);
                }
                (None, _) => self.textures.preview = None,
            }
        }
        if let Some((kind, text)) = req.prompt {
            self.prompt = Some(Prompt::new(kind, text));
        }
        if req.fit_view {
            self.canvas.view.needs_fit = true;
        }
        if req.reset_gesture {
            self.canvas.reset_gesture();
        }
        if req.deselect_line {
            self.canvas.selected_line = None;
        }
        if req.quit {
            self.ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        }
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
    use std::time::Instant;

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
        let current = |a: &GrimeApp| a.ctl.preview().current().unwrap().clone();
        let quick = current(h.state());
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
        let full = current(h.state());
        assert!(!full.quick);
        assert_eq!(full.sim_preset.rain.k_a, 0.7);
        assert_eq!(full.sim_preset.sim.max_side, Preset::default().sim.max_side);
        // The full pass is the plain run of the document, restyled.
        let l = h.state().ctl.loaded().unwrap();
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
}
