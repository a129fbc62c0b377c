//! Fuzz-style check of the loaders and validation (issue 13): 12,000
//! deterministic mutations of image bytes, masks, preset TOML and `--set`
//! strings. No input may panic, and none may make a single allocation over
//! [`ALLOC_BOUND`] (a counting allocator watches every one). The regression
//! files of tests/regressions/ are the first inputs.
//!
//! A failing input is written to `target/fuzz-failure.bin` with its index.

use std::alloc::{GlobalAlloc, Layout, System};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

use image::DynamicImage;
use rand::{Rng, SeedableRng};

/// Largest single allocation any input may cause. The memory limit below
/// (64 MiB at 37 B/px, about 1.8 MP) bounds the decoded image to ~15 MB.
const ALLOC_BOUND: usize = 64 << 20;

struct Counting;

static LARGEST: AtomicUsize = AtomicUsize::new(0);

// SAFETY: forwards to the system allocator; only records sizes.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        LARGEST.fetch_max(layout.size(), Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        LARGEST.fetch_max(layout.size(), Ordering::Relaxed);
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        LARGEST.fetch_max(new_size, Ordering::Relaxed);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

type Rand = rand_pcg::Pcg64;

/// Valid seeds for the image mutations: one file per input format and depth.
fn image_seeds() -> Vec<Vec<u8>> {
    let base = grime::demo::facade(40, 30).photo.image().clone();
    let mut out = Vec::new();
    for (img, format) in [
        (
            DynamicImage::ImageRgb8(base.to_rgb8()),
            image::ImageFormat::Png,
        ),
        (
            DynamicImage::ImageRgba16(base.to_rgba16()),
            image::ImageFormat::Png,
        ),
        (
            DynamicImage::ImageLumaA8(base.to_luma_alpha8()),
            image::ImageFormat::Png,
        ),
        (
            DynamicImage::ImageRgb8(base.to_rgb8()),
            image::ImageFormat::Jpeg,
        ),
        (
            DynamicImage::ImageRgb16(base.to_rgb16()),
            image::ImageFormat::Tiff,
        ),
        (
            DynamicImage::ImageRgba8(base.to_rgba8()),
            image::ImageFormat::WebP,
        ),
    ] {
        let mut buf = std::io::Cursor::new(Vec::new());
        img.write_to(&mut buf, format).unwrap();
        out.push(buf.into_inner());
    }
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/regressions");
    let mut names: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    names.sort();
    out.extend(names.iter().map(|p| std::fs::read(p).unwrap()));
    out
}

/// Bit flips, byte overwrites (often with 0x00/0xFF/0x7F, which make huge
/// sizes), truncation, insertion and duplication of a slice.
fn mutate(rng: &mut Rand, data: &[u8]) -> Vec<u8> {
    let mut d = data.to_vec();
    for _ in 0..rng.random_range(1..=4) {
        if d.is_empty() {
            d.push(rng.random());
            continue;
        }
        let i = rng.random_range(0..d.len());
        match rng.random_range(0..6) {
            0 => d[i] ^= 1 << rng.random_range(0..8),
            1 => d[i] = [0x00, 0xFF, 0x7F, 0x80][rng.random_range(0..4)],
            2 => d[i] = rng.random(),
            3 => d.truncate(i),
            4 => {
                let extra: Vec<u8> = (0..rng.random_range(1..16)).map(|_| rng.random()).collect();
                d.splice(i..i, extra);
            }
            _ => {
                let end = (i + rng.random_range(1..64)).min(d.len());
                let piece = d[i..end].to_vec();
                let at = rng.random_range(0..=d.len());
                d.splice(at..at, piece);
            }
        }
    }
    d
}

