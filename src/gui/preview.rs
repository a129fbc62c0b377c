//! The preview scheduler: after each change, decide whether the preview
//! needs a new simulation on the worker, only a re-composite here (the
//! core says no effect is stale: [`render::restyles`]), or nothing; take
//! the worker's quick and full passes as they come; time change-to-preview.

use std::collections::BTreeMap;
use std::time::Instant;

use eframe::egui;

use crate::preset::Preset;

use super::controller::Loaded;
use super::render::{self, Preview, PreviewJob, Previewer};
use super::state::LayerSetting;
use super::worker::{Repaint, Status, Worker};

/// The simulation the worker is running.
struct Running {
    rev: u64,
    preset: Preset,
    layers: BTreeMap<String, LayerSetting>,
}

/// What a poll brought.
#[derive(Debug, Clone, PartialEq)]
pub enum Polled {
    /// Nothing new.
    Nothing,
    /// A quick or full pass is shown.
    Shown,
    /// The simulation failed; the message for the status bar.
    Failed(String),
}

/// The preview's runtime state.
pub struct Scheduler {
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
    /// `current` changed since the view last took it.
    fresh: bool,
    /// When the change the preview is catching up with was made.
    changed_at: Option<Instant>,
    /// The same, once the quick pass showed, until the full pass does.
    refine_from: Option<Instant>,
    /// Change-to-preview time of the last update, ms.
    latency_ms: Option<f64>,
    /// Change-to-refined-preview time of the last simulation, ms.
    refined_ms: Option<f64>,
    /// Simulation time of the last preview, ms.
    sim_ms: Option<f64>,
    /// Simulations started so far.
    started: u64,
    /// The age shown ("Age (years)"), `None` = the preset's.
    age_view: Option<u32>,
    /// Playing the ages: when the shown one last advanced.
    playing: Option<Instant>,
}

impl Scheduler {
    /// A scheduler with its worker thread; the worker calls `repaint`.
    pub fn new(repaint: Repaint) -> Scheduler {
        let mut previewer = Previewer::default();
        Scheduler {
            worker: Worker::spawn_progressive("grime-preview", repaint, move |job, p, emit| {
                previewer.run(job, p, emit)
            }),
            current: None,
            sim_rev: 0,
            sim_preset: Preset::default(),
            sim_failed: false,
            styled: None,
            running: None,
            shown_quick: false,
            dirty: false,
            fresh: false,
            changed_at: None,
            refine_from: None,
            latency_ms: None,
            refined_ms: None,
            sim_ms: None,
            started: 0,
            age_view: None,
            playing: None,
        }
    }

    /// The document changed: the preview follows on the next
    /// [`Scheduler::schedule`].
    pub fn touch(&mut self) {
        self.dirty = true;
        self.changed_at.get_or_insert_with(Instant::now);
    }

    /// A new document: forget the preview and cancel its simulation.
    pub fn reset(&mut self) {
        self.worker.cancel();
        self.current = None;
        self.styled = None;
        self.sim_failed = false;
        self.running = None;
        self.shown_quick = false;
        self.fresh = true;
        self.dirty = true;
        self.changed_at = Some(Instant::now());
    }

    /// The shown preview.
    pub fn current(&self) -> Option<&Preview> {
        self.current.as_ref()
    }

    /// The shown preview, once after each change (for the texture).
    pub fn take_fresh(&mut self) -> Option<Option<&Preview>> {
        std::mem::take(&mut self.fresh).then_some(self.current.as_ref())
    }

    /// True while a simulation runs.
    pub fn is_running(&self) -> bool {
        self.running.is_some()
    }

    /// True while work is running or waiting to be scheduled.
    pub fn is_busy(&self) -> bool {
        self.running.is_some() || self.dirty
    }

    /// True while the quick pass is shown and the full pass runs.
    pub fn is_refining(&self) -> bool {
        self.shown_quick && self.running.is_some()
    }

    /// The worker's progress.
    pub fn status(&self) -> Status {
        self.worker.status()
    }

    /// Simulations started so far (restyle-only changes start none).
    pub fn simulations(&self) -> u64 {
        self.started
    }

    /// Change-to-preview time of the last update (for a new simulation,
    /// until its quick pass showed), ms.
    pub fn latency_ms(&self) -> Option<f64> {
        self.latency_ms
    }

    /// Change-to-refined-preview time of the last simulation, ms.
    pub fn refined_ms(&self) -> Option<f64> {
        self.refined_ms
    }

    /// Simulation time of the last preview, ms.
    pub fn sim_ms(&self) -> Option<f64> {
        self.sim_ms
    }

    /// Shows the preview at `years` (a frame of the last simulation, no new
    /// one), or at the preset's age.
    pub fn show_age(&mut self, years: Option<u32>) {
        if self.age_view != years {
            self.age_view = years;
            self.fresh = true;
        }
    }

    /// The age shown, `None` = the preset's.
    pub fn age_view(&self) -> Option<u32> {
        self.age_view
    }

    /// Starts (from year 0 when at the end) or stops playing the ages.
    pub fn play(&mut self, on: bool) {
        self.playing = on.then(Instant::now);
        if on && self.age_view.is_none() {
            self.show_age(Some(0));
        }
    }

