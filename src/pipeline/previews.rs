//! An animation's frames drawn at the frame size from layers already
//! computed (issue 15: "the frames composite the stack at each time"): the
//! full-size run's layers shrunk once, of which each frame shows the
//! rainfalls so far; moss, dust and the washed runs (what the age changes
//! besides the rain) run at a few key frames only, on the rain the
//! full-size run kept then, and the frames between show the two nearest key
//! frames' layers cross-faded by age. A frame is so a preview of the
//! full-size run at its age (`tests/years.rs` bounds how far it is off),
//! not that run: the frames folder ([`super::run_frames`]) stays exact.

use std::sync::Arc;

use image::{GrayImage, RgbImage, RgbaImage};
use rayon::prelude::*;

use super::frames::{Below, Frame, check_frame};
use super::{Outcome, Prepared, Scene};
use crate::effects::carry::Carry;
use crate::effects::rain::regrid::GivenRain;
use crate::effects::region::Region;
use crate::effects::{Effect, Products, WASHED, stale, washed_layer};
use crate::error::{Error, Result};
use crate::preset::Preset;
use crate::progress::Progress;
use crate::shrink::buffer_to_size;
use crate::stack::{Layer, LayerPixels, Stack};

/// Frames from one key frame to the next, at most: a key frame costs its
/// moss, dust and washed runs at the frame size (about 0.15 s of CPU at
/// 1024 x 768), a frame between them a cross-fade (about 10 ms). 31 frames
/// have 4 key frames (years 0, 10, 20, 30 of a 30-year run).
pub const KEY_EVERY: usize = 10;

/// The frames of `small` (the scene the full-size run `full` was made on,
/// scaled to the frame size) at `frames` (presets scaled alike, differing
/// from `last` only in the clock), with the rain the full-size run gave
/// (`rain`, kept after each [`key_frames`]' rainfalls). Calls `each` with every
/// frame's index and layers, in order.
///
/// # Errors
/// [`Error::OutOfRange`] when a frame's preset differs from `last` other
/// than in the clock's fields; the effects' errors; `each`'s.
pub fn run_previews(
    small: &Scene,
    last: &Preset,
    frames: &[Preset],
    full: &Outcome,
    rain: &GivenRain,
    progress: &Progress,
    each: &mut dyn FnMut(usize, Frame) -> Result<()>,
) -> Result<()> {
    for frame in frames {
        check_frame(frame, last)?;
    }
    let prepared = Prepared::new(small, last)?;
    let (w, h) = small.size();
    let wall = Region::new(w, h, small.region.as_deref())?;
    let ctx = prepared.context(small, &wall);
    // The full-size run's rain on the frames' grid: as it is when the two
    // grids are alike (the defaults: both 1024 px), else read cell by cell.
    let same_grid = (rain.grid.width, rain.grid.height) == (ctx.grid.width, ctx.grid.height);
    let (rain_out, kept) = match same_grid {
        true => (Arc::clone(&rain.out), rain.kept.clone()),
        false => rain.on(ctx.grid, (w, h)),
    };
    let own: Vec<Effect> = Effect::ALL
        .into_iter()
        .filter(|e| *e != Effect::Rain && e.enabled(last))
        .filter(|e| frames.iter().any(|f| stale(last, f).contains(e)))
        .collect();
    // Every other layer is the full-size run's, shrunk once; the rain
    // layers' shared colour map too.
    let painted = full.stack.layers.iter().find_map(|l| match &l.pixels {
        LayerPixels::Painted { color, .. } => {
            Some((Arc::clone(color), Arc::new(buffer_to_size(&**color, w, h))))
        }
        _ => None,
    });
    let shared: Vec<Layer> = full
        .stack
        .layers
        .par_iter()
        .filter(|l| !l.kind.is_some_and(|k| own.contains(&k)) && l.name != WASHED)
        .map(|l| shrunk(l, w, h, painted.as_ref()))
        .collect();
    let keys = key_frames(frames);
    let age = |i: usize| frames[i].age.years.map_or(i as f32, |y| y as f32);
    let mut products = Products {
        carry: Some(Box::new(Carry::default())),
        ..Products::default()
    };
    // The key frames made so far that later frames still need, by index.
    let mut made: Vec<(usize, Made)> = Vec::new();
    let stack = Stack {
        base: Arc::clone(&small.photo),
        layers: Vec::new(),
        region: small.region.clone(),
    };
    let mut below = Below::new(&small.photo);
    let n = frames.len();
    for (i, frame) in frames.iter().enumerate() {
        progress.check()?;
        progress.update("time-lapse", i as f32 / n as f32);
        let a = *keys.iter().rev().find(|&&k| k <= i).unwrap_or(&i);
        let b = *keys.iter().find(|&&k| k >= i).unwrap_or(&i);
        made.retain(|(k, _)| *k >= a);
        for k in [a, b] {
            if !made.iter().any(|(m, _)| *m == k) {
                let key = key_frame(&ctx, &mut products, &rain_out, &kept, &own, &frames[k])?;
                made.push((k, key));
            }
        }
        let find = |k: usize| made.iter().find(|(m, _)| *m == k).map(|(_, m)| m);
        let (Some(ma), Some(mb)) = (find(a), find(b)) else {
            return Err(Error::Preset("a key frame was not made".into()));
        };
        let t = match age(b) - age(a) {
            d if d > 0.0 => ((age(i) - age(a)) / d).clamp(0.0, 1.0),
            _ => 0.0,
        };
        let mixed = ma.mix(mb, t);
        // Bottom to top: each effect's layers, the shared ones or the mix.
        let mut layers: Vec<&Layer> = Vec::new();
        let mut split = None;
        for e in Effect::ALL {
            match mixed.effects.iter().find(|(m, _)| *m == e) {
                Some((_, these)) => {
                    if !these.is_empty() {
                        split.get_or_insert(layers.len());
                    }
                    layers.extend(these);
                }
                None => {
                    let of_e = shared.iter().filter(|l| l.kind == Some(e));
                    match e {
                        Effect::Rain => {
                            layers.extend(of_e.take(frame.rain.layers as usize));
                            if let Some(w) = &mixed.washed {
                                split.get_or_insert(layers.len());
                                layers.push(w);
                            }
                        }
                        _ => layers.extend(of_e),
                    }
                }
            }
        }
        let split = split.unwrap_or(layers.len());
        // The shared lowest layers: add to the last frame's when they go on
        // from them (more rainfalls), else start again from the photo.
        let (low, above) = layers.split_at(split);
        let partial = below.advance(&small.photo, low);
        each(
            i,
            Frame {
                stack: &stack,
                layers: layers.clone(),
                below: partial,
                above: above.to_vec(),
            },
        )?;
    }
    Ok(())
}

