//! What a file really is, from its first bytes (not its extension), and a
//! bounded look at a PNG's ICC chunk before the decoder inflates it.

use std::fs::File;
use std::io::{Read, Seek, SeekFrom};
use std::path::Path;

use image::ImageFormat;

use super::icc;
use crate::error::{Error, Result};

/// The input format of `head` (a file's first bytes), from its signature.
///
/// # Errors
/// [`Error::UnsupportedInput`] for a known image format grime does not read
/// (GIF, BMP, ...), [`Error::NotAnImage`] for anything else, [`Error::Decode`]
/// for an empty file.
pub fn format(path: &Path, head: &[u8]) -> Result<ImageFormat> {
    let starts = |m: &[u8]| head.starts_with(m);
    if starts(b"\x89PNG\r\n\x1a\n") {
        return Ok(ImageFormat::Png);
    }
    if starts(&[0xFF, 0xD8, 0xFF]) {
        return Ok(ImageFormat::Jpeg);
    }
    if starts(b"II*\0") || starts(b"MM\0*") || starts(b"II+\0") || starts(b"MM\0+") {
        return Ok(ImageFormat::Tiff);
    }
    if starts(b"RIFF") && head.get(8..12) == Some(b"WEBP") {
        return Ok(ImageFormat::WebP);
    }
    if head.is_empty() {
        return Err(Error::Decode {
            path: path.to_path_buf(),
            reason: "the file is empty".into(),
        });
    }
    let other = |kind: &str| Error::UnsupportedInput {
        path: path.to_path_buf(),
        kind: kind.into(),
    };
    if starts(b"GIF87a") || starts(b"GIF89a") {
        return Err(other("a GIF image"));
    }
    if starts(b"BM") {
        return Err(other("a BMP image"));
    }
    if starts(b"8BPS") {
        return Err(other("a Photoshop document"));
    }
    if head.get(4..8) == Some(b"ftyp") {
        return Err(other("an AVIF/HEIF image"));
    }
    if starts(b"%PDF") {
        return Err(other("a PDF document"));
    }
    if starts(b"PK\x03\x04") {
        return Err(other("a zip archive (or OpenRaster document)"));
    }
    let text = head
        .iter()
        .all(|&b| b.is_ascii_graphic() || b.is_ascii_whitespace() || b >= 0x80);
    Err(Error::NotAnImage {
        path: path.to_path_buf(),
        found: if text {
            "it holds text".into()
        } else {
            "its first bytes are no image signature".into()
        },
    })
}

/// Reads a PNG's chunk headers up to the first `IDAT` and, if there is an
/// `iCCP` chunk, inflates its profile with a bound of
/// [`icc::MAX_ICC_BYTES`] and checks it ([`icc::check`]). The PNG decoder
/// would otherwise inflate any profile up to its 2 GiB allocation limit.
///
/// # Errors
/// [`Error::BadIcc`] for a profile too large, not inflatable or damaged;
/// [`Error::Io`] if the file cannot be read. A PNG whose chunks end early is
/// left to the decoder to report.
pub fn check_png_icc(path: &Path) -> Result<()> {
    let bad = |reason: String| Error::BadIcc {
        path: path.to_path_buf(),
        reason,
    };
    let mut f = File::open(path).map_err(|e| Error::io(path, e))?;
    let file_len = f.metadata().map_err(|e| Error::io(path, e))?.len();
    let mut pos = 8u64;
    // A PNG has a few dozen chunks before its image data; give up after many.
    for _ in 0..10_000 {
        let mut head = [0u8; 8];
        if f.seek(SeekFrom::Start(pos)).is_err() || f.read_exact(&mut head).is_err() {
            return Ok(());
        }
        let len = u32::from_be_bytes([head[0], head[1], head[2], head[3]]) as u64;
        match &head[4..8] {
            b"IDAT" | b"IEND" => return Ok(()),
            b"iCCP" => {
                // Deflate shrinks at most ~1032:1 but never grows by more
                // than a few bytes per 64 kB block: a chunk much larger than
                // the bound inflates past it.
                let cap = icc::MAX_ICC_BYTES as u64 + icc::MAX_ICC_BYTES as u64 / 64 + 1024;
                if len > cap || len > file_len {
                    return Err(bad(format!(
                        "chunk is {}, larger than any profile grime accepts ({})",
                        super::human_bytes(len),
                        super::human_bytes(icc::MAX_ICC_BYTES as u64)
                    )));
                }
                let mut data = vec![0; len as usize];
                f.read_exact(&mut data).map_err(|e| Error::io(path, e))?;
                // Profile name (1-79 bytes), NUL, compression method 0.
                let name_end = data
                    .iter()
                    .take(80)
                    .position(|&b| b == 0)
                    .ok_or_else(|| bad("chunk has no profile name".into()))?;
                let deflated = data
                    .get(name_end + 2..)
                    .ok_or_else(|| bad("chunk is cut short".into()))?;
                let profile = fdeflate::decompress_to_vec_bounded(deflated, icc::MAX_ICC_BYTES)
                    .map_err(|e| match e {
                        fdeflate::BoundedDecompressionError::OutputTooLarge { .. } => bad(format!(
                            "inflates to over {}, more than any profile grime accepts",
                            super::human_bytes(icc::MAX_ICC_BYTES as u64)
                        )),
                        _ => bad("cannot be inflated (corrupt compressed data)".into()),
                    })?;
                return icc::check(&profile).map_err(bad);
            }
            _ => pos += 12 + len,
        }
    }
    Ok(())
}

