//! OpenRaster export: zip entry order, an uncompressed `mimetype` first,
//! `stack.xml` parsed (layers top first, composite ops, opacity,
//! visibility), every PNG decoded at the right size with the right pixels.

use std::io::Read;
use std::sync::Arc;

use grime::export;
use grime::photo::Photo;
use grime::stack::{BlendMode, Layer, LayerPixels, Stack};
use image::{DynamicImage, GrayImage, ImageBuffer, Luma, Rgb, Rgba, RgbaImage};

const W: u32 = 300;
const H: u32 = 200;

fn stack(photo: DynamicImage) -> Stack {
    Stack {
        base: Arc::new(Photo::new(photo)),
        layers: vec![
            Layer {
                name: "rain 01".into(),
                kind: None,
                blend: BlendMode::Multiply,
                opacity: 0.8,
                visible: true,
                pixels: LayerPixels::Tint {
                    color: [90, 80, 70],
                    alpha: GrayImage::from_fn(W, H, |x, y| Luma([((x + y) % 256) as u8])),
                },
            },
            Layer {
                name: "moss & <co>".into(),
                kind: None,
                blend: BlendMode::Normal,
                opacity: 0.25,
                visible: false,
                pixels: LayerPixels::Rgba(RgbaImage::from_fn(W, H, |x, y| {
                    Rgba([x as u8, 120, y as u8, if y > 100 { 200 } else { 0 }])
                })),
            },
        ],
        region: Some(Arc::new(GrayImage::from_fn(W, H, |x, _| {
            Luma([if x > 10 { 255 } else { 0 }])
        }))),
    }
}

fn photo8() -> DynamicImage {
    DynamicImage::ImageRgb8(image::RgbImage::from_fn(W, H, |x, y| {
        Rgb([x as u8, y as u8, 77])
    }))
}

fn entry(zip: &mut zip::ZipArchive<std::fs::File>, name: &str) -> Vec<u8> {
    let mut f = zip
        .by_name(name)
        .unwrap_or_else(|_| panic!("{name} in the zip"));
    let mut buf = Vec::new();
    f.read_to_end(&mut buf).unwrap();
    buf
}

#[test]
fn structure_follows_the_spec() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("aged.ora");
    let stack = stack(photo8());
    export::save(&stack, &path).unwrap();

    // mimetype: first, stored, no extra field, so its content sits at 38.
    let bytes = std::fs::read(&path).unwrap();
    assert_eq!(&bytes[..4], b"PK\x03\x04");
    assert_eq!(u16::from_le_bytes([bytes[8], bytes[9]]), 0, "stored");
    assert_eq!(&bytes[30..38], b"mimetype");
    assert_eq!(
        u16::from_le_bytes([bytes[28], bytes[29]]),
        0,
        "no extra field"
    );
    assert_eq!(&bytes[38..54], b"image/openraster");

    let mut zip = zip::ZipArchive::new(std::fs::File::open(&path).unwrap()).unwrap();
    let names: Vec<String> = (0..zip.len())
        .map(|i| zip.by_index(i).unwrap().name().to_string())
        .collect();
    assert_eq!(names[0], "mimetype");
    assert_eq!(
        zip.by_index(0).unwrap().compression(),
        zip::CompressionMethod::Stored
    );
    assert_eq!(names[1], "stack.xml");
    let n = names.len();
    assert!(
        names[2..n - 2]
            .iter()
            .all(|s| s.starts_with("data/") && s.ends_with(".png")),
        "{names:?}"
    );
    assert_eq!(n - 4, 4, "photo, two layers, region: {names:?}");
    assert_eq!(
        &names[n - 2..],
        ["mergedimage.png", "Thumbnails/thumbnail.png"]
    );

    // stack.xml, top first.
    let xml = String::from_utf8(entry(&mut zip, "stack.xml")).unwrap();
    let doc = roxmltree::Document::parse(&xml).unwrap();
    let image = doc.root_element();
    assert_eq!(image.tag_name().name(), "image");
    assert_eq!(image.attribute("w"), Some("300"));
    assert_eq!(image.attribute("h"), Some("200"));
    let stack_el = image.children().find(|n| n.has_tag_name("stack")).unwrap();
    let layers: Vec<_> = stack_el
        .children()
        .filter(|n| n.has_tag_name("layer"))
        .collect();
    let attrs = |i: usize, a: &str| layers[i].attribute(a).unwrap().to_string();
    let got: Vec<(String, String, String, String)> = (0..layers.len())
        .map(|i| {
            (
                attrs(i, "name"),
                attrs(i, "composite-op"),
                attrs(i, "visibility"),
                attrs(i, "opacity"),
            )
        })
        .collect();
    let want = [
        ("region", "svg:src-over", "hidden", 1.0),
        ("moss & <co>", "svg:src-over", "hidden", 0.25),
        ("rain 01", "svg:multiply", "visible", 0.8),
        ("photo", "svg:src-over", "visible", 1.0),
    ];
    assert_eq!(got.len(), want.len());
    for (g, w) in got.iter().zip(want) {
        assert_eq!((g.0.as_str(), g.1.as_str(), g.2.as_str()), (w.0, w.1, w.2));
        assert!((g.3.parse::<f32>().unwrap() - w.3).abs() < 1e-6, "{g:?}");
    }

    // Every layer PNG: photo size, the layer's pixels.
    let expected: Vec<RgbaImage> = vec![
        RgbaImage::from_fn(W, H, |x, _| {
            Rgba([255, 255, 255, if x > 10 { 255 } else { 0 }])
        }),
        stack.layers[1].to_rgba(),
        stack.layers[0].to_rgba(),
        stack.base.image().to_rgba8(),
    ];
    for (i, want) in expected.iter().enumerate() {
        assert_eq!(attrs(i, "x"), "0");
        assert_eq!(attrs(i, "y"), "0");
        let src = attrs(i, "src");
        assert!(names.contains(&src), "{src} listed in the zip");
        let png = image::load_from_memory(&entry(&mut zip, &src)).unwrap();
        assert_eq!((png.width(), png.height()), (W, H), "{src}");
        assert!(png.to_rgba8() == *want, "pixels of {src}");
    }

    // Merged image: the composite, RGBA 8-bit; thumbnail: at most 256 px.
    let merged = image::load_from_memory(&entry(&mut zip, "mergedimage.png")).unwrap();
    assert_eq!(merged.color(), image::ColorType::Rgba8);
    assert!(merged.to_rgba8() == stack.composite().to_rgba8());
    let thumb = image::load_from_memory(&entry(&mut zip, "Thumbnails/thumbnail.png")).unwrap();
    assert_eq!((thumb.width(), thumb.height()), (256, 171));
    assert_eq!(thumb.color(), image::ColorType::Rgba8);
}

