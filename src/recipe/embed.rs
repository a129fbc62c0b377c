//! Writing a recipe into encoded image bytes, by each container's own
//! means (PNG `iTXt`, JPEG `COM`, WebP and TIFF XMP), and the XMP packet
//! PSD also uses.

use crate::io::Format;

/// The PNG text keyword and the JPEG comment prefix.
pub const KEY: &str = "grime-recipe";

/// The XMP property holding the recipe (namespace `grime`).
const XMP_OPEN: &str = "<grime:recipe>";
const XMP_CLOSE: &str = "</grime:recipe>";

/// An XMP packet holding `recipe` as the `grime:recipe` property.
pub fn xmp(recipe: &str) -> String {
    let text = recipe
        .replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;");
    format!(
        "<?xpacket begin=\"\u{feff}\" id=\"W5M0MpCehiHzreSzNTczkc9d\"?>\n\
         <x:xmpmeta xmlns:x=\"adobe:ns:meta/\"><rdf:RDF xmlns:rdf=\"http://www.w3.org/1999/02/22-rdf-syntax-ns#\">\
         <rdf:Description rdf:about=\"\" xmlns:grime=\"https://grime.invalid/ns/1.0/\">\
         {XMP_OPEN}{text}{XMP_CLOSE}</rdf:Description></rdf:RDF></x:xmpmeta>\n\
         <?xpacket end=\"w\"?>"
    )
}

/// The recipe in an XMP packet made by [`xmp`].
pub fn from_xmp(packet: &[u8]) -> Option<String> {
    let text = std::str::from_utf8(packet).ok()?;
    let start = text.find(XMP_OPEN)? + XMP_OPEN.len();
    let end = start + text[start..].find(XMP_CLOSE)?;
    Some(
        text[start..end]
            .replace("&lt;", "<")
            .replace("&gt;", ">")
            .replace("&amp;", "&"),
    )
}

/// Adds `recipe` to an encoded flat image of `format`.
///
/// # Errors
/// What in the bytes was not as the encoder writes it.
pub fn into(format: Format, bytes: &mut Vec<u8>, recipe: &str) -> Result<(), String> {
    match format {
        Format::Png => png(bytes, recipe),
        Format::Jpeg => jpeg(bytes, recipe),
        Format::Webp => webp(bytes, recipe),
        Format::Tiff => tiff(bytes, recipe),
        Format::Psd | Format::Ora => Err("a layered format".into()),
    }
}

/// A PNG chunk: length, type, data, CRC of type and data.
pub fn png_chunk(kind: &[u8; 4], data: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(data.len() + 12);
    out.extend_from_slice(&(data.len() as u32).to_be_bytes());
    out.extend_from_slice(kind);
    out.extend_from_slice(data);
    let mut crc = crc32fast::Hasher::new();
    crc.update(kind);
    crc.update(data);
    out.extend_from_slice(&crc.finalize().to_be_bytes());
    out
}

/// An uncompressed `iTXt` chunk's data: keyword, no compression, no
/// language, the UTF-8 text.
pub fn itxt(recipe: &str) -> Vec<u8> {
    let mut data = Vec::with_capacity(recipe.len() + KEY.len() + 5);
    data.extend_from_slice(KEY.as_bytes());
    data.extend_from_slice(&[0, 0, 0, 0, 0]);
    data.extend_from_slice(recipe.as_bytes());
    data
}

/// PNG: an `iTXt` chunk just before `IEND`.
fn png(bytes: &mut Vec<u8>, recipe: &str) -> Result<(), String> {
    let end = bytes.len().checked_sub(12).ok_or("too short")?;
    if &bytes[end + 4..end + 8] != b"IEND" {
        return Err("no IEND chunk at the end".into());
    }
    let chunk = png_chunk(b"iTXt", &itxt(recipe));
    bytes.splice(end..end, chunk);
    Ok(())
}

/// JPEG: `COM` segments after the leading `APPn` segments, each starting
/// with `grime-recipe:` (a segment holds at most 65533 bytes).
fn jpeg(bytes: &mut Vec<u8>, recipe: &str) -> Result<(), String> {
    if !bytes.starts_with(&[0xFF, 0xD8]) {
        return Err("no JPEG start marker".into());
    }
    let mut at = 2;
    while at + 4 <= bytes.len() && bytes[at] == 0xFF && (0xE0..=0xEF).contains(&bytes[at + 1]) {
        at += 2 + u16::from_be_bytes([bytes[at + 2], bytes[at + 3]]) as usize;
    }
    let prefix = format!("{KEY}:");
    let mut segments = Vec::new();
    for part in recipe.as_bytes().chunks(65533 - prefix.len()) {
        segments.extend_from_slice(&[0xFF, 0xFE]);
        segments.extend_from_slice(&((2 + prefix.len() + part.len()) as u16).to_be_bytes());
        segments.extend_from_slice(prefix.as_bytes());
        segments.extend_from_slice(part);
    }
    bytes.splice(at..at, segments);
    Ok(())
}

