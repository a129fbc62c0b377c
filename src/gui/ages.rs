//! The preview at every age: with the clock on (`age.years` set), the full
//! pass also composites the wall at each year from 0 to the preset's age
//! ([`pipeline::run_frames`]: the rain is simulated once), so the "Age
//! (years)" slider and the play button only swap images, with no new
//! simulation.

use std::collections::BTreeMap;
use std::sync::Arc;

use eframe::egui::ColorImage;

use crate::clock;
use crate::error::Result;
use crate::pipeline::{self, Outcome, Scene};
use crate::preset::Preset;
use crate::progress::Progress;

use super::render::to_color_image;
use super::state::{LayerSetting, apply_layer_settings};

/// One frame: its age and its composite.
pub type Frame = (u32, Arc<ColorImage>);

/// The run of `scene` at `preset` and, when its clock is on, the composite
/// at every year up to its age (layer settings applied).
///
/// # Errors
/// The pipeline's errors.
pub fn run(
    scene: &Scene,
    preset: &Preset,
    layers: &BTreeMap<String, LayerSetting>,
    progress: &Progress,
) -> Result<(Outcome, Vec<Frame>)> {
    let Some(age) = preset.age.years else {
        return Ok((pipeline::run(scene, preset, progress)?, Vec::new()));
    };
    let pins = clock::pins_of(preset);
    let presets = (0..=age)
        .map(|y| clock::at(preset, y, pins))
        .collect::<Result<Vec<_>>>()?;
    let mut frames = Vec::with_capacity(presets.len());
    let out = pipeline::run_frames(scene, preset, &presets, progress, &mut |i, frame| {
        let mut stack = frame.stack();
        apply_layer_settings(layers, &mut stack);
        let image = to_color_image(&stack.composite());
        frames.push((i as u32, Arc::new(image)));
        Ok(())
    })?;
    Ok((out, frames))
}

/// The frame of `years`, if there is one.
pub fn at(frames: &[Frame], years: u32) -> Option<&Arc<ColorImage>> {
    frames.iter().find(|(y, _)| *y == years).map(|(_, f)| f)
}

/// The "Age (years)" slider and the play button: they show the frames of
/// the last simulation. With the clock off, a button turns it on.
pub fn panel(
    ui: &mut eframe::egui::Ui,
    ctl: &super::controller::Controller,
    out: &mut Vec<super::command::Command>,
) {
    use super::command::Command;
    let Some(l) = ctl.loaded() else { return };
    let Some(age) = l.doc.preset.age.years else {
        if ui
            .button("Age with one clock (15 years)")
            .on_hover_text("Set age.years: rainfalls, moss years and dust days follow it")
            .clicked()
        {
            out.push(Command::SetParam {
                path: "age.years".into(),
                value: "15".into(),
                merge: false,
            });
        }
        return;
    };
    let preview = ctl.preview();
    let ready = preview
        .current()
        .is_some_and(|p| p.ages.len() as u32 == age + 1);
    let shown = preview.age_view().unwrap_or(age);
    let mut years = shown;
    ui.add_enabled(
        ready,
        eframe::egui::Slider::new(&mut years, 0..=age).text("Age (years)"),
    )
    .on_hover_text("Scrub the wall's age: the frames of the last simulation, no new one");
    if years != shown {
        out.push(Command::ShowAge((years != age).then_some(years)));
    }
    let playing = preview.is_playing();
    let label = if playing { "Stop" } else { "Play" };
    if ui
        .add_enabled(ready, eframe::egui::Button::new(label))
        .clicked()
    {
        out.push(Command::PlayAges(!playing));
    }
}
