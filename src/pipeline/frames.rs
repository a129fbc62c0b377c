//! A time-lapse: the scene at several ages with the rain simulated once.
//!
//! The run at the oldest age keeps the wall after each frame's number of
//! rainfalls ([`crate::effects::rain::simulate_keeping`]). A frame then
//! shows that run's first rainfalls as they are (each rainfall depends only
//! on those before it) and runs again only the effects the age changes
//! (moss on the wall kept at that age, dust over fewer days), on one
//! [`Context`] for all frames. What does not age is carried from frame to
//! frame ([`Carry`]: the dust so far, which only grows, and the maps the
//! moss and dust settle by), and the photo with the shared lowest layers
//! is composited once and added to as the rainfalls grow ([`Partial`]). A
//! frame equals [`super::run`] with its own preset, byte for byte.

use std::sync::Arc;

use image::DynamicImage;

use super::{Cache, Outcome, Prepared, plane_of, plane_preset, run_cached};
use crate::clock;
use crate::effects::carry::Carry;
use crate::effects::rain::regrid::GivenRain;
use crate::effects::region::Region;
use crate::effects::{Effect, Products, stale, washed_layer};
use crate::error::{Error, Result};
use crate::photo::Photo;
use crate::pipeline::Scene;
use crate::preset::Preset;
use crate::progress::Progress;
use crate::stack::{Layer, Partial, Stack};

/// One frame: the scene's layers at the frame's age.
pub struct Frame<'a> {
    /// The run's stack (its photo and region).
    pub(super) stack: &'a Stack,
    /// Every layer, bottom to top.
    pub(super) layers: Vec<&'a Layer>,
    /// The photo with the lowest layers, which the frames share.
    pub(super) below: &'a Partial,
    /// The layers above `below`.
    pub(super) above: Vec<&'a Layer>,
}

impl Frame<'_> {
    /// The frame's composite (as [`Stack::composite`] of [`Frame::stack`]).
    pub fn composite(&self) -> DynamicImage {
        self.below.finish(&self.above)
    }

    /// The frame's layer stack (a copy of every layer).
    pub fn stack(&self) -> Stack {
        Stack {
            base: Arc::clone(&self.stack.base),
            layers: self.layers.iter().map(|l| (*l).clone()).collect(),
            region: self.stack.region.clone(),
        }
    }
}

/// [`super::run`] at `last`, and its rain with the walls it kept after each
/// of `frames`' rainfalls, for [`super::run_previews`] on the scene scaled;
/// no rain with a wall plane (its grid is on the plane, not the photo).
///
/// # Errors
/// As [`super::run`].
pub fn run_sharing_rain(
    scene: &Scene,
    last: &Preset,
    frames: &[Preset],
    progress: &Progress,
) -> Result<(Outcome, Option<GivenRain>)> {
    let mut cache = Cache {
        scene: Some(scene.clone()),
        ..Cache::none()
    };
    cache.products.keep_rain_at = frames.iter().map(|f| f.rain.layers).collect();
    let out = run_cached(scene, last, progress, &mut cache)?;
    let rain = scene.quad.is_none().then(|| GivenRain {
        out: Arc::clone(&out.rain),
        kept: std::mem::take(&mut cache.products.rain_kept),
        grid: out.grid,
        photo: scene.size(),
    });
    Ok((out, rain))
}

