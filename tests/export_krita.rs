//! Krita 5.1 opens grime's 16-bit ORA headless, without a colour-profile
//! prompt and as sRGB (issue 13 items 17-18: without the embedded profile
//! `krita --export` waited forever on a modal prompt, and 16-bit pixels
//! opened as linear light, up to 73/255 lighter).
//!
//! Needs `krita` and `xvfb-run` (`.ci/run` installs both). The test fails
//! when `CI` is set and they are missing, and is skipped with a message
//! otherwise. Krita runs under `timeout`, so a prompt fails the test instead
//! of hanging it.

use std::path::Path;
use std::process::Command;

use image::{ImageBuffer, Rgb};

fn available(tool: &str) -> bool {
    let found = Command::new("sh")
        .args(["-c", &format!("command -v {tool}")])
        .output()
        .is_ok_and(|o| o.status.success());
    if !found && std::env::var_os("CI").is_some() {
        panic!("{tool} is required in CI (.ci/run installs it with apt)");
    }
    found
}

fn grime(args: &[&str]) {
    let o = Command::new(env!("CARGO_BIN_EXE_grime"))
        .args(args)
        .output()
        .expect("run grime");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn krita_exports_a_sixteen_bit_ora_as_srgb_without_a_prompt() {
    if !available("krita") || !available("xvfb-run") || !available("timeout") {
        eprintln!("skipped: krita, xvfb-run or timeout not installed");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    // A 16-bit photo without an ICC profile.
    let photo = grime::demo::facade(160, 120).photo.image().to_rgb8();
    let deep: ImageBuffer<Rgb<u16>, Vec<u16>> = ImageBuffer::from_fn(160, 120, |x, y| {
        Rgb(photo.get_pixel(x, y).0.map(|v| v as u16 * 257))
    });
    let input = dir.path().join("photo16.png");
    deep.save(&input).unwrap();
    let (ora, png) = (dir.path().join("aged.ora"), dir.path().join("aged.png"));
    let common = ["--region", "full", "--layers", "3", "-q"];
    for out in [&ora, &png] {
        let mut args = vec!["run", s(&input), "-o", s(out)];
        args.extend_from_slice(&common);
        grime(&args);
    }
    let exported = dir.path().join("krita.png");
    let home = dir.path().join("home");
    std::fs::create_dir(&home).unwrap();
    // Xvfb sometimes fails to come up on a machine's first start (xvfb-run
    // then runs Krita with no display): try again, up to three times.
    let mut o = krita_export(&exported, &ora, &home);
    for _ in 0..2 {
        let no_display =
            String::from_utf8_lossy(&o.stderr).contains("could not connect to display");
        if o.status.success() || !no_display {
            break;
        }
        o = krita_export(&exported, &ora, &home);
    }
    assert!(
        o.status.success(),
        "krita --export failed or hung (exit {:?}): {}",
        o.status.code(),
        String::from_utf8_lossy(&o.stderr)
    );
    let ours = image::open(&png).unwrap().to_rgb8();
    let theirs = image::open(&exported).unwrap().to_rgb8();
    assert_eq!(ours.dimensions(), theirs.dimensions());
    let worst = ours
        .as_raw()
        .iter()
        .zip(theirs.as_raw())
        .map(|(a, b)| a.abs_diff(*b))
        .max()
        .unwrap();
    // Krita composites 8-bit exports in integer arithmetic (README: within
    // 7/255); linear-light misreading would be tens of levels off.
    assert!(worst <= 7, "Krita's composite differs by {worst}/255");
}

/// `krita --export` of `ora` to `exported` in a virtual X server.
fn krita_export(exported: &Path, ora: &Path, home: &Path) -> std::process::Output {
    Command::new("timeout")
        .args(["120", "xvfb-run", "-a", "-s", "-screen 0 1024x768x24"])
        .args([
            "krita",
            "--export",
            "--export-filename",
            s(exported),
            s(ora),
        ])
        .env("HOME", home)
        .output()
        .expect("run krita")
}
