//! Layers and how they combine: the result every front end shows and every
//! exporter writes.
//!
//! Blending follows the separable formulas of the W3C Compositing spec (the
//! ones Photoshop, GIMP's legacy modes, Krita and psd-tools use) on straight
//! (non-premultiplied) sRGB values, in floating point, rounded once at the
//! end. Over an opaque base, for a layer of colour `c`, alpha `a` and opacity
//! `o`:
//!
//! ```text
//! normal:   out = b + (c - b) * a * o
//! multiply: out = b + (b * c - b) * a * o
//! ```

use std::sync::Arc;

use image::{DynamicImage, GrayImage, ImageBuffer, RgbImage, Rgba, RgbaImage};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::effects::Effect;
use crate::photo::Photo;

/// How a layer combines with what is below it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum BlendMode {
    /// Paint over.
    Normal,
    /// Darken: base times layer colour.
    Multiply,
    /// Lighten: one minus the product of the inverses (the W3C `screen`).
    Screen,
}

impl BlendMode {
    /// Blends one channel, values in 0..1.
    #[inline]
    pub fn blend(self, base: f32, src: f32) -> f32 {
        match self {
            BlendMode::Normal => src,
            BlendMode::Multiply => base * src,
            BlendMode::Screen => base + src - base * src,
        }
    }
}

/// A layer's pixels, at photo size.
#[derive(Debug, Clone)]
pub enum LayerPixels {
    /// One colour everywhere; coverage varies per pixel (rain, granules).
    Tint {
        /// The colour, sRGB.
        color: [u8; 3],
        /// Coverage, 0 = transparent.
        alpha: GrayImage,
    },
    /// Colour and coverage per pixel, straight alpha (moss, dust film).
    Rgba(RgbaImage),
    /// Colour per pixel from a map layers share (the rain's deposit takes
    /// the local wall's hue in every rainfall), coverage per layer: the
    /// same pixels as an [`LayerPixels::Rgba`] of the map's colour and this
    /// alpha, a quarter of the memory per layer.
    Painted {
        /// The colour, sRGB, of the layer's size.
        color: Arc<RgbImage>,
        /// Coverage, 0 = transparent.
        alpha: GrayImage,
    },
}

/// One named layer of the stack.
#[derive(Debug, Clone)]
pub struct Layer {
    /// Name shown in editors ("rain 01", "moss", ...).
    pub name: String,
    /// The effect that made it; `None` for layers no effect made (the PSD's
    /// hidden region layer, layers built by hand).
    pub kind: Option<Effect>,
    /// Blend mode.
    pub blend: BlendMode,
    /// Opacity, 0..1.
    pub opacity: f32,
    /// Whether the layer takes part in the composite.
    pub visible: bool,
    /// The pixels.
    pub pixels: LayerPixels,
}

impl Layer {
    /// Width in pixels.
    pub fn width(&self) -> u32 {
        match &self.pixels {
            LayerPixels::Tint { alpha, .. } | LayerPixels::Painted { alpha, .. } => alpha.width(),
            LayerPixels::Rgba(img) => img.width(),
        }
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        match &self.pixels {
            LayerPixels::Tint { alpha, .. } | LayerPixels::Painted { alpha, .. } => alpha.height(),
            LayerPixels::Rgba(img) => img.height(),
        }
    }

    /// Straight-alpha RGBA of one pixel.
    pub fn rgba(&self, x: u32, y: u32) -> [u8; 4] {
        match &self.pixels {
            LayerPixels::Tint { color, alpha } => {
                [color[0], color[1], color[2], alpha.get_pixel(x, y)[0]]
            }
            LayerPixels::Rgba(img) => img.get_pixel(x, y).0,
            LayerPixels::Painted { color, alpha } => {
                let [r, g, b] = color.get_pixel(x, y).0;
                [r, g, b, alpha.get_pixel(x, y)[0]]
            }
        }
    }

