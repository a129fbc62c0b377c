//! `grime batch` end to end: the real binary on a folder this test builds,
//! with the awkward files a real folder has.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use image::codecs::jpeg::JpegEncoder;
use image::codecs::png::PngEncoder;
use image::{DynamicImage, ImageDecoder, ImageEncoder, ImageReader, Rgb, RgbImage};
use serde_json::Value;

/// Small images and a fast preset keep the test quick.
const FAST: &[&str] = &["--layers", "2", "--set", "sim.max_side=128"];
/// A valid ICC profile (grime checks embedded ones) that is not grime's own
/// sRGB: its manufacturer field says GRIM.
fn icc() -> Vec<u8> {
    let mut p = grime::io::icc::srgb().to_vec();
    p[48..52].copy_from_slice(b"GRIM");
    p
}

fn grime(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_grime"))
        .args(args)
        .output()
        .expect("run grime")
}

fn batch(input: &Path, output: &Path, extra: &[&str]) -> (Output, Value) {
    let mut args = vec![
        "batch",
        input.to_str().unwrap(),
        "-o",
        output.to_str().unwrap(),
        "--json",
    ];
    args.extend_from_slice(FAST);
    // Every picture here is wall: these tests are about files, not sight.
    args.extend_from_slice(&["--seed", "5", "--region", "full"]);
    args.extend_from_slice(extra);
    let out = grime(&args);
    let json = serde_json::from_slice(&out.stdout).unwrap_or_else(|e| {
        panic!(
            "no JSON on stdout ({e}); stderr: {}",
            String::from_utf8_lossy(&out.stderr)
        )
    });
    (out, json)
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// A textured test picture, so that ageing has something to change.
fn picture(w: u32, h: u32) -> RgbImage {
    RgbImage::from_fn(w, h, |x, y| {
        Rgb([(x * 3 + y) as u8, (y * 4) as u8, ((x ^ y) * 5) as u8])
    })
}

fn jpeg_bytes(img: &RgbImage) -> Vec<u8> {
    let mut out = Vec::new();
    JpegEncoder::new_with_quality(&mut out, 90)
        .write_image(
            img.as_raw(),
            img.width(),
            img.height(),
            image::ExtendedColorType::Rgb8,
        )
        .unwrap();
    out
}

/// Inserts an APP1 Exif segment with Orientation = `orientation` after SOI.
fn with_exif_orientation(jpeg: &[u8], orientation: u16) -> Vec<u8> {
    let mut tiff = Vec::new();
    tiff.extend_from_slice(b"MM\0\x2a\0\0\0\x08"); // big-endian TIFF, IFD at 8
    tiff.extend_from_slice(&1u16.to_be_bytes()); // one entry
    tiff.extend_from_slice(&0x0112u16.to_be_bytes()); // Orientation
    tiff.extend_from_slice(&3u16.to_be_bytes()); // SHORT
    tiff.extend_from_slice(&1u32.to_be_bytes()); // count
    tiff.extend_from_slice(&orientation.to_be_bytes());
    tiff.extend_from_slice(&[0, 0]);
    tiff.extend_from_slice(&0u32.to_be_bytes()); // no next IFD
    let mut payload = b"Exif\0\0".to_vec();
    payload.extend_from_slice(&tiff);
    let mut out = jpeg[..2].to_vec();
    out.extend_from_slice(&[0xFF, 0xE1]);
    out.extend_from_slice(&((payload.len() + 2) as u16).to_be_bytes());
    out.extend_from_slice(&payload);
    out.extend_from_slice(&jpeg[2..]);
    out
}

fn crc32(data: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in data {
        crc ^= b as u32;
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

/// A PNG header claiming 100000 x 100000 pixels: a decompression bomb.
fn bomb_png() -> Vec<u8> {
    let mut ihdr = b"IHDR".to_vec();
    ihdr.extend_from_slice(&100_000u32.to_be_bytes());
    ihdr.extend_from_slice(&100_000u32.to_be_bytes());
    ihdr.extend_from_slice(&[8, 2, 0, 0, 0]);
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    png.extend_from_slice(&13u32.to_be_bytes());
    png.extend_from_slice(&ihdr);
    png.extend_from_slice(&crc32(&ihdr).to_be_bytes());
    png
}

/// Builds the input folder; returns the images expected to succeed.
fn make_input(dir: &Path) -> Vec<&'static str> {
    std::fs::create_dir_all(dir.join("sub/deeper")).unwrap();
    let w = |rel: &str, bytes: &[u8]| std::fs::write(dir.join(rel), bytes).unwrap();

    picture(64, 48).save(dir.join("a_plain.png")).unwrap();
    w("B.JPG", &jpeg_bytes(&picture(64, 48)));
    // Orientation 6: stored 64x48 with a red top band; shown rotated 90°
    // clockwise, i.e. 48x64 with the red band on the right.
    let rot = RgbImage::from_fn(64, 48, |_, y| {
        if y < 10 {
            Rgb([250, 20, 20])
        } else {
            Rgb([20, 20, 250])
        }
    });
    w("rot6.jpg", &with_exif_orientation(&jpeg_bytes(&rot), 6));
    // 16-bit PNG with an ICC profile.
    let deep = image::ImageBuffer::<Rgb<u16>, Vec<u16>>::from_fn(40, 30, |x, y| {
        Rgb([
            x as u16 * 1000 + 7,
            y as u16 * 2000 + 3,
            40_000 + (x * y) as u16,
        ])
    });
    let mut png16 = Vec::new();
    let mut enc = PngEncoder::new(&mut png16);
    enc.set_icc_profile(icc()).unwrap();
    enc.write_image(
        bytemuck_u16(deep.as_raw()).as_slice(),
        40,
        30,
        image::ExtendedColorType::Rgb16,
    )
    .unwrap();
    w("sub/deeper/deep16.png", &png16);

    let whole = jpeg_bytes(&picture(64, 48));
    w("sub/trunc.jpg", &whole[..whole.len() * 2 / 3]);
    w("sub/empty.jpg", b"");
    w("sub/bomb.png", &bomb_png());
    w("notes.txt", b"not an image\n");
    vec!["B.JPG", "a_plain.png", "rot6.jpg", "sub/deeper/deep16.png"]
}

/// 16-bit samples as the native-endian bytes `write_image` expects.
fn bytemuck_u16(v: &[u16]) -> Vec<u8> {
    v.iter().flat_map(|s| s.to_ne_bytes()).collect()
}

/// Every file under `dir` (relative path → bytes).
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    fn walk(root: &Path, dir: &Path, out: &mut BTreeMap<PathBuf, Vec<u8>>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                walk(root, &p, out);
            } else {
                out.insert(
                    p.strip_prefix(root).unwrap().to_path_buf(),
                    std::fs::read(&p).unwrap(),
                );
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(dir, dir, &mut out);
    out
}

fn files(json: &Value) -> &Vec<Value> {
    json["files"].as_array().expect("files array")
}

fn entry<'a>(json: &'a Value, path: &str) -> &'a Value {
    files(json)
        .iter()
        .find(|f| f["path"] == path)
        .unwrap_or_else(|| panic!("{path} not in report: {json:#}"))
}

