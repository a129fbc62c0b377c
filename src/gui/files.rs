//! File I/O off the UI thread: opening photos, samples and projects,
//! saving projects and presets, loading presets. One thread runs the jobs
//! in the order they were asked for (unlike [`super::worker::Worker`], no
//! job replaces another: a save must not be dropped because an open
//! followed it), and the UI polls the results each frame.

use std::path::PathBuf;
use std::sync::mpsc::{self, Receiver, Sender};

use crate::demo;
use crate::io;
use crate::photo::Photo;
use crate::preset::Preset;

use super::state::{Document, ImageSource};
use super::worker::Repaint;

/// One file operation.
#[derive(Debug, Clone)]
pub enum FileJob {
    /// Open a photo; the new document starts from `preset`.
    OpenImage(PathBuf, Preset),
    /// Open a built-in sample with `preset`.
    OpenDemo(String, Preset),
    /// Open a project.
    OpenProject(PathBuf),
    /// Save a project (the document as it was when asked).
    SaveProject(Box<Document>, PathBuf),
    /// Load a preset TOML.
    LoadPreset(PathBuf),
    /// Write preset TOML text.
    SavePreset(String, PathBuf),
}

/// What a file operation gave.
#[derive(Debug)]
pub enum FileDone {
    /// A document to show.
    Opened {
        /// The document.
        doc: Box<Document>,
        /// Its photo.
        photo: Photo,
        /// The files behind it, which no export may overwrite.
        from: Vec<PathBuf>,
        /// What to tell the user.
        note: String,
    },
    /// A preset to use.
    Preset(Box<Preset>, PathBuf),
    /// Something was written; what to tell the user.
    Saved(String),
}

/// Runs one job. The error is the message for the status bar.
///
/// # Errors
/// A message naming the file and what was wrong.
pub fn run(job: FileJob) -> Result<FileDone, String> {
    match job {
        FileJob::OpenImage(path, preset) => {
            let photo = io::load_photo(&path).map_err(|e| format!("cannot open image: {e}"))?;
            let doc = Document::new(
                ImageSource::File(path.clone()),
                photo.width(),
                photo.height(),
                preset,
            );
            Ok(opened(doc, photo, vec![path]))
        }
        FileJob::OpenDemo(name, preset) => {
            let d = demo::load(&name).map_err(|e| e.to_string())?;
            let (w, h) = (d.photo.width(), d.photo.height());
            let mut doc = Document::new(ImageSource::Demo(name), w, h, preset);
            if let Some(r) = d.region {
                doc.mask = r;
            }
            doc.lines = d.source_lines;
            Ok(opened(doc, d.photo, Vec::new()))
        }
        FileJob::OpenProject(path) => {
            let (doc, photo, mask) =
                Document::load_project(&path).map_err(|e| format!("cannot open project: {e}"))?;
            let mut from = vec![path.clone(), mask];
            if let ImageSource::File(p) = &doc.source {
                from.push(p.clone());
            }
            let mut done = opened(doc, photo, from);
            if let FileDone::Opened { note, .. } = &mut done {
                *note = format!("Opened project {}", path.display());
            }
            Ok(done)
        }
        FileJob::SaveProject(doc, path) => doc
            .save_project(&path)
            .map(|()| FileDone::Saved(format!("Saved project {}", path.display())))
            .map_err(|e| format!("cannot save project: {e}")),
        FileJob::LoadPreset(path) => std::fs::read_to_string(&path)
            .map_err(|e| crate::Error::io(&path, e).to_string())
            .and_then(|t| crate::clock::load(&t).map_err(|e| format!("{}: {e}", path.display())))
            .map(|p| FileDone::Preset(Box::new(p), path))
            .map_err(|e| format!("cannot load preset: {e}")),
        FileJob::SavePreset(text, path) => io::write_atomic(&path, |out| {
            std::io::Write::write_all(out, text.as_bytes()).map_err(|e| crate::Error::io(&path, e))
        })
        .map(|()| FileDone::Saved(format!("Saved preset {}", path.display())))
        .map_err(|e| format!("cannot save preset: {e}")),
    }
}

fn opened(doc: Document, photo: Photo, from: Vec<PathBuf>) -> FileDone {
    let note = format!(
        "Opened {} ({}×{})",
        doc.source.display_name(),
        photo.width(),
        photo.height()
    );
    FileDone::Opened {
        doc: Box::new(doc),
        photo,
        from,
        note,
    }
}

/// The file thread: jobs run one after another, every result comes back.
pub struct Files {
    tx: Option<Sender<FileJob>>,
    rx: Receiver<Result<FileDone, String>>,
    pending: usize,
}

impl Files {
    /// Starts the thread; it calls `repaint` after each job.
    pub fn spawn(repaint: Repaint) -> Files {
        let (tx, jobs) = mpsc::channel::<FileJob>();
        let (done, rx) = mpsc::channel();
        let spawned = std::thread::Builder::new()
            .name("grime-files".into())
            .spawn(move || {
                while let Ok(job) = jobs.recv() {
                    if done.send(run(job)).is_err() {
                        break;
                    }
                    repaint();
                }
            });
        Files {
            tx: spawned.is_ok().then_some(tx),
            rx,
            pending: 0,
        }
    }

    /// Queues a job.
    ///
    /// # Errors
    /// When the thread could not be started or has stopped.
    pub fn submit(&mut self, job: FileJob) -> Result<(), String> {
        let sent = self.tx.as_ref().is_some_and(|tx| tx.send(job).is_ok());
        if !sent {
            return Err("the file thread is not running".into());
        }
        self.pending += 1;
        Ok(())
    }

    /// The results that are in, in the order the jobs were queued.
    pub fn poll(&mut self) -> Vec<Result<FileDone, String>> {
        let done: Vec<_> = self.rx.try_iter().collect();
        self.pending = self.pending.saturating_sub(done.len());
        done
    }

    /// True while a job is queued or running.
    pub fn is_busy(&self) -> bool {
        self.pending > 0
    }
}
