//! Finding the recipe in a file grime wrote (`grime recipe FILE`), by the
//! file's first bytes: PNG, JPEG, WebP, TIFF, PSD or ORA.

use std::io::Read;
use std::path::Path;

use super::embed::{self, KEY, TIFF_XMP};
use crate::error::{Error, Result};

/// The recipe text stored in the file at `path`.
///
/// # Errors
/// [`Error::Io`] when it cannot be read, [`Error::NoRecipe`] when it holds
/// none (or is not a format grime writes).
pub fn from_file(path: &Path) -> Result<String> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    let none = |reason: &str| Error::NoRecipe {
        path: path.to_path_buf(),
        reason: reason.into(),
    };
    let found = if bytes.starts_with(b"\x89PNG\r\n\x1a\n") {
        png(&bytes)
    } else if bytes.starts_with(&[0xFF, 0xD8]) {
        jpeg(&bytes)
    } else if bytes.len() > 12 && &bytes[..4] == b"RIFF" && &bytes[8..12] == b"WEBP" {
        webp(&bytes)
    } else if bytes.starts_with(b"II*\0") {
        tiff(&bytes)
    } else if bytes.starts_with(b"8BPS") {
        psd(&bytes)
    } else if bytes.starts_with(b"PK\x03\x04") {
        ora(&bytes)
    } else {
        return Err(none("not a PNG, JPEG, WebP, TIFF, PSD or ORA file"));
    };
    found.ok_or_else(|| none("it was not written by grime, or the recipe was removed"))
}

fn be32(b: &[u8], i: usize) -> Option<usize> {
    Some(u32::from_be_bytes(b.get(i..i + 4)?.try_into().ok()?) as usize)
}

/// The `iTXt` chunk with the recipe's keyword.
fn png(b: &[u8]) -> Option<String> {
    let mut at = 8;
    while at + 12 <= b.len() {
        let len = be32(b, at)?;
        let data = b.get(at + 8..at + 8 + len)?;
        if &b[at + 4..at + 8] == b"iTXt" && data.starts_with(&embed::itxt("")) {
            return String::from_utf8(data[KEY.len() + 5..].to_vec()).ok();
        }
        at += 12 + len;
    }
    None
}

/// The `COM` segments with the recipe's prefix, joined.
fn jpeg(b: &[u8]) -> Option<String> {
    let prefix = format!("{KEY}:");
    let mut text = Vec::new();
    let mut at = 2;
    while at + 4 <= b.len() && b[at] == 0xFF && b[at + 1] != 0xDA {
        let len = u16::from_be_bytes([b[at + 2], b[at + 3]]) as usize;
        let data = b.get(at + 4..at + 2 + len)?;
        if b[at + 1] == 0xFE
            && let Some(part) = data.strip_prefix(prefix.as_bytes())
        {
            text.extend_from_slice(part);
        }
        at += 2 + len;
    }
    (!text.is_empty()).then(|| String::from_utf8(text).ok())?
}

/// The `XMP ` chunk.
fn webp(b: &[u8]) -> Option<String> {
    let mut at = 12;
    while at + 8 <= b.len() {
        let len = u32::from_le_bytes(b[at + 4..at + 8].try_into().ok()?) as usize;
        if &b[at..at + 4] == b"XMP " {
            return embed::from_xmp(b.get(at + 8..at + 8 + len)?);
        }
        at += 8 + len + len % 2;
    }
    None
}

/// The XMP tag of the first IFD.
fn tiff(b: &[u8]) -> Option<String> {
    let u16_at = |i: usize| Some(u16::from_le_bytes(b.get(i..i + 2)?.try_into().ok()?));
    let u32_at = |i: usize| Some(u32::from_le_bytes(b.get(i..i + 4)?.try_into().ok()?) as usize);
    let ifd = u32_at(4)?;
    for i in 0..u16_at(ifd)? as usize {
        let e = ifd + 2 + i * 12;
        if u16_at(e)? == TIFF_XMP {
            let (len, at) = (u32_at(e + 4)?, u32_at(e + 8)?);
            return embed::from_xmp(b.get(at..at + len)?);
        }
    }
    None
}

/// The XMP image resource (1060).
fn psd(b: &[u8]) -> Option<String> {
    let mode_len = be32(b, 26)?;
    let res_at = 30 + mode_len;
    let end = res_at + 4 + be32(b, res_at)?;
    let mut at = res_at + 4;
    while at + 12 <= end {
        let id = u16::from_be_bytes([b[at + 4], b[at + 5]]);
        let name = 1 + *b.get(at + 6)? as usize;
        let size_at = at + 6 + name + name % 2;
        let size = be32(b, size_at)?;
        if id == crate::export::psd::XMP_RESOURCE {
            return embed::from_xmp(b.get(size_at + 4..size_at + 4 + size)?);
        }
        at = size_at + 4 + size + size % 2;
    }
    None
}

/// `recipe.toml` in the archive.
fn ora(b: &[u8]) -> Option<String> {
    let mut zip = zip::ZipArchive::new(std::io::Cursor::new(b)).ok()?;
    let mut file = zip.by_name(crate::export::ora::RECIPE_FILE).ok()?;
    let mut text = String::new();
    file.read_to_string(&mut text).ok()?;
    Some(text)
}