/// Which frames are key frames: the first, the last and every
/// [`KEY_EVERY`]-th; every frame when the ages do not rise from frame to
/// frame (a cross-fade needs the frames between two keys to lie between
/// their ages). The full-size run need keep its rain only at these.
pub fn key_frames(frames: &[Preset]) -> Vec<usize> {
    let n = frames.len();
    let rising = frames
        .windows(2)
        .all(|p| p[0].age.years.unwrap_or(0) <= p[1].age.years.unwrap_or(0));
    (0..n)
        .filter(|&i| !rising || i % KEY_EVERY == 0 || i + 1 == n)
        .collect()
}

/// A key frame's own layers: each of `own`'s (moss, dust) and the washed
/// runs, at its preset's age.
struct Made {
    effects: Vec<(Effect, Vec<Layer>)>,
    washed: Option<Layer>,
}

/// The layers of the frame at `preset`, on the rain kept after its rainfalls.
fn key_frame(
    ctx: &crate::effects::Context,
    products: &mut Products,
    rain: &crate::effects::rain::RainOutput,
    kept: &[Arc<crate::effects::rain::Kept>],
    own: &[Effect],
    preset: &Preset,
) -> Result<Made> {
    let wall_then = kept
        .iter()
        .find(|k| k.rainfalls == preset.rain.layers)
        .ok_or_else(|| Error::Preset("a frame's rainfalls were not kept".into()))?;
    products.rain = Some(Arc::new(rain.prefix(wall_then)));
    let mut effects = Vec::with_capacity(own.len());
    for e in own {
        let mut layers = e.run(ctx, products, preset, &Progress::none())?.layers;
        for (k, layer) in layers.iter_mut().enumerate() {
            e.restyle(layer, k, preset);
        }
        effects.push((*e, layers));
    }
    let washed = wall_then
        .washed
        .as_ref()
        .map(|w| washed_layer(ctx, preset, w));
    Ok(Made { effects, washed })
}

impl Made {
    /// `self` and `other` cross-faded: `t` = 0 is `self`, 1 is `other`.
    fn mix(&self, other: &Made, t: f32) -> Made {
        let effects = self
            .effects
            .iter()
            .zip(&other.effects)
            .map(|((e, a), (_, b))| (*e, mix_layers(a, b, t)))
            .collect();
        let washed = mix_layers(self.washed.as_slice(), other.washed.as_slice(), t).pop();
        Made { effects, washed }
    }
}