#[test]
fn sixteen_bit_photo_layer_stays_sixteen_bit() {
    let photo = ImageBuffer::<Rgb<u16>, Vec<u16>>::from_fn(W, H, |x, y| {
        Rgb([(x * 200) as u16, (y * 300) as u16, 1])
    });
    let stack = stack(DynamicImage::ImageRgb16(photo.clone()));
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("deep.ora");
    export::save(&stack, &path).unwrap();
    let mut zip = zip::ZipArchive::new(std::fs::File::open(&path).unwrap()).unwrap();
    let png = image::load_from_memory(&entry(&mut zip, "data/00-photo.png")).unwrap();
    assert_eq!(png.to_rgb16(), photo);
}

/// The ICC profile of a PNG held in memory.
fn png_icc(data: Vec<u8>) -> Option<Vec<u8>> {
    use image::ImageDecoder;
    let mut dec = image::codecs::png::PngDecoder::new(std::io::Cursor::new(data)).unwrap();
    dec.icc_profile().unwrap()
}

/// Issue 13, item 18: a 16-bit photo PNG without a colour chunk stops
/// `krita --export` at a profile prompt. The photo layer and the merged
/// image say sRGB when the photo has no profile, and keep the photo's own.
#[test]
fn photo_and_merged_pngs_carry_a_profile() {
    let dir = tempfile::tempdir().unwrap();
    let deep = DynamicImage::ImageRgb16(ImageBuffer::from_pixel(W, H, Rgb([9000u16, 500, 1])));
    let mut own = Photo::new(photo8());
    own.icc = Some(grime::io::icc::srgb()[..].to_vec());
    own.icc.as_mut().unwrap()[48] = b'X'; // a different, still valid profile
    for (photo, want) in [
        (Photo::new(deep), grime::io::icc::srgb().to_vec()),
        (Photo::new(photo8()), grime::io::icc::srgb().to_vec()),
        (own.clone(), own.icc.clone().unwrap()),
    ] {
        let mut st = stack(DynamicImage::ImageRgb8(photo8().to_rgb8()));
        st.base = Arc::new(photo);
        let path = dir.path().join("p.ora");
        export::save(&st, &path).unwrap();
        let mut zip = zip::ZipArchive::new(std::fs::File::open(&path).unwrap()).unwrap();
        for name in ["data/00-photo.png", "mergedimage.png"] {
            assert_eq!(
                png_icc(entry(&mut zip, name)).as_ref(),
                Some(&want),
                "{name}"
            );
        }
    }
}

#[test]
fn missing_folder_is_a_clear_error_and_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("missing").join("aged.ora");
    let err = export::save(&stack(photo8()), &path)
        .unwrap_err()
        .to_string();
    assert!(err.contains("does not exist"), "{err}");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}
