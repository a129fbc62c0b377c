//! Layered Photoshop documents (`.psd`), written from Adobe's "Photoshop File
//! Formats Specification" (no crate writes layered PSD).
//!
//! What the file holds:
//!
//! - RGB at 8 bits per channel, or 16 when the photo is 16-bit (effect layers
//!   are then scaled by 257, so 255 stays full white).
//! - One layer per [`crate::stack::Layer`] in stacking order, above the
//!   original photo as the bottom layer named `photo`. Every layer covers the
//!   whole canvas and has a transparency channel (id -1) and R, G, B, all
//!   RLE (PackBits) compressed row by row. Blend keys are `norm` and `mul `,
//!   the opacity byte is `round(opacity * 255)`, hidden layers have flag bit 1
//!   set. Names are stored as a Pascal string and, in full Unicode, in a
//!   `luni` block.
//! - **The region** (when the stack has one) as a separate hidden layer named
//!   `region` at the top: white, with the region as its transparency. It does
//!   not change the picture; Ctrl/Cmd-click its thumbnail in Photoshop (Alpha
//!   to Selection in GIMP, Krita) to select the wall. A layer mask was not
//!   used because the effect layers are already cut to the region and a mask
//!   on each of them would only repeat it.
//! - The merged image section is [`Stack::composite`], RLE compressed, so
//!   viewers that ignore layers show the aged result. An alpha channel in the
//!   photo becomes the merged image's transparency (negative layer count).
//! - The photo's ICC profile as image resource 1039; the sRGB profile
//!   ([`io::icc::srgb`]) when the photo has none.
//!
//! The PSD format allows at most 30000 pixels per side; larger stacks are
//! refused with [`Error::Encode`] (write `.ora` instead).
//!
//! Compression runs in parallel, one task per channel of each layer (rayon).

use std::io::Write;
use std::path::Path;

use image::{DynamicImage, GrayImage};
use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::io;
use crate::stack::{BlendMode, Layer, LayerPixels, Stack};

/// Largest width or height a PSD file can have.
pub const MAX_SIDE: u32 = 30_000;

/// Name of the bottom layer holding the original photo.
pub const PHOTO_LAYER: &str = "photo";

/// Name of the hidden layer holding the region.
pub const REGION_LAYER: &str = "region";

/// Writes `stack` as a layered PSD to `path`, atomically (see
/// [`io::write_atomic`]).
///
/// # Errors
/// [`Error::Io`] when the folder is missing or the file cannot be written;
/// [`Error::Encode`] when the image is larger than PSD allows.
pub fn write(stack: &Stack, path: &Path) -> Result<()> {
    write_with(stack, path, None)
}

/// Image resource of XMP metadata, where [`write_with`] puts the recipe.
pub const XMP_RESOURCE: u16 = 1060;

/// [`write`], with an XMP packet (the recipe) as image resource 1060.
///
/// # Errors
/// As [`write`].
pub fn write_with(stack: &Stack, path: &Path, xmp: Option<&[u8]>) -> Result<()> {
    let doc = Document::build(stack, path, xmp)?;
    io::write_atomic(path, |out| {
        doc.write_to(out).map_err(|e| Error::io(path, e))
    })
}

/// Encodes `stack` as a layered PSD in memory (see [`write`]).
///
/// # Errors
/// [`Error::Encode`] when the image is larger than PSD allows.
pub fn to_vec(stack: &Stack) -> Result<Vec<u8>> {
    let doc = Document::build(stack, Path::new("<memory>"), None)?;
    let mut out = Vec::with_capacity(doc.len() as usize);
    doc.write_to(&mut out)
        .map_err(|e| Error::io("<memory>", e))?;
    Ok(out)
}

/// Where the pixels of one PSD layer (or the merged image) come from.
enum Source<'a> {
    /// A flat image at the document's depth (the photo, the composite).
    Image(&'a DynamicImage),
    /// An 8-bit straight-alpha layer.
    Layer(&'a Layer),
}

/// One layer record's settings.
struct Entry<'a> {
    name: &'a str,
    blend: BlendMode,
    opacity: f32,
    visible: bool,
    source: Source<'a>,
}