/// The layers `a` and `b` cross-faded (`t` = 0 is `a`). A side without
/// layers counts as the other's layers made transparent; layers that do
/// not pair up (another count, kind or size) switch at the middle.
fn mix_layers(a: &[Layer], b: &[Layer], t: f32) -> Vec<Layer> {
    match (a.is_empty(), b.is_empty()) {
        (true, true) => return Vec::new(),
        (true, false) => return b.iter().map(|l| fade(l, t)).collect(),
        (false, true) => return a.iter().map(|l| fade(l, 1.0 - t)).collect(),
        _ => {}
    }
    if t <= 0.0 {
        return a.to_vec();
    }
    if t >= 1.0 || a.len() != b.len() {
        return if t < 0.5 { a.to_vec() } else { b.to_vec() };
    }
    a.iter()
        .zip(b)
        .map(|(la, lb)| {
            let pixels = match (&la.pixels, &lb.pixels) {
                (LayerPixels::Tint { color, alpha: xa }, LayerPixels::Tint { alpha: xb, .. })
                    if xa.dimensions() == xb.dimensions() =>
                {
                    LayerPixels::Tint {
                        color: *color,
                        alpha: GrayImage::from_raw(xa.width(), xa.height(), lerp_bytes(xa, xb, t))
                            .unwrap_or_else(|| xa.clone()),
                    }
                }
                (
                    LayerPixels::Painted { color, alpha: xa },
                    LayerPixels::Painted { alpha: xb, .. },
                ) if xa.dimensions() == xb.dimensions() => LayerPixels::Painted {
                    color: Arc::clone(color),
                    alpha: GrayImage::from_raw(xa.width(), xa.height(), lerp_bytes(xa, xb, t))
                        .unwrap_or_else(|| xa.clone()),
                },
                (LayerPixels::Rgba(xa), LayerPixels::Rgba(xb))
                    if xa.dimensions() == xb.dimensions() =>
                {
                    LayerPixels::Rgba(mix_rgba(xa, xb, t))
                }
                _ => return if t < 0.5 { la.clone() } else { lb.clone() },
            };
            let mut l = with_pixels(la, pixels);
            l.opacity = la.opacity + (lb.opacity - la.opacity) * t;
            l
        })
        .collect()
}

/// `t` in 0..1 as a weight out of 255.
fn weight(t: f32) -> u32 {
    (t.clamp(0.0, 1.0) * 255.0).round() as u32
}

/// `x` (0..255) times the weight `t` out of 255, rounded.
fn scale(x: u8, t: u32) -> u8 {
    ((x as u32 * t + 127) / 255) as u8
}

/// `l` with its coverage times `t`.
fn fade(l: &Layer, t: f32) -> Layer {
    let t = weight(t);
    let pixels = match &l.pixels {
        LayerPixels::Tint { color, alpha } => {
            let mut alpha = alpha.clone();
            alpha.par_iter_mut().for_each(|v| *v = scale(*v, t));
            LayerPixels::Tint {
                color: *color,
                alpha,
            }
        }
        LayerPixels::Rgba(img) => {
            let mut img = img.clone();
            img.par_chunks_mut(4).for_each(|p| p[3] = scale(p[3], t));
            LayerPixels::Rgba(img)
        }
        LayerPixels::Painted { color, alpha } => {
            let mut alpha = alpha.clone();
            alpha.par_iter_mut().for_each(|v| *v = scale(*v, t));
            LayerPixels::Painted {
                color: Arc::clone(color),
                alpha,
            }
        }
    };
    with_pixels(l, pixels)
}

/// Byte by byte, `a` (1 - `t`) + `b` `t`, rounded.
fn lerp_bytes(a: &GrayImage, b: &GrayImage, t: f32) -> Vec<u8> {
    let t = weight(t);
    a.as_raw()
        .par_iter()
        .zip(b.as_raw().par_iter())
        .map(|(&x, &y)| ((x as u32 * (255 - t) + y as u32 * t + 127) / 255) as u8)
        .collect()
}

