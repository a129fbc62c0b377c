//! PSD export read back by an independent reader (the `psd` crate): layer
//! count, names, sizes, blend modes, opacities and pixels; 16-bit in gives
//! 16-bit out; failures leave no file behind.

use std::path::Path;
use std::sync::Arc;

use grime::export;
use grime::export::psd::unpackbits;
use grime::photo::Photo;
use grime::stack::{BlendMode, Layer, LayerPixels, Stack};
use image::{DynamicImage, GrayImage, ImageBuffer, Luma, Rgb, Rgba, RgbaImage};

const W: u32 = 37;
const H: u32 = 23;

fn layers() -> Vec<Layer> {
    vec![
        Layer {
            name: "rain 01".into(),
            kind: None,
            blend: BlendMode::Multiply,
            opacity: 0.8,
            visible: true,
            pixels: LayerPixels::Tint {
                color: [90, 80, 70],
                alpha: GrayImage::from_fn(W, H, |x, y| {
                    Luma([((x * 7 + y * 3) % 256) as u8 * (x % 3 != 0) as u8])
                }),
            },
        },
        Layer {
            name: "moss".into(),
            kind: None,
            blend: BlendMode::Normal,
            opacity: 0.55,
            visible: true,
            pixels: LayerPixels::Rgba(RgbaImage::from_fn(W, H, |x, y| {
                Rgba([
                    (x * 6) as u8,
                    120,
                    (y * 11) as u8,
                    if y > 10 { (x * 5) as u8 } else { 0 },
                ])
            })),
        },
        Layer {
            name: "dust film é".into(),
            kind: None,
            blend: BlendMode::Normal,
            opacity: 1.0,
            visible: false,
            pixels: LayerPixels::Tint {
                color: [200, 190, 170],
                alpha: GrayImage::from_pixel(W, H, Luma([100])),
            },
        },
        Layer {
            name: "rain washed".into(),
            kind: None,
            blend: BlendMode::Screen,
            opacity: 0.35,
            visible: true,
            pixels: LayerPixels::Tint {
                color: [200, 196, 186],
                alpha: GrayImage::from_fn(W, H, |x, _| Luma([(x * 7) as u8])),
            },
        },
    ]
}

fn region() -> GrayImage {
    GrayImage::from_fn(W, H, |x, _| Luma([if x > 4 { 255 } else { 0 }]))
}

fn stack8() -> Stack {
    let photo = image::RgbImage::from_fn(W, H, |x, y| {
        Rgb([(x * 5) as u8, (y * 9) as u8, 200 - x as u8])
    });
    Stack {
        base: Arc::new(Photo::new(DynamicImage::ImageRgb8(photo))),
        layers: layers(),
        region: Some(Arc::new(region())),
    }
}

fn read(path: &Path) -> psd::Psd {
    let bytes = std::fs::read(path).unwrap();
    psd::Psd::from_bytes(&bytes).expect("the psd crate reads our file")
}

#[test]
fn round_trip_through_the_psd_crate() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("aged.psd");
    let stack = stack8();
    export::save(&stack, &path).unwrap();
    let psd = read(&path);

    assert_eq!((psd.width(), psd.height()), (W, H));
    assert!(matches!(psd.depth(), psd::PsdDepth::Eight));
    assert!(matches!(psd.color_mode(), psd::ColorMode::Rgb));
    let names: Vec<&str> = psd.layers().iter().map(|l| l.name()).collect();
    // The psd crate lists layers top first.
    assert_eq!(
        names,
        [
            "region",
            "rain washed",
            "dust film é",
            "moss",
            "rain 01",
            "photo"
        ]
    );

    // Photo: the bottom layer, opaque.
    let photo = psd.layer_by_name("photo").unwrap();
    let want = stack.base.image().to_rgba8();
    assert_eq!((photo.width() as u32, photo.height() as u32), (W, H));
    assert_eq!(photo.rgba(), want.as_raw().as_slice());
    assert_eq!(photo.opacity(), 255);

    // Effect layers: pixels, blend mode, opacity byte.
    for l in &stack.layers {
        let got = psd.layer_by_name(&l.name).unwrap();
        assert_eq!(
            (got.width() as u32, got.height() as u32),
            (W, H),
            "{}",
            l.name
        );
        assert_eq!(
            got.rgba(),
            l.to_rgba().as_raw().as_slice(),
            "pixels of {}",
            l.name
        );
        assert_eq!(
            got.opacity(),
            (l.opacity * 255.0).round() as u8,
            "{}",
            l.name
        );
        // The psd crate does not export its BlendMode type; compare names.
        let blend = match l.blend {
            BlendMode::Normal => "Normal",
            BlendMode::Multiply => "Multiply",
            BlendMode::Screen => "Screen",
        };
        assert_eq!(format!("{:?}", got.blend_mode()), blend, "{}", l.name);
    }

    // Region: white, region as transparency.
    let region = psd.layer_by_name("region").unwrap();
    let want: Vec<u8> = region_rgba().into_raw();
    assert_eq!(region.rgba(), want);

    // Merged image section = the composite.
    assert_eq!(psd.rgba(), stack.composite().to_rgba8().into_raw());
}