/// One RLE-compressed channel, in bands of rows as they were compressed.
struct Packed {
    bands: Vec<Band>,
}

/// Some rows of a channel: the byte count of each row, then the rows.
struct Band {
    counts: Vec<u16>,
    data: Vec<u8>,
}

impl Packed {
    /// Bytes of the row counts and data (without the compression field).
    fn len(&self) -> u64 {
        self.bands
            .iter()
            .map(|b| 2 * b.counts.len() as u64 + b.data.len() as u64)
            .sum()
    }

    /// Writes the row byte counts, big-endian.
    fn write_counts(&self, out: &mut impl Write) -> std::io::Result<()> {
        for b in &self.bands {
            let bytes: Vec<u8> = b.counts.iter().flat_map(|c| c.to_be_bytes()).collect();
            out.write_all(&bytes)?;
        }
        Ok(())
    }

    /// Writes the compressed rows.
    fn write_data(&self, out: &mut impl Write) -> std::io::Result<()> {
        for b in &self.bands {
            out.write_all(&b.data)?;
        }
        Ok(())
    }
}

/// Layer channel ids in the order they are written, with the RGBA index each
/// one reads: transparency first, as Photoshop writes them.
const LAYER_CHANNELS: [(i16, usize); 4] = [(-1, 3), (0, 0), (1, 1), (2, 2)];

/// Everything needed to write the file, compressed.
struct Document {
    /// File header, colour mode data and image resources.
    head: Vec<u8>,
    /// Section lengths, layer count and the layer records.
    layer_info_head: Vec<u8>,
    /// The four channels of each layer, bottom layer first.
    layer_channels: Vec<Packed>,
    /// Zero bytes that round the layer info up to a multiple of 4.
    layer_info_pad: usize,
    /// The (empty) global layer mask info.
    mask_section_tail: Vec<u8>,
    /// The merged image's channels.
    merged: Vec<Packed>,
}

