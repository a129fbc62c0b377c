//! Perspective adjustment (Endo et al.): the rain runs in the wall's own
//! plane, so streaks follow the wall's vertical and shrink with distance.
//!
//! The user drags a quadrilateral onto the photo whose corners are the
//! corners of a rectangle on the wall (top-left, top-right, bottom-right,
//! bottom-left). A homography maps a `W` x `H` rectangle onto it. grime
//! resamples the photo and the region into that rectangle ("rectifies"),
//! runs the effects there ([`crate::pipeline::run`] does, for a scene with a
//! quad), and warps every layer back onto the photo.
//! Pixels outside the quad (or outside the region) get zero coverage, so
//! they are left byte-identical by compositing.
//!
//! Coordinates are continuous photo pixels: pixel `(x, y)` covers
//! `[x, x+1) x [y, y+1)` and its centre is `(x + 0.5, y + 0.5)`, so a quad
//! on the image's corners `(0,0) (w,0) (w,h) (0,h)` is the identity.

use image::{DynamicImage, GrayImage, Luma, Rgb, RgbImage, Rgba, RgbaImage};
use imageproc::geometric_transformations::Projection;
use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::photo::Photo;
use crate::stack::{Layer, LayerPixels};

/// Four corners in photo pixels: top-left, top-right, bottom-right,
/// bottom-left of a rectangle on the wall.
pub type Quad = [[f32; 2]; 4];

/// Parses `x1,y1,x2,y2,x3,y3,x4,y4` (photo pixels; top-left, top-right,
/// bottom-right, bottom-left) and checks it with [`validate`].
///
/// ```
/// let q = grime::perspective::parse_quad("0,0, 100,10, 100,90, 0,100").unwrap();
/// assert_eq!(q[2], [100.0, 90.0]);
/// assert!(grime::perspective::parse_quad("0,0,1,1").is_err());
/// ```
///
/// # Errors
/// [`Error::OutOfRange`] naming `quad` for anything but eight numbers
/// making a valid quad.
pub fn parse_quad(text: &str) -> Result<Quad> {
    let bad = || {
        Error::OutOfRange {
        field: "quad".into(),
        value: format!("{text:?}"),
        range: "eight numbers x1,y1,...,x4,y4: the corners top-left, top-right, bottom-right, bottom-left in photo pixels".into(),
    }
    };
    let v: Vec<f32> = text
        .split(',')
        .map(|t| t.trim().parse::<f32>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| bad())?;
    let [x1, y1, x2, y2, x3, y3, x4, y4] = v[..] else {
        return Err(bad());
    };
    let quad = [[x1, y1], [x2, y2], [x3, y3], [x4, y4]];
    validate(&quad)?;
    Ok(quad)
}

/// Checks that a quad is finite, convex, not degenerate and ordered
/// clockwise on screen (top-left, top-right, bottom-right, bottom-left).
///
/// # Errors
/// [`Error::OutOfRange`] naming `quad` and what a valid one looks like.
pub fn validate(quad: &Quad) -> Result<()> {
    let bad = |why: &str| Error::OutOfRange {
        field: "quad".into(),
        value: format!("{quad:?}"),
        range: format!(
            "a convex quadrilateral given top-left, top-right, bottom-right, bottom-left ({why})"
        ),
    };
    if quad.iter().flatten().any(|c| !c.is_finite()) {
        return Err(bad("a corner is not a finite number"));
    }
    for i in 0..4 {
        let (a, b, c) = (quad[i], quad[(i + 1) % 4], quad[(i + 2) % 4]);
        let cross = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]);
        if cross <= 0.0 {
            return Err(bad("corners cross over or are out of order"));
        }
    }
    if area(quad) < 16.0 {
        return Err(bad("it is smaller than 4 x 4 pixels"));
    }
    Ok(())
}

/// Area of a quad in square pixels (shoelace formula).
pub fn area(quad: &Quad) -> f32 {
    let mut s = 0.0;
    for i in 0..4 {
        let (a, b) = (quad[i], quad[(i + 1) % 4]);
        s += a[0] * b[1] - b[0] * a[1];
    }
    s.abs() / 2.0
}

