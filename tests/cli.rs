//! The real `grime` binary: success paths and every error case of `run`.

mod common;

use std::process::Command;

use common::{FAST, assert_clear_error, grime, photo, s, stderr};
use image::{DynamicImage, ImageBuffer, Luma, Rgba};

#[test]
fn demo_run_writes_the_aged_image() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("aged.png");
    let o = grime(&["run", "--demo", "-o", s(&out), "--layers", "2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let img = image::open(&out).unwrap();
    assert_eq!((img.width(), img.height()), (960, 720));
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        1,
        "no temp files left"
    );
}

#[test]
fn reads_every_input_format_and_depth() {
    let dir = tempfile::tempdir().unwrap();
    let base = grime::demo::facade(64, 48).photo.image().to_rgb8();
    let inputs: Vec<(&str, DynamicImage)> = vec![
        (
            "grey.png",
            DynamicImage::ImageLuma8(DynamicImage::ImageRgb8(base.clone()).to_luma8()),
        ),
        (
            "rgba.png",
            DynamicImage::ImageRgba8(DynamicImage::ImageRgb8(base.clone()).to_rgba8()),
        ),
        (
            "deep.png",
            DynamicImage::ImageRgb16(DynamicImage::ImageRgb8(base.clone()).to_rgb16()),
        ),
        (
            "deep.tif",
            DynamicImage::ImageRgb16(DynamicImage::ImageRgb8(base.clone()).to_rgb16()),
        ),
        ("photo.jpg", DynamicImage::ImageRgb8(base.clone())),
        ("photo.webp", DynamicImage::ImageRgb8(base.clone())),
        (
            "grey16.png",
            DynamicImage::ImageLuma16(DynamicImage::ImageRgb8(base).to_luma16()),
        ),
    ];
    for (name, img) in inputs {
        let input = dir.path().join(name);
        img.save(&input).unwrap();
        let out = dir.path().join(format!("out-{name}.png"));
        let mut args = vec!["run", s(&input), "-o", s(&out)];
        args.extend(FAST);
        let o = grime(&args);
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        let aged = image::open(&out).unwrap();
        assert_eq!((aged.width(), aged.height()), (64, 48), "{name}");
        let deep = name.contains("16") || name.starts_with("deep");
        assert_eq!(
            aged.color().bytes_per_pixel() > 4,
            deep,
            "{name} keeps its depth: {:?}",
            aged.color()
        );
    }
}

#[test]
fn writes_the_format_the_extension_names() {
    let dir = tempfile::tempdir().unwrap();
    let input = photo(dir.path(), "in.png");
    for (ext, format) in [
        ("jpg", image::ImageFormat::Jpeg),
        ("tiff", image::ImageFormat::Tiff),
        ("webp", image::ImageFormat::WebP),
    ] {
        let out = dir.path().join(format!("out.{ext}"));
        let mut args = vec!["run", s(&input), "-o", s(&out)];
        args.extend(FAST);
        assert!(grime(&args).status.success());
        assert_eq!(
            image::ImageReader::open(&out)
                .unwrap()
                .with_guessed_format()
                .unwrap()
                .format(),
            Some(format)
        );
    }
}

#[test]
fn missing_input_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let o = grime(&[
        "run",
        "/nonexistent/facade.jpg",
        "-o",
        s(&dir.path().join("a.png")),
    ]);
    assert_clear_error(&o, "/nonexistent/facade.jpg");
}

#[test]
fn corrupt_image_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.png");
    std::fs::write(&bad, b"\x89PNG\r\n\x1a\nthis is not really a png").unwrap();
    let o = grime(&["run", s(&bad), "-o", s(&dir.path().join("a.png"))]);
    assert_clear_error(&o, "cannot decode");
    let empty = dir.path().join("empty.jpg");
    std::fs::write(&empty, b"").unwrap();
    assert_clear_error(
        &grime(&["run", s(&empty), "-o", s(&dir.path().join("b.png"))]),
        "empty",
    );
}

#[test]
fn unknown_extensions_are_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    let input = photo(dir.path(), "in.png");
    assert_clear_error(
        &grime(&["run", s(&input), "-o", s(&dir.path().join("a.bmpx"))]),
        "unknown image extension",
    );
    let text = dir.path().join("notes.txt");
    std::fs::write(&text, "hello").unwrap();
    assert_clear_error(
        &grime(&["run", s(&text), "-o", s(&dir.path().join("a.png"))]),
        "notes.txt",
    );
}

