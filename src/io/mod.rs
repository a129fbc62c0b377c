//! Reading photos and masks, writing images atomically.
//!
//! Inputs: PNG, JPEG, TIFF, WebP at 8 or 16 bits, greyscale or RGB(A); EXIF
//! orientation is applied and the ICC profile kept. Decoding limits refuse
//! decompression bombs. Outputs are written to a temporary file in the
//! target folder and renamed into place, so an interrupted run never leaves a
//! half-written file, and an input is never overwritten.

use std::fs::File;
use std::io::{BufReader, BufWriter, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use image::{DynamicImage, GrayImage, ImageDecoder, ImageEncoder, ImageError, ImageReader};

use crate::error::{Error, Result};
use crate::photo::Photo;

pub mod icc;
pub mod limits;
pub mod sniff;
pub mod temp;

/// A byte count for people: `512 B`, `3.2 MiB`, `8.8 GiB`.
pub fn human_bytes(n: u64) -> String {
    const UNITS: [&str; 5] = ["B", "KiB", "MiB", "GiB", "TiB"];
    let mut v = n as f64;
    let mut unit = 0;
    while v >= 1024.0 && unit + 1 < UNITS.len() {
        v /= 1024.0;
        unit += 1;
    }
    if unit == 0 {
        format!("{n} B")
    } else {
        format!("{v:.1} {}", UNITS[unit])
    }
}

/// Largest image grime decodes, in pixels (about 16k x 16k).
pub const MAX_PIXELS: u64 = 268_435_456;

/// The image formats grime writes, chosen by file extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// PNG, 8 or 16 bit.
    Png,
    /// JPEG, 8 bit.
    Jpeg,
    /// TIFF, 8 or 16 bit.
    Tiff,
    /// WebP (lossless), 8 bit.
    Webp,
    /// Layered Photoshop document.
    Psd,
    /// Layered OpenRaster document.
    Ora,
}

impl Format {
    /// The format an output path names.
    ///
    /// # Errors
    /// [`Error::UnknownFormat`] for any other extension.
    pub fn from_path(path: &Path) -> Result<Format> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .unwrap_or_default();
        Ok(match ext.as_str() {
            "png" => Format::Png,
            "jpg" | "jpeg" => Format::Jpeg,
            "tif" | "tiff" => Format::Tiff,
            "webp" => Format::Webp,
            "psd" => Format::Psd,
            "ora" => Format::Ora,
            _ => {
                return Err(Error::UnknownFormat {
                    path: path.to_path_buf(),
                });
            }
        })
    }

    /// True for extensions grime reads as photos.
    pub fn is_input(path: &Path) -> bool {
        matches!(
            Format::from_path(path),
            Ok(Format::Png | Format::Jpeg | Format::Tiff | Format::Webp)
        )
    }
}

fn limits() -> image::Limits {
    let mut l = image::Limits::default();
    l.max_image_width = Some(1 << 16);
    l.max_image_height = Some(1 << 16);
    l.max_alloc = Some(MAX_PIXELS * 8);
    l
}

fn decode_error(path: &Path, e: ImageError) -> Error {
    match e {
        ImageError::Limits(l) => Error::TooLarge {
            path: path.to_path_buf(),
            reason: l.to_string(),
            max_pixels: MAX_PIXELS,
        },
        ImageError::IoError(io) => Error::io(path, io),
        ImageError::Unsupported(u) => Error::Decode {
            path: path.to_path_buf(),
            reason: u.to_string(),
        },
        other => Error::Decode {
            path: path.to_path_buf(),
            reason: other.to_string(),
        },
    }
}

/// Decodes an image file: format from its first bytes, EXIF orientation
/// applied, ICC profile checked and kept.
///
/// # Errors
/// [`Error::Io`] if the file cannot be opened, [`Error::NotAnImage`] or
/// [`Error::UnsupportedInput`] for a file that is no PNG, JPEG, TIFF or WebP
/// whatever its extension, [`Error::Decode`] for a corrupt one,
/// [`Error::TooLarge`] past the decoding limits, [`Error::BadIcc`] for an
/// oversized or damaged colour profile.
pub fn load_image(path: &Path) -> Result<(DynamicImage, Option<Vec<u8>>)> {
    load_image_checked(path, |_, _| Ok(()))
}