impl Document {
    fn build(stack: &Stack, path: &Path, xmp: Option<&[u8]>) -> Result<Document> {
        let photo = stack.base.image();
        let (w, h) = (photo.width(), photo.height());
        if w > MAX_SIDE || h > MAX_SIDE || w == 0 || h == 0 {
            return Err(Error::Encode {
                path: path.to_path_buf(),
                reason: format!(
                    "the image is {w}x{h}; PSD files hold 1 to {MAX_SIDE} pixels per side (write .ora instead)"
                ),
            });
        }
        let deep = stack.base.is_16bit();
        let composite = stack.composite();
        let merged_alpha = composite.color().has_alpha();
        let region_layer = stack.region.as_deref().map(region_layer);

        let mut entries = Vec::with_capacity(stack.layers.len() + 2);
        entries.push(Entry {
            name: PHOTO_LAYER,
            blend: BlendMode::Normal,
            opacity: 1.0,
            visible: true,
            source: Source::Image(photo),
        });
        for l in &stack.layers {
            entries.push(Entry {
                name: &l.name,
                blend: l.blend,
                opacity: l.opacity,
                visible: l.visible,
                source: Source::Layer(l),
            });
        }
        if let Some(l) = &region_layer {
            entries.push(Entry {
                name: &l.name,
                blend: l.blend,
                opacity: l.opacity,
                visible: l.visible,
                source: Source::Layer(l),
            });
        }
        if entries.len() > i16::MAX as usize {
            return Err(Error::Encode {
                path: path.to_path_buf(),
                reason: format!(
                    "{} layers; PSD files hold at most {}",
                    entries.len(),
                    i16::MAX
                ),
            });
        }

        // Compress every channel of every layer, and the merged image's, in
        // parallel: one task per band of rows of each layer, which expands
        // each row once and packs all its channels.
        let merged_channels: Vec<usize> = if merged_alpha {
            vec![0, 1, 2, 3]
        } else {
            vec![0, 1, 2]
        };
        let layer_channels: Vec<usize> = LAYER_CHANNELS.iter().map(|&(_, c)| c).collect();
        let composite_src = Source::Image(&composite);
        let sources: Vec<(&Source, &[usize])> = entries
            .iter()
            .map(|e| (&e.source, layer_channels.as_slice()))
            .chain(std::iter::once((
                &composite_src,
                merged_channels.as_slice(),
            )))
            .collect();
        let mut packed = pack_all(&sources, w, h, deep);
        let merged = packed.split_off(entries.len() * 4);

        // Header, colour mode data, image resources.
        let mut head = Vec::new();
        head.extend_from_slice(b"8BPS");
        head.put_u16(1);
        head.extend_from_slice(&[0; 6]);
        head.put_u16(merged_channels.len() as u16);
        head.put_u32(h);
        head.put_u32(w);
        head.put_u16(if deep { 16 } else { 8 });
        head.put_u16(3); // RGB
        head.put_u32(0); // no colour mode data
        let mut resources = Vec::new();
        // Without a profile Krita opens a 16-bit PSD as linear light: say
        // sRGB (issue 13, item 17).
        let icc = stack.base.icc.as_deref().unwrap_or(io::icc::srgb());
        for (id, data) in [(1039, Some(icc)), (XMP_RESOURCE, xmp)] {
            let Some(data) = data else { continue };
            resources.extend_from_slice(b"8BIM");
            resources.put_u16(id); // 1039: ICC profile
            resources.put_u16(0); // empty name, padded to even
            resources.put_u32(len_u32(data.len() as u64, path)?);
            resources.extend_from_slice(data);
            if data.len() % 2 == 1 {
                resources.push(0);
            }
        }
        head.put_u32(len_u32(resources.len() as u64, path)?);
        head.extend_from_slice(&resources);

        // Layer info: count, records; channel data follows when writing.
        let mut info = Vec::new();
        let count = entries.len() as i16;
        info.put_u16(if merged_alpha { -count } else { count } as u16);
        for (e, chans) in entries.iter().zip(packed.chunks_exact(4)) {
            layer_record(&mut info, e, w, h, chans, path)?;
        }
        let channel_bytes: u64 = packed.iter().map(|p| 2 + p.len()).sum();
        let info_len = info.len() as u64 + channel_bytes;
        let layer_info_pad = ((4 - info_len % 4) % 4) as usize;
        let info_len = info_len + layer_info_pad as u64;
        // Section length: layer info length field + layer info + empty global
        // layer mask info.
        let section_len = len_u32(4 + info_len + 4, path)?;
        let mut layer_info_head = Vec::with_capacity(info.len() + 8);
        layer_info_head.put_u32(section_len);
        layer_info_head.put_u32(len_u32(info_len, path)?);
        layer_info_head.extend_from_slice(&info);
        let mut mask_section_tail = Vec::new();
        mask_section_tail.put_u32(0); // global layer mask info: none

        Ok(Document {
            head,
            layer_info_head,
            layer_channels: packed,
            layer_info_pad,
            mask_section_tail,
            merged,
        })
    }

    /// Size of the file in bytes.
    fn len(&self) -> u64 {
        self.head.len() as u64
            + self.layer_info_head.len() as u64
            + self.layer_channels.iter().map(|p| 2 + p.len()).sum::<u64>()
            + self.layer_info_pad as u64
            + self.mask_section_tail.len() as u64
            + 2
            + self.merged.iter().map(Packed::len).sum::<u64>()
    }

    fn write_to(&self, out: &mut impl Write) -> std::io::Result<()> {
        out.write_all(&self.head)?;
        out.write_all(&self.layer_info_head)?;
        for p in &self.layer_channels {
            out.write_all(&1u16.to_be_bytes())?; // RLE
            p.write_counts(out)?;
            p.write_data(out)?;
        }
        out.write_all(&[0; 4][..self.layer_info_pad])?;
        out.write_all(&self.mask_section_tail)?;
        // Merged image: compression, all row counts, then all data.
        out.write_all(&1u16.to_be_bytes())?;
        for p in &self.merged {
            p.write_counts(out)?;
        }
        for p in &self.merged {
            p.write_data(out)?;
        }
        Ok(())
    }
}