    /// Writes row `y` as straight-alpha RGBA into `out` (4 bytes per pixel).
    pub fn rgba_row(&self, y: u32, out: &mut [u8]) {
        let w = self.width() as usize;
        let y = y as usize;
        match &self.pixels {
            LayerPixels::Tint { color, alpha } => {
                let row = &alpha.as_raw()[y * w..(y + 1) * w];
                for (o, &a) in out.chunks_exact_mut(4).zip(row) {
                    o.copy_from_slice(&[color[0], color[1], color[2], a]);
                }
            }
            LayerPixels::Rgba(img) => {
                out.copy_from_slice(&img.as_raw()[y * w * 4..(y + 1) * w * 4])
            }
            LayerPixels::Painted { color, alpha } => {
                let row = &alpha.as_raw()[y * w..(y + 1) * w];
                let rgb = &color.as_raw()[y * w * 3..(y + 1) * w * 3];
                for ((o, &a), c) in out.chunks_exact_mut(4).zip(row).zip(rgb.chunks_exact(3)) {
                    o.copy_from_slice(&[c[0], c[1], c[2], a]);
                }
            }
        }
    }

    /// The layer as a straight-alpha RGBA image.
    pub fn to_rgba(&self) -> RgbaImage {
        match &self.pixels {
            LayerPixels::Tint { color, alpha } => {
                RgbaImage::from_fn(alpha.width(), alpha.height(), |x, y| {
                    Rgba([color[0], color[1], color[2], alpha.get_pixel(x, y)[0]])
                })
            }
            LayerPixels::Rgba(img) => img.clone(),
            LayerPixels::Painted { color, alpha } => {
                RgbaImage::from_fn(alpha.width(), alpha.height(), |x, y| {
                    let [r, g, b] = color.get_pixel(x, y).0;
                    Rgba([r, g, b, alpha.get_pixel(x, y)[0]])
                })
            }
        }
    }

    /// Coverage of the whole layer: mean alpha in 0..1.
    pub fn coverage(&self) -> f64 {
        let (sum, n) = match &self.pixels {
            LayerPixels::Tint { alpha, .. } | LayerPixels::Painted { alpha, .. } => (
                alpha.as_raw().par_iter().map(|&a| a as u64).sum::<u64>(),
                alpha.as_raw().len(),
            ),
            LayerPixels::Rgba(img) => (
                img.as_raw()
                    .par_chunks_exact(4)
                    .map(|p| p[3] as u64)
                    .sum::<u64>(),
                img.as_raw().len() / 4,
            ),
        };
        sum as f64 / (255.0 * n.max(1) as f64)
    }
}

/// The photo and the effect layers above it, bottom to top.
#[derive(Debug, Clone)]
pub struct Stack {
    /// The original photo, the bottom layer.
    pub base: std::sync::Arc<Photo>,
    /// Effect layers, in stacking order (first = lowest).
    pub layers: Vec<Layer>,
    /// The wall region (255 = wall), if one was given.
    pub region: Option<std::sync::Arc<GrayImage>>,
}

impl Stack {
    /// Flattens the visible layers onto the photo, at the photo's bit depth;
    /// an alpha channel in the photo is kept as is.
    pub fn composite(&self) -> DynamicImage {
        let visible = shown(&self.layers.iter().collect::<Vec<_>>());
        flatten(&self.base, &visible, None)
    }
}

/// The layers that take part in a composite: visible, not fully transparent.
fn shown<'a>(layers: &[&'a Layer]) -> Vec<&'a Layer> {
    layers
        .iter()
        .copied()
        .filter(|l| l.visible && l.opacity > 0.0)
        .collect()
}

/// A composite built up from the bottom: the photo with the layers added so
/// far blended, unrounded. Stacks that share their lowest layers (the frames
/// of a time-lapse share the rainfalls so far) blend those once:
/// [`Partial::finish`] equals [`Stack::composite`] of a stack holding the
/// added layers and then its own, byte for byte (the same operations on the
/// same numbers, rounded once at the end).
#[derive(Debug, Clone)]
pub struct Partial {
    base: std::sync::Arc<Photo>,
    /// Levels in 0..1, the photo's channels per pixel (empty for a photo
    /// type the compositor leaves as is).
    acc: Vec<f32>,
    /// Whether a layer painted the pixel (the others keep the photo's value).
    touched: Vec<bool>,
}

impl Partial {
    /// The photo with no layer yet.
    pub fn new(base: &std::sync::Arc<Photo>) -> Partial {
        let acc = match base.image() {
            DynamicImage::ImageRgb8(img) => levels(img, 255.0),
            DynamicImage::ImageRgba8(img) => levels(img, 255.0),
            DynamicImage::ImageRgb16(img) => levels(img, 65535.0),
            DynamicImage::ImageRgba16(img) => levels(img, 65535.0),
            _ => Vec::new(),
        };
        let (w, h) = (base.image().width(), base.image().height());
        let touched = match acc.is_empty() {
            true => Vec::new(),
            false => vec![false; w as usize * h as usize],
        };
        Partial {
            base: std::sync::Arc::clone(base),
            acc,
            touched,
        }
    }

