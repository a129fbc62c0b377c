//! `grime batch` against a plain decode + encode of the same files (issue 5).
//!
//! 50 JPEGs of about 2 MP (the procedural facade, varied) are generated once
//! into `target/tmp/bench-batch/`. Then, each `REPS` times, side by side:
//!
//! - `grime batch in -o out --format png --jobs 2 -q` with the default
//!   preset (the real binary, under `/usr/bin/time -v` for peak RSS);
//! - the plain round trip with the `image` crate: decode JPEG, encode PNG,
//!   on a rayon pool of the same number of threads;
//! - ImageMagick (`/usr/bin/convert`, 2 at a time via xargs), if installed.
//!
//! Peak RSS of `grime batch` is also measured at `--jobs 1, 2, 4` and on 10
//! versus 50 images (bounded memory, no growth with the number of images).
//! Not criterion: one sample is a minute of work, and the comparison needs
//! the real binary. Prints a Markdown table for BENCHMARKS.md.
//!
//! `cargo bench --bench batch`; env `BENCH_IMAGES` (50), `BENCH_REPS` (3),
//! `BENCH_JOBS` (2), `GRIME_BIN` (the binary to time; default: this build's).

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use image::Rgb;
use image::codecs::png::PngEncoder;
use rayon::prelude::*;

fn env_or(name: &str, default: usize) -> usize {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// `n` facades of about 1700 x 1200, each a little different.
fn generate(dir: &Path, n: usize) {
    std::fs::create_dir_all(dir).unwrap();
    (0..n).into_par_iter().for_each(|i| {
        let path = dir.join(format!("facade-{i:03}.jpg"));
        if path.exists() {
            return;
        }
        let (w, h) = (1700 - 8 * (i as u32 % 5), 1200 - 6 * (i as u32 % 4));
        let demo = grime::demo::facade(w, h);
        let mut img = demo.photo.image().to_rgb8();
        let tint = [
            1.0 - 0.02 * (i % 4) as f32,
            1.0,
            1.0 - 0.015 * (i % 6) as f32,
        ];
        for Rgb(p) in img.pixels_mut() {
            for c in 0..3 {
                p[c] = (p[c] as f32 * tint[c]) as u8;
            }
        }
        img.save(&path).unwrap();
    });
}

fn clean(dir: &Path) {
    let _ = std::fs::remove_dir_all(dir);
    std::fs::create_dir_all(dir).unwrap();
}

/// Wall seconds and peak RSS (MiB) of a command, via GNU time if present.
fn measure(args: &[&str]) -> (f64, Option<f64>) {
    let gnu_time = Path::new("/usr/bin/time").exists();
    let t = Instant::now();
    let out = if gnu_time {
        Command::new("/usr/bin/time").arg("-v").args(args).output()
    } else {
        Command::new(args[0]).args(&args[1..]).output()
    }
    .expect("run command");
    let secs = t.elapsed().as_secs_f64();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{args:?} failed: {err}");
    let rss = err
        .lines()
        .find_map(|l| {
            l.trim()
                .strip_prefix("Maximum resident set size (kbytes): ")
        })
        .and_then(|v| v.trim().parse::<f64>().ok())
        .map(|kb| kb / 1024.0);
    (secs, rss)
}

fn plain_round_trip(files: &[PathBuf], out: &Path, jobs: usize) -> f64 {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs)
        .build()
        .unwrap();
    let t = Instant::now();
    pool.install(|| {
        files.par_iter().for_each(|f| {
            let img = image::open(f).unwrap();
            let path = out.join(f.file_name().unwrap()).with_extension("png");
            let mut w = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
            img.write_with_encoder(PngEncoder::new(&mut w)).unwrap();
        })
    });
    t.elapsed().as_secs_f64()
}

