//! Scene analysis for "Auto region" and "Detect ledges", off the UI thread:
//! [`crate::analysis::analyse`] of the full photo (about 100-200 ms for a
//! 12 MP photo) runs on its own thread, and the controller polls for it. The
//! result is kept with the document, so the second button costs nothing.

use std::sync::Arc;
use std::sync::mpsc::{self, Receiver};

use crate::analysis::{self, Analysis, Options};
use crate::grid::WALL;
use crate::photo::Photo;
use crate::preset::SourceLine;

use image::GrayImage;

use super::worker::Repaint;

/// What the analysis is wanted for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Want {
    /// Fill the region with the detected wall.
    Region,
    /// Add the detected ledges as source lines.
    Ledges,
}

/// The analysis of the open photo, running or not.
pub struct Analyser {
    running: Option<Running>,
    repaint: Repaint,
}

struct Running {
    rx: Receiver<Result<Analysis, String>>,
    /// The photo being analysed (results for another photo are dropped).
    photo: Arc<Photo>,
    wants: Vec<Want>,
}

/// A finished analysis and what it was wanted for.
pub struct Finished {
    /// The photo it is of.
    pub photo: Arc<Photo>,
    /// The analysis, or the message for the status bar.
    pub result: Result<Arc<Analysis>, String>,
    /// What to do with it, in the order asked.
    pub wants: Vec<Want>,
}

impl Analyser {
    /// No analysis running; `repaint` is called when one finishes.
    pub fn new(repaint: Repaint) -> Analyser {
        Analyser {
            running: None,
            repaint,
        }
    }

    /// Analyses `photo` on a new thread for `want`; when the same photo is
    /// already being analysed, `want` joins that run.
    pub fn start(&mut self, photo: &Arc<Photo>, name: &str, want: Want) {
        if let Some(r) = &mut self.running
            && Arc::ptr_eq(&r.photo, photo)
        {
            if !r.wants.contains(&want) {
                r.wants.push(want);
            }
            return;
        }
        let (tx, rx) = mpsc::channel();
        let repaint = Arc::clone(&self.repaint);
        let (p, opts) = (
            Arc::clone(photo),
            Options {
                name: name.to_string(),
                ..Options::default()
            },
        );
        let spawned = std::thread::Builder::new()
            .name("grime-analysis".into())
            .spawn(move || {
                let result = analysis::analyse(&p, &opts).map_err(|e| e.to_string());
                if tx.send(result).is_ok() {
                    repaint();
                }
            });
        let rx = match spawned {
            Ok(_) => rx,
            Err(e) => {
                // No thread: report it through the same channel.
                let (tx, rx) = mpsc::channel();
                let _ = tx.send(Err(format!("cannot start the analysis: {e}")));
                rx
            }
        };
        self.running = Some(Running {
            rx,
            photo: Arc::clone(photo),
            wants: vec![want],
        });
    }

    /// The analysis, once it has finished.
    pub fn poll(&mut self) -> Option<Finished> {
        let r = self.running.as_ref()?;
        let result = match r.rx.try_recv() {
            Ok(res) => res.map(Arc::new),
            Err(mpsc::TryRecvError::Empty) => return None,
            Err(mpsc::TryRecvError::Disconnected) => Err("the analysis stopped".into()),
        };
        let r = self.running.take()?;
        Some(Finished {
            photo: r.photo,
            result,
            wants: r.wants,
        })
    }

    /// True while an analysis runs.
    pub fn is_busy(&self) -> bool {
        self.running.is_some()
    }

    /// Forgets the running analysis (another photo was opened).
    pub fn reset(&mut self) {
        self.running = None;
    }
}

