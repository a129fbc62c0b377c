//! Layered OpenRaster documents (`.ora`) for GIMP, Krita and MyPaint,
//! following the OpenRaster 0.0.5 specification.
//!
//! The file is a zip whose entries are, in this order:
//!
//! 1. `mimetype`: `image/openraster`, stored uncompressed, so the bytes
//!    `mimetype` and `image/openraster` sit at offsets 30 and 38;
//! 2. `stack.xml`: the layers, **top first**, each with `name`, `src`, `x`,
//!    `y`, `opacity` (0..1), `visibility` (`visible`/`hidden`) and
//!    `composite-op` (`svg:src-over` for normal, `svg:multiply`);
//! 3. `data/*.png`: one RGBA PNG per layer at photo size (straight alpha);
//!    the bottom layer `photo` keeps the photo's bit depth and ICC profile
//!    (the sRGB profile when it has none: Krita asks which profile a 16-bit
//!    PNG without one has, which hangs `krita --export`);
//! 4. `mergedimage.png`: the flattened image ([`Stack::composite`]), 8-bit
//!    RGBA, with the same profile;
//! 5. `Thumbnails/thumbnail.png`: the same, at most 256 px per side.
//!
//! As in the PSD (see [`super::psd`]), the region is a hidden top layer
//! named `region`: white, the region as its alpha.

use std::io::Write;
use std::path::Path;

use image::codecs::png::{CompressionType, FilterType, PngEncoder};
use image::{DynamicImage, ImageEncoder};
use rayon::prelude::*;
use zip::CompressionMethod;
use zip::write::SimpleFileOptions;

use crate::error::{Error, Result};
use crate::io;
use crate::stack::{BlendMode, Stack};

use super::layers_dir::slug;
use super::psd::{PHOTO_LAYER, REGION_LAYER};

/// The `mimetype` entry's content.
pub const MIMETYPE: &str = "image/openraster";

/// Largest side of `Thumbnails/thumbnail.png`.
pub const THUMBNAIL_MAX: u32 = 256;

/// One `<layer>` of `stack.xml`, with its encoded PNG.
struct OraLayer {
    name: String,
    src: String,
    blend: BlendMode,
    opacity: f32,
    visible: bool,
    png: Vec<u8>,
}

/// Writes `stack` as an OpenRaster file to `path`, atomically (see
/// [`io::write_atomic`]).
///
/// # Errors
/// [`Error::Io`] when the folder is missing or the file cannot be written,
/// [`Error::Encode`] if a PNG cannot be encoded.
pub fn write(stack: &Stack, path: &Path) -> Result<()> {
    write_with(stack, path, None)
}

/// The archive entry holding the recipe ([`write_with`]).
pub const RECIPE_FILE: &str = "recipe.toml";