/// Text mutations: a character dropped, doubled or replaced, or a number
/// swapped for an extreme one.
fn mutate_text(rng: &mut Rand, text: &str) -> String {
    const WILD: [&str; 12] = [
        "-1",
        "0",
        "1e308",
        "nan",
        "inf",
        "-inf",
        "18446744073709551615",
        "9223372036854775807",
        "\"x\"",
        "[]",
        "{}",
        "0.5",
    ];
    let mut t: Vec<char> = text.chars().collect();
    for _ in 0..rng.random_range(1..=3) {
        if t.is_empty() {
            break;
        }
        let i = rng.random_range(0..t.len());
        match rng.random_range(0..4) {
            0 => {
                t.remove(i);
            }
            1 => t.insert(i, t[i]),
            2 => t[i] = ['=', '[', ']', '"', '\n', '.', '-', '9'][rng.random_range(0..8)],
            _ => {
                let w: Vec<char> = WILD[rng.random_range(0..WILD.len())].chars().collect();
                let end = (i..t.len())
                    .find(|&j| !t[j].is_ascii_digit() && t[j] != '.')
                    .unwrap_or(t.len());
                t.splice(i..end, w);
            }
        }
    }
    t.into_iter().collect()
}

/// Runs `f` on input `index`, failing the test on a panic or an oversized
/// allocation, with the input saved for replay.
fn check(kind: &str, index: usize, input: &[u8], f: impl FnOnce()) {
    LARGEST.store(0, Ordering::Relaxed);
    let result = catch_unwind(AssertUnwindSafe(f));
    let largest = LARGEST.load(Ordering::Relaxed);
    if result.is_err() || largest > ALLOC_BOUND {
        let out = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/fuzz-failure.bin");
        let _ = std::fs::write(&out, input);
        panic!(
            "{kind} input {index} (saved to {}): {}",
            out.display(),
            if result.is_err() {
                "panicked".to_string()
            } else {
                format!("allocated {largest} bytes at once")
            }
        );
    }
}

#[test]
fn loaders_and_validation_survive_mutated_inputs() {
    let start = std::time::Instant::now();
    grime::io::limits::set_max_memory(64 << 20);
    let mut rng = Rand::seed_from_u64(13);
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("input.png");
    let mut count = 0;

    // Photos and masks: 6,000 mutated files through the loaders.
    let seeds = image_seeds();
    for i in 0..6000 {
        let data = if i < seeds.len() {
            seeds[i].clone()
        } else {
            let seed = rng.random_range(0..seeds.len());
            mutate(&mut rng, &seeds[seed])
        };
        std::fs::write(&file, &data).unwrap();
        if i % 2 == 0 {
            check("photo", i, &data, || {
                let _ = grime::io::load_photo(&file);
            });
        } else {
            check("mask", i, &data, || {
                let _ = grime::io::load_mask(&file, 40, 30);
            });
        }
        count += 1;
    }

    // Preset files: 3,000 mutations of the documented default preset.
    let toml = grime::preset::Preset::default().to_commented_toml();
    for i in 0..3000 {
        let text = mutate_text(&mut rng, &toml);
        check("preset", i, text.as_bytes(), || {
            if let Ok(p) = grime::preset::Preset::from_toml(&text) {
                let _ = p.validate();
            }
        });
        count += 1;
    }

    // `--set` strings: 3,000 over every parameter, the extreme values and garbage.
    let keys: Vec<&str> = grime::preset::PARAMS.iter().map(|p| p.path).collect();
    for i in 0..3000 {
        let key = keys[rng.random_range(0..keys.len())];
        let number = rng.random_range(0..1000).to_string();
        let value = mutate_text(&mut rng, &number);
        let set = match rng.random_range(0..4) {
            0 => format!("{key}={value}"),
            1 => key.to_string(),
            2 => format!("{key}.x={value}"),
            _ => mutate_text(&mut rng, &format!("{key}={value}")),
        };
        check("--set", i, set.as_bytes(), || {
            let mut p = grime::preset::Preset::default();
            let _ = p.set(&set);
        });
        count += 1;
    }
    assert!(count >= 10_000);
    eprintln!("{count} inputs in {:.1} s", start.elapsed().as_secs_f64());
}