fn outputs_of(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    snapshot(dir)
        .into_iter()
        .filter(|(p, _)| !p.file_name().unwrap().to_string_lossy().starts_with('.'))
        .collect()
}

#[test]
fn batch_ages_a_messy_folder_and_loses_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let input = tmp.path().join("photos");
    let good = make_input(&input);
    let before = snapshot(&input);
    let out = tmp.path().join("aged");

    // --- the full run -------------------------------------------------------
    let (run, json) = batch(&input, &out, &["-r", "--jobs", "2", "--format", "keep,png"]);
    let err = stderr(&run);
    assert_eq!(
        run.status.code(),
        Some(1),
        "a bad file makes the exit code 1; stderr: {err}"
    );
    assert!(err.contains("4 succeeded, 3 failed, 0 skipped"), "{err}");
    assert_eq!(json["found"], 7, "{json:#}");
    assert_eq!(
        (
            json["succeeded"].as_u64(),
            json["failed"].as_u64(),
            json["skipped"].as_u64()
        ),
        (Some(4), Some(3), Some(0))
    );
    let listed: Vec<&str> = files(&json)
        .iter()
        .map(|f| f["path"].as_str().unwrap())
        .collect();
    assert_eq!(
        listed,
        [
            "B.JPG",
            "a_plain.png",
            "rot6.jpg",
            "sub/bomb.png",
            "sub/deeper/deep16.png",
            "sub/empty.jpg",
            "sub/trunc.jpg"
        ],
        "sorted, recursive, notes.txt left out"
    );
    for (path, why) in [
        ("sub/trunc.jpg", "truncated"),
        ("sub/empty.jpg", "empty"),
        ("sub/bomb.png", "too large"),
    ] {
        let e = entry(&json, path);
        assert_eq!(e["status"], "failed");
        let msg = e["error"].as_str().unwrap();
        assert!(msg.contains(why), "{path}: {msg}");
        let shown = format!("{}: ", input.join(path).display());
        assert!(
            err.lines().any(|l| l.contains(&shown) && l.contains(why)),
            "stderr names {path}: {err}"
        );
    }
    for path in &good {
        assert_eq!(entry(&json, path)["status"], "ok");
    }

    // Outputs: mirrored, one per format, nothing for failures, no temp files.
    let first = snapshot(&out);
    let names: BTreeSet<String> = first
        .keys()
        .map(|p| p.to_string_lossy().replace('\\', "/"))
        .collect();
    let expected: BTreeSet<String> = [
        "B.JPG",
        "B.png",
        "a_plain.png",
        "rot6.jpg",
        "rot6.png",
        "sub/deeper/deep16.png",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    assert_eq!(names, expected);

    let dims = |rel: &str| {
        let img = image::open(out.join(rel)).unwrap();
        (img.width(), img.height())
    };
    assert_eq!(dims("a_plain.png"), (64, 48));
    assert_eq!(dims("B.JPG"), (64, 48));
    assert_eq!(dims("B.png"), (64, 48));
    assert_eq!(dims("rot6.png"), (48, 64), "EXIF orientation 6 applied");
    assert_eq!(dims("rot6.jpg"), (48, 64));
    let rot = image::open(out.join("rot6.png")).unwrap().to_rgb8();
    let (right, left) = (rot.get_pixel(45, 32), rot.get_pixel(2, 32));
    assert!(
        right[0] > right[2] && left[2] > left[0],
        "rotated clockwise: red band on the right ({right:?}, {left:?})"
    );
    // 16-bit and ICC survive.
    let mut dec = ImageReader::open(out.join("sub/deeper/deep16.png"))
        .unwrap()
        .into_decoder()
        .unwrap();
    assert_eq!(
        dec.icc_profile().unwrap().as_deref(),
        Some(&icc()[..]),
        "ICC profile kept"
    );
    let deep = DynamicImage::from_decoder(dec).unwrap();
    assert_eq!(deep.color(), image::ColorType::Rgb16, "16-bit kept");
    assert_eq!((deep.width(), deep.height()), (40, 30));
    // Ageing did something.
    let plain_in = image::open(input.join("a_plain.png")).unwrap().to_rgb8();
    let plain_out = image::open(out.join("a_plain.png")).unwrap().to_rgb8();
    assert_ne!(plain_in, plain_out, "the output is aged");

    // --- outputs equal single runs with the reported seed ------------------
    for path in &good {
        let seed = entry(&json, path)["seed"].as_u64().unwrap().to_string();
        for o in entry(&json, path)["outputs"].as_array().unwrap() {
            let batch_out = PathBuf::from(o.as_str().unwrap());
            let ext = batch_out.extension().unwrap().to_str().unwrap();
            let single = tmp.path().join(format!("single.{ext}"));
            let photo = input.join(path);
            let mut args = vec![
                "run",
                photo.to_str().unwrap(),
                "-o",
                single.to_str().unwrap(),
                "-q",
            ];
            args.extend_from_slice(FAST);
            args.extend_from_slice(&["--seed", &seed, "--region", "full"]);
            let r = grime(&args);
            assert!(r.status.success(), "{}", stderr(&r));
            assert!(
                std::fs::read(&single).unwrap() == std::fs::read(&batch_out).unwrap(),
                "{path}: batch output {} differs from grime run --seed {seed}",
                batch_out.display()
            );
        }
    }
    let seeds: BTreeSet<u64> = files(&json)
        .iter()
        .map(|f| f["seed"].as_u64().unwrap())
        .collect();
    assert_eq!(seeds.len(), 7, "every image has its own seed");

    // --- resume after an interruption -------------------------------------
    std::fs::remove_file(out.join("B.png")).unwrap();
    std::fs::write(out.join(".B.png.grime-999-0.tmp"), b"half an image").unwrap();
    let (resume, json2) = batch(
        &input,
        &out,
        &["-r", "--format", "keep,png", "--skip-existing"],
    );
    assert!(
        stderr(&resume).contains("1 succeeded, 3 failed, 3 skipped"),
        "{}",
        stderr(&resume)
    );
    assert_eq!(resume.status.code(), Some(1));
    assert_eq!(
        entry(&json2, "B.JPG")["status"],
        "ok",
        "one of its formats was missing"
    );
    assert_eq!(entry(&json2, "a_plain.png")["status"], "skipped");
    assert_eq!(
        outputs_of(&out),
        outputs_of_map(&first),
        "resume rebuilt exactly what was missing"
    );

    // --- shards: union is everything, no overlap, same bytes ---------------
    let mut seen = BTreeMap::new();
    for k in 1..=3 {
        let dir = tmp.path().join(format!("shard{k}"));
        let (_, j) = batch(
            &input,
            &dir,
            &[
                "-r",
                "--format",
                "keep,png",
                "--shard",
                &format!("{k}/3"),
                "--jobs",
                "1",
            ],
        );
        assert_eq!(j["found"], 7);
        for f in files(&j) {
            let i = f["index"].as_u64().unwrap();
            assert_eq!(i % 3, k - 1, "index {i} in shard {k}/3");
            assert!(
                seen.insert(f["path"].as_str().unwrap().to_string(), k)
                    .is_none(),
                "overlap: {f}"
            );
        }
        for (rel, bytes) in outputs_of(&dir) {
            assert!(
                first.get(&rel) == Some(&bytes),
                "shard {k}: {} differs from the full run",
                rel.display()
            );
        }
    }
    assert_eq!(
        seen.keys().map(String::as_str).collect::<Vec<_>>(),
        listed,
        "shards cover the whole folder"
    );
    let union: usize = (1..=3)
        .map(|k| outputs_of(&tmp.path().join(format!("shard{k}"))).len())
        .sum();
    assert_eq!(union, first.len());

    // --- safety: never inside the input unless asked, never over it --------
    for bad in [input.join("aged"), input.clone()] {
        let r = grime(&[
            "batch",
            input.to_str().unwrap(),
            "-o",
            bad.to_str().unwrap(),
            "-q",
        ]);
        assert_eq!(r.status.code(), Some(1));
        assert!(stderr(&r).contains("input"), "{}", stderr(&r));
    }
    assert_eq!(snapshot(&input), before, "the input folder is unchanged");

    // --- a clean folder exits 0 --------------------------------------------
    let clean = tmp.path().join("clean");
    let (ok, j) = batch(&input.join("sub/deeper"), &clean, &[]);
    assert!(ok.status.success(), "{}", stderr(&ok));
    assert!(stderr(&ok).contains("1 succeeded, 0 failed, 0 skipped"));
    assert_ne!(
        j["files"][0]["seed"],
        entry(&json, "sub/deeper/deep16.png")["seed"],
        "the seed follows the path relative to INPUT"
    );
    assert_eq!(snapshot(&input), before, "the input folder is unchanged");
}

