//! Issue 13 through the real binary: hostile and unusual inputs get one
//! clear line, no garbage reaches an output, nothing is left behind.

mod common;

use std::path::Path;
use std::process::Command;

use common::{FAST, assert_clear_error, grime, photo, s, stderr};
use image::{DynamicImage, ImageBuffer, LumaA};

/// The regression corpus (tests/regressions/): small hostile files.
fn corpus(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/regressions")
        .join(name)
}

#[test]
fn gif_and_non_images_named_png_say_what_they_are() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("a.png");
    let gif = corpus("animated.gif");
    assert_clear_error(
        &grime(&["run", s(&gif), "-o", s(&out)]),
        "a GIF image is not a supported input",
    );
    for (file, says) in [
        ("random-bytes.png", "not a PNG, JPEG, TIFF or WebP file"),
        ("text.png", "(it holds text)"),
    ] {
        let o = grime(&["run", s(&corpus(file)), "-o", s(&out)]);
        assert_clear_error(&o, says);
        assert!(!stderr(&o).contains("extension"), "{}", stderr(&o));
    }
    assert!(!out.exists());
}

/// A PNG whose iCCP chunk inflates to `size` bytes of zeros (not a profile).
fn png_with_icc(size: usize) -> Vec<u8> {
    let mut png = Vec::new();
    DynamicImage::ImageRgb8(grime::demo::facade(32, 24).photo.image().to_rgb8())
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .unwrap();
    let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::best());
    let zeros = vec![0u8; 1 << 20];
    for _ in 0..size / zeros.len() {
        std::io::Write::write_all(&mut z, &zeros).unwrap();
    }
    std::io::Write::write_all(&mut z, &zeros[..size % zeros.len()]).unwrap();
    let mut data = b"junk\0\0".to_vec();
    data.extend(z.finish().unwrap());
    let mut chunk = (data.len() as u32).to_be_bytes().to_vec();
    chunk.extend_from_slice(b"iCCP");
    chunk.extend_from_slice(&data);
    let crc = crc32fast::hash(&chunk[4..]);
    chunk.extend_from_slice(&crc.to_be_bytes());
    // After the 8-byte signature and the 25-byte IHDR chunk.
    png.splice(33..33, chunk);
    png
}

#[test]
fn huge_or_garbage_icc_profiles_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("a.png");
    for (size, says) in [
        (64 << 20, "inflates to over 4.0 MiB"),
        (2000, "header gives 0 bytes but it has 2000"),
    ] {
        let input = dir.path().join(format!("icc-{size}.png"));
        std::fs::write(&input, png_with_icc(size)).unwrap();
        assert_clear_error(&grime(&["run", s(&input), "-o", s(&out)]), says);
        assert!(!out.exists());
    }
}

