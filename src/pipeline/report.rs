//! What a run did, in numbers (`--report`).

use std::collections::BTreeMap;
use std::time::Instant;

use serde::Serialize;

use crate::effects::dust::DustStats;
use crate::effects::moss::MossStats;
use crate::effects::rain::LayerStats;
use crate::effects::{Effect, Stats};
use crate::stack::{BlendMode, Layer};

/// Size of an image.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Size {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
}

/// One layer as reported.
#[derive(Debug, Clone, Serialize)]
pub struct LayerReport {
    /// Layer name.
    pub name: String,
    /// The effect that made it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub effect: Option<Effect>,
    /// Blend mode.
    pub blend: BlendMode,
    /// Opacity.
    pub opacity: f32,
    /// Mean coverage over the photo, 0..1.
    pub coverage: f64,
    /// Rain numbers, for rain layers.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rain: Option<LayerStats>,
}

impl LayerReport {
    /// The report of `layer`, with its effect's per-layer numbers.
    pub fn of(layer: &Layer, rain: Option<LayerStats>) -> LayerReport {
        LayerReport {
            name: layer.name.clone(),
            effect: layer.kind,
            blend: layer.blend,
            opacity: layer.opacity,
            coverage: layer.coverage(),
            rain,
        }
    }
}

/// Time spent in one stage.
#[derive(Debug, Clone, Serialize)]
pub struct Timing {
    /// Stage name.
    pub stage: String,
    /// Milliseconds.
    pub ms: f64,
}

/// What a run did, in numbers (`--report`).
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    /// Photo size.
    pub image: Size,
    /// Simulation grid size and photo pixels per grid pixel.
    pub grid: GridReport,
    /// Master seed.
    pub seed: u64,
    /// Every layer, bottom to top.
    pub layers: Vec<LayerReport>,
    /// Each enabled effect's numbers, under its name (`rain`, `moss`, ...).
    #[serde(flatten)]
    pub effects: BTreeMap<Effect, Stats>,
    /// Time per stage.
    pub timings: Vec<Timing>,
}

impl Report {
    /// Moss numbers, when moss ran.
    pub fn moss(&self) -> Option<&MossStats> {
        match self.effects.get(&Effect::Moss) {
            Some(Stats::Moss(s)) => Some(s),
            _ => None,
        }
    }

    /// Dust numbers, when dust ran.
    pub fn dust(&self) -> Option<&DustStats> {
        match self.effects.get(&Effect::Dust) {
            Some(Stats::Dust(s)) => Some(s),
            _ => None,
        }
    }
}

/// The grid as reported.
#[derive(Debug, Clone, Serialize)]
pub struct GridReport {
    /// Grid width.
    pub width: usize,
    /// Grid height.
    pub height: usize,
    /// Photo pixels per grid pixel.
    pub scale: f32,
}

/// Times the stages of a run.
pub(super) struct Clock {
    last: Instant,
    pub(super) timings: Vec<Timing>,
}

impl Clock {
    pub(super) fn start() -> Clock {
        Clock {
            last: Instant::now(),
            timings: Vec::new(),
        }
    }

    /// Records the time since the last lap as `stage`.
    pub(super) fn lap(&mut self, stage: &str) {
        let now = Instant::now();
        self.timings.push(Timing {
            stage: stage.to_string(),
            ms: (now - self.last).as_secs_f64() * 1000.0,
        });
        self.last = now;
    }
}