/// The homography between a quad on the photo and its rectified rectangle.
#[derive(Debug, Clone, Copy)]
pub struct Rectifier {
    /// Rectangle to photo.
    to_photo: Projection,
    /// Photo to rectangle.
    to_rect: Projection,
    /// Width of the rectified wall, pixels.
    pub width: u32,
    /// Height of the rectified wall, pixels.
    pub height: u32,
}

impl Rectifier {
    /// The rectifier for `quad`. The rectangle is as wide as the quad's
    /// longer horizontal edge and as tall as its longer vertical edge, scaled
    /// down if needed to at most `max_pixels` pixels.
    ///
    /// # Errors
    /// As [`validate`], or [`Error::OutOfRange`] when no homography exists.
    pub fn new(quad: &Quad, max_pixels: u64) -> Result<Rectifier> {
        validate(quad)?;
        let len = |a: [f32; 2], b: [f32; 2]| ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt();
        let mut w = len(quad[0], quad[1]).max(len(quad[3], quad[2]));
        let mut h = len(quad[0], quad[3]).max(len(quad[1], quad[2]));
        let pixels = (w as f64 * h as f64).max(1.0);
        if pixels > max_pixels.max(16) as f64 {
            let s = (max_pixels.max(16) as f64 / pixels).sqrt() as f32;
            w *= s;
            h *= s;
        }
        let (width, height) = ((w.round() as u32).max(2), (h.round() as u32).max(2));
        let (fw, fh) = (width as f32, height as f32);
        let from = [(0.0, 0.0), (fw, 0.0), (fw, fh), (0.0, fh)];
        let to = quad.map(|p| (p[0], p[1]));
        let to_photo =
            Projection::from_control_points(from, to).ok_or_else(|| Error::OutOfRange {
                field: "quad".into(),
                value: format!("{quad:?}"),
                range: "four corners no three of which lie on a line".into(),
            })?;
        Ok(Rectifier {
            to_photo,
            to_rect: to_photo.invert(),
            width,
            height,
        })
    }

    /// A rectangle point to the photo.
    pub fn rect_to_photo(&self, x: f32, y: f32) -> (f32, f32) {
        self.to_photo * (x, y)
    }

    /// A photo point to the rectangle, or `None` when it lies outside it.
    pub fn photo_to_rect(&self, x: f32, y: f32) -> Option<(f32, f32)> {
        let (u, v) = self.to_rect * (x, y);
        let inside = u >= 0.0 && v >= 0.0 && u <= self.width as f32 && v <= self.height as f32;
        inside.then_some((u, v))
    }

    /// A photo point to the rectangle's coordinates, even outside it.
    pub fn photo_to_rect_unbounded(&self, x: f32, y: f32) -> (f32, f32) {
        self.to_rect * (x, y)
    }

    /// The photo resampled into the rectangle (8-bit RGB; black outside the
    /// photo). Only the wall's luminance is read from it.
    pub fn rectify_photo(&self, photo: &Photo) -> Photo {
        let rgb: std::borrow::Cow<RgbImage> = match photo.image() {
            DynamicImage::ImageRgb8(img) => std::borrow::Cow::Borrowed(img),
            other => std::borrow::Cow::Owned(other.to_rgb8()),
        };
        Photo::new(DynamicImage::ImageRgb8(self.rectify_rgb(&rgb)))
    }

    /// An RGB image (photo, normal map) resampled into the rectangle.
    pub fn rectify_rgb(&self, rgb: &RgbImage) -> RgbImage {
        let mut out = RgbImage::new(self.width, self.height);
        let w = self.width as usize;
        out.par_chunks_mut(w * 3).enumerate().for_each(|(y, row)| {
            for (x, px) in row.chunks_exact_mut(3).enumerate() {
                let (px_x, px_y) = self.rect_to_photo(x as f32 + 0.5, y as f32 + 0.5);
                if let Some(v) = sample_rgb(rgb, px_x, px_y) {
                    px.copy_from_slice(&v.0);
                }
            }
        });
        out
    }

