//! Opens PSDs written by the real `grime` binary with psd-tools (Python), an
//! independent reader: names, blend modes, opacities, visibility, pixels,
//! and its composite against our flattened PNG (within 2/255). See
//! `tests/psd_tools_check.py`.
//!
//! Needs `python3` with `psd-tools` (`.ci/run` installs it). Without it the
//! test fails when `CI` is set and is skipped (with a message) otherwise.

use std::path::Path;
use std::process::Command;

use image::{DynamicImage, ImageBuffer, Rgb};

fn psd_tools_available() -> bool {
    let ok = Command::new("python3")
        .args(["-c", "import psd_tools, numpy, PIL"])
        .status()
        .map(|s| s.success())
        .unwrap_or(false);
    if !ok {
        if std::env::var_os("CI").is_some() {
            panic!("python3 with psd-tools is required in CI (python3 -m pip install psd-tools)");
        }
        eprintln!(
            "SKIPPED: python3 cannot import psd_tools; install it with `python3 -m pip install psd-tools`"
        );
    }
    ok
}

fn grime(args: &[&str]) {
    let out = Command::new(env!("CARGO_BIN_EXE_grime"))
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "grime {args:?} failed:\n{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

fn check(psd: &Path, png: &Path, layers: &Path, depth: u32) {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/psd_tools_check.py");
    let out = Command::new("python3")
        .arg(script)
        .args([psd, png, layers])
        .args(["--depth", &depth.to_string()])
        .output()
        .unwrap();
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    println!("{text}");
    assert!(out.status.success(), "psd-tools check failed:\n{text}");
}

#[test]
fn psd_tools_reads_the_demo_and_agrees_with_the_png() {
    if !psd_tools_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let s = |p: &str| d.join(p).to_str().unwrap().to_string();
    grime(&["run", "--demo", "-q", "--seed", "3", "-o", &s("aged.psd")]);
    grime(&[
        "run",
        "--demo",
        "-q",
        "--seed",
        "3",
        "-o",
        &s("aged.png"),
        "--layers-dir",
        &s("layers"),
    ]);
    check(
        &d.join("aged.psd"),
        &d.join("aged.png"),
        &d.join("layers"),
        8,
    );
}

#[test]
fn psd_tools_reads_a_sixteen_bit_psd() {
    if !psd_tools_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let s = |p: &str| d.join(p).to_str().unwrap().to_string();
    // A 16-bit photo with texture, so the rain has something to follow.
    let photo = ImageBuffer::<Rgb<u16>, Vec<u16>>::from_fn(240, 160, |x, y| {
        let n = ((x * 7919 + y * 104_729) % 97) as u16 * 90;
        Rgb([
            30_000 + n + (x * 60) as u16,
            28_000 + n + (y * 50) as u16,
            25_000 + n,
        ])
    });
    DynamicImage::ImageRgb16(photo)
        .save(d.join("deep.png"))
        .unwrap();
    grime(&[
        "run",
        &s("deep.png"),
        "-q",
        "--seed",
        "5",
        "-o",
        &s("aged.psd"),
    ]);
    grime(&[
        "run",
        &s("deep.png"),
        "-q",
        "--seed",
        "5",
        "-o",
        &s("aged16.png"),
        "--layers-dir",
        &s("layers"),
    ]);
    // PIL reads 16-bit RGB PNGs as their high bytes: compare against an
    // 8-bit copy rounded properly instead.
    let flat = image::open(d.join("aged16.png")).unwrap();
    assert_eq!(flat.color(), image::ColorType::Rgb16);
    let flat8 = image::RgbImage::from_fn(flat.width(), flat.height(), |x, y| {
        let p = flat.as_rgb16().unwrap().get_pixel(x, y);
        Rgb(p.0.map(|v| ((v as u32 + 128) / 257) as u8))
    });
    flat8.save(d.join("aged8.png")).unwrap();
    check(
        &d.join("aged.psd"),
        &d.join("aged8.png"),
        &d.join("layers"),
        16,
    );
}