/// The detected ledges (photo pixels) whose middle lies inside `region`
/// and that repeat none of `existing` nor one another: a line repeats
/// another when they overlap horizontally and their mean heights over the
/// overlap differ by less than `tolerance` pixels.
pub fn new_ledges(
    a: &Analysis,
    region: &GrayImage,
    existing: &[SourceLine],
    tolerance: f32,
) -> Vec<SourceLine> {
    let inside = |line: &SourceLine| {
        let (x, y) = mid(line);
        let (w, h) = region.dimensions();
        let (x, y) = (
            (x.max(0.0) as u32).min(w - 1),
            (y.max(0.0) as u32).min(h - 1),
        );
        region.get_pixel(x, y)[0] >= WALL
    };
    let mut kept: Vec<SourceLine> = Vec::new();
    for line in a.source_lines() {
        if line.len() < 2 || !inside(&line) {
            continue;
        }
        let repeats = existing
            .iter()
            .chain(&kept)
            .any(|o| same_ledge(&line, o, tolerance));
        if !repeats {
            kept.push(line);
        }
    }
    kept
}

/// The middle of a polyline (of its end points' span, on the line).
fn mid(line: &SourceLine) -> (f32, f32) {
    let (x0, x1) = x_range(line);
    let xm = (x0 + x1) / 2.0;
    (xm, y_at(line, xm))
}

fn x_range(line: &SourceLine) -> (f32, f32) {
    line.iter()
        .fold((f32::MAX, f32::MIN), |(a, b), p| (a.min(p[0]), b.max(p[0])))
}

/// The polyline's height at `x` (clamped to its ends).
fn y_at(line: &SourceLine, x: f32) -> f32 {
    let mut pts: Vec<[f32; 2]> = line.clone();
    pts.sort_by(|a, b| a[0].total_cmp(&b[0]));
    let (first, last) = (pts[0], pts[pts.len() - 1]);
    if x <= first[0] {
        return first[1];
    }
    for s in pts.windows(2) {
        if x <= s[1][0] {
            let t = (x - s[0][0]) / (s[1][0] - s[0][0]).max(1e-6);
            return s[0][1] + (s[1][1] - s[0][1]) * t;
        }
    }
    last[1]
}

/// True when `a` and `b` overlap horizontally and lie within `tolerance`
/// of each other in the middle of the overlap.
fn same_ledge(a: &SourceLine, b: &SourceLine, tolerance: f32) -> bool {
    if a.is_empty() || b.is_empty() {
        return false;
    }
    let ((a0, a1), (b0, b1)) = (x_range(a), x_range(b));
    let (o0, o1) = (a0.max(b0), a1.min(b1));
    if o0 > o1 {
        return false;
    }
    let xm = (o0 + o1) / 2.0;
    (y_at(a, xm) - y_at(b, xm)).abs() < tolerance
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_repeat_where_they_overlap_at_the_same_height() {
        let level = vec![[0.0, 10.0], [50.0, 10.0]];
        let slanted = vec![[40.0, 20.0], [100.0, 30.0]];
        assert!(same_ledge(&vec![[5.0, 12.0], [40.0, 12.0]], &level, 6.0));
        assert!(!same_ledge(&vec![[5.0, 40.0], [40.0, 40.0]], &level, 6.0));
        assert!(!same_ledge(&vec![[60.0, 10.0], [90.0, 10.0]], &level, 6.0));
        // A slanted line is compared where the two overlap, not at its start.
        assert!(same_ledge(&vec![[60.0, 24.0], [70.0, 25.0]], &slanted, 2.0));
        assert!(!same_ledge(
            &vec![[60.0, 20.0], [70.0, 20.0]],
            &slanted,
            2.0
        ));
        assert_eq!(mid(&slanted), (70.0, 25.0));
    }

    #[test]
    fn detected_ledges_outside_the_region_or_already_there_are_skipped() {
        let d = crate::demo::facade(480, 360);
        let a = analysis::analyse(&d.photo, &Options::default()).unwrap();
        let all = GrayImage::from_pixel(480, 360, [255].into());
        let found = new_ledges(&a, &all, &[], 4.0);
        assert!(found.len() >= 5, "{found:?}");
        assert!(new_ledges(&a, &all, &found, 4.0).is_empty());
        let none = GrayImage::new(480, 360);
        assert!(new_ledges(&a, &none, &[], 4.0).is_empty());
    }
}