/// The hidden layer carrying the region: white, region as transparency.
fn region_layer(region: &GrayImage) -> Layer {
    Layer {
        name: REGION_LAYER.into(),
        kind: None,
        blend: BlendMode::Normal,
        opacity: 1.0,
        visible: false,
        pixels: LayerPixels::Tint {
            color: [255, 255, 255],
            alpha: region.clone(),
        },
    }
}

fn len_u32(n: u64, path: &Path) -> Result<u32> {
    u32::try_from(n).map_err(|_| Error::Encode {
        path: path.to_path_buf(),
        reason: "the layers need more than 4 GiB; PSD cannot hold them (write .ora instead)".into(),
    })
}

/// Appends one layer record.
fn layer_record(
    out: &mut Vec<u8>,
    e: &Entry,
    w: u32,
    h: u32,
    chans: &[Packed],
    path: &Path,
) -> Result<()> {
    out.put_u32(0); // top
    out.put_u32(0); // left
    out.put_u32(h); // bottom
    out.put_u32(w); // right
    out.put_u16(LAYER_CHANNELS.len() as u16);
    for (&(id, _), p) in LAYER_CHANNELS.iter().zip(chans) {
        out.put_u16(id as u16);
        out.put_u32(len_u32(2 + p.len(), path)?);
    }
    out.extend_from_slice(b"8BIM");
    out.extend_from_slice(blend_key(e.blend));
    out.push(opacity_byte(e.opacity));
    out.push(0); // clipping: base
    // Bit 3: bit 4 is meaningful (pixel data relevant); bit 1: hidden.
    out.push(0x08 | if e.visible { 0 } else { 0x02 });
    out.push(0); // filler

    let mut extra = Vec::new();
    extra.put_u32(0); // no layer mask
    extra.put_u32(0); // no blending ranges
    // Legacy name: Pascal string (ASCII, '?' for others), padded to 4.
    let legacy: Vec<u8> = e
        .name
        .chars()
        .map(|c| {
            if c.is_ascii() && !c.is_ascii_control() {
                c as u8
            } else {
                b'?'
            }
        })
        .take(255)
        .collect();
    extra.push(legacy.len() as u8);
    extra.extend_from_slice(&legacy);
    while extra.len() % 4 != 0 {
        extra.push(0);
    }
    // 'luni': the full Unicode name. Data padded to a multiple of 4 so every
    // reader's idea of block alignment agrees.
    let utf16: Vec<u16> = e.name.encode_utf16().collect();
    let mut luni = Vec::with_capacity(4 + 2 * utf16.len() + 2);
    luni.put_u32(utf16.len() as u32);
    for u in &utf16 {
        luni.put_u16(*u);
    }
    while luni.len() % 4 != 0 {
        luni.push(0);
    }
    extra.extend_from_slice(b"8BIM");
    extra.extend_from_slice(b"luni");
    extra.put_u32(luni.len() as u32);
    extra.extend_from_slice(&luni);

    out.put_u32(extra.len() as u32);
    out.extend_from_slice(&extra);
    Ok(())
}

/// Photoshop's blend-mode key.
pub fn blend_key(blend: BlendMode) -> &'static [u8; 4] {
    match blend {
        BlendMode::Normal => b"norm",
        BlendMode::Multiply => b"mul ",
        BlendMode::Screen => b"scrn",
    }
}

/// Layer opacity as the PSD opacity byte (0 = transparent, 255 = opaque).
/// Computed in f64: in f32, 0.7 * 255 rounds up to exactly 178.5.
pub fn opacity_byte(opacity: f32) -> u8 {
    (opacity.clamp(0.0, 1.0) as f64 * 255.0).round() as u8
}

/// Rows per parallel task.
const BAND: usize = 64;