#[test]
fn mask_of_another_size_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let input = photo(dir.path(), "in.png");
    let mask = dir.path().join("mask.png");
    ImageBuffer::<Luma<u8>, _>::from_pixel(50, 50, Luma([255]))
        .save(&mask)
        .unwrap();
    let o = grime(&[
        "run",
        s(&input),
        "-o",
        s(&dir.path().join("a.png")),
        "--mask",
        s(&mask),
    ]);
    assert_clear_error(&o, "mask is 50x50 but the image is 96x72");
}

#[test]
fn invalid_presets_are_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    let input = photo(dir.path(), "in.png");
    let out = dir.path().join("a.png");
    let o = grime(&["run", s(&input), "-o", s(&out), "--set", "rain.k_a=3"]);
    assert_clear_error(&o, "rain.k_a = 3");
    assert!(
        stderr(&o).contains("0 ..= 1"),
        "names the range: {}",
        stderr(&o)
    );
    assert_clear_error(
        &grime(&["run", s(&input), "-o", s(&out), "--set", "rain.nope=1"]),
        "rain.nope",
    );
    let toml = dir.path().join("p.toml");
    std::fs::write(&toml, "[rain]\ntau = 0.5\n").unwrap();
    assert_clear_error(
        &grime(&["run", s(&input), "-o", s(&out), "--preset", s(&toml)]),
        "rain.tau",
    );
    std::fs::write(&toml, "[rain]\nbogus = 1\n").unwrap();
    assert_clear_error(
        &grime(&["run", s(&input), "-o", s(&out), "--preset", s(&toml)]),
        "bogus",
    );
    assert_clear_error(
        &grime(&[
            "run",
            s(&input),
            "-o",
            s(&out),
            "--preset",
            "no-such-preset",
        ]),
        "built-in presets",
    );
    let too_big = grime(&[
        "run",
        s(&input),
        "-o",
        s(&out),
        "--seed",
        "9223372036854775808",
    ]);
    assert_clear_error(&too_big, "seed");
    assert!(!out.exists());
}

#[test]
fn output_equal_to_input_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let input = photo(dir.path(), "in.png");
    let before = std::fs::read(&input).unwrap();
    assert_clear_error(
        &grime(&["run", s(&input), "-o", s(&input)]),
        "refusing to overwrite",
    );
    let same = format!("{}/./in.png", dir.path().display());
    assert_clear_error(
        &grime(&["run", s(&input), "-o", &same]),
        "refusing to overwrite",
    );
    assert_eq!(std::fs::read(&input).unwrap(), before);
}

#[test]
fn output_in_a_missing_folder_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let input = photo(dir.path(), "in.png");
    let o = grime(&["run", s(&input), "-o", s(&dir.path().join("nope/a.png"))]);
    assert_clear_error(&o, "does not exist");
}

#[test]
fn same_output_at_one_and_two_threads() {
    let dir = tempfile::tempdir().unwrap();
    let run = |threads: &str| {
        let out = dir.path().join(format!("t{threads}.png"));
        let o = Command::new(env!("CARGO_BIN_EXE_grime"))
            .args([
                "run",
                "--demo",
                "-o",
                s(&out),
                "--seed",
                "7",
                "--set",
                "sim.max_side=300",
            ])
            .env("RAYON_NUM_THREADS", threads)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", stderr(&o));
        std::fs::read(out).unwrap()
    };
    assert!(
        run("1") == run("2"),
        "outputs differ between 1 and 2 threads"
    );
}