#[test]
fn a_run_past_the_memory_limit_is_refused_before_decoding() {
    let dir = tempfile::tempdir().unwrap();
    let input = photo(dir.path(), "in.png");
    let out = dir.path().join("a.png");
    let o = Command::new(env!("CARGO_BIN_EXE_grime"))
        .args(["run", s(&input), "-o", s(&out)])
        .env("GRIME_MAX_MEMORY", "100K")
        .output()
        .unwrap();
    // 96 x 72 px x 37 B = 250 kB.
    assert_clear_error(&o, "a 96x72 photo needs about 249.8 KiB");
    assert!(stderr(&o).contains("--max-memory 1G"), "{}", stderr(&o));
    let o = grime(&["run", s(&input), "-o", s(&out), "--max-memory", "100K"]);
    assert_clear_error(&o, "over the 100.0 KiB limit");
    let o = grime(&["run", s(&input), "-o", s(&out), "--max-memory", "1M"]);
    assert!(o.status.success(), "{}", stderr(&o));
    // A time-lapse holds more: 118 B/px and its 3 frames (issue 15).
    let gif = dir.path().join("t.gif");
    let mut args = vec!["run", s(&input), "-o", s(&out), "--max-memory", "700K"];
    args.extend(["--years", "2"]);
    let o = grime(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    args.extend(["--timelapse", s(&gif)]);
    let o = grime(&args);
    assert_clear_error(&o, "a 96x72 photo needs about 877.5 KiB");
    assert!(!gif.exists());
}

#[test]
fn a_wall_drawn_only_in_alpha_is_used() {
    let dir = tempfile::tempdir().unwrap();
    let input = photo(dir.path(), "in.png");
    // White everywhere; the wall is the opaque left half.
    let mask = dir.path().join("mask.png");
    ImageBuffer::from_fn(96, 72, |x, _| LumaA([255u8, if x < 48 { 255 } else { 0 }]))
        .save(&mask)
        .unwrap();
    let out = dir.path().join("a.png");
    let mut args = vec!["run", s(&input), "-o", s(&out), "--mask", s(&mask)];
    args.extend(FAST);
    let o = grime(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let (a, b) = (
        image::open(&input).unwrap().to_rgb8(),
        image::open(&out).unwrap().to_rgb8(),
    );
    let changed = |x0: u32, x1: u32| {
        (0..72)
            .flat_map(|y| (x0..x1).map(move |x| (x, y)))
            .filter(|&(x, y)| a.get_pixel(x, y) != b.get_pixel(x, y))
            .count()
    };
    assert_eq!(changed(48, 96), 0, "the transparent half is not wall");
    assert!(changed(0, 48) > 0, "the opaque half is aged");
}

#[test]
fn seeds_past_i64_are_out_of_range() {
    let dir = tempfile::tempdir().unwrap();
    let input = photo(dir.path(), "in.png");
    let out = dir.path().join("a.png");
    let o = grime(&[
        "run",
        s(&input),
        "-o",
        s(&out),
        "--set",
        "seed=18446744073709551615",
    ]);
    assert_clear_error(
        &o,
        "seed = 18446744073709551615 is out of range; allowed: 0 ..= 9223372036854775807",
    );
    assert!(!stderr(&o).contains("invalid type"));
}

#[test]
fn an_ora_on_a_full_disk_reports_one_error() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("a.ora");
    // Files may grow to 64 kB: past that writes fail (EFBIG), as on a full
    // disk. SIGXFSZ is ignored so the write fails instead of killing grime.
    let o = Command::new("bash")
        .arg("-c")
        .arg(format!(
            "trap '' XFSZ; ulimit -f 64; exec {} run --demo -q --layers 2 -o {}",
            env!("CARGO_BIN_EXE_grime"),
            s(&out)
        ))
        .output()
        .unwrap();
    assert_clear_error(&o, "file too large");
    assert!(!stderr(&o).contains("ZipWriter"), "{}", stderr(&o));
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn a_smaller_run_in_a_layers_dir_removes_the_stale_layers_only() {
    let dir = tempfile::tempdir().unwrap();
    let input = photo(dir.path(), "in.png");
    let layers = dir.path().join("layers");
    let out = dir.path().join("a.png");
    let run = |n: &str| {
        let o = grime(&[
            "run",
            s(&input),
            "-o",
            s(&out),
            "--layers",
            n,
            "--set",
            "sim.max_side=64",
            "--layers-dir",
            s(&layers),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
    };
    run("6");
    std::fs::write(layers.join("notes.txt"), "mine").unwrap();
    std::fs::write(layers.join("09-sketch.png"), "mine too").unwrap();
    let names = || {
        let mut v: Vec<String> = std::fs::read_dir(&layers)
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        v.sort();
        v
    };
    assert!(
        names().iter().any(|n| n.contains("rain-06")),
        "{:?}",
        names()
    );
    run("2");
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(layers.join("manifest.json")).unwrap())
            .unwrap();
    let mut expected: Vec<String> = manifest["layers"]
        .as_array()
        .unwrap()
        .iter()
        .chain([&manifest["region"]])
        .filter_map(|f| f.as_str().or(f["file"].as_str()))
        .map(str::to_string)
        .chain(["09-sketch.png", "manifest.json", "notes.txt"].map(String::from))
        .collect();
    expected.sort();
    assert_eq!(names(), expected);
}

#[test]
fn sixteen_bit_png_outputs_say_srgb() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in16.png");
    DynamicImage::ImageRgb16(grime::demo::facade(48, 36).photo.image().to_rgb16())
        .save(&input)
        .unwrap();
    let out = dir.path().join("a.png");
    let mut args = vec!["run", s(&input), "-o", s(&out)];
    args.extend(FAST);
    let o = grime(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let (_, icc) = grime::io::load_image(&out).unwrap();
    assert_eq!(icc.as_deref(), Some(grime::io::icc::srgb()));
    // An 8-bit PNG stays without a profile, as before.
    let out8 = dir.path().join("b.png");
    let input8 = photo(dir.path(), "in8.png");
    let mut args = vec!["run", s(&input8), "-o", s(&out8)];
    args.extend(FAST);
    assert!(grime(&args).status.success());
    assert_eq!(grime::io::load_image(&out8).unwrap().1, None);
}

/// Images `dir/0.png ..` large enough that ageing each takes a moment.
fn slow_photos(dir: &Path, n: usize) {
    std::fs::create_dir_all(dir).unwrap();
    let img = DynamicImage::ImageRgb8(grime::demo::facade(480, 360).photo.image().to_rgb8());
    for i in 0..n {
        img.save(dir.join(format!("{i}.png"))).unwrap();
    }
}

fn temp_files(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n.ends_with(".tmp"))
        .collect()
}

#[test]
fn sigterm_stops_a_batch_with_its_summary_so_far() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in");
    let output = dir.path().join("out");
    slow_photos(&input, 8);
    let child = Command::new(env!("CARGO_BIN_EXE_grime"))
        .args(["batch", s(&input), "-o", s(&output), "--json", "-q"])
        .args(["--jobs", "1", "--layers", "12"])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let t = std::time::Instant::now();
    while !output.join("0.png").exists() {
        assert!(t.elapsed().as_secs() < 120, "no image written");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let kill = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(130), "{}", stderr(&o));
    assert!(stderr(&o).contains("interrupted"), "{}", stderr(&o));
    let summary: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let files = summary["files"].as_array().unwrap();
    assert!(!files.is_empty() && files.len() < 8, "{summary}");
    assert!(temp_files(&output).is_empty(), "{:?}", temp_files(&output));
}

#[test]
fn skip_existing_removes_orphans_of_a_killed_run() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in");
    let output = dir.path().join("out");
    std::fs::create_dir_all(&input).unwrap();
    std::fs::create_dir_all(&output).unwrap();
    photo(&input, "a.png");
    // What SIGKILL leaves: a temp file of a process that is gone (this pid
    // is above Linux's pid_max), an hour old; and a user's file.
    let orphan = output.join(".a.png.grime-2147483632-0.tmp");
    std::fs::write(&orphan, b"half").unwrap();
    std::fs::File::options()
        .write(true)
        .open(&orphan)
        .unwrap()
        .set_modified(std::time::SystemTime::now() - std::time::Duration::from_secs(3600))
        .unwrap();
    std::fs::write(output.join("keep.tmp"), b"mine").unwrap();
    let mut args = vec!["batch", s(&input), "-o", s(&output), "--skip-existing"];
    args.extend(FAST);
    let o = grime(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("removed 1 orphaned temporary files"));
    assert!(!orphan.exists());
    assert!(output.join("keep.tmp").exists() && output.join("a.png").exists());
}