/// Compresses the given channels (RGBA indices) of every source, returning
/// them in order: all channels of the first source, then the next...
fn pack_all(sources: &[(&Source, &[usize])], w: u32, h: u32, deep: bool) -> Vec<Packed> {
    let n_bands = (h as usize).div_ceil(BAND);
    let tasks: Vec<(usize, usize)> = (0..sources.len())
        .flat_map(|s| (0..n_bands).map(move |b| (s, b)))
        .collect();
    let parts: Vec<Vec<Band>> = tasks
        .par_iter()
        .map(|&(s, b)| {
            let (src, channels) = sources[s];
            let rows = b * BAND..((b + 1) * BAND).min(h as usize);
            pack_band(src, channels, rows, w as usize, deep)
        })
        .collect();
    // Regroup: for each source, for each channel, its bands in order.
    let mut parts: Vec<std::vec::IntoIter<Band>> = parts.into_iter().map(Vec::into_iter).collect();
    let mut out = Vec::new();
    for (s, (_, channels)) in sources.iter().enumerate() {
        for _ in 0..channels.len() {
            let bands = parts[s * n_bands..(s + 1) * n_bands]
                .iter_mut()
                .flat_map(|p| p.next())
                .collect();
            out.push(Packed { bands });
        }
    }
    out
}

/// Compresses `rows` of the given channels (RGBA indices) of `src`.
fn pack_band(
    src: &Source,
    channels: &[usize],
    rows: std::ops::Range<usize>,
    w: usize,
    deep: bool,
) -> Vec<Band> {
    let n = rows.len();
    let mut out: Vec<Band> = channels
        .iter()
        .map(|_| Band {
            counts: Vec::with_capacity(n),
            data: Vec::new(),
        })
        .collect();
    let bytes_per = if deep { 2 } else { 1 };
    // One plane per RGBA channel; alpha stays opaque for images without it.
    let mut planes: [Vec<u8>; 4] = std::array::from_fn(|_| vec![255u8; w * bytes_per]);
    let mut rgba = vec![0u8; w * 4];
    for y in rows {
        match src {
            Source::Layer(layer) => {
                layer.rgba_row(y as u32, &mut rgba);
                if deep {
                    split_rgba8_deep(&rgba, &mut planes);
                } else {
                    split_rgba8(&rgba, &mut planes);
                }
            }
            Source::Image(img) => {
                let w = img.width() as usize;
                match img {
                    DynamicImage::ImageRgb8(i) => {
                        split_rgb8(&i.as_raw()[y * w * 3..(y + 1) * w * 3], &mut planes)
                    }
                    DynamicImage::ImageRgba8(i) => {
                        split_rgba8(&i.as_raw()[y * w * 4..(y + 1) * w * 4], &mut planes)
                    }
                    DynamicImage::ImageRgb16(i) => {
                        split16::<3>(&i.as_raw()[y * w * 3..(y + 1) * w * 3], &mut planes)
                    }
                    DynamicImage::ImageRgba16(i) => {
                        split16::<4>(&i.as_raw()[y * w * 4..(y + 1) * w * 4], &mut planes)
                    }
                    _ => unreachable!("Photo::new normalises the layout"),
                }
            }
        }
        for (&c, band) in channels.iter().zip(&mut out) {
            let before = band.data.len();
            packbits(&planes[c], &mut band.data);
            // At most 30000 * 2 bytes plus one header per 128: fits in u16.
            band.counts.push((band.data.len() - before) as u16);
        }
    }
    out
}

/// Splits 8-bit RGBA pixels into four planes, in one pass.
fn split_rgba8(src: &[u8], planes: &mut [Vec<u8>; 4]) {
    let [r, g, b, a] = planes;
    let px = src.as_chunks::<4>().0;
    for ((((p, r), g), b), a) in px
        .iter()
        .zip(r.iter_mut())
        .zip(g.iter_mut())
        .zip(b.iter_mut())
        .zip(a.iter_mut())
    {
        // One load per pixel, shifts instead of four byte loads: lets the
        // compiler vectorise this with plain SSE2.
        let v = u32::from_le_bytes(*p);
        (*r, *g, *b, *a) = (v as u8, (v >> 8) as u8, (v >> 16) as u8, (v >> 24) as u8);
    }
}

