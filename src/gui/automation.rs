//! Scripted runs (`grime gui --screenshot`, `--quit-after-frames`): count
//! frames, take a screenshot once the preview is ready, then close.

use eframe::egui;

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use egui::ColorImage;
use image::RgbImage;

use crate::io;

/// How a scripted run ended.
pub type Outcome = Arc<Mutex<Option<Result<(), String>>>>;

/// A scripted run in progress.
pub struct Automation {
    screenshot: Option<PathBuf>,
    after: u64,
    frames: u64,
    started: Instant,
    requested: bool,
    shot: Arc<Mutex<Option<Arc<ColorImage>>>>,
    /// Filled when the run ends.
    pub outcome: Outcome,
}

impl Automation {
    /// A run that saves `screenshot` (if any) after at least `after` frames.
    pub fn new(screenshot: Option<PathBuf>, after: u64) -> Automation {
        Automation {
            screenshot,
            after,
            frames: 0,
            started: Instant::now(),
            requested: false,
            shot: Arc::default(),
            outcome: Arc::default(),
        }
    }

    /// Scripted runs: count frames, take the screenshot once the preview is
    /// ready, then close.
    pub fn step(&mut self, ctx: &egui::Context, busy: bool) {
        let a = self;
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blank_screenshots_are_refused() {
        let blank = RgbImage::from_pixel(64, 48, image::Rgb([30, 30, 30]));
        assert!(check_not_blank(&blank).unwrap_err().contains("blank"));
        let d = crate::demo::facade(64, 48);
        assert!(check_not_blank(&d.photo.image().to_rgb8()).is_ok());
    }
}