/// WebP: an `XMP ` chunk at the end, the simple lossless format turned
/// into the extended one (`VP8X`, which says the XMP is there).
fn webp(bytes: &mut Vec<u8>, recipe: &str) -> Result<(), String> {
    if bytes.len() < 20 || &bytes[..4] != b"RIFF" || &bytes[8..12] != b"WEBP" {
        return Err("not a RIFF WebP".into());
    }
    const XMP_FLAG: u8 = 0x04;
    const ALPHA_FLAG: u8 = 0x10;
    match &bytes[12..16] {
        b"VP8X" => bytes[20] |= XMP_FLAG,
        b"VP8L" => {
            // VP8L header: 0x2f, then 14 bits width-1, 14 bits height-1,
            // 1 bit alpha (little-endian).
            let bits = u32::from_le_bytes([bytes[21], bytes[22], bytes[23], bytes[24]]);
            let (w1, h1) = (bits & 0x3FFF, (bits >> 14) & 0x3FFF);
            let alpha = if bits >> 28 & 1 == 1 { ALPHA_FLAG } else { 0 };
            let mut vp8x = vec![XMP_FLAG | alpha, 0, 0, 0];
            vp8x.extend_from_slice(&w1.to_le_bytes()[..3]);
            vp8x.extend_from_slice(&h1.to_le_bytes()[..3]);
            let mut chunk = b"VP8X".to_vec();
            chunk.extend_from_slice(&10u32.to_le_bytes());
            chunk.extend_from_slice(&vp8x);
            bytes.splice(12..12, chunk);
        }
        _ => return Err("a lossy or unknown WebP layout".into()),
    }
    let packet = xmp(recipe);
    bytes.extend_from_slice(b"XMP ");
    bytes.extend_from_slice(&(packet.len() as u32).to_le_bytes());
    bytes.extend_from_slice(packet.as_bytes());
    if packet.len() % 2 == 1 {
        bytes.push(0);
    }
    let riff = (bytes.len() - 8) as u32;
    bytes[4..8].copy_from_slice(&riff.to_le_bytes());
    Ok(())
}

/// TIFF tag of XMP metadata.
pub const TIFF_XMP: u16 = 700;

/// TIFF (little-endian, as the encoder writes): the XMP packet and a copy
/// of the first IFD with the XMP tag added, both appended; the header then
/// points at the new IFD (the old one stays, unreferenced).
fn tiff(bytes: &mut Vec<u8>, recipe: &str) -> Result<(), String> {
    if !bytes.starts_with(b"II*\0") {
        return Err("not a little-endian TIFF".into());
    }
    let u16_at = |b: &[u8], i: usize| u16::from_le_bytes([b[i], b[i + 1]]);
    let u32_at = |b: &[u8], i: usize| u32::from_le_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]);
    let ifd = u32_at(bytes, 4) as usize;
    let count = u16_at(bytes, ifd) as usize;
    let entries_end = ifd + 2 + count * 12;
    if entries_end + 4 > bytes.len() {
        return Err("IFD past the end".into());
    }
    let mut entries: Vec<[u8; 12]> = (0..count)
        .map(|i| {
            bytes[ifd + 2 + i * 12..ifd + 14 + i * 12]
                .try_into()
                .unwrap_or([0; 12])
        })
        .filter(|e| u16_at(e, 0) != TIFF_XMP)
        .collect();
    let next = u32_at(bytes, entries_end);
    if bytes.len() % 2 == 1 {
        bytes.push(0);
    }
    let packet = xmp(recipe);
    let data_at = bytes.len() as u32;
    bytes.extend_from_slice(packet.as_bytes());
    if bytes.len() % 2 == 1 {
        bytes.push(0);
    }
    let mut entry = [0u8; 12];
    entry[..2].copy_from_slice(&TIFF_XMP.to_le_bytes());
    entry[2..4].copy_from_slice(&1u16.to_le_bytes()); // BYTE
    entry[4..8].copy_from_slice(&(packet.len() as u32).to_le_bytes());
    entry[8..].copy_from_slice(&data_at.to_le_bytes());
    entries.push(entry);
    entries.sort_by_key(|e| u16_at(e, 0));
    let new_ifd = bytes.len() as u32;
    bytes.extend_from_slice(&(entries.len() as u16).to_le_bytes());
    entries.iter().for_each(|e| bytes.extend_from_slice(e));
    bytes.extend_from_slice(&next.to_le_bytes());
    bytes[4..8].copy_from_slice(&new_ifd.to_le_bytes());
    Ok(())
}
