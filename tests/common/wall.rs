//! A plain wall aged by the rain alone, for the tests of streaks' shapes
//! (`streaks.rs`, `twins.rs`, `breaks.rs`).

use grime::analysis::{Ledge, LedgeKind};
use grime::photo::Photo;
use grime::pipeline::{self, Scene, Site};
use grime::preset::Preset;
use grime::progress::Progress;
use image::{DynamicImage, Rgb, RgbImage};

/// A wall of one colour `wall`, `w` x `h` pixels at 0.01 m a pixel, after
/// `layers` rainfalls with `seed` (moss, dust and the top edge off), fed
/// by the preset's source `lines`; each line the analysis found as a sill
/// with its `confidence` (`None`: a line of the preset's own, not found);
/// the preset then changed by `change`.
pub fn rain_on(
    (w, h, wall): (u32, u32, [u8; 3]),
    lines: Vec<Vec<[f32; 2]>>,
    confidence: Option<f32>,
    (layers, seed): (u32, u64),
    change: impl Fn(&mut Preset),
) -> pipeline::Outcome {
    let photo = RgbImage::from_pixel(w, h, Rgb(wall));
    let found = confidence.map(|c| (LedgeKind::Sill, c));
    rain_on_photo(photo, lines, found, (layers, seed), change)
}

/// `photo` (0.01 m a pixel) after `layers` rainfalls with `seed` (moss,
/// dust and the top edge off), fed by the preset's source `lines`; each
/// line found by the analysis as a ledge of the `found` kind and
/// confidence (`None`: lines of the preset's own); the preset then
/// changed by `change`.
pub fn rain_on_photo(
    photo: RgbImage,
    lines: Vec<Vec<[f32; 2]>>,
    found: Option<(LedgeKind, f32)>,
    (layers, seed): (u32, u64),
    change: impl Fn(&mut Preset),
) -> pipeline::Outcome {
    let w = photo.width();
    let ledges = found
        .map(|(kind, confidence)| {
            lines
                .iter()
                .map(|line| Ledge {
                    kind,
                    polyline: line.clone(),
                    confidence,
                })
                .collect()
        })
        .unwrap_or_default();
    let scene = Scene::new(Photo::new(DynamicImage::ImageRgb8(photo)), None)
        .unwrap()
        .with_site(Site {
            metres_per_pixel: 0.01,
            ledges,
            ..Site::assumed(w)
        })
        .unwrap();
    let mut p = Preset::default();
    p.moss.enabled = false;
    p.dust.enabled = false;
    p.rain.top_edge = false;
    p.rain.layers = layers;
    p.seed = seed;
    p.rain.source_lines = lines;
    change(&mut p);
    pipeline::run(&scene, &p, &Progress::none()).unwrap()
}

/// Luma, Rec. 601.
pub fn luma(p: &[u8]) -> f32 {
    0.299 * p[0] as f32 + 0.587 * p[1] as f32 + 0.114 * p[2] as f32
}

/// The composite of a run's rain stains, without its washed runs (which
/// lighten where water runs often: more rain may wash an edge cleaner).
pub fn stains(mut out: pipeline::Outcome) -> RgbImage {
    for layer in &mut out.stack.layers {
        layer.visible &= layer.name != "rain washed";
    }
    out.stack.composite().to_rgb8()
}
