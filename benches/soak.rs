//! Soak test of `grime batch` (issue 13): 1,000 small images, 5% of them
//! corrupt (truncated, random bytes, text named .png, a GIF), through the
//! real binary. Records the wall time and the peak RSS (`/usr/bin/time -v`)
//! and checks that exactly the corrupt images are reported as failed, every
//! other one written, and no temporary file left.
//!
//! `cargo bench --bench soak`; env `SOAK_IMAGES` (1000), `SOAK_JOBS` (2),
//! `GRIME_BIN` (default: this build's binary). Prints a Markdown table row.

use std::collections::BTreeSet;
use std::path::Path;
use std::process::Command;
use std::time::Instant;

use image::DynamicImage;

fn env_or(name: &str, default: usize) -> usize {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// Writes `n` images of 96 x 72 (the facade, shifted so each differs); every
/// 20th is corrupt. Returns the corrupt names.
fn make_inputs(dir: &Path, n: usize) -> BTreeSet<String> {
    let base = grime::demo::facade(192, 144).photo.image().to_rgb8();
    let mut png = Vec::new();
    let mut corrupt = BTreeSet::new();
    for i in 0..n {
        let name = format!("img-{i:04}.png");
        let path = dir.join(&name);
        if i % 20 == 7 {
            let bytes: Vec<u8> = match (i / 20) % 4 {
                // Truncated in the middle of its image data.
                0 => png[..png.len() / 2].to_vec(),
                1 => (0..600u32)
                    .map(|k| (k.wrapping_mul(2_654_435_761).wrapping_add(i as u32) >> 13) as u8)
                    .collect(),
                2 => b"not an image\n".to_vec(),
                _ => b"GIF89a\x01\x00\x01\x00\x00\x00\x00;".to_vec(),
            };
            std::fs::write(&path, bytes).unwrap();
            corrupt.insert(name);
            continue;
        }
        let (x, y) = ((i * 7 % 96) as u32, (i * 5 % 72) as u32);
        let img = image::imageops::crop_imm(&base, x, y, 96, 72).to_image();
        png.clear();
        DynamicImage::ImageRgb8(img)
            .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
            .unwrap();
        std::fs::write(&path, &png).unwrap();
    }
    corrupt
}

fn main() {
    let n = env_or("SOAK_IMAGES", 1000);
    let jobs = env_or("SOAK_JOBS", 2);
    let bin = std::env::var("GRIME_BIN").unwrap_or_else(|_| env!("CARGO_BIN_EXE_grime").into());
    let work = tempfile::tempdir().unwrap();
    let input = work.path().join("in");
    let output = work.path().join("out");
    std::fs::create_dir_all(&input).unwrap();
    let corrupt = make_inputs(&input, n);

    let t = Instant::now();
    let o = Command::new("/usr/bin/time")
        .arg("-v")
        .arg(&bin)
        .args(["batch"])
        .arg(&input)
        .arg("-o")
        .arg(&output)
        .args(["--json", "-q", "--jobs", &jobs.to_string()])
        .output()
        .expect("run /usr/bin/time -v grime batch");
    let secs = t.elapsed().as_secs_f64();
    let stderr = String::from_utf8_lossy(&o.stderr);
    let rss_kb: u64 = stderr
        .lines()
        .find_map(|l| {
            l.trim()
                .strip_prefix("Maximum resident set size (kbytes): ")
        })
        .and_then(|v| v.trim().parse().ok())
        .expect("peak RSS in /usr/bin/time -v output");
    let summary: serde_json::Value = serde_json::from_slice(&o.stdout).expect("the --json summary");
    let failed: BTreeSet<String> = summary["files"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|f| f["status"] == "failed")
        .map(|f| f["path"].as_str().unwrap().to_string())
        .collect();
    let written = std::fs::read_dir(&output)
        .unwrap()
        .filter(|e| {
            let name = e.as_ref().unwrap().file_name();
            let name = name.to_str().unwrap();
            assert!(!name.ends_with(".tmp"), "temporary file left: {name}");
            true
        })
        .count();
    assert_eq!(failed, corrupt, "exactly the corrupt images fail");
    assert_eq!(written, n - corrupt.len(), "every other image is written");
    assert_eq!(o.status.code(), Some(1), "exit 1 when some failed");
    println!("| images | corrupt | --jobs | wall time | per image | peak RSS | failed = corrupt |");
    println!("|---|---|---|---|---|---|---|");
    println!(
        "| {n} | {} | {jobs} | {secs:.1} s | {:.1} ms | {:.0} MiB | yes |",
        corrupt.len(),
        secs * 1000.0 / n as f64,
        rss_kb as f64 / 1024.0
    );
}