fn region_rgba() -> RgbaImage {
    let r = region();
    RgbaImage::from_fn(W, H, |x, y| Rgba([255, 255, 255, r.get_pixel(x, y)[0]]))
}

/// The visibility flag, read from the raw layer records (the `psd` crate
/// reads bit 1 as "visible", the specification's wording, while Photoshop,
/// GIMP and psd-tools treat a set bit 1 as hidden).
#[test]
fn hidden_layers_have_flag_bit_1_set() {
    let bytes = export::psd::to_vec(&stack8()).unwrap();
    let records = layer_records(&bytes);
    let flags: Vec<(String, u8)> = records.iter().map(|r| (r.name.clone(), r.flags)).collect();
    let hidden: Vec<&str> = flags
        .iter()
        .filter(|(_, f)| f & 2 != 0)
        .map(|(n, _)| n.as_str())
        .collect();
    assert_eq!(hidden, ["dust film ?", "region"]);
    assert!(records.iter().all(|r| r.channels == [-1, 0, 1, 2]));
}

#[test]
fn sixteen_bit_in_gives_sixteen_bit_out() {
    let photo = ImageBuffer::<Rgb<u16>, Vec<u16>>::from_fn(W, H, |x, y| {
        Rgb([
            (x * 1700) as u16,
            (y * 2800 + 3) as u16,
            65535 - (x * y * 60) as u16,
        ])
    });
    let stack = Stack {
        base: Arc::new(Photo::new(DynamicImage::ImageRgb16(photo))),
        layers: layers(),
        region: Some(Arc::new(region())),
    };
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("deep.psd");
    export::save(&stack, &path).unwrap();

    let psd = read(&path);
    assert!(
        matches!(psd.depth(), psd::PsdDepth::Sixteen),
        "depth {:?}",
        psd.depth()
    );
    let names: Vec<&str> = psd.layers().iter().map(|l| l.name()).collect();
    assert_eq!(
        names,
        [
            "region",
            "rain washed",
            "dust film é",
            "moss",
            "rain 01",
            "photo"
        ]
    );

    // The psd crate does not decode 16-bit channels, so decode the merged
    // image ourselves and compare it with the 16-bit composite exactly.
    let bytes = std::fs::read(&path).unwrap();
    let merged = merged_image(&bytes);
    let want = stack.composite().to_rgb16();
    assert_eq!(merged.len(), 3);
    for (c, plane) in merged.iter().enumerate() {
        let got: Vec<u16> = plane
            .chunks_exact(2)
            .map(|b| u16::from_be_bytes([b[0], b[1]]))
            .collect();
        let expect: Vec<u16> = want.pixels().map(|p| p[c]).collect();
        assert_eq!(got, expect, "channel {c}");
    }
    // Layer data is scaled by 257 (so 255 stays white): the moss layer.
    let records = layer_records(&bytes);
    assert_eq!(records[2].name, "moss");
    let moss = stack.layers[1].to_rgba();
    for (i, c) in [3usize, 0, 1, 2].into_iter().enumerate() {
        let plane = layer_channel(&bytes, &records, 2, i);
        let got: Vec<u16> = plane
            .chunks_exact(2)
            .map(|b| u16::from_be_bytes([b[0], b[1]]))
            .collect();
        let expect: Vec<u16> = moss.pixels().map(|p| p[c] as u16 * 257).collect();
        assert_eq!(got, expect, "moss channel {c}");
    }
}

#[test]
fn rgba_photo_keeps_its_transparency() {
    let photo = RgbaImage::from_fn(W, H, |x, y| {
        Rgba([100, (x * 3) as u8, (y * 4) as u8, (x * 7) as u8])
    });
    let stack = Stack {
        base: Arc::new(Photo::new(DynamicImage::ImageRgba8(photo.clone()))),
        layers: Vec::new(),
        region: None,
    };
    let bytes = export::psd::to_vec(&stack).unwrap();
    assert_eq!(
        u16::from_be_bytes([bytes[12], bytes[13]]),
        4,
        "merged image has alpha"
    );
    let psd = psd::Psd::from_bytes(&bytes).unwrap();
    assert_eq!(psd.layers().len(), 1);
    assert_eq!(
        psd.layer_by_name("photo").unwrap().rgba(),
        photo.as_raw().as_slice()
    );
    assert_eq!(psd.rgba(), photo.into_raw());
}