    /// The region resampled into the rectangle: the mask where the quad lies
    /// on the photo (all wall without a mask), 0 where it lies off it.
    pub fn rectify_mask(&self, mask: Option<&GrayImage>, photo_w: u32, photo_h: u32) -> GrayImage {
        let mut out = GrayImage::new(self.width, self.height);
        let w = self.width as usize;
        out.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
            for (x, px) in row.iter_mut().enumerate() {
                let (px_x, px_y) = self.rect_to_photo(x as f32 + 0.5, y as f32 + 0.5);
                let on_photo =
                    px_x >= 0.0 && px_y >= 0.0 && px_x <= photo_w as f32 && px_y <= photo_h as f32;
                *px = match mask {
                    _ if !on_photo => 0,
                    None => 255,
                    Some(m) => {
                        sample_gray(m, px_x, px_y).map_or(0, |v| v.round().clamp(0.0, 255.0) as u8)
                    }
                };
            }
        });
        out
    }

    /// A rectified layer warped back onto a `photo_w` x `photo_h` photo.
    /// Coverage is zero outside the quad and where `mask` is zero.
    pub fn unrectify_layer(
        &self,
        layer: &Layer,
        photo_w: u32,
        photo_h: u32,
        mask: Option<&GrayImage>,
    ) -> Layer {
        let keep =
            |x: usize, y: usize| mask.is_none_or(|m| m.as_raw()[y * photo_w as usize + x] > 0);
        let pixels = match &layer.pixels {
            LayerPixels::Tint { color, alpha } => {
                let mut out = GrayImage::new(photo_w, photo_h);
                out.par_chunks_mut(photo_w as usize)
                    .enumerate()
                    .for_each(|(y, row)| {
                        for (x, px) in row.iter_mut().enumerate() {
                            if !keep(x, y) {
                                continue;
                            }
                            if let Some((u, v)) = self.photo_to_rect(x as f32 + 0.5, y as f32 + 0.5)
                            {
                                *px = sample_gray(alpha, u, v)
                                    .map_or(0, |a| a.round().clamp(0.0, 255.0) as u8);
                            }
                        }
                    });
                LayerPixels::Tint {
                    color: *color,
                    alpha: out,
                }
            }
            // A per-pixel colour map is unrectified with its layer's alpha.
            LayerPixels::Rgba(_) | LayerPixels::Painted { .. } => {
                let painted;
                let img = match &layer.pixels {
                    LayerPixels::Rgba(img) => img,
                    _ => {
                        painted = layer.to_rgba();
                        &painted
                    }
                };
                let mut out = RgbaImage::new(photo_w, photo_h);
                out.par_chunks_mut(photo_w as usize * 4)
                    .enumerate()
                    .for_each(|(y, row)| {
                        for (x, px) in row.chunks_exact_mut(4).enumerate() {
                            if !keep(x, y) {
                                continue;
                            }
                            if let Some((u, v)) = self.photo_to_rect(x as f32 + 0.5, y as f32 + 0.5)
                                && let Some(p) = sample_rgba(img, u, v)
                            {
                                px.copy_from_slice(&p.0);
                            }
                        }
                    });
                LayerPixels::Rgba(out)
            }
        };
        Layer {
            name: layer.name.clone(),
            kind: layer.kind,
            blend: layer.blend,
            opacity: layer.opacity,
            visible: layer.visible,
            pixels,
        }
    }
}

/// Bilinear sampling weights at continuous point `(x, y)` of a `w` x `h`
/// image, clamped at the border; `None` outside the image.
fn taps(w: u32, h: u32, x: f32, y: f32) -> Option<[(usize, f32); 4]> {
    if !(x >= 0.0 && y >= 0.0 && x <= w as f32 && y <= h as f32) || w == 0 || h == 0 {
        return None;
    }
    let u = (x - 0.5).clamp(0.0, (w - 1) as f32);
    let v = (y - 0.5).clamp(0.0, (h - 1) as f32);
    let (x0, y0) = (u.floor() as usize, v.floor() as usize);
    let (x1, y1) = ((x0 + 1).min(w as usize - 1), (y0 + 1).min(h as usize - 1));
    let (tx, ty) = (u - x0 as f32, v - y0 as f32);
    let w = w as usize;
    Some([
        (y0 * w + x0, (1.0 - tx) * (1.0 - ty)),
        (y0 * w + x1, tx * (1.0 - ty)),
        (y1 * w + x0, (1.0 - tx) * ty),
        (y1 * w + x1, tx * ty),
    ])
}

