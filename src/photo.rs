//! The input photo: pixels at their original depth, plus colour profile.

use image::DynamicImage;

/// A photo with EXIF orientation applied, normalised to RGB or RGBA at 8 or
/// 16 bits per channel. Greyscale inputs become RGB; float inputs become
/// 16-bit.
#[derive(Debug, Clone)]
pub struct Photo {
    image: DynamicImage,
    /// ICC colour profile of the source, written back on output where the
    /// format allows.
    pub icc: Option<Vec<u8>>,
}

impl Photo {
    /// Wraps an image, converting it to one of the four supported layouts.
    pub fn new(image: DynamicImage) -> Photo {
        let image = match image {
            DynamicImage::ImageRgb8(_)
            | DynamicImage::ImageRgba8(_)
            | DynamicImage::ImageRgb16(_)
            | DynamicImage::ImageRgba16(_) => image,
            DynamicImage::ImageLuma8(_) => DynamicImage::ImageRgb8(image.to_rgb8()),
            DynamicImage::ImageLumaA8(_) => DynamicImage::ImageRgba8(image.to_rgba8()),
            DynamicImage::ImageLuma16(_) => DynamicImage::ImageRgb16(image.to_rgb16()),
            other if other.color().has_alpha() => DynamicImage::ImageRgba16(other.to_rgba16()),
            other => DynamicImage::ImageRgb16(other.to_rgb16()),
        };
        Photo { image, icc: None }
    }

    /// The pixels.
    pub fn image(&self) -> &DynamicImage {
        &self.image
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.image.width()
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.image.height()
    }

    /// True when the photo has 16 bits per channel.
    pub fn is_16bit(&self) -> bool {
        matches!(
            self.image,
            DynamicImage::ImageRgb16(_) | DynamicImage::ImageRgba16(_)
        )
    }

    /// Luma B(p) in 0..255 (Rec. 601 weights) of row `y`, written to `out`
    /// (length = width).
    pub fn luma_row(&self, y: u32, out: &mut [f32]) {
        self.each_in_row(y, |x, [r, g, b], scale| {
            if let Some(o) = out.get_mut(x) {
                *o = (0.299 * r + 0.587 * g + 0.114 * b) * scale;
            }
        });
    }

    /// Row `y` as R, G and B in 0..255, written to `out` (length = width).
    pub fn rgb_row(&self, y: u32, out: &mut [[f32; 3]]) {
        self.each_in_row(y, |x, [r, g, b], scale| {
            if let Some(o) = out.get_mut(x) {
                *o = [r * scale, g * scale, b * scale];
            }
        });
    }

    /// Calls `f(x, [r, g, b], scale)` for each pixel of row `y`, with the
    /// channels as stored and the scale that takes them to 0..255.
    fn each_in_row(&self, y: u32, mut f: impl FnMut(usize, [f32; 3], f32)) {
        fn walk<T: Copy + Into<f32>>(
            row: &[T],
            channels: usize,
            scale: f32,
            f: &mut impl FnMut(usize, [f32; 3], f32),
        ) {
            for (x, p) in row.chunks_exact(channels).enumerate() {
                f(x, [p[0].into(), p[1].into(), p[2].into()], scale);
            }
        }
        let w = self.width() as usize;
        let y = y as usize;
        match &self.image {
            DynamicImage::ImageRgb8(i) => {
                walk(&i.as_raw()[y * w * 3..(y + 1) * w * 3], 3, 1.0, &mut f)
            }
            DynamicImage::ImageRgba8(i) => {
                walk(&i.as_raw()[y * w * 4..(y + 1) * w * 4], 4, 1.0, &mut f)
            }
            DynamicImage::ImageRgb16(i) => walk(
                &i.as_raw()[y * w * 3..(y + 1) * w * 3],
                3,
                1.0 / 257.0,
                &mut f,
            ),
            DynamicImage::ImageRgba16(i) => walk(
                &i.as_raw()[y * w * 4..(y + 1) * w * 4],
                4,
                1.0 / 257.0,
                &mut f,
            ),
            _ => unreachable!("Photo::new normalises the layout"),
        }
    }

    /// The colour at `(x, y)`, 0..255 per channel.
    pub fn rgb_at(&self, x: u32, y: u32) -> [f32; 3] {
        match &self.image {
            DynamicImage::ImageRgb8(i) => i.get_pixel(x, y).0.map(f32::from),
            DynamicImage::ImageRgba8(i) => {
                let [r, g, b, _] = i.get_pixel(x, y).0;
                [r, g, b].map(f32::from)
            }
            DynamicImage::ImageRgb16(i) => i.get_pixel(x, y).0.map(|v| f32::from(v) / 257.0),
            DynamicImage::ImageRgba16(i) => {
                let [r, g, b, _] = i.get_pixel(x, y).0;
                [r, g, b].map(|v| f32::from(v) / 257.0)
            }
            _ => unreachable!("Photo::new normalises the layout"),
        }
    }

    /// Consumes the photo, returning its pixels.
    pub fn into_image(self) -> DynamicImage {
        self.image
    }
}