#[test]
fn missing_folder_is_a_clear_error_and_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("no-such-folder").join("aged.psd");
    let err = export::save(&stack8(), &path).unwrap_err();
    let msg = err.to_string();
    assert!(
        msg.contains("does not exist") && msg.contains("no-such-folder"),
        "{msg}"
    );
    assert!(!path.exists());
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn failed_write_leaves_no_partial_file() {
    // The target is a folder, so the final rename fails after the data was
    // written to the temporary file: nothing may be left behind.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("aged.psd");
    std::fs::create_dir(&path).unwrap();
    assert!(export::save(&stack8(), &path).is_err());
    let left: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(left, [std::ffi::OsString::from("aged.psd")]);
    assert!(path.is_dir());
}

#[test]
fn too_wide_for_psd_is_refused() {
    let stack = Stack {
        base: Arc::new(Photo::new(DynamicImage::ImageRgb8(image::RgbImage::new(
            30_001, 1,
        )))),
        layers: Vec::new(),
        region: None,
    };
    let err = export::psd::to_vec(&stack).unwrap_err().to_string();
    assert!(err.contains("30000") && err.contains(".ora"), "{err}");
}

// ---- a minimal reader for what the psd crate does not expose ----

struct Record {
    name: String,
    flags: u8,
    channels: Vec<i16>,
    lengths: Vec<usize>,
    /// Where the channel data of all layers starts.
    data_at: usize,
}

fn be16(b: &[u8], at: usize) -> u16 {
    u16::from_be_bytes([b[at], b[at + 1]])
}

fn be32(b: &[u8], at: usize) -> u32 {
    u32::from_be_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]])
}

/// Offset of the layer and mask information section.
fn layer_section(b: &[u8]) -> usize {
    assert_eq!(&b[..4], b"8BPS");
    let mut at = 26;
    at += 4 + be32(b, at) as usize; // colour mode data
    at += 4 + be32(b, at) as usize; // image resources
    at
}

fn layer_records(b: &[u8]) -> Vec<Record> {
    let mut at = layer_section(b) + 8;
    let count = (be16(b, at) as i16).unsigned_abs();
    at += 2;
    let mut out = Vec::new();
    for _ in 0..count {
        at += 16;
        let n = be16(b, at) as usize;
        at += 2;
        let channels = (0..n).map(|i| be16(b, at + 6 * i) as i16).collect();
        let lengths = (0..n).map(|i| be32(b, at + 6 * i + 2) as usize).collect();
        at += 6 * n;
        assert_eq!(&b[at..at + 4], b"8BIM");
        let flags = b[at + 10];
        let extra = be32(b, at + 12) as usize;
        let extra_at = at + 16;
        let mut p = extra_at;
        p += 4 + be32(b, p) as usize; // mask
        p += 4 + be32(b, p) as usize; // blending ranges
        let len = b[p] as usize;
        let name = String::from_utf8(b[p + 1..p + 1 + len].to_vec()).unwrap();
        out.push(Record {
            name,
            flags,
            channels,
            lengths,
            data_at: 0,
        });
        at = extra_at + extra;
    }
    for r in &mut out {
        r.data_at = at;
    }
    out
}

/// Decodes channel `index` (position in the record) of layer `layer`.
fn layer_channel(b: &[u8], records: &[Record], layer: usize, index: usize) -> Vec<u8> {
    let h = be32(b, 14) as usize;
    let skip: usize = records[..layer]
        .iter()
        .flat_map(|r| &r.lengths)
        .sum::<usize>()
        + records[layer].lengths[..index].iter().sum::<usize>();
    let mut at = records[0].data_at + skip;
    assert_eq!(be16(b, at), 1, "RLE");
    at += 2;
    let counts: Vec<usize> = (0..h).map(|i| be16(b, at + 2 * i) as usize).collect();
    at += 2 * h;
    let mut plane = Vec::new();
    for n in counts {
        unpackbits(&b[at..at + n], &mut plane).expect("valid PackBits");
        at += n;
    }
    plane
}

/// Decodes the merged image section (RLE) into one byte plane per channel.
fn merged_image(b: &[u8]) -> Vec<Vec<u8>> {
    let channels = be16(b, 12) as usize;
    let h = be32(b, 14) as usize;
    let ls = layer_section(b);
    let mut at = ls + 4 + be32(b, ls) as usize;
    assert_eq!(be16(b, at), 1, "RLE");
    at += 2;
    let counts: Vec<usize> = (0..channels * h)
        .map(|i| be16(b, at + 2 * i) as usize)
        .collect();
    at += 2 * channels * h;
    let mut planes = Vec::new();
    for c in 0..channels {
        let mut plane = Vec::new();
        for &n in &counts[c * h..(c + 1) * h] {
            unpackbits(&b[at..at + n], &mut plane).expect("valid PackBits");
            at += n;
        }
        planes.push(plane);
    }
    assert_eq!(at, b.len(), "merged image ends the file");
    planes
}