fn sample_gray(img: &GrayImage, x: f32, y: f32) -> Option<f32> {
    let raw = img.as_raw();
    taps(img.width(), img.height(), x, y).map(|t| t.iter().map(|&(i, k)| raw[i] as f32 * k).sum())
}

fn sample_rgb(img: &RgbImage, x: f32, y: f32) -> Option<Rgb<u8>> {
    let raw = img.as_raw();
    let t = taps(img.width(), img.height(), x, y)?;
    let mut out = [0u8; 3];
    for (c, o) in out.iter_mut().enumerate() {
        let v: f32 = t.iter().map(|&(i, k)| raw[i * 3 + c] as f32 * k).sum();
        *o = v.round().clamp(0.0, 255.0) as u8;
    }
    Some(Rgb(out))
}

/// Premultiplied bilinear sampling, so transparent neighbours do not bleed
/// their colour in.
fn sample_rgba(img: &RgbaImage, x: f32, y: f32) -> Option<Rgba<u8>> {
    let raw = img.as_raw();
    let t = taps(img.width(), img.height(), x, y)?;
    let a: f32 = t.iter().map(|&(i, k)| raw[i * 4 + 3] as f32 * k).sum();
    if a < 0.5 {
        return None;
    }
    let mut out = [0u8; 4];
    for (c, o) in out.iter_mut().take(3).enumerate() {
        let v: f32 = t
            .iter()
            .map(|&(i, k)| raw[i * 4 + c] as f32 * raw[i * 4 + 3] as f32 * k)
            .sum();
        *o = (v / a).round().clamp(0.0, 255.0) as u8;
    }
    out[3] = a.round().clamp(0.0, 255.0) as u8;
    Some(Rgba(out))
}