    /// Blends `layers` (the hidden ones skipped) over what is there.
    pub fn add(&mut self, layers: &[&Layer]) {
        let layers = shown(layers);
        let w = self.base.image().width() as usize;
        if self.acc.is_empty() || layers.is_empty() || w == 0 {
            return;
        }
        let channels = self.acc.len() / self.touched.len();
        self.acc
            .par_chunks_exact_mut(w * channels)
            .zip(self.touched.par_chunks_exact_mut(w))
            .enumerate()
            .for_each(|(y, (acc, touched))| blend_row(&layers, y, channels, acc, touched));
    }

    /// The composite with `layers` over the ones added, which stay as they are.
    pub fn finish(&self, layers: &[&Layer]) -> DynamicImage {
        let layers = shown(layers);
        let start = Some((self.acc.as_slice(), self.touched.as_slice()));
        flatten(&self.base, &layers, start)
    }
}

/// Every subpixel of `img` as a level in 0..1.
fn levels<P, T>(img: &ImageBuffer<P, Vec<T>>, full: f32) -> Vec<f32>
where
    P: image::Pixel<Subpixel = T>,
    T: Channel + image::Primitive,
{
    img.as_raw().par_iter().map(|v| v.level() / full).collect()
}

/// A subpixel type the compositor can read and write.
trait Channel: Copy + Send + Sync + 'static {
    fn level(self) -> f32;
    fn from_level(v: f32) -> Self;
}

impl Channel for u8 {
    fn level(self) -> f32 {
        self as f32
    }
    fn from_level(v: f32) -> Self {
        crate::round::to_u8(v)
    }
}

impl Channel for u16 {
    fn level(self) -> f32 {
        self as f32
    }
    fn from_level(v: f32) -> Self {
        crate::round::to_u16(v)
    }
}

/// One layer over one pixel (channels in 0..1): `b + (blend(b, c) - b) * a`.
#[inline]
fn blend_pixel(blend: impl Fn(f32, f32) -> f32, px: &mut [f32], c: [f32; 3], a: f32) {
    for (b, c) in px.iter_mut().zip(c) {
        *b += (blend(*b, c) - *b) * a;
    }
}

/// Blends `layers` over row `y`: `acc` holds its levels (`channels` per
/// pixel), `touched` whether a layer painted each pixel.
fn blend_row(layers: &[&Layer], y: usize, channels: usize, acc: &mut [f32], touched: &mut [bool]) {
    for layer in layers {
        // One loop per mode (the mode's formula inlined in it).
        let row = (*layer, y, channels, &mut *acc, &mut *touched);
        match layer.blend {
            BlendMode::Normal => blend_layer_row(row, |b, c| BlendMode::Normal.blend(b, c)),
            BlendMode::Multiply => blend_layer_row(row, |b, c| BlendMode::Multiply.blend(b, c)),
            BlendMode::Screen => blend_layer_row(row, |b, c| BlendMode::Screen.blend(b, c)),
        }
    }
}

/// One layer over row `y` (as [`blend_row`]), blending by `blend`.
#[inline]
fn blend_layer_row(
    (layer, y, channels, acc, touched): (&Layer, usize, usize, &mut [f32], &mut [bool]),
    blend: impl Fn(f32, f32) -> f32 + Copy,
) {
    let wu = touched.len();
    // Alpha byte to effective alpha, opacity included.
    let o = layer.opacity / 255.0;
    match &layer.pixels {
        LayerPixels::Tint { color, alpha } => {
            let c = color.map(|v| v as f32 / 255.0);
            let alpha = &alpha.as_raw()[y * wu..(y + 1) * wu];
            for (x, &a) in alpha.iter().enumerate().filter(|(_, a)| **a != 0) {
                touched[x] = true;
                let px = &mut acc[x * channels..x * channels + 3];
                blend_pixel(blend, px, c, a as f32 * o);
            }
        }
        LayerPixels::Rgba(img) => {
            let src = &img.as_raw()[y * wu * 4..(y + 1) * wu * 4];
            for (x, s) in src.chunks_exact(4).enumerate().filter(|(_, s)| s[3] != 0) {
                touched[x] = true;
                let c = [
                    s[0] as f32 / 255.0,
                    s[1] as f32 / 255.0,
                    s[2] as f32 / 255.0,
                ];
                let px = &mut acc[x * channels..x * channels + 3];
                blend_pixel(blend, px, c, s[3] as f32 * o);
            }
        }
        LayerPixels::Painted { color, alpha } => {
            let alpha = &alpha.as_raw()[y * wu..(y + 1) * wu];
            let rgb = &color.as_raw()[y * wu * 3..(y + 1) * wu * 3];
            for (x, &a) in alpha.iter().enumerate().filter(|(_, a)| **a != 0) {
                touched[x] = true;
                let s = &rgb[x * 3..x * 3 + 3];
                let c = [
                    s[0] as f32 / 255.0,
                    s[1] as f32 / 255.0,
                    s[2] as f32 / 255.0,
                ];
                let px = &mut acc[x * channels..x * channels + 3];
                blend_pixel(blend, px, c, a as f32 * o);
            }
        }
    }
}