/// Checks that no tag of a TIFF's first directory claims more data than the
/// file holds. The TIFF decoder reads strip and tile tables whole when it
/// opens the file, before grime sees the image size: a count of 33 million
/// in a 7 kB file made it allocate 266 MB.
///
/// # Errors
/// [`Error::Decode`] naming the tag; [`Error::Io`] if the file cannot be
/// read. A directory cut short is left to the decoder to report.
pub fn check_tiff_tags(path: &Path) -> Result<()> {
    let data = {
        let mut f = File::open(path).map_err(|e| Error::io(path, e))?;
        let len = f.metadata().map_err(|e| Error::io(path, e))?.len();
        // The first 64 MiB: a directory past them is left unchecked.
        let mut buf = Vec::new();
        (&mut f)
            .take(len.min(64 << 20))
            .read_to_end(&mut buf)
            .map_err(|e| Error::io(path, e))?;
        (buf, len)
    };
    let (buf, file_len) = data;
    let big_endian = buf.starts_with(b"MM");
    let u16_at = |i: usize| -> Option<u64> {
        let b: [u8; 2] = buf.get(i..i + 2)?.try_into().ok()?;
        Some(if big_endian {
            u16::from_be_bytes(b)
        } else {
            u16::from_le_bytes(b)
        } as u64)
    };
    let u32_at = |i: usize| -> Option<u64> {
        let b: [u8; 4] = buf.get(i..i + 4)?.try_into().ok()?;
        Some(if big_endian {
            u32::from_be_bytes(b)
        } else {
            u32::from_le_bytes(b)
        } as u64)
    };
    let u64_at = |i: usize| -> Option<u64> {
        let b: [u8; 8] = buf.get(i..i + 8)?.try_into().ok()?;
        Some(if big_endian {
            u64::from_be_bytes(b)
        } else {
            u64::from_le_bytes(b)
        })
    };
    let big = u16_at(2) == Some(43);
    let (ifd, count_size, entry_size) = if big {
        (u64_at(8), 8, 20)
    } else {
        (u32_at(4), 2, 12)
    };
    let Some(ifd) = ifd.map(|o| o as usize) else {
        return Ok(());
    };
    let entries = if big { u64_at(ifd) } else { u16_at(ifd) };
    let Some(entries) = entries else {
        return Ok(());
    };
    for k in 0..entries.min(4096) as usize {
        let at = ifd + count_size + k * entry_size;
        let (Some(tag), Some(kind)) = (u16_at(at), u16_at(at + 2)) else {
            return Ok(());
        };
        let count = if big { u64_at(at + 4) } else { u32_at(at + 4) };
        let Some(count) = count else {
            return Ok(());
        };
        let unit = match kind {
            3 | 8 => 2,
            4 | 9 | 11 | 13 => 4,
            5 | 10 | 12 | 16..=18 => 8,
            _ => 1,
        };
        if count.saturating_mul(unit) > file_len {
            return Err(Error::Decode {
                path: path.to_path_buf(),
                reason: format!(
                    "TIFF tag {tag} claims {count} values, more data than the file holds"
                ),
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn signatures_name_the_format() {
        let p = Path::new("x.png");
        assert_eq!(
            format(p, b"\x89PNG\r\n\x1a\n....").unwrap(),
            ImageFormat::Png
        );
        assert_eq!(
            format(p, b"RIFF\0\0\0\0WEBPVP8 ").unwrap(),
            ImageFormat::WebP
        );
        let gif = format(p, b"GIF89a\x01\0\x01\0").unwrap_err().to_string();
        assert!(gif.contains("GIF image is not a supported input"), "{gif}");
        let text = format(p, b"hello, world\n").unwrap_err().to_string();
        assert!(
            text.contains("not a PNG, JPEG, TIFF or WebP file (it holds text)"),
            "{text}"
        );
        let junk = format(p, &[0x00, 0x13, 0xFE, 0x77])
            .unwrap_err()
            .to_string();
        assert!(junk.contains("no image signature"), "{junk}");
        assert!(!junk.contains("extension"), "{junk}");
    }
}