/// Runs `scene` at `last` (the oldest age), then calls `each` with every
/// frame's index and layers, in order; returns the outcome at `last`.
///
/// # Errors
/// [`Error::OutOfRange`] when a frame's preset differs from `last` other
/// than in the clock's fields or asks for more rainfalls; the pipeline's
/// errors; `each`'s.
pub fn run_frames(
    scene: &Scene,
    last: &Preset,
    frames: &[Preset],
    progress: &Progress,
    each: &mut dyn FnMut(usize, Frame) -> Result<()>,
) -> Result<Outcome> {
    for frame in frames {
        check_frame(frame, last)?;
    }
    let mut cache = Cache {
        scene: Some(scene.clone()),
        ..Cache::none()
    };
    cache.products.keep_rain_at = frames.iter().map(|f| f.rain.layers).collect();
    let share = 1.0 / (frames.len() + 1) as f32;
    let full = run_cached(scene, last, &progress.span(0.0, share), &mut cache)?;
    let kept = std::mem::take(&mut cache.products.rain_kept);
    drop(cache);
    // The effects the clock changes, besides the rain, run per frame; the
    // others' layers are the run's.
    let own: Vec<Effect> = Effect::ALL
        .into_iter()
        .filter(|e| *e != Effect::Rain && e.enabled(last))
        .filter(|e| frames.iter().any(|f| stale(last, f).contains(e)))
        .collect();
    let first_own = Effect::ALL
        .iter()
        .position(|e| own.contains(e))
        .unwrap_or(Effect::ALL.len());
    let plane = scene
        .quad
        .as_ref()
        .map(|q| plane_of(scene, q))
        .transpose()?;
    let at = plane.as_ref().map_or(scene, |(_, s)| s);
    let prepared = Prepared::new(at, last)?;
    let (w, h) = at.size();
    let wall = Region::new(w, h, at.region.as_deref())?;
    let ctx = prepared.context(at, &wall);
    let mut products = Products {
        carry: Some(Box::new(Carry::default())),
        ..Products::default()
    };
    let mut below = Below::new(&scene.photo);
    for (i, frame) in frames.iter().enumerate() {
        progress.check()?;
        let span = progress.span(share * (i + 1) as f32, share * (i + 2) as f32);
        let wall_then = kept
            .iter()
            .find(|k| k.rainfalls == frame.rain.layers)
            .ok_or_else(|| Error::Preset("a frame's rainfalls were not kept".into()))?;
        products.rain = Some(Arc::new(full.rain.prefix(wall_then)));
        let preset = match &plane {
            Some((rect, _)) => plane_preset(rect, frame),
            None => frame.clone(),
        };
        let mut made: Vec<(Effect, Vec<Layer>)> = Vec::with_capacity(own.len());
        for (j, e) in own.iter().enumerate() {
            let part = span.span(
                j as f32 / own.len() as f32,
                (j + 1) as f32 / own.len() as f32,
            );
            let mut layers = e.run(&ctx, &mut products, &preset, &part)?.layers;
            for (k, layer) in layers.iter_mut().enumerate() {
                e.restyle(layer, k, frame);
                if let Some((rect, _)) = &plane {
                    let (pw, ph) = scene.size();
                    *layer = rect.unrectify_layer(layer, pw, ph, scene.region.as_deref());
                }
            }
            made.push((*e, layers));
        }
        // The washed runs sum the rainfalls so far: the frame's own, from
        // the wall the run kept then.
        let washed = wall_then.washed.as_ref().map(|w| {
            let layer = washed_layer(&ctx, &preset, w);
            match &plane {
                Some((rect, _)) => {
                    let (pw, ph) = scene.size();
                    rect.unrectify_layer(&layer, pw, ph, scene.region.as_deref())
                }
                None => layer,
            }
        });
        // Bottom to top: each effect's layers, the run's or the frame's.
        let mut layers: Vec<&Layer> = Vec::new();
        let mut split = 0;
        let mut washed_at = None;
        for (n, e) in Effect::ALL.into_iter().enumerate() {
            match made.iter().find(|(m, _)| *m == e) {
                Some((_, own)) => layers.extend(own),
                None => {
                    let of_e = full.stack.layers.iter().filter(|l| l.kind == Some(e));
                    match e {
                        Effect::Rain => {
                            layers.extend(of_e.take(frame.rain.layers as usize));
                            if let Some(w) = &washed {
                                washed_at = Some(layers.len());
                                layers.push(w);
                            }
                        }
                        _ => layers.extend(of_e),
                    }
                }
            }
            if n + 1 == first_own {
                split = layers.len();
            }
        }
        // The frame's own washed runs are not shared with the next frame.
        if let Some(at) = washed_at {
            split = split.min(at);
        }
        // The shared lowest layers: add to the last frame's when they go on
        // from them (more rainfalls), else start again from the photo.
        let (low, above) = layers.split_at(split);
        let partial = below.advance(&scene.photo, low);
        let frame = Frame {
            stack: &full.stack,
            layers: layers.clone(),
            below: partial,
            above: above.to_vec(),
        };
        each(i, frame)?;
    }
    Ok(full)
}