/// [`write`], with the recipe as [`RECIPE_FILE`] in the archive, named by
/// `stack.xml`'s `grime:recipe` attribute.
///
/// # Errors
/// As [`write`].
pub fn write_with(stack: &Stack, path: &Path, recipe: Option<&str>) -> Result<()> {
    let w = stack.base.width();
    let h = stack.base.height();
    let profile = stack.base.icc.as_deref().unwrap_or(io::icc::srgb());

    // Encode the layer PNGs in parallel, bottom first.
    enum What<'a> {
        Photo,
        Layer(usize, &'a crate::stack::Layer),
        Region(&'a image::GrayImage),
    }
    let mut jobs = vec![What::Photo];
    jobs.extend(
        stack
            .layers
            .iter()
            .enumerate()
            .map(|(i, l)| What::Layer(i, l)),
    );
    if let Some(r) = stack.region.as_deref() {
        jobs.push(What::Region(r));
    }
    let layers: Vec<OraLayer> = jobs
        .par_iter()
        .map(|job| -> Result<OraLayer> {
            Ok(match job {
                What::Photo => OraLayer {
                    name: PHOTO_LAYER.into(),
                    src: "data/00-photo.png".into(),
                    blend: BlendMode::Normal,
                    opacity: 1.0,
                    visible: true,
                    png: png(stack.base.image(), Some(profile), path)?,
                },
                What::Layer(i, l) => OraLayer {
                    name: l.name.clone(),
                    src: format!("data/{:02}-{}.png", i + 1, slug(&l.name)),
                    blend: l.blend,
                    opacity: l.opacity,
                    visible: l.visible,
                    png: png(&DynamicImage::ImageRgba8(l.to_rgba()), None, path)?,
                },
                What::Region(r) => {
                    let img = image::RgbaImage::from_fn(w, h, |x, y| {
                        image::Rgba([255, 255, 255, r.get_pixel(x, y)[0]])
                    });
                    OraLayer {
                        name: REGION_LAYER.into(),
                        src: "data/region.png".into(),
                        blend: BlendMode::Normal,
                        opacity: 1.0,
                        visible: false,
                        png: png(&DynamicImage::ImageRgba8(img), None, path)?,
                    }
                }
            })
        })
        .collect::<Result<_>>()?;

    let merged = stack.composite().to_rgba8();
    let (tw, th) = thumbnail_size(w, h);
    let thumb = DynamicImage::ImageRgba8(image::imageops::thumbnail(&merged, tw, th));
    let merged = DynamicImage::ImageRgba8(merged);
    let (merged_png, thumb_png) = rayon::join(
        || png(&merged, Some(profile), path),
        || png(&thumb, None, path),
    );
    let (merged_png, thumb_png) = (merged_png?, thumb_png?);
    let xml = stack_xml(w, h, &layers, recipe.is_some());

    io::write_atomic(path, |out| {
        // The zip writer tries to finish the archive when dropped after an
        // error, and prints that second failure on stderr. Once a write has
        // failed, `Latch` keeps the error and takes every later write
        // silently, so the first error is the one reported.
        let mut latch = Latch::new(out);
        let result = write_zip(&mut latch, &xml, &layers, &merged_png, &thumb_png, recipe);
        match (latch.error.take(), result) {
            (Some(e), _) => Err(Error::io(path, e)),
            (None, r) => r.map_err(|e| Error::Encode {
                path: path.to_path_buf(),
                reason: format!("zip: {e}"),
            }),
        }
    })
}

/// The archive's entries in the order the specification asks.
fn write_zip<W: Write + std::io::Seek>(
    out: W,
    xml: &str,
    layers: &[OraLayer],
    merged_png: &[u8],
    thumb_png: &[u8],
    recipe: Option<&str>,
) -> zip::result::ZipResult<()> {
    let stored = SimpleFileOptions::default().compression_method(CompressionMethod::Stored);
    let deflated = SimpleFileOptions::default().compression_method(CompressionMethod::Deflated);
    let mut zip = zip::ZipWriter::new(out);
    zip.start_file("mimetype", stored)?;
    zip.write_all(MIMETYPE.as_bytes())?;
    zip.start_file("stack.xml", deflated)?;
    zip.write_all(xml.as_bytes())?;
    // PNGs are compressed already.
    for l in layers {
        zip.start_file(l.src.as_str(), stored)?;
        zip.write_all(&l.png)?;
    }
    zip.start_file("mergedimage.png", stored)?;
    zip.write_all(merged_png)?;
    zip.start_file("Thumbnails/thumbnail.png", stored)?;
    zip.write_all(thumb_png)?;
    if let Some(recipe) = recipe {
        zip.start_file(RECIPE_FILE, deflated)?;
        zip.write_all(recipe.as_bytes())?;
    }
    zip.finish()?;
    Ok(())
}

/// A writer that remembers its first error and from then on takes every
/// write and seek without touching `inner`, keeping only the position.
struct Latch<W> {
    inner: W,
    error: Option<std::io::Error>,
    /// Position and furthest end, tracked for the seeks after an error.
    pos: u64,
    end: u64,
}

impl<W> Latch<W> {
    fn new(inner: W) -> Self {
        Latch {
            inner,
            error: None,
            pos: 0,
            end: 0,
        }
    }

    fn moved(&mut self, pos: u64) {
        self.pos = pos;
        self.end = self.end.max(pos);
    }

    fn failed(&mut self, e: &std::io::Error) {
        self.error = Some(std::io::Error::new(e.kind(), e.to_string()));
    }
}

impl<W: Write> Write for Latch<W> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        if self.error.is_none() {
            match self.inner.write(buf) {
                Ok(n) => {
                    self.moved(self.pos + n as u64);
                    return Ok(n);
                }
                Err(e) => self.failed(&e),
            }
        }
        self.moved(self.pos + buf.len() as u64);
        Ok(buf.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        if self.error.is_none()
            && let Err(e) = self.inner.flush()
        {
            self.failed(&e);
        }
        Ok(())
    }
}

impl<W: std::io::Seek> std::io::Seek for Latch<W> {
    fn seek(&mut self, pos: std::io::SeekFrom) -> std::io::Result<u64> {
        use std::io::SeekFrom;
        if self.error.is_none() {
            match self.inner.seek(pos) {
                Ok(p) => {
                    self.moved(p);
                    return Ok(p);
                }
                Err(e) => self.failed(&e),
            }
        }
        let to = match pos {
            SeekFrom::Start(n) => n,
            SeekFrom::Current(d) => self.pos.saturating_add_signed(d),
            SeekFrom::End(d) => self.end.saturating_add_signed(d),
        };
        self.pos = to;
        Ok(to)
    }
}