#[test]
fn layers_dir_has_a_png_per_layer_and_a_manifest() {
    let dir = tempfile::tempdir().unwrap();
    let layers = dir.path().join("layers");
    let o = grime(&[
        "run",
        "--demo",
        "-o",
        s(&dir.path().join("a.png")),
        "--layers",
        "4",
        "--layers-dir",
        s(&layers),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let manifest: serde_json::Value =
        serde_json::from_slice(&std::fs::read(layers.join("manifest.json")).unwrap()).unwrap();
    let entries = manifest["layers"].as_array().unwrap();
    assert_eq!(entries[0]["name"], "photo");
    let rain: Vec<_> = entries
        .iter()
        .filter(|e| e["name"].as_str().unwrap().starts_with("rain 0"))
        .collect();
    assert_eq!(rain.len(), 4);
    assert_eq!(rain[0]["name"], "rain 01");
    let washed = entries.iter().find(|e| e["name"] == "rain washed").unwrap();
    assert_eq!(washed["blend"], "screen");
    for e in entries {
        let img = image::open(layers.join(e["file"].as_str().unwrap())).unwrap();
        assert_eq!((img.width(), img.height()), (960, 720));
        assert!(e["opacity"].as_f64().unwrap() > 0.0);
        assert!(["normal", "multiply", "screen"].contains(&e["blend"].as_str().unwrap()));
    }
    for e in rain {
        // A deposit painted over the wall in its own colour per pixel.
        assert_eq!(e["blend"], "normal");
        let img = image::open(layers.join(e["file"].as_str().unwrap()))
            .unwrap()
            .to_rgba8();
        let alpha: Vec<u8> = img.pixels().map(|p: &Rgba<u8>| p[3]).collect();
        assert!(
            alpha.contains(&0),
            "transparent where the layer has no effect"
        );
        assert!(alpha.iter().any(|&a| a > 32), "and visible somewhere");
        // Windows are outside the region: fully transparent there.
        assert_eq!(img.get_pixel(120, 250)[3], 0);
    }
}

#[test]
fn report_says_what_happened() {
    let dir = tempfile::tempdir().unwrap();
    let report = dir.path().join("r.json");
    let o = grime(&[
        "run",
        "--demo",
        "-o",
        s(&dir.path().join("a.png")),
        "--layers",
        "3",
        "--seed",
        "42",
        "--report",
        s(&report),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let r: serde_json::Value = serde_json::from_slice(&std::fs::read(report).unwrap()).unwrap();
    assert_eq!(r["image"]["width"], 960);
    assert_eq!(r["seed"], 42);
    assert!(r["rain"]["droplets_per_layer"].as_u64().unwrap() > 100);
    let rain: Vec<_> = r["layers"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|l| l["rain"].is_object())
        .collect();
    assert_eq!(rain.len(), 3);
    for l in rain {
        assert!(l["rain"]["droplets"].as_u64().unwrap() > 0);
        assert!(l["rain"]["droplet_steps"].as_u64().unwrap() > 1000);
        assert!(l["rain"]["mean_dirt"].as_f64().unwrap() > 0.0);
        assert!(l["rain"]["max_dirt"].as_f64().unwrap() > l["rain"]["mean_dirt"].as_f64().unwrap());
    }
    let stages: Vec<_> = r["timings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| t["stage"].as_str().unwrap().to_string())
        .collect();
    assert!(stages.contains(&"rain".to_string()), "{stages:?}");
}

#[test]
fn preset_default_round_trips_and_documents_every_field() {
    let o = grime(&["preset", "default"]);
    assert!(o.status.success());
    let text = String::from_utf8(o.stdout).unwrap();
    let parsed = grime::preset::Preset::from_toml(&text).unwrap();
    assert_eq!(parsed, grime::preset::Preset::default());
    for line in text
        .lines()
        .filter(|l| l.contains(" = ") && !l.starts_with('#'))
    {
        let key = line.split(" = ").next().unwrap();
        assert!(text.contains(&format!("\n{key} = ")), "{key}");
    }
    assert!(
        text.contains("[k_a]") && text.contains("Range 0 ..= 1"),
        "symbols and ranges in comments"
    );
    let list = grime(&["preset", "--list"]);
    assert!(
        String::from_utf8(list.stdout)
            .unwrap()
            .contains("chang-table1")
    );
}

#[test]
fn set_and_preset_file_change_the_result() {
    let dir = tempfile::tempdir().unwrap();
    let input = photo(dir.path(), "in.png");
    let run = |extra: &[&str]| {
        let out = dir.path().join("x.png");
        let mut args = vec!["run", s(&input), "-o", s(&out)];
        args.extend(FAST);
        args.extend(extra);
        let o = grime(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        std::fs::read(out).unwrap()
    };
    let base = run(&[]);
    assert!(run(&["--set", "stain.color=[200, 0, 0]"]) != base);
    let toml = dir.path().join("p.toml");
    std::fs::write(&toml, "seed = 99\n").unwrap();
    assert!(run(&["--preset", s(&toml)]) != base);
}