/// `layers` over `base` (or over a partial composite `start` of it), at the
/// photo's bit depth; a photo type the compositor does not handle is kept.
fn flatten(base: &Photo, layers: &[&Layer], start: Option<(&[f32], &[bool])>) -> DynamicImage {
    match base.image() {
        DynamicImage::ImageRgb8(img) => {
            DynamicImage::ImageRgb8(composite_buffer(img, 3, 255.0, layers, start))
        }
        DynamicImage::ImageRgba8(img) => {
            DynamicImage::ImageRgba8(composite_buffer(img, 4, 255.0, layers, start))
        }
        DynamicImage::ImageRgb16(img) => {
            DynamicImage::ImageRgb16(composite_buffer(img, 3, 65535.0, layers, start))
        }
        DynamicImage::ImageRgba16(img) => {
            DynamicImage::ImageRgba16(composite_buffer(img, 4, 65535.0, layers, start))
        }
        other => other.clone(),
    }
}

/// `layers` over `base`, or over `start` (the levels and touched pixels of
/// a [`Partial`] made from `base`).
fn composite_buffer<P, T>(
    base: &ImageBuffer<P, Vec<T>>,
    channels: usize,
    full: f32,
    layers: &[&Layer],
    start: Option<(&[f32], &[bool])>,
) -> ImageBuffer<P, Vec<T>>
where
    P: image::Pixel<Subpixel = T>,
    T: Channel + image::Primitive,
{
    let (w, h) = base.dimensions();
    let row_len = w as usize * channels;
    let mut out = base.as_raw().clone();
    let wu = w as usize;
    out.par_chunks_exact_mut(row_len)
        .enumerate()
        .for_each(|(y, row)| {
            let (mut acc, mut touched): (Vec<f32>, Vec<bool>) = match start {
                None => (
                    row.iter().map(|v| v.level() / full).collect(),
                    vec![false; wu],
                ),
                Some((acc, touched)) => (
                    acc[y * row_len..(y + 1) * row_len].to_vec(),
                    touched[y * wu..(y + 1) * wu].to_vec(),
                ),
            };
            blend_row(layers, y, channels, &mut acc, &mut touched);
            for (x, _) in touched.iter().enumerate().filter(|(_, t)| **t) {
                for c in 0..3 {
                    row[x * channels + c] = T::from_level(acc[x * channels + c] * full);
                }
            }
        });
    ImageBuffer::from_raw(w, h, out).expect("same size as the base")
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::RgbImage;

    fn tint(alpha: u8, blend: BlendMode, color: [u8; 3], opacity: f32) -> Layer {
        Layer {
            name: "t".into(),
            kind: None,
            blend,
            opacity,
            visible: true,
            pixels: LayerPixels::Tint {
                color,
                alpha: GrayImage::from_pixel(2, 1, image::Luma([alpha])),
            },
        }
    }

    fn one(base: [u8; 3], layers: Vec<Layer>) -> [u8; 3] {
        let stack =
            Stack {
                base: std::sync::Arc::new(Photo::new(DynamicImage::ImageRgb8(
                    RgbImage::from_pixel(2, 1, image::Rgb(base)),
                ))),
                layers,
                region: None,
            };
        stack.composite().to_rgb8().get_pixel(0, 0).0
    }

    /// Plain reference: the W3C formula with one rounding at the end.
    fn reference(base: [u8; 3], l: &Layer) -> [u8; 3] {
        let s = l.rgba(0, 0);
        let a = s[3] as f32 / 255.0 * l.opacity;
        let mut out = [0u8; 3];
        for c in 0..3 {
            let b = base[c] as f32 / 255.0;
            let src = s[c] as f32 / 255.0;
            let blended = match l.blend {
                BlendMode::Normal => src,
                BlendMode::Multiply => b * src,
                BlendMode::Screen => 1.0 - (1.0 - b) * (1.0 - src),
            };
            out[c] = ((b * (1.0 - a) + blended * a) * 255.0).round() as u8;
        }
        out
    }

    #[test]
    fn transparent_layers_leave_base_exact() {
        let base = [13, 200, 77];
        assert_eq!(
            one(base, vec![tint(0, BlendMode::Multiply, [0, 0, 0], 1.0)]),
            base
        );
    }

    #[test]
    fn blends_match_reference_formula() {
        use proptest::prelude::*;
        let modes = [BlendMode::Normal, BlendMode::Multiply, BlendMode::Screen];
        proptest!(|(b in any::<[u8; 3]>(), c in any::<[u8; 3]>(), a in any::<u8>(), o in 0.0f32..=1.0, m in 0usize..3)| {
            let blend = modes[m];
            let l = tint(a, blend, c, o);
            let want = reference(b, &l);
            let got = one(b, vec![l]);
            for ch in 0..3 {
                prop_assert!((got[ch] as i32 - want[ch] as i32).abs() <= 1, "{got:?} vs {want:?}");
            }
        });
    }

    #[test]
    fn multiply_never_lightens() {
        let base = [120, 130, 140];
        let out = one(
            base,
            vec![tint(255, BlendMode::Multiply, [200, 255, 10], 1.0)],
        );
        assert!(out.iter().zip(base).all(|(o, b)| *o <= b));
        assert_eq!(out[1], 130, "white multiplies to no change");
    }

    #[test]
    fn a_partial_composite_finishes_as_the_whole_stack() {
        let (w, h) = (7, 5);
        let noise = |k: u32| move |x: u32, y: u32| ((x * 37 + y * 91 + k * 53) % 256) as u8;
        let base = RgbImage::from_fn(w, h, |x, y| {
            image::Rgb([noise(1)(x, y), noise(2)(x, y), noise(3)(x, y)])
        });
        let base = std::sync::Arc::new(Photo::new(DynamicImage::ImageRgb8(base)));
        let tint = |k: u32, blend| Layer {
            name: format!("t{k}"),
            kind: None,
            blend,
            opacity: 0.3 + 0.1 * k as f32,
            visible: k != 2,
            pixels: LayerPixels::Tint {
                color: [k as u8 * 40, 90, 200],
                alpha: GrayImage::from_fn(w, h, |x, y| {
                    image::Luma([if (x + y + k).is_multiple_of(3) {
                        0
                    } else {
                        noise(k)(x, y)
                    }])
                }),
            },
        };
        let rgba = Layer {
            name: "rgba".into(),
            kind: None,
            blend: BlendMode::Normal,
            opacity: 0.8,
            visible: true,
            pixels: LayerPixels::Rgba(RgbaImage::from_fn(w, h, |x, y| {
                Rgba([
                    noise(7)(x, y),
                    10,
                    250,
                    if x == 3 { 0 } else { noise(8)(x, y) },
                ])
            })),
        };
        let layers = vec![
            tint(0, BlendMode::Multiply),
            tint(1, BlendMode::Multiply),
            tint(2, BlendMode::Normal),
            rgba,
            tint(4, BlendMode::Normal),
        ];
        let whole = Stack {
            base: std::sync::Arc::clone(&base),
            layers: layers.clone(),
            region: None,
        }
        .composite();
        let refs: Vec<&Layer> = layers.iter().collect();
        for split in 0..=layers.len() {
            let mut partial = Partial::new(&base);
            // Added in two steps: the same as in one.
            partial.add(&refs[..split / 2]);
            partial.add(&refs[split / 2..split]);
            let got = partial.finish(&refs[split..]);
            assert_eq!(got.as_bytes(), whole.as_bytes(), "split at {split}");
            assert_eq!(partial.finish(&refs[split..]).as_bytes(), whole.as_bytes());
        }
        assert_ne!(whole.as_bytes(), base.image().as_bytes());
    }

    #[test]
    fn hidden_layers_are_skipped() {
        let base = [100, 100, 100];
        let mut l = tint(255, BlendMode::Normal, [0, 0, 0], 1.0);
        l.visible = false;
        assert_eq!(one(base, vec![l]), base);
    }
}