/// The size of the thumbnail: the photo scaled to fit 256 x 256, at least 1
/// pixel per side, never enlarged.
pub fn thumbnail_size(w: u32, h: u32) -> (u32, u32) {
    let side = w.max(h).max(1);
    if side <= THUMBNAIL_MAX {
        return (w.max(1), h.max(1));
    }
    let scale =
        |v: u32| ((v as u64 * THUMBNAIL_MAX as u64 + side as u64 / 2) / side as u64).max(1) as u32;
    (scale(w), scale(h))
}

/// The OpenRaster `composite-op` of a blend mode.
pub fn composite_op(blend: BlendMode) -> &'static str {
    match blend {
        BlendMode::Normal => "svg:src-over",
        BlendMode::Multiply => "svg:multiply",
        BlendMode::Screen => "svg:screen",
    }
}

fn png(img: &DynamicImage, icc: Option<&[u8]>, path: &Path) -> Result<Vec<u8>> {
    let mut buf = Vec::new();
    let mut enc =
        PngEncoder::new_with_quality(&mut buf, CompressionType::Fast, FilterType::Adaptive);
    if let Some(icc) = icc {
        let _ = enc.set_icc_profile(icc.to_vec());
    }
    img.write_with_encoder(enc).map_err(|e| Error::Encode {
        path: path.to_path_buf(),
        reason: e.to_string(),
    })?;
    Ok(buf)
}

/// `stack.xml`: layers top first, as the specification asks.
fn stack_xml(w: u32, h: u32, bottom_first: &[OraLayer], recipe: bool) -> String {
    let mut s = String::new();
    s.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let recipe = match recipe {
        true => {
            format!(" xmlns:grime=\"https://grime.invalid/ns/1.0/\" grime:recipe=\"{RECIPE_FILE}\"")
        }
        false => String::new(),
    };
    s.push_str(&format!(
        "<image version=\"0.0.5\" w=\"{w}\" h=\"{h}\" xres=\"72\" yres=\"72\"{recipe}>\n"
    ));
    s.push_str("  <stack>\n");
    for l in bottom_first.iter().rev() {
        s.push_str(&format!(
            "    <layer name=\"{}\" src=\"{}\" x=\"0\" y=\"0\" opacity=\"{}\" visibility=\"{}\" composite-op=\"{}\"/>\n",
            escape(&l.name),
            escape(&l.src),
            l.opacity.clamp(0.0, 1.0),
            if l.visible { "visible" } else { "hidden" },
            composite_op(l.blend),
        ));
    }
    s.push_str("  </stack>\n</image>\n");
    s
}

/// Escapes text for an XML attribute value.
fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\t' | '\n' | '\r' => out.push_str(&format!("&#{};", c as u32)),
            c if c.is_control() => out.push('?'),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thumbnail_fits() {
        assert_eq!(thumbnail_size(960, 720), (256, 192));
        assert_eq!(thumbnail_size(100, 50), (100, 50));
        assert_eq!(thumbnail_size(4000, 3), (256, 1));
    }

    /// Fails every write once `room` bytes are taken, like a full disk.
    struct Full {
        data: std::io::Cursor<Vec<u8>>,
        room: usize,
    }

    impl Write for Full {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            if self.data.get_ref().len() + buf.len() > self.room {
                return Err(std::io::Error::from_raw_os_error(28)); // ENOSPC
            }
            self.data.write(buf)
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    impl std::io::Seek for Full {
        fn seek(&mut self, pos: std::io::SeekFrom) -> std::io::Result<u64> {
            self.data.seek(pos)
        }
    }

    #[test]
    fn a_full_disk_gives_its_own_error_once() {
        let layer = |i: usize| OraLayer {
            name: format!("l{i}"),
            src: format!("data/{i}.png"),
            blend: BlendMode::Normal,
            opacity: 1.0,
            visible: true,
            png: vec![7; 3000],
        };
        let layers: Vec<_> = (0..4).map(layer).collect();
        for room in [0, 10, 100, 5000, 12_000] {
            let mut latch = Latch::new(Full {
                data: Default::default(),
                room,
            });
            let r = write_zip(&mut latch, "<image/>", &layers, &[1; 100], &[2; 10], None);
            // The zip writer saw only successes after the failure, so its
            // drop has nothing to print; the first error is kept.
            assert!(r.is_ok(), "{r:?}");
            let err = latch.error.expect("the write failed");
            assert!(err.to_string().contains("No space left"), "{err}");
        }
    }

    #[test]
    fn escapes_names() {
        assert_eq!(escape("a<\"b\">&'"), "a&lt;&quot;b&quot;&gt;&amp;&apos;");
    }
}
