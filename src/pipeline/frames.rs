//! A time-lapse: the scene at several ages with the rain simulated once.
//!
//! The run at the oldest age keeps the wall after each frame's number of
//! rainfalls ([`crate::effects::rain::simulate_keeping`]). Each frame then
//! re-uses that run's first rainfalls as they are (each rainfall depends
//! only on those before it) and re-runs only what the age changes (moss on
//! the wall kept at that age, dust over fewer days) through
//! [`run_cached`], so a frame equals [`run`] with its own preset.

use std::collections::BTreeMap;
use std::sync::Arc;

use super::{Cache, Outcome, run_cached};
use crate::clock;
use crate::effects::{Effect, Produced, Products, stale};
use crate::error::{Error, Result};
use crate::pipeline::Scene;
use crate::preset::Preset;
use crate::progress::Progress;
use crate::stack::Layer;

/// Runs `scene` at `last` (the oldest age), then calls `each` with every
/// frame's index and outcome, in order; returns the outcome at `last`.
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
    each: &mut dyn FnMut(usize, Outcome) -> Result<()>,
) -> Result<Outcome> {
    for frame in frames {
        check_frame(frame, last)?;
    }
    let mut cache = Cache {
        scene: Some(scene.clone()),
        ..Cache::default()
    };
    cache.products.keep_rain_at = frames.iter().map(|f| f.rain.layers).collect();
    let share = 1.0 / (frames.len() + 1) as f32;
    let full = run_cached(scene, last, &progress.span(0.0, share), &mut cache)?;
    let (_, rain) = cache
        .made
        .remove(&Effect::Rain)
        .ok_or_else(|| Error::Preset("the rain did not run".into()))?;
    let whole = full.rain.clone();
    for (i, frame) in frames.iter().enumerate() {
        progress.check()?;
        let kept = cache
            .products
            .rain_kept
            .iter()
            .find(|k| k.rainfalls == frame.rain.layers)
            .ok_or_else(|| Error::Preset("a frame's rainfalls were not kept".into()))?;
        // What the frame can keep: effects that read nothing and whose
        // fields it does not change (copying the others would be wasted).
        let mut made: BTreeMap<Effect, (Preset, Produced)> = cache
            .made
            .iter()
            .filter(|(e, (p, _))| e.inputs().is_empty() && !stale(p, frame).contains(e))
            .map(|(e, m)| (*e, m.clone()))
            .collect();
        let washed = cache
            .products
            .rain_washed
            .iter()
            .find(|(n, _)| *n == kept.rainfalls)
            .map(|(_, l)| l);
        made.insert(
            Effect::Rain,
            (frame.clone(), first(&rain, kept.rainfalls, washed)),
        );
        let mut frame_cache = Cache {
            keep: false,
            scene: cache.scene.clone(),
            made,
            stamps: cache.stamps.clone(),
            products: Products {
                rain: Some(Arc::new(whole.prefix(kept))),
                ..Products::default()
            },
        };
        let at = share * (i + 1) as f32;
        let out = run_cached(
            scene,
            frame,
            &progress.span(at, at + share),
            &mut frame_cache,
        )?;
        each(i, out)?;
    }
    Ok(full)
}

/// The rain's first `n` layers and their stats, and the washed runs after
/// them when there are any.
fn first(rain: &Produced, n: u32, washed: Option<&Layer>) -> Produced {
    let n = n as usize;
    let mut layers = rain.layers[..n].to_vec();
    let mut layer_stats = rain.layer_stats[..n].to_vec();
    if let Some(washed) = washed {
        layers.push(washed.clone());
        layer_stats.push(None);
    }
    Produced {
        layers,
        layer_stats,
        stats: rain.stats.clone(),
    }
}

/// A frame may differ from the last only in the clock and ask for no more
/// rainfalls than it.
fn check_frame(frame: &Preset, last: &Preset) -> Result<()> {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::clock::{self, Pins};
    use crate::demo;

    #[test]
    fn every_frame_is_the_run_at_its_age() {
        let d = demo::facade(120, 90);
        let scene = Scene::new(d.photo, d.region).unwrap();
        let mut p = Preset::default();
        p.rain.droplets = 120;
        p.rain.source_lines = d.source_lines;
        let years = [0, 2, 5];
        let last = clock::at(&p, 5, Pins::none()).unwrap();
        let frames: Vec<Preset> = years
            .iter()
            .map(|&y| clock::at(&p, y, Pins::none()).unwrap())
            .collect();
        let mut seen = Vec::new();
        let full = run_frames(&scene, &last, &frames, &Progress::none(), &mut |i, out| {
            seen.push((i, out.stack.composite()));
            Ok(())
        })
        .unwrap();
        assert_eq!(seen.len(), 3);
        for ((i, frame), preset) in seen.iter().zip(&frames) {
            let alone = super::super::run(&scene, preset, &Progress::none()).unwrap();
            assert!(
                frame.as_bytes() == alone.stack.composite().as_bytes(),
                "frame {i} differs from the run at {} years",
                years[*i]
            );
        }
        assert_eq!(
            seen[2].1.as_bytes(),
            full.stack.composite().as_bytes(),
            "the last frame is the run"
        );
        assert_eq!(seen[0].1.as_bytes(), scene.photo.image().as_bytes());
    }
}