/// Splits 8-bit RGB pixels into the first three planes.
fn split_rgb8(src: &[u8], planes: &mut [Vec<u8>; 4]) {
    let [r, g, b, _] = planes;
    let px = src.as_chunks::<3>().0;
    for (((p, r), g), b) in px
        .iter()
        .zip(r.iter_mut())
        .zip(g.iter_mut())
        .zip(b.iter_mut())
    {
        (*r, *g, *b) = (p[0], p[1], p[2]);
    }
}

/// Splits 8-bit RGBA pixels into four 16-bit big-endian planes: v * 257 is
/// the byte v twice.
fn split_rgba8_deep(src: &[u8], planes: &mut [Vec<u8>; 4]) {
    let [r, g, b, a] = planes;
    let px = src.as_chunks::<4>().0;
    let (r, g, b, a) = (
        r.as_chunks_mut::<2>().0,
        g.as_chunks_mut::<2>().0,
        b.as_chunks_mut::<2>().0,
        a.as_chunks_mut::<2>().0,
    );
    for ((((p, r), g), b), a) in px
        .iter()
        .zip(r.iter_mut())
        .zip(g.iter_mut())
        .zip(b.iter_mut())
        .zip(a.iter_mut())
    {
        let v = u32::from_le_bytes(*p);
        (*r, *g, *b, *a) = (
            [v as u8; 2],
            [(v >> 8) as u8; 2],
            [(v >> 16) as u8; 2],
            [(v >> 24) as u8; 2],
        );
    }
}

/// Splits 16-bit pixels of `N` channels into big-endian planes.
fn split16<const N: usize>(src: &[u16], planes: &mut [Vec<u8>; 4]) {
    let px = src.as_chunks::<N>().0;
    for (k, plane) in planes.iter_mut().take(N).enumerate() {
        for (o, p) in plane.as_chunks_mut::<2>().0.iter_mut().zip(px) {
            *o = p[k].to_be_bytes();
        }
    }
}

/// PackBits (Apple, TIFF, PSD) compression of `src`, appended to `out`:
/// runs of 2 to 128 equal bytes become a repeat packet, everything else
/// literal packets of up to 128 bytes.
pub fn packbits(src: &[u8], out: &mut Vec<u8>) {
    let n = src.len();
    let mut i = 0;
    while i < n {
        let b = src[i];
        let max = (n - i).min(128);
        let mut run = 1;
        // Eight bytes at a time through long runs, then byte by byte.
        while run + 8 <= max && src[i + run..i + run + 8] == [b; 8] {
            run += 8;
        }
        while run < max && src[i + run] == b {
            run += 1;
        }
        if run >= 2 {
            out.push((257 - run) as u8); // -(run - 1) as a signed byte
            out.push(b);
            i += run;
            continue;
        }
        // Literal: up to the start of a run of 3, or 128 bytes.
        let start = i;
        let end = (start + 128).min(n);
        i += 1;
        while i < end {
            // Skip eight bytes at a time while no byte equals its successor.
            while i + 9 <= end {
                let x = load8(src, i) ^ load8(src, i + 1);
                if x.wrapping_sub(0x0101_0101_0101_0101) & !x & 0x8080_8080_8080_8080 != 0 {
                    break;
                }
                i += 8;
            }
            if i >= end || (i + 2 < n && src[i] == src[i + 1] && src[i] == src[i + 2]) {
                break;
            }
            i += 1;
        }
        out.push((i - start - 1) as u8);
        out.extend_from_slice(&src[start..i]);
    }
}