fn outputs_of_map(m: &BTreeMap<PathBuf, Vec<u8>>) -> BTreeMap<PathBuf, Vec<u8>> {
    m.iter()
        .filter(|(p, _)| !p.file_name().unwrap().to_string_lossy().starts_with('.'))
        .map(|(p, b)| (p.clone(), b.clone()))
        .collect()
}

#[test]
fn batch_refuses_bad_arguments_clearly() {
    let tmp = tempfile::tempdir().unwrap();
    let input = tmp.path().join("in");
    std::fs::create_dir_all(&input).unwrap();
    picture(32, 24).save(input.join("x.png")).unwrap();
    let out = tmp.path().join("out");
    let o = out.to_str().unwrap();
    let i = input.to_str().unwrap();
    for (args, says) in [
        (vec!["batch", i, "-o", o, "--shard", "0/3"], "K/N"),
        (vec!["batch", i, "-o", o, "--shard", "4/3"], "K/N"),
        (
            vec!["batch", i, "-o", o, "--format", "bmp"],
            "unknown output format",
        ),
        (
            vec!["batch", input.join("x.png").to_str().unwrap(), "-o", o],
            "not a folder",
        ),
    ] {
        let r = grime(&args);
        assert!(!r.status.success(), "{args:?}");
        assert!(stderr(&r).contains(says), "{args:?}: {}", stderr(&r));
    }
    assert!(!out.exists(), "nothing written on refusal");
}
