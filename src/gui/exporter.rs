//! The export worker: the document at full resolution through
//! [`render::export`] (the core's one ageing entry point and its guard),
//! its progress, cancellation and last result.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::pipeline::Scene;

use super::controller::Loaded;
use super::render::{self, ExportJob, Exported};
use super::worker::{Repaint, Status, Worker};

/// The export worker and what it is doing.
pub struct Exporter {
    worker: Worker<ExportJob, Exported>,
    running: Option<PathBuf>,
    last: Option<Result<Exported, String>>,
}

impl Exporter {
    /// An exporter with its worker thread, which calls `repaint`.
    pub fn new(repaint: Repaint) -> Exporter {
        Exporter {
            worker: Worker::spawn("grime-export", repaint, render::export),
            running: None,
            last: None,
        }
    }

    /// Starts exporting `l` to `path`. The output is checked on the worker,
    /// by [`crate::age::guard`], against the files `l` came from.
    ///
    /// # Errors
    /// The message for the status bar when no job can be made.
    pub fn start(&mut self, l: &Loaded, path: PathBuf, timelapse: bool) -> Result<String, String> {
        let scene = Scene::shared(Arc::clone(&l.photo), Some(Arc::new(l.doc.mask.clone())))
            .and_then(|s| s.with_quad(l.doc.quad))
            .and_then(|s| match l.site() {
                Some(site) => s.with_site(site),
                None => Ok(s),
            })
            .map_err(|e| format!("cannot export: {e}"))?;
        let note = format!("Exporting {} at full resolution…", path.display());
        self.worker.submit(ExportJob {
            scene,
            from: l.from.clone(),
            preset: l.doc.run_preset(),
            layers: l.doc.layers.clone(),
            path: path.clone(),
            timelapse,
        });
        self.running = Some(path);
        Ok(note)
    }

    /// Stops the running export.
    pub fn cancel(&mut self) {
        self.worker.cancel();
        self.running = None;
    }

    /// The finished export's message, once: `Err` for a failure.
    pub fn poll(&mut self) -> Option<Result<String, String>> {
        let done = self.worker.poll()?;
        self.running = None;
        Some(match done.result {
            Ok(e) => {
                let note = format!(
                    "Exported {}×{} ({} layers) to {} in {:.1} s",
                    e.width,
                    e.height,
                    e.layers,
                    e.path.display(),
                    done.elapsed.as_secs_f64()
                );
                self.last = Some(Ok(e));
                Ok(note)
            }
            Err(crate::Error::Cancelled) => Ok("Export cancelled".into()),
            Err(e) => {
                self.last = Some(Err(e.to_string()));
                Err(format!("export failed: {e}"))
            }
        })
    }

    /// The file being exported and the progress.
    pub fn running(&self) -> Option<(&Path, Status)> {
        self.running.as_deref().map(|p| (p, self.worker.status()))
    }

    /// The last export's result.
    pub fn last(&self) -> Option<&Result<Exported, String>> {
        self.last.as_ref()
    }
}
