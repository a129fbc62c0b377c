//! Progress reporting and cancellation for long runs.
//!
//! The pipeline calls [`Progress::update`] as it goes and checks
//! [`Progress::check`] often (at least every few dozen droplets), so a GUI
//! worker can stop a run mid-layer.

use std::sync::atomic::{AtomicBool, Ordering};

use crate::error::{Error, Result};

/// Callback receiving (stage name, overall fraction done in 0..1).
pub type Callback<'a> = &'a (dyn Fn(&str, f32) + Sync);

/// Where to report progress and where to look for a cancel request.
#[derive(Clone, Copy)]
pub struct Progress<'a> {
    callback: Option<Callback<'a>>,
    cancel: Option<&'a AtomicBool>,
    start: f32,
    end: f32,
}

impl Default for Progress<'_> {
    fn default() -> Self {
        Progress {
            callback: None,
            cancel: None,
            start: 0.0,
            end: 1.0,
        }
    }
}

impl<'a> Progress<'a> {
    /// No reporting, no cancelling.
    pub fn none() -> Self {
        Progress::default()
    }

    /// Reports to `callback` (if any) and stops when `cancel` (if any) is set.
    pub fn new(callback: Option<Callback<'a>>, cancel: Option<&'a AtomicBool>) -> Self {
        Progress {
            callback,
            cancel,
            ..Progress::default()
        }
    }

    /// A view of this progress whose 0..1 maps onto `start..end` of this one.
    pub fn span(&self, start: f32, end: f32) -> Progress<'a> {
        let len = self.end - self.start;
        Progress {
            start: self.start + start * len,
            end: self.start + end * len,
            ..*self
        }
    }

    /// Reports that `fraction` (0..1) of the whole run is done.
    pub fn update(&self, stage: &str, fraction: f32) {
        if let Some(cb) = self.callback {
            cb(
                stage,
                self.start + fraction.clamp(0.0, 1.0) * (self.end - self.start),
            );
        }
    }

    /// Returns [`Error::Cancelled`] once the caller has asked to stop.
    ///
    /// # Errors
    /// [`Error::Cancelled`] when the cancel flag is set.
    pub fn check(&self) -> Result<()> {
        match self.cancel {
            Some(flag) if flag.load(Ordering::Relaxed) => Err(Error::Cancelled),
            _ => Ok(()),
        }
    }
}
