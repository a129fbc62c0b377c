//! Helpers shared by the tests that run the real `grime` binary.
#![allow(dead_code)]

pub mod wall;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use image::DynamicImage;

/// Runs `grime` with `args` and waits for it.
pub fn grime(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_grime"))
        .args(args)
        .output()
        .expect("run grime")
}

/// Its standard error as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A failed run: non-zero exit, one line on stderr naming `needle`, no panic.
pub fn assert_clear_error(o: &Output, needle: &str) {
    let err = stderr(o);
    assert!(
        !o.status.success(),
        "expected failure, got success; stderr: {err}"
    );
    assert!(
        !err.contains("panicked") && !err.contains("RUST_BACKTRACE"),
        "panic: {err}"
    );
    assert_eq!(
        err.trim_end().lines().count(),
        1,
        "one line expected: {err}"
    );
    assert!(
        err.to_lowercase().contains(&needle.to_lowercase()),
        "{needle:?} not in: {err}"
    );
}

/// A small facade photo saved as `dir/name`.
pub fn photo(dir: &Path, name: &str) -> PathBuf {
    let path = dir.join(name);
    DynamicImage::ImageRgb8(grime::demo::facade(96, 72).photo.image().to_rgb8())
        .save(&path)
        .unwrap();
    path
}

/// A path as &str.
pub fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Flags for a fast run.
pub const FAST: [&str; 4] = ["--layers", "3", "--set", "sim.max_side=64"];