/// PackBits decoding of `src`, appended to `out`: a header byte h in
/// 0..=127 copies the next h + 1 bytes, h in -127..=-1 (as a signed byte)
/// repeats the next byte 1 - h times, and -128 is skipped. `None` when a
/// packet runs past the end of `src`; `out` then holds the packets before
/// it. Never panics, and never writes more than 64 bytes per input byte.
///
/// ```
/// use grime::export::psd::{packbits, unpackbits};
/// let mut packed = Vec::new();
/// packbits(&[7, 7, 7, 1, 2], &mut packed);
/// let mut out = Vec::new();
/// assert_eq!(unpackbits(&packed, &mut out), Some(()));
/// assert_eq!(out, [7, 7, 7, 1, 2]);
/// assert_eq!(unpackbits(&[5, 1], &mut out), None); // 6 literals promised, 1 given
/// ```
pub fn unpackbits(mut src: &[u8], out: &mut Vec<u8>) -> Option<()> {
    while let Some((&h, rest)) = src.split_first() {
        let h = h as i8;
        src = if h >= 0 {
            let n = h as usize + 1;
            out.extend_from_slice(rest.get(..n)?);
            &rest[n..]
        } else if h != -128 {
            let (&b, after) = rest.split_first()?;
            out.extend(std::iter::repeat_n(b, (1 - h as isize) as usize));
            after
        } else {
            rest
        };
    }
    Some(())
}

/// Eight bytes from `at` as a little-endian word (`at + 8 <= src.len()`).
#[inline]
fn load8(src: &[u8], at: usize) -> u64 {
    let mut b = [0u8; 8];
    b.copy_from_slice(&src[at..at + 8]);
    u64::from_le_bytes(b)
}

/// Big-endian writes.
trait PutBe {
    fn put_u16(&mut self, v: u16);
    fn put_u32(&mut self, v: u32);
}

impl PutBe for Vec<u8> {
    fn put_u16(&mut self, v: u16) {
        self.extend_from_slice(&v.to_be_bytes());
    }
    fn put_u32(&mut self, v: u32) {
        self.extend_from_slice(&v.to_be_bytes());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unpack(src: &[u8]) -> Vec<u8> {
        let mut out = Vec::new();
        unpackbits(src, &mut out).expect("valid PackBits");
        out
    }

    #[test]
    fn packbits_round_trips() {
        use proptest::prelude::*;
        // Few distinct values so runs of every length occur.
        proptest!(|(v in proptest::collection::vec(0u8..3, 0..600))| {
            let mut out = Vec::new();
            packbits(&v, &mut out);
            prop_assert_eq!(unpack(&out), v.clone());
            prop_assert!(out.len() <= v.len() + v.len().div_ceil(128));
        });
    }

    #[test]
    fn unpackbits_refuses_truncated_input_without_panicking() {
        use proptest::prelude::*;
        proptest!(|(v in proptest::collection::vec(any::<u8>(), 0..300))| {
            let mut out = Vec::new();
            if unpackbits(&v, &mut out).is_some() {
                // A valid stream re-encodes to the same bytes.
                let mut again = Vec::new();
                packbits(&out, &mut again);
                prop_assert_eq!(unpack(&again), out.clone());
            }
            prop_assert!(out.len() <= 64 * v.len() + 64);
        });
        let mut out = Vec::new();
        assert_eq!(
            unpackbits(&[2, 1, 2], &mut out),
            None,
            "3 literals, 2 given"
        );
        assert_eq!(
            unpackbits(&[0xFE], &mut out),
            None,
            "a repeat without its byte"
        );
        out.clear();
        assert_eq!(unpackbits(&[0x80, 0xFF, 9], &mut out), Some(()));
        assert_eq!(out, [9, 9], "-128 is skipped, -1 repeats twice");
    }

    #[test]
    fn packbits_known_bytes() {
        let mut out = Vec::new();
        packbits(&[7; 300], &mut out);
        assert_eq!(out, [129, 7, 129, 7, 213, 7]); // 128 + 128 + 44
        out.clear();
        packbits(&[1, 2, 3], &mut out);
        assert_eq!(out, [2, 1, 2, 3]);
    }

    #[test]
    fn opacity_and_keys() {
        assert_eq!(opacity_byte(1.0), 255);
        assert_eq!(opacity_byte(0.5), 128);
        assert_eq!(opacity_byte(-1.0), 0);
        assert_eq!(blend_key(BlendMode::Multiply), b"mul ");
        assert_eq!(blend_key(BlendMode::Screen), b"scrn");
    }
}