/// Straight-alpha RGBA cross-faded through premultiplied colour, so a
/// colour fades in with its coverage rather than from black.
fn mix_rgba(a: &RgbaImage, b: &RgbaImage, t: f32) -> RgbaImage {
    let t = weight(t);
    let mut out = a.clone();
    out.par_chunks_mut(4)
        .zip(b.as_raw().par_chunks(4))
        .for_each(|(p, q)| {
            let (wa, wb) = (p[3] as u32 * (255 - t), q[3] as u32 * t);
            let sum = wa + wb;
            if sum == 0 {
                p.fill(0);
                return;
            }
            for c in 0..3 {
                p[c] = ((p[c] as u32 * wa + q[c] as u32 * wb + sum / 2) / sum) as u8;
            }
            p[3] = ((sum + 127) / 255) as u8;
        });
    out
}

/// `l` area-averaged to `w` x `h` ([`crate::shrink`]); a colour map
/// shared by painted layers is `painted`'s second when it is its first.
fn shrunk(l: &Layer, w: u32, h: u32, painted: Option<&(Arc<RgbImage>, Arc<RgbImage>)>) -> Layer {
    let pixels = match &l.pixels {
        LayerPixels::Tint { color, alpha } => LayerPixels::Tint {
            color: *color,
            alpha: buffer_to_size(alpha, w, h),
        },
        LayerPixels::Rgba(img) => LayerPixels::Rgba(buffer_to_size(img, w, h)),
        LayerPixels::Painted { color, alpha } => LayerPixels::Painted {
            color: match painted {
                Some((full, small)) if Arc::ptr_eq(full, color) => Arc::clone(small),
                _ => Arc::new(buffer_to_size(&**color, w, h)),
            },
            alpha: buffer_to_size(alpha, w, h),
        },
    };
    with_pixels(l, pixels)
}

/// `l`'s name, kind, blend, opacity and visibility with `pixels`.
fn with_pixels(l: &Layer, pixels: LayerPixels) -> Layer {
    Layer {
        name: l.name.clone(),
        kind: l.kind,
        blend: l.blend,
        opacity: l.opacity,
        visible: l.visible,
        pixels,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(years: &[u32]) -> Vec<Preset> {
        years
            .iter()
            .map(|&y| {
                let mut p = Preset::default();
                p.age.years = Some(y);
                p
            })
            .collect()
    }

    #[test]
    fn key_frames_are_every_tenth_and_the_last_or_all_out_of_order() {
        let thirty: Vec<u32> = (0..=30).collect();
        assert_eq!(key_frames(&at(&thirty)), [0, 10, 20, 30]);
        assert_eq!(key_frames(&at(&[0, 4, 12])), [0, 2]);
        assert_eq!(key_frames(&at(&[4, 1, 4])), [0, 1, 2]);
    }

    #[test]
    fn cross_fades_run_from_one_layer_to_the_other() {
        let a = RgbaImage::from_raw(3, 1, vec![200, 0, 0, 255, 0, 0, 0, 0, 9, 9, 9, 0]).unwrap();
        let b =
            RgbaImage::from_raw(3, 1, vec![0, 0, 200, 255, 0, 200, 0, 100, 9, 9, 9, 0]).unwrap();
        assert_eq!(mix_rgba(&a, &b, 0.0).as_raw()[..8], a.as_raw()[..8]);
        assert_eq!(mix_rgba(&a, &b, 1.0).as_raw()[..8], b.as_raw()[..8]);
        let half = mix_rgba(&a, &b, 0.5);
        // Opaque to opaque: the colours' mean; a colour fading in from
        // nothing keeps its colour, at half its coverage; none stays none.
        assert_eq!(
            half.as_raw(),
            &[100, 0, 100, 255, 0, 200, 0, 50, 0, 0, 0, 0]
        );
        let ga = GrayImage::from_raw(2, 1, vec![0, 255]).unwrap();
        let gb = GrayImage::from_raw(2, 1, vec![255, 55]).unwrap();
        assert_eq!(lerp_bytes(&ga, &gb, 0.25), [64, 205]);
        let layer = Layer {
            name: "moss".into(),
            kind: Some(Effect::Moss),
            blend: crate::stack::BlendMode::Normal,
            opacity: 0.5,
            visible: true,
            pixels: LayerPixels::Rgba(b.clone()),
        };
        // Against no layer at all: the layer faded in.
        let faded = mix_layers(&[], std::slice::from_ref(&layer), 0.5);
        match &faded[0].pixels {
            LayerPixels::Rgba(img) => {
                assert_eq!(img.as_raw()[..8], [0, 0, 200, 128, 0, 200, 0, 50])
            }
            LayerPixels::Tint { .. } | LayerPixels::Painted { .. } => panic!("not RGBA"),
        }
        assert!(mix_layers(&[], &[], 0.5).is_empty());
    }
}