/// A photo-sized mask of the quad's inside (255) for display and tests.
pub fn quad_mask(quad: &Quad, w: u32, h: u32) -> Result<GrayImage> {
    let rect = Rectifier::new(quad, 1 << 20)?;
    Ok(GrayImage::from_fn(w, h, |x, y| {
        Luma([
            if rect.photo_to_rect(x as f32 + 0.5, y as f32 + 0.5).is_some() {
                255
            } else {
                0
            },
        ])
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::demo;
    use crate::pipeline::{self, Scene};
    use crate::preset::Preset;
    use crate::progress::Progress;

    /// The pipeline on `scene` in the wall plane of `quad`.
    fn in_plane(scene: &Scene, quad: Quad, preset: &Preset) -> pipeline::Outcome {
        let scene = scene.clone().with_quad(Some(quad)).unwrap();
        pipeline::run(&scene, preset, &Progress::none()).unwrap()
    }

    fn small_preset(lines: Vec<Vec<[f32; 2]>>) -> Preset {
        let mut p = Preset::default();
        p.rain.layers = 2;
        p.rain.droplets = 150;
        p.rain.source_lines = lines;
        p
    }

    #[test]
    fn corners_map_onto_the_quad() {
        let quad = [[10.0, 20.0], [90.0, 5.0], [95.0, 80.0], [5.0, 70.0]];
        let r = Rectifier::new(&quad, 1 << 20).unwrap();
        let (w, h) = (r.width as f32, r.height as f32);
        for (c, q) in [(0.0, 0.0), (w, 0.0), (w, h), (0.0, h)].iter().zip(quad) {
            let p = r.rect_to_photo(c.0, c.1);
            assert!(
                (p.0 - q[0]).abs() < 1e-2 && (p.1 - q[1]).abs() < 1e-2,
                "{p:?} vs {q:?}"
            );
        }
        assert!(r.photo_to_rect(50.0, 40.0).is_some());
        assert!(r.photo_to_rect(1.0, 1.0).is_none());
    }

    #[test]
    fn bad_quads_are_refused_with_a_clear_error() {
        let crossed = [[0.0, 0.0], [10.0, 10.0], [10.0, 0.0], [0.0, 10.0]];
        let err = validate(&crossed).unwrap_err().to_string();
        assert!(err.contains("quad") && err.contains("convex"), "{err}");
        let mirrored = [[10.0, 0.0], [0.0, 0.0], [0.0, 10.0], [10.0, 10.0]];
        assert!(validate(&mirrored).is_err());
        assert!(
            validate(&[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]).is_err(),
            "too small"
        );
        assert!(validate(&[[f32::NAN, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]]).is_err());
    }

    #[test]
    fn whole_image_quad_is_the_identity() {
        let d = demo::facade(160, 120);
        let scene = Scene::new(d.photo, d.region).unwrap();
        let preset = small_preset(d.source_lines);
        let plain = pipeline::run(&scene, &preset, &Progress::none()).unwrap();
        let quad = [[0.0, 0.0], [160.0, 0.0], [160.0, 120.0], [0.0, 120.0]];
        let warped = in_plane(&scene, quad, &preset);
        assert_eq!(plain.stack.layers.len(), warped.stack.layers.len());
        for (la, lb) in plain.stack.layers.iter().zip(&warped.stack.layers) {
            let (a, b) = (la.to_rgba(), lb.to_rgba());
            // Colour under zero coverage is invisible: compare what shows.
            let worst = a
                .pixels()
                .zip(b.pixels())
                .filter(|(p, q)| p[3] > 1 || q[3] > 1)
                .map(|(p, q)| (0..4).map(|c| p[c].abs_diff(q[c])).max().unwrap_or(0))
                .max()
                .unwrap_or(0);
            assert!(worst <= 1, "layer {} differs by {worst}", la.name);
        }
        assert!(plain.stack.layers[0].coverage() > 0.0);
    }

    #[test]
    fn nothing_outside_the_quad_changes() {
        let d = demo::facade(160, 120);
        let scene = Scene::new(d.photo, None).unwrap();
        let quad = [[40.0, 20.0], [120.0, 30.0], [118.0, 100.0], [42.0, 110.0]];
        let mut preset = small_preset(vec![vec![[40.0, 40.0], [120.0, 45.0]]]);
        preset.stain.strength = 3.0;
        let out = in_plane(&scene, quad, &preset);
        let composite = out.stack.composite().to_rgb8();
        let base = scene.photo.image().to_rgb8();
        let inside = quad_mask(&quad, 160, 120).unwrap();
        let mut changed_inside = 0;
        for (x, y, p) in composite.enumerate_pixels() {
            if inside.get_pixel(x, y)[0] == 0 {
                assert_eq!(
                    p,
                    base.get_pixel(x, y),
                    "pixel {x},{y} outside the quad changed"
                );
            } else if p != base.get_pixel(x, y) {
                changed_inside += 1;
            }
        }
        assert!(
            changed_inside > 50,
            "only {changed_inside} pixels changed inside"
        );
        assert_eq!(out.report.image.width, 160);
    }

    #[test]
    fn streaks_follow_the_walls_vertical() {
        // A quad leaning right: the wall's vertical runs from (40,10) down to
        // (70,110). The centre of mass of the stain should drift right as it
        // goes down.
        let d = demo::facade(160, 120);
        let scene = Scene::new(d.photo, None).unwrap();
        let quad = [[40.0, 10.0], [100.0, 10.0], [130.0, 110.0], [70.0, 110.0]];
        let mut preset = small_preset(vec![vec![[45.0, 14.0], [95.0, 14.0]]]);
        preset.rain.top_edge = false;
        preset.rain.layers = 1;
        preset.stain.strength = 3.0;
        // The geometry alone: water leaves anywhere along the ledge and
        // its streaks do not fade.
        preset.rain.drip_spacing_m = 0.0;
        preset.rain.end_share = 0.0;
        preset.rain.fall_m = 0.0;
        preset.stain.wall_hue = 0.0;
        let out = in_plane(&scene, quad, &preset);
        let LayerPixels::Tint { alpha, .. } = &out.stack.layers[0].pixels else {
            panic!("tint")
        };
        let centre = |y0: u32, y1: u32| {
            let (mut s, mut n) = (0.0, 0.0);
            for y in y0..y1 {
                for x in 0..160 {
                    let a = alpha.get_pixel(x, y)[0] as f64;
                    s += a * x as f64;
                    n += a;
                }
            }
            s / n.max(1e-9)
        };
        let (top, low) = (centre(15, 40), centre(60, 100));
        assert!(
            low > top + 5.0,
            "stain centre {top:.1} at the top, {low:.1} lower down"
        );
    }
}
