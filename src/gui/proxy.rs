//! The preview proxy: the photo and mask scaled down to about 1 MP, the
//! mapping from photo pixels to it, and the preview job it makes.

use std::collections::BTreeMap;
use std::sync::Arc;

use image::GrayImage;

use crate::error::Result;
use crate::perspective::Quad;
use crate::photo::Photo;
use crate::pipeline::{Scene, Site};
use crate::preset::Preset;

use super::render::PreviewJob;
use super::state::LayerSetting;
use super::tools::PixelRect;

/// Pixels of the preview proxy (about 1 MP).
pub const PROXY_PIXELS: u64 = 1_000_000;

/// The photo and mask scaled down for previews, and the mapping to them.
#[derive(Debug, Clone)]
pub struct Proxy {
    /// Proxy pixels per photo pixel, horizontally.
    pub sx: f32,
    /// Proxy pixels per photo pixel, vertically.
    pub sy: f32,
    /// The scaled photo (the photo itself when it is small enough).
    pub photo: Arc<Photo>,
    /// The scaled mask, area-averaged. Shared with the preview jobs, and
    /// copied only when it changes while a job holds it, so the pipeline's
    /// cache ([`Scene::same_as`]) sees the same mask until it changes.
    pub mask: Arc<GrayImage>,
    /// The building around the wall at the proxy's size, once the scene
    /// analysis has seen it (`None`: the assumed site).
    pub site: Option<Site>,
}

impl Proxy {
    /// The proxy of `photo` with at most `max_pixels` pixels.
    pub fn new(photo: &Arc<Photo>, mask: &GrayImage, max_pixels: u64) -> Proxy {
        let (w, h) = (photo.width(), photo.height());
        let s = (max_pixels as f64 / (w as f64 * h as f64)).sqrt().min(1.0);
        if s >= 1.0 {
            return Proxy {
                sx: 1.0,
                sy: 1.0,
                photo: Arc::clone(photo),
                mask: Arc::new(mask.clone()),
                site: None,
            };
        }
        let (pw, ph) = (
            ((w as f64 * s).round() as u32).max(1),
            ((h as f64 * s).round() as u32).max(1),
        );
        let img = photo
            .image()
            .resize_exact(pw, ph, image::imageops::FilterType::Triangle);
        let mut small = Photo::new(img);
        small.icc = photo.icc.clone();
        let mut proxy = Proxy {
            sx: pw as f32 / w as f32,
            sy: ph as f32 / h as f32,
            photo: Arc::new(small),
            mask: Arc::new(GrayImage::new(pw, ph)),
            site: None,
        };
        proxy.update_mask(mask, PixelRect::full(w, h));
        proxy
    }

    /// True when the proxy is the photo itself.
    pub fn is_full_size(&self) -> bool {
        self.sx == 1.0 && self.sy == 1.0
    }

    /// Re-samples the proxy mask where the photo mask changed (`rect`, photo
    /// pixels). Returns the proxy pixels that were updated.
    pub fn update_mask(&mut self, full: &GrayImage, rect: PixelRect) -> Option<PixelRect> {
        let (pw, ph) = self.mask.dimensions();
        let (w, h) = full.dimensions();
        let (sx, sy) = (self.sx, self.sy);
        let full_size = self.is_full_size();
        let mask = Arc::make_mut(&mut self.mask);
        let r = PixelRect::around(
            rect.x0 as f32 * sx,
            rect.y0 as f32 * sy,
            rect.x1 as f32 * sx,
            rect.y1 as f32 * sy,
            pw,
            ph,
        )?;
        if full_size {
            for y in r.y0..r.y1 {
                let s = (y * w + r.x0) as usize;
                let e = s + r.width() as usize;
                mask.as_mut()[s..e].copy_from_slice(&full.as_raw()[s..e]);
            }
            return Some(r);
        }
        let span = |p: u32, s: f32, max: u32| {
            let a = ((p as f32 / s) as u32).min(max - 1);
            let b = (((p + 1) as f32 / s).ceil() as u32).clamp(a + 1, max);
            (a, b)
        };
        let raw = full.as_raw();
        for py in r.y0..r.y1 {
            let (ya, yb) = span(py, sy, h);
            for px in r.x0..r.x1 {
                let (xa, xb) = span(px, sx, w);
                let mut sum = 0u64;
                for y in ya..yb {
                    let row = &raw[(y * w + xa) as usize..(y * w + xb) as usize];
                    sum += row.iter().map(|&v| v as u64).sum::<u64>();
                }
                let n = ((yb - ya) * (xb - xa)) as u64;
                mask.put_pixel(px, py, image::Luma([((sum + n / 2) / n) as u8]));
            }
        }
        Some(r)
    }

    /// A photo point on the proxy.
    pub fn to_proxy(&self, p: [f32; 2]) -> [f32; 2] {
        [p[0] * self.sx, p[1] * self.sy]
    }

    /// The preview job for a document's state: the proxy's photo and mask
    /// (shared, not copied) with the quad, and the preset
    /// ([`Preset::scaled`]: its source lines, sources and placements), in
    /// proxy pixels.
    ///
    /// # Errors
    /// [`Scene::with_quad`]'s errors for a bad quad.
    pub fn job(
        &self,
        preset: &Preset,
        quad: Option<&Quad>,
        layers: &BTreeMap<String, LayerSetting>,
    ) -> Result<PreviewJob> {
        let preset = preset.scaled(self.sx, self.sy);
        let mut scene = Scene::shared(Arc::clone(&self.photo), Some(Arc::clone(&self.mask)))?
            .with_quad(quad.map(|q| q.map(|p| self.to_proxy(p))))?;
        if let Some(site) = &self.site {
            scene = scene.with_site(site.clone())?;
        }
        Ok(PreviewJob {
            scene,
            preset,
            layers: layers.clone(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::DynamicImage;

    #[test]
    fn proxy_is_about_one_megapixel_and_averages_the_mask() {
        let photo = Arc::new(Photo::new(DynamicImage::ImageRgb8(image::RgbImage::new(
            3000, 2000,
        ))));
        let mut mask = GrayImage::new(3000, 2000);
        for y in 0..2000 {
            for x in 0..1500 {
                mask.put_pixel(x, y, image::Luma([255]));
            }
        }
        let p = Proxy::new(&photo, &mask, PROXY_PIXELS);
        let (w, h) = (p.photo.width(), p.photo.height());
        assert!(
            (w * h) as f64 / 1e6 > 0.95 && (w * h) as f64 / 1e6 < 1.05,
            "{w}x{h}"
        );
        assert_eq!(p.mask.dimensions(), (w, h));
        assert_eq!(p.mask.get_pixel(10, 10)[0], 255);
        assert_eq!(p.mask.get_pixel(w - 10, 10)[0], 0);
        let mid = p.mask.get_pixel(w / 2, 10)[0];
        assert!(mid > 0, "edge is averaged: {mid}");
        assert_eq!(p.to_proxy([3000.0, 2000.0]), [w as f32, h as f32]);
        let small = Proxy::new(
            &Arc::new(Photo::new(DynamicImage::ImageRgb8(image::RgbImage::new(
                100, 80,
            )))),
            &GrayImage::new(100, 80),
            PROXY_PIXELS,
        );
        assert!(small.is_full_size());
    }
}