/// [`load_image`], calling `check(width, height)` once the size is known and
/// before any pixel is decoded.
///
/// # Errors
/// As [`load_image`], and whatever `check` returns.
pub fn load_image_checked(
    path: &Path,
    check: impl FnOnce(u32, u32) -> Result<()>,
) -> Result<(DynamicImage, Option<Vec<u8>>)> {
    let mut file = File::open(path).map_err(|e| Error::io(path, e))?;
    let mut head = Vec::with_capacity(16);
    (&mut file)
        .take(16)
        .read_to_end(&mut head)
        .map_err(|e| Error::io(path, e))?;
    let format = sniff::format(path, &head)?;
    match format {
        image::ImageFormat::Png => sniff::check_png_icc(path)?,
        image::ImageFormat::Tiff => sniff::check_tiff_tags(path)?,
        image::ImageFormat::Jpeg => {
            // The JPEG decoder fills a truncated scan with grey instead of failing.
            let data = std::fs::read(path).map_err(|e| Error::io(path, e))?;
            jpeg_complete(&data).map_err(|reason| Error::Decode {
                path: path.to_path_buf(),
                reason,
            })?;
        }
        _ => {}
    }
    file.seek(SeekFrom::Start(0))
        .map_err(|e| Error::io(path, e))?;
    let mut reader = ImageReader::with_format(BufReader::new(file), format);
    reader.limits(limits());
    let mut decoder = reader.into_decoder().map_err(|e| decode_error(path, e))?;
    let (w, h) = decoder.dimensions();
    if w as u64 * h as u64 > MAX_PIXELS {
        return Err(Error::TooLarge {
            path: path.to_path_buf(),
            reason: format!("{w}x{h}"),
            max_pixels: MAX_PIXELS,
        });
    }
    check(w, h)?;
    // Now that the size is known, no buffer may be much larger than the
    // image: a crafted file cannot make the decoder allocate the 2 GiB the
    // format-blind limit allowed (a TIFF claiming a 250 MB strip for a 40 x
    // 30 image did).
    let mut tight = limits();
    tight.max_alloc = Some(
        decoder
            .total_bytes()
            .saturating_mul(2)
            .saturating_add(16 << 20)
            .min(MAX_PIXELS * 8),
    );
    decoder
        .set_limits(tight)
        .map_err(|e| decode_error(path, e))?;
    let icc = decoder.icc_profile().ok().flatten();
    if let Some(profile) = &icc {
        icc::check(profile).map_err(|reason| Error::BadIcc {
            path: path.to_path_buf(),
            reason,
        })?;
    }
    let orientation = decoder
        .orientation()
        .unwrap_or(image::metadata::Orientation::NoTransforms);
    let mut img = DynamicImage::from_decoder(decoder).map_err(|e| decode_error(path, e))?;
    img.apply_orientation(orientation);
    Ok((img, icc))
}

/// Checks that JPEG data is whole: its segments and scans run, marker by
/// marker, up to the end-of-image marker. Bytes after that marker are
/// allowed (some cameras append data there).
///
/// # Errors
/// A short reason when the data is not JPEG or ends early (truncated).
pub fn jpeg_complete(data: &[u8]) -> std::result::Result<(), String> {
    const TRUNCATED: &str = "truncated: the file ends before the JPEG end-of-image marker";
    if !data.starts_with(&[0xFF, 0xD8]) {
        return Err("no JPEG start-of-image marker".into());
    }
    let mut i = 2;
    loop {
        // Decoders skip stray bytes between segments; so do we.
        i += data[i.min(data.len())..]
            .iter()
            .position(|&b| b == 0xFF)
            .ok_or(TRUNCATED)?;
        while data.get(i) == Some(&0xFF) {
            i += 1;
        }
        let marker = *data.get(i).ok_or(TRUNCATED)?;
        i += 1;
        match marker {
            0xD9 => return Ok(()),
            0x01 | 0xD0..=0xD7 => continue,
            _ => {}
        }
        let len = match data.get(i..i + 2) {
            Some(b) => u16::from_be_bytes([b[0], b[1]]) as usize,
            None => return Err(TRUNCATED.into()),
        };
        if len < 2 || i + len > data.len() {
            return Err(TRUNCATED.into());
        }
        i += len;
        if marker == 0xDA {
            // Entropy-coded data: runs to the next marker that is neither a
            // stuffed 0xFF00 nor a restart marker.
            loop {
                i += data[i.min(data.len())..]
                    .iter()
                    .position(|&b| b == 0xFF)
                    .ok_or(TRUNCATED)?;
                match data.get(i + 1) {
                    None => return Err(TRUNCATED.into()),
                    Some(0x00 | 0xD0..=0xD7 | 0xFF) => i += 1,
                    Some(_) => break,
                }
            }
        }
    }
}

/// Loads a photo (see [`load_image`]), first checking that ageing it fits
/// the memory limit ([`limits::check`]).
///
/// # Errors
/// As [`load_image`], plus [`Error::MemoryLimit`].
pub fn load_photo(path: &Path) -> Result<Photo> {
    load_photo_needing(path, &limits::estimate)
}

