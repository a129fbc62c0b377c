//! Nothing lost: the real binary never writes over an input, never writes
//! two outputs to one file, and refuses a bad output before any work
//! (issue 13 items 1-4 and 16). Also `--quad` and batch `.quad` sidecars.

mod common;

use common::{grime, s};

use std::path::{Path, PathBuf};
use std::process::Output;

/// A small photo at `dir/name`; returns its path and bytes.
fn photo(dir: &Path, name: &str) -> (PathBuf, Vec<u8>) {
    let path = dir.join(name);
    grime::demo::facade(96, 72)
        .photo
        .image()
        .to_rgb8()
        .save(&path)
        .unwrap();
    let bytes = std::fs::read(&path).unwrap();
    (path, bytes)
}

/// A failure on one line naming `needle`, and `kept` still holds `bytes`.
fn refused(o: &Output, needle: &str, kept: &Path, bytes: &[u8]) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "expected a refusal; stderr: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
    assert!(err.contains(needle), "{needle:?} not in: {err}");
    assert_eq!(
        std::fs::read(kept).unwrap(),
        bytes,
        "{} was changed",
        kept.display()
    );
}

const FAST: [&str; 4] = ["--layers", "2", "--set", "sim.max_side=64"];

fn run(args: &[&str]) -> Output {
    let mut all = vec!["run", "-q"];
    all.extend_from_slice(args);
    all.extend_from_slice(&FAST);
    grime(&all)
}

#[test]
fn report_on_the_photo_or_the_mask_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let (input, bytes) = photo(dir.path(), "p.png");
    let (mask, mask_bytes) = photo(dir.path(), "m.png");
    let out = dir.path().join("aged.png");
    let o = run(&[s(&input), "-o", s(&out), "--report", s(&input)]);
    refused(&o, "refusing to overwrite an input", &input, &bytes);
    let o = run(&[
        s(&input),
        "-o",
        s(&out),
        "--mask",
        s(&mask),
        "--report",
        s(&mask),
    ]);
    refused(&o, "refusing to overwrite an input", &mask, &mask_bytes);
    assert!(!out.exists(), "nothing written on refusal");
}

#[test]
fn report_on_the_image_output_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let (input, _) = photo(dir.path(), "p.png");
    let (out, old) = photo(dir.path(), "aged.png");
    let o = run(&[s(&input), "-o", s(&out), "--report", s(&out)]);
    refused(&o, "--report", &out, &old);
}

#[test]
fn layers_dir_holding_an_input_named_like_a_layer_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let (input, bytes) = photo(dir.path(), "00-photo.png");
    let out = dir.path().join("aged.png");
    let o = run(&[s(&input), "-o", s(&out), "--layers-dir", s(dir.path())]);
    refused(&o, "refusing to overwrite an input", &input, &bytes);
}

#[test]
fn demo_with_a_mask_never_overwrites_the_mask() {
    let dir = tempfile::tempdir().unwrap();
    let mask = dir.path().join("m.png");
    image::GrayImage::from_pixel(960, 720, image::Luma([255]))
        .save(&mask)
        .unwrap();
    let bytes = std::fs::read(&mask).unwrap();
    let o = run(&["--demo", "--mask", s(&mask), "-o", s(&mask)]);
    refused(&o, "refusing to overwrite an input", &mask, &bytes);
}

#[test]
fn a_missing_output_folder_is_refused_before_the_input_is_read() {
    let dir = tempfile::tempdir().unwrap();
    // The input does not exist either: the output is checked first, so
    // the message is about the folder (no simulation, no decoding).
    let o = run(&[
        s(&dir.path().join("absent.png")),
        "-o",
        s(&dir.path().join("no/such/aged.png")),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(err.contains("output folder does not exist"), "{err}");
    assert!(
        !err.contains(".grime-"),
        "names the real output, not a temp file: {err}"
    );
}

#[test]
fn a_quad_runs_in_the_wall_plane_and_leaves_the_outside_alone() {
    let dir = tempfile::tempdir().unwrap();
    let (input, _) = photo(dir.path(), "p.png");
    let out = dir.path().join("aged.png");
    let o = run(&[
        s(&input),
        "-o",
        s(&out),
        "--quad",
        "20,10,80,14,78,60,22,58",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let a = image::open(&input).unwrap().to_rgb8();
    let b = image::open(&out).unwrap().to_rgb8();
    assert_ne!(a, b, "the wall inside the quad aged");
    for (x, y) in [(2, 2), (93, 70), (5, 69), (90, 3)] {
        assert_eq!(
            a.get_pixel(x, y),
            b.get_pixel(x, y),
            "({x}, {y}) is outside the quad"
        );
    }
    let o = run(&[s(&input), "-o", s(&out), "--quad", "1,2,3"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("quad"), "{err}");
}

#[test]
fn batch_reads_a_quad_sidecar() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in");
    std::fs::create_dir(&input).unwrap();
    let (plain, _) = photo(&input, "a.png");
    std::fs::copy(&plain, input.join("b.png")).unwrap();
    std::fs::write(input.join("b.png.quad"), "20,10,80,14,78,60,22,58\n").unwrap();
    let out = dir.path().join("out");
    let mut args = vec!["batch", "-q", s(&input), "-o", s(&out)];
    args.extend_from_slice(&FAST);
    let o = grime(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let src = image::open(&plain).unwrap().to_rgb8();
    let a = image::open(out.join("a.png")).unwrap().to_rgb8();
    let b = image::open(out.join("b.png")).unwrap().to_rgb8();
    // Same seed base, but b ran in its quad's plane: the corner is untouched.
    assert_eq!(b.get_pixel(2, 2), src.get_pixel(2, 2));
    assert_ne!(a, b);
    // A bad sidecar fails that image only.
    std::fs::write(input.join("a.png.quad"), "nonsense").unwrap();
    let o = grime(&args);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("a.png") && err.contains("quad"), "{err}");
}

#[test]
fn batch_names_a_missing_mask_as_the_mask() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in");
    let masks = dir.path().join("masks");
    std::fs::create_dir(&input).unwrap();
    std::fs::create_dir(&masks).unwrap();
    photo(&input, "a.png");
    let out = dir.path().join("out");
    let mut args = vec![
        "batch",
        "-q",
        s(&input),
        "-o",
        s(&out),
        "--masks",
        s(&masks),
    ];
    args.extend_from_slice(&FAST);
    let o = grime(&args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(
        err.contains("its mask") && err.contains("a.png is missing"),
        "{err}"
    );
}