fn main() {
    let n = env_or("BENCH_IMAGES", 50);
    let reps = env_or("BENCH_REPS", 3).max(1);
    let jobs = env_or("BENCH_JOBS", 2);
    let root = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("bench-batch");
    let input = root.join(format!("in-{n}"));
    eprintln!("generating {n} images in {} ...", input.display());
    generate(&input, n);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&input)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    let mpx: f64 = files
        .iter()
        .map(|f| {
            let (w, h) = image::image_dimensions(f).unwrap();
            (w * h) as f64 / 1e6
        })
        .sum::<f64>()
        / n as f64;
    // GRIME_BIN: a copy of the binary, so that concurrent builds in the
    // shared target folder cannot swap it mid-measurement.
    let grime_bin =
        std::env::var("GRIME_BIN").unwrap_or_else(|_| env!("CARGO_BIN_EXE_grime").to_string());
    let grime = grime_bin.as_str();
    let out = root.join("out");
    let input_s = input.to_str().unwrap();
    let out_s = out.to_str().unwrap();
    let jobs_s = jobs.to_string();

    let (mut t_grime, mut t_plain, mut t_magick, mut rss) = (vec![], vec![], vec![], vec![]);
    let magick = Path::new("/usr/bin/convert").exists()
        && Command::new("/usr/bin/convert")
            .arg("-version")
            .output()
            .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).contains("ImageMagick"));
    for r in 0..reps {
        eprintln!("rep {}/{reps}", r + 1);
        clean(&out);
        let (s, m) = measure(&[
            grime, "batch", input_s, "-o", out_s, "--format", "png", "--jobs", &jobs_s, "-q",
        ]);
        t_grime.push(s);
        rss.extend(m);
        clean(&out);
        t_plain.push(plain_round_trip(&files, &out, jobs));
        if magick {
            clean(&out);
            let script = format!(
                "cd {input_s} && ls *.jpg | xargs -P {jobs} -I{{}} /usr/bin/convert {{}} {out_s}/{{}}.png"
            );
            t_magick.push(measure(&["sh", "-c", &script]).0);
        }
    }
    let (g, p) = (median(t_grime), median(t_plain));
    println!(
        "\n{n} images, {mpx:.2} MP each on average, --jobs {jobs}, default preset, PNG out; median of {reps}\n"
    );
    println!("| what | wall time | per image | ratio to grime |");
    println!("|---|---|---|---|");
    println!("| `grime batch` | {g:.1} s | {:.2} s | 1 |", g / n as f64);
    println!(
        "| plain round trip, `image` crate (decode JPEG, encode PNG) | {p:.1} s | {:.2} s | grime = {:.1}x |",
        p / n as f64,
        g / p
    );
    if magick {
        let m = median(t_magick);
        println!(
            "| plain round trip, ImageMagick `convert` to PNG | {m:.1} s | {:.2} s | grime = {:.1}x |",
            m / n as f64,
            g / m
        );
    }
    if let Some(&peak) = rss.iter().max_by(|a, b| a.total_cmp(b)) {
        println!("\nPeak RSS of `grime batch --jobs {jobs}` over {n} images: {peak:.0} MiB");
    }

    // Where one image's time goes (grime run --report on the first file).
    let report = root.join("report.json");
    let single = out.join("single.png");
    measure(&[
        grime,
        "run",
        files[0].to_str().unwrap(),
        "-o",
        single.to_str().unwrap(),
        "-q",
        "--report",
        report.to_str().unwrap(),
    ]);
    let r: serde_json::Value = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
    let stages: Vec<String> = r["timings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| {
            format!(
                "{} {:.0} ms",
                t["stage"].as_str().unwrap_or("?"),
                t["ms"].as_f64().unwrap_or(0.0)
            )
        })
        .collect();
    println!(
        "\nOne image alone (`grime run --report`): {}",
        stages.join(", ")
    );

    // Peak memory against jobs, and against the number of images.
    let small = root.join("in-10");
    std::fs::create_dir_all(&small).unwrap();
    for f in files.iter().take(10) {
        let dst = small.join(f.file_name().unwrap());
        if !dst.exists() {
            std::fs::copy(f, dst).unwrap();
        }
    }
    println!("\n| images | --jobs | wall time | peak RSS |");
    println!("|---|---|---|---|");
    for (dir, count, j) in [
        (&small, 10, 1),
        (&small, 10, 2),
        (&small, 10, 4),
        (&input, n, 1),
    ] {
        clean(&out);
        let js = j.to_string();
        let (s, m) = measure(&[
            grime,
            "batch",
            dir.to_str().unwrap(),
            "-o",
            out_s,
            "--format",
            "png",
            "--jobs",
            &js,
            "-q",
        ]);
        let m = m.map_or("n/a".to_string(), |m| format!("{m:.0} MiB"));
        println!("| {count} | {j} | {s:.1} s | {m} |");
    }
}
