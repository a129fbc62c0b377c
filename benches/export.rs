//! Layered export benchmark (issue 4): a 4000x3000 photo with 12 rain-like
//! layers (multiply tints, streaky coverage) plus its region, written as a
//! PSD to a temporary folder. Target: under 1.5 s. Results: BENCHMARKS.md.

use std::sync::Arc;

use criterion::{Criterion, criterion_group, criterion_main};
use grime::export;
use grime::photo::Photo;
use grime::stack::{BlendMode, Layer, LayerPixels, Stack};
use image::{DynamicImage, GrayImage, Luma, Rgb, RgbImage};

const W: u32 = 4000;
const H: u32 = 3000;

/// A small deterministic hash, so the bench needs no random crate state.
fn hash(mut v: u64) -> u64 {
    v ^= v >> 33;
    v = v.wrapping_mul(0xff51_afd7_ed55_8ccd);
    v ^= v >> 33;
    v = v.wrapping_mul(0xc4ce_b9fe_1a85_ec53);
    v ^ (v >> 33)
}

/// Coverage like a rainfall's: vertical streaks of varying strength that
/// start at random heights and fade downwards, with grain, zero elsewhere;
/// nothing outside the region.
fn rain_alpha(layer: u64, region: &GrayImage) -> GrayImage {
    let streaks: Vec<(u32, u32, f32)> = (0..W)
        .map(|x| {
            let h = hash(layer * 1_000_003 + x as u64);
            let start = (h % H as u64) as u32;
            let len = ((h >> 20) % (H as u64 / 2)) as u32;
            let strength = if (h >> 40).is_multiple_of(3) {
                ((h >> 44) % 200) as f32
            } else {
                0.0
            };
            (start, len, strength)
        })
        .collect();
    GrayImage::from_fn(W, H, |x, y| {
        if region.get_pixel(x, y)[0] == 0 {
            return Luma([0]);
        }
        let (start, len, strength) = streaks[x as usize];
        if strength == 0.0 || y < start || y > start + len {
            return Luma([0]);
        }
        let fade = 1.0 - (y - start) as f32 / (len + 1) as f32;
        let grain = (hash(layer ^ ((y as u64) << 32 | x as u64)) % 24) as f32;
        Luma([(strength * fade + grain).min(255.0) as u8])
    })
}

fn stack() -> Stack {
    let photo = RgbImage::from_fn(W, H, |x, y| {
        let n = (hash((y as u64) << 32 | x as u64) % 40) as u8;
        Rgb([150 + n, 120 + n, 100 + (x / 100) as u8])
    });
    let region = GrayImage::from_fn(W, H, |x, y| {
        Luma([if y > 300 && x > 200 && x < 3800 {
            255
        } else {
            0
        }])
    });
    let layers = (0..12)
        .map(|i| Layer {
            name: format!("rain {:02}", i + 1),
            kind: None,
            blend: BlendMode::Multiply,
            opacity: 0.8,
            visible: true,
            pixels: LayerPixels::Tint {
                color: [92, 84, 74],
                alpha: rain_alpha(i, &region),
            },
        })
        .collect();
    Stack {
        base: Arc::new(Photo::new(DynamicImage::ImageRgb8(photo))),
        layers,
        region: Some(Arc::new(region)),
    }
}

fn psd_4000x3000(c: &mut Criterion) {
    let stack = stack();
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("aged.psd");
    let mut g = c.benchmark_group("export");
    g.sample_size(10);
    g.bench_function("psd_4000x3000_12_layers", |b| {
        b.iter(|| export::psd::write(&stack, &path).expect("write"))
    });
    g.finish();
    let size = std::fs::metadata(&path).map(|m| m.len()).unwrap_or(0);
    eprintln!("PSD size: {:.1} MB", size as f64 / 1e6);
}

criterion_group!(benches, psd_4000x3000);
criterion_main!(benches);