/// [`load_photo`] for work that needs `need(width, height)` bytes at its
/// peak (e.g. [`limits::estimate_timelapse`]).
///
/// # Errors
/// As [`load_photo`].
pub fn load_photo_needing(path: &Path, need: &dyn Fn(u32, u32) -> u64) -> Result<Photo> {
    let (img, icc) =
        load_image_checked(path, |w, h| limits::check_needing(path, w, h, need(w, h)))?;
    let mut photo = Photo::new(img);
    photo.icc = icc;
    Ok(photo)
}

/// Loads a region mask (white = wall) that must match `w` x `h`.
///
/// The mask is its grey level, except when its colour is the same
/// everywhere and only its alpha varies (a wall painted as opacity): then
/// the alpha is the mask (opaque = wall).
///
/// # Errors
/// As [`load_image`], plus [`Error::MaskSize`] when the size differs.
pub fn load_mask(path: &Path, w: u32, h: u32) -> Result<GrayImage> {
    // The size is checked before decoding, so a mask claiming a huge size
    // allocates nothing.
    let (img, _) = load_image_checked(path, |mask_w, mask_h| {
        if (mask_w, mask_h) == (w, h) {
            Ok(())
        } else {
            Err(Error::MaskSize {
                mask_w,
                mask_h,
                img_w: w,
                img_h: h,
            })
        }
    })?;
    Ok(mask_values(&img))
}

/// The mask values of a decoded mask image (see [`load_mask`]).
pub fn mask_values(img: &DynamicImage) -> GrayImage {
    if img.color().has_alpha() {
        let la = img.to_luma_alpha8();
        let mut px = la.pixels();
        if let Some(first) = px.next() {
            let uniform_grey = px.clone().all(|p| p[0] == first[0]);
            let alpha_varies = px.any(|p| p[1] != first[1]);
            if uniform_grey && alpha_varies {
                return GrayImage::from_fn(la.width(), la.height(), |x, y| {
                    image::Luma([la.get_pixel(x, y)[1]])
                });
            }
        }
    }
    img.to_luma8()
}

static TEMP_COUNTER: AtomicU64 = AtomicU64::new(0);