/// A frame may differ from the last only in the clock and ask for no more
/// rainfalls than it.
pub(super) fn check_frame(frame: &Preset, last: &Preset) -> Result<()> {
    let mut same = frame.clone();
    same.age.years = last.age.years;
    same.rain.layers = last.rain.layers;
    same.moss.years = last.moss.years;
    same.dust.days = last.dust.days;
    if same != *last || frame.rain.layers > last.rain.layers {
        return Err(Error::OutOfRange {
            field: "age.years".into(),
            value: format!("{:?}", frame.age.years),
            range: format!(
                "a frame may change only {} and no later than the run",
                clock::FIELDS.join(", ")
            ),
        });
    }
    Ok(())
}

/// The photo with a frame's shared lowest layers composited, carried from
/// frame to frame: when a frame's lowest layers go on from the last one's
/// (more rainfalls), only the new ones are added; else it starts again from
/// the photo.
pub(super) struct Below {
    partial: Partial,
    /// The layers in `partial`, by address (the run's, shared by the frames).
    layers: Vec<*const Layer>,
}

impl Below {
    pub(super) fn new(photo: &Arc<Photo>) -> Below {
        Below {
            partial: Partial::new(photo),
            layers: Vec::new(),
        }
    }

    /// Brings the composite to `low` (the frame's shared lowest layers).
    pub(super) fn advance(&mut self, photo: &Arc<Photo>, low: &[&Layer]) -> &Partial {
        let goes_on = self.layers.len() <= low.len()
            && self
                .layers
                .iter()
                .zip(low)
                .all(|(a, b)| std::ptr::eq(*a, *b));
        if !goes_on {
            *self = Below::new(photo);
        }
        self.partial.add(&low[self.layers.len()..]);
        self.layers = low.iter().map(|l| *l as *const Layer).collect();
        &self.partial
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::clock::{self, Pins};
    use crate::demo;

    fn frames_equal_runs(scene: &Scene, p: &Preset, years: &[u32]) {
        let oldest = *years.iter().max().unwrap();
        let last = clock::at(p, oldest, Pins::none()).unwrap();
        let frames: Vec<Preset> = years
            .iter()
            .map(|&y| clock::at(p, y, Pins::none()).unwrap())
            .collect();
        let mut seen = Vec::new();
        let full = run_frames(scene, &last, &frames, &Progress::none(), &mut |i, f| {
            let stack = f.stack().composite();
            assert_eq!(f.composite().as_bytes(), stack.as_bytes(), "frame {i}");
            seen.push(f.composite());
            Ok(())
        })
        .unwrap();
        assert_eq!(seen.len(), years.len());
        for ((i, frame), preset) in seen.iter().enumerate().zip(&frames) {
            let alone = super::super::run(scene, preset, &Progress::none()).unwrap();
            assert!(
                frame.as_bytes() == alone.stack.composite().as_bytes(),
                "frame {i} differs from the run at {} years",
                years[i]
            );
            if years[i] == oldest {
                assert_eq!(frame.as_bytes(), full.stack.composite().as_bytes());
            }
            if years[i] == 0 {
                assert_eq!(frame.as_bytes(), scene.photo.image().as_bytes());
            }
        }
    }

    fn small() -> (Scene, Preset) {
        let d = demo::facade(120, 90);
        let scene = Scene::new(d.photo, d.region).unwrap();
        let mut p = Preset::default();
        p.rain.droplets = 120;
        p.rain.source_lines = d.source_lines;
        (scene, p)
    }

    #[test]
    fn every_frame_is_the_run_at_its_age() {
        let (scene, p) = small();
        // In order, out of order (the shared layers start again) and with
        // dust past the bulk film (the wall at 4 ppi) and the mask's
        // saturation.
        frames_equal_runs(&scene, &p, &[0, 2, 5]);
        frames_equal_runs(&scene, &p, &[4, 1, 4, 3]);
        let mut dusty = p.clone();
        dusty.dust.ppi = 4.0;
        dusty.dust.granule_size = 3.0;
        frames_equal_runs(&scene, &dusty, &[0, 1, 3, 6, 30]);
    }

    #[test]
    fn frames_in_a_wall_plane_are_the_runs_too() {
        let (scene, p) = small();
        let (w, h) = scene.size();
        let quad = [
            [4.0, 2.0],
            [w as f32 - 3.0, 6.0],
            [w as f32 - 1.0, h as f32 - 2.0],
            [0.0, h as f32 - 5.0],
        ];
        let scene = scene.with_quad(Some(quad)).unwrap();
        frames_equal_runs(&scene, &p, &[0, 3, 5]);
    }
}