    /// True while the ages play.
    pub fn is_playing(&self) -> bool {
        self.playing.is_some()
    }

    /// While playing, shows the next age every `step`; stops at the last.
    pub fn tick(&mut self, step: std::time::Duration) {
        let Some(since) = self.playing else { return };
        if since.elapsed() < step {
            return;
        }
        let last = self
            .current
            .as_ref()
            .map_or(0, |p| p.ages.len() as u32)
            .saturating_sub(1);
        match self.age_view {
            Some(y) if y + 1 < last => self.show_age(Some(y + 1)),
            _ => {
                self.show_age(None);
                self.playing = None;
                return;
            }
        }
        self.playing = Some(Instant::now());
    }

    /// The image to show: the frame of the age shown, or the preview.
    pub fn shown_image(&self) -> Option<&std::sync::Arc<egui::ColorImage>> {
        let p = self.current.as_ref()?;
        Some(
            self.age_view
                .and_then(|y| super::ages::at(&p.ages, y))
                .unwrap_or(&p.image),
        )
    }

    /// Takes the worker's newest result, if any.
    pub fn poll(&mut self) -> Polled {
        let Some(done) = self.worker.poll() else {
            return Polled::Nothing;
        };
        if done.partial {
            // The quick pass: show it; the running job goes on.
            let Ok(p) = done.result else {
                return Polled::Nothing;
            };
            self.styled = self
                .running
                .as_ref()
                .map(|r| (r.preset.clone(), r.layers.clone()));
            self.shown_quick = true;
            self.show(Some(p), true);
            // Restyle it if the document moved on by a restyle-only change.
            self.dirty = true;
            return Polled::Shown;
        }
        self.shown_quick = false;
        let running = self.running.take();
        if let Some(r) = &running {
            self.sim_rev = r.rev;
            self.sim_preset = r.preset.clone();
            self.sim_failed = done.result.is_err();
        }
        // The document may have moved on while it ran.
        self.dirty = true;
        match done.result {
            Ok(p) => {
                self.styled = running.map(|r| (r.preset, r.layers));
                self.sim_ms = Some(done.elapsed.as_secs_f64() * 1000.0);
                self.show(Some(p), true);
                Polled::Shown
            }
            Err(e) => {
                self.styled = None;
                self.show(None, false);
                Polled::Failed(format!("preview: {e}"))
            }
        }
    }

    /// Shows `p`; `sim` when it comes from the worker (a quick or full
    /// pass), not from a re-composite.
    fn show(&mut self, p: Option<Preview>, sim: bool) {
        let quick = p.as_ref().is_some_and(|p| p.quick);
        self.current = p;
        self.fresh = true;
        let ms = |t: Instant| Some(t.elapsed().as_secs_f64() * 1000.0);
        let changed = self.changed_at.take();
        if let Some(t) = changed {
            self.latency_ms = ms(t);
        }
        if sim && quick {
            if let Some(t) = changed {
                self.refine_from.get_or_insert(t);
            }
        } else if sim && let Some(t) = self.refine_from.take().or(changed) {
            self.refined_ms = ms(t);
        }
    }

    /// Starts a simulation, re-composites, or waits, as the change needs.
    ///
    /// # Errors
    /// The message for the status bar when no preview job can be made.
    pub fn schedule(&mut self, l: Option<&Loaded>) -> Result<(), String> {
        if !self.dirty {
            return Ok(());
        }
        let Some(l) = l else {
            self.dirty = false;
            return Ok(());
        };
        if l.stroking() {
            return Ok(()); // the preview follows when the stroke ends
        }
        self.dirty = false;
        let doc = &l.doc;
        let need_sim = match (&self.running, &self.current) {
            (Some(r), _) => r.rev != l.rev || !render::restyles(&r.preset, &doc.preset),
            (None, _) if self.sim_failed => self.sim_rev != l.rev || self.sim_preset != doc.preset,
            (None, Some(_)) => {
                self.sim_rev != l.rev || !render::restyles(&self.sim_preset, &doc.preset)
            }
            (None, None) => true,
        };
        let styled = self
            .styled
            .as_ref()
            .is_some_and(|(sp, sl)| *sp == doc.preset && *sl == doc.layers);
        if need_sim {
            let job = l
                .proxy
                .job(&doc.run_preset(), doc.quad.as_ref(), &doc.layers)
                .map_err(|e| format!("preview: {e}"))?;
            self.worker.submit(job);
            self.started += 1;
            self.shown_quick = false;
            self.refine_from = None;
            self.running = Some(Running {
                rev: l.rev,
                preset: doc.preset.clone(),
                layers: doc.layers.clone(),
            });
        } else if (self.running.is_none() || self.shown_quick) && !styled {
            // Also while the full pass runs: the quick pass shown follows at
            // once, the full one is restyled when it arrives.
            if let Some(mut cur) = self.current.take() {
                cur.restyle(&doc.preset, &doc.layers);
                self.styled = Some((doc.preset.clone(), doc.layers.clone()));
                self.show(Some(cur), false);
            }
        } else if self.running.is_none() {
            self.changed_at = None;
        }
        Ok(())
    }
}