/// The folder `path` is in (`.` for a bare file name).
pub fn folder_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Writes a file atomically: `write` fills a temporary file next to `path`,
/// which is then renamed over `path`. On any error the temporary file is
/// removed and `path` is left as it was.
///
/// # Errors
/// [`Error::Io`] when the folder is missing or not writable, or whatever
/// `write` returns.
pub fn write_atomic(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> Result<()>,
) -> Result<()> {
    let dir = folder_of(path);
    if !dir.is_dir() {
        return Err(Error::io(
            path,
            std::io::Error::new(
                std::io::ErrorKind::NotFound,
                format!("folder {} does not exist; create it first", dir.display()),
            ),
        ));
    }
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("out");
    let tmp = dir.join(format!(
        ".{name}.grime-{}-{}.tmp",
        std::process::id(),
        TEMP_COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    temp::register(&tmp);
    let result = (|| {
        let file = File::create(&tmp).map_err(|e| Error::io(&tmp, e))?;
        let mut out = BufWriter::new(file);
        write(&mut out)?;
        let file = out
            .into_inner()
            .map_err(|e| Error::io(&tmp, e.into_error()))?;
        file.sync_all().map_err(|e| Error::io(&tmp, e))?;
        std::fs::rename(&tmp, path).map_err(|e| Error::io(path, e))
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    temp::unregister(&tmp);
    result
}

/// Encodes `img` in `format` (PNG/JPEG/TIFF/WebP) to `out`, embedding `icc`
/// where the format allows. 16-bit images stay 16-bit in PNG and TIFF; a
/// 16-bit PNG without `icc` gets the sRGB profile ([`icc::srgb`]).
///
/// # Errors
/// [`Error::Encode`] if the encoder fails, [`Error::UnknownFormat`] for a
/// layered format.
pub fn encode(
    img: &DynamicImage,
    icc: Option<&[u8]>,
    format: Format,
    path: &Path,
    out: &mut impl Write,
) -> Result<()> {
    let enc_err = |e: ImageError| Error::Encode {
        path: path.to_path_buf(),
        reason: e.to_string(),
    };
    fn with_icc<E: ImageEncoder>(mut e: E, icc: Option<&[u8]>) -> E {
        if let Some(icc) = icc {
            let _ = e.set_icc_profile(icc.to_vec());
        }
        e
    }
    match format {
        Format::Png => {
            // A 16-bit PNG without a colour chunk opens as linear light in
            // Krita: say sRGB (issue 13, item 17).
            let icc = icc.or(is_16bit(img).then(icc::srgb));
            img.write_with_encoder(with_icc(image::codecs::png::PngEncoder::new(out), icc))
                .map_err(enc_err)
        }
        Format::Jpeg => {
            let rgb = DynamicImage::ImageRgb8(img.to_rgb8());
            rgb.write_with_encoder(with_icc(
                image::codecs::jpeg::JpegEncoder::new_with_quality(out, 92),
                icc,
            ))
            .map_err(enc_err)
        }
        Format::Tiff => {
            let mut buf = std::io::Cursor::new(Vec::new());
            img.write_with_encoder(with_icc(
                image::codecs::tiff::TiffEncoder::new(&mut buf),
                icc,
            ))
            .map_err(enc_err)?;
            out.write_all(buf.get_ref()).map_err(|e| Error::io(path, e))
        }
        Format::Webp => {
            let img8 = if img.color().has_alpha() {
                DynamicImage::ImageRgba8(img.to_rgba8())
            } else {
                DynamicImage::ImageRgb8(img.to_rgb8())
            };
            img8.write_with_encoder(with_icc(
                image::codecs::webp::WebPEncoder::new_lossless(out),
                icc,
            ))
            .map_err(enc_err)
        }
        Format::Psd | Format::Ora => Err(Error::UnknownFormat {
            path: path.to_path_buf(),
        }),
    }
}

/// True for 16 bits per channel.
pub fn is_16bit(img: &DynamicImage) -> bool {
    matches!(
        img,
        DynamicImage::ImageLuma16(_)
            | DynamicImage::ImageLumaA16(_)
            | DynamicImage::ImageRgb16(_)
            | DynamicImage::ImageRgba16(_)
    )
}

/// Saves a flat image atomically in the format the extension names.
///
/// # Errors
/// As [`write_atomic`] and [`encode`].
pub fn save_image(img: &DynamicImage, icc: Option<&[u8]>, path: &Path) -> Result<()> {
    save_image_with(img, icc, path, None)
}

/// [`save_image`], with a grime recipe stored in the file
/// ([`crate::recipe::embed`]).
///
/// # Errors
/// As [`save_image`].
pub fn save_image_with(
    img: &DynamicImage,
    icc: Option<&[u8]>,
    path: &Path,
    recipe: Option<&str>,
) -> Result<()> {
    let format = Format::from_path(path)?;
    let Some(recipe) = recipe else {
        return write_atomic(path, |out| encode(img, icc, format, path, out));
    };
    let mut bytes = Vec::new();
    encode(img, icc, format, path, &mut bytes)?;
    crate::recipe::embed::into(format, &mut bytes, recipe).map_err(|reason| Error::Encode {
        path: path.to_path_buf(),
        reason: format!("cannot store the recipe: {reason}"),
    })?;
    write_atomic(path, |out| {
        out.write_all(&bytes).map_err(|e| Error::io(path, e))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn atomic_write_leaves_nothing_on_error() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("x.png");
        std::fs::write(&path, b"old").unwrap();
        let r = write_atomic(&path, |out| {
            out.write_all(b"partial").unwrap();
            Err(Error::Cancelled)
        });
        assert!(r.is_err());
        assert_eq!(std::fs::read(&path).unwrap(), b"old");
        assert_eq!(
            std::fs::read_dir(dir.path()).unwrap().count(),
            1,
            "temp file removed"
        );
    }

    #[test]
    fn missing_folder_is_a_clear_error() {
        let err = write_atomic(Path::new("/nonexistent-grime/x.png"), |_| Ok(())).unwrap_err();
        assert!(err.to_string().contains("does not exist"), "{err}");
    }

    #[test]
    fn truncated_jpeg_is_refused() {
        let img = DynamicImage::ImageRgb8(image::RgbImage::from_fn(64, 48, |x, y| {
            image::Rgb([(x * 4) as u8, (y * 5) as u8, ((x ^ y) * 3) as u8])
        }));
        let mut jpeg = Vec::new();
        encode(&img, None, Format::Jpeg, Path::new("a.jpg"), &mut jpeg).unwrap();
        assert_eq!(jpeg_complete(&jpeg), Ok(()));
        let mut trailing = jpeg.clone();
        trailing.extend_from_slice(b"camera junk");
        assert_eq!(jpeg_complete(&trailing), Ok(()));
        for cut in [3, 30, jpeg.len() / 2, jpeg.len() - 2] {
            assert!(jpeg_complete(&jpeg[..cut]).is_err(), "cut at {cut}");
        }
        assert!(jpeg_complete(b"not a jpeg").is_err());
    }

    #[test]
    fn formats_by_extension() {
        assert_eq!(Format::from_path(Path::new("a.JPG")).unwrap(), Format::Jpeg);
        assert_eq!(
            Format::from_path(Path::new("a.tiff")).unwrap(),
            Format::Tiff
        );
        assert!(Format::from_path(Path::new("a.bmpx")).is_err());
        assert!(!Format::is_input(Path::new("a.psd")));
    }
}
