//! The memory a run will need, checked before decoding: a large photo is
//! refused with the estimate and how to raise the limit, instead of running
//! for a minute and taking gigabytes.

use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

use crate::error::{Error, Result};

/// Peak memory of a run per photo pixel: 37 B/px measured on a 4000x3000
/// JPEG with rain, moss and dust (BENCHMARKS.md, table 2 row 2).
pub const BYTES_PER_PIXEL: u64 = 37;

/// The limit when neither `--max-memory` nor `GRIME_MAX_MEMORY` sets one:
/// 4 GiB, a photo of about 116 megapixels.
pub const DEFAULT_MAX_MEMORY: u64 = 4 << 30;

/// The environment variable that sets the limit (e.g. `GRIME_MAX_MEMORY=12G`).
pub const ENV: &str = "GRIME_MAX_MEMORY";

/// 0 = not set by the program.
static LIMIT: AtomicU64 = AtomicU64::new(0);

/// Sets the limit for this process (`--max-memory`); it wins over
/// `GRIME_MAX_MEMORY`.
pub fn set_max_memory(bytes: u64) {
    LIMIT.store(bytes.max(1), Ordering::Relaxed);
}

/// The limit: [`set_max_memory`]'s, else `GRIME_MAX_MEMORY`'s, else
/// [`DEFAULT_MAX_MEMORY`].
///
/// # Errors
/// [`Error::OutOfRange`] when `GRIME_MAX_MEMORY` is not a size.
pub fn max_memory() -> Result<u64> {
    match LIMIT.load(Ordering::Relaxed) {
        0 => match std::env::var(ENV) {
            Ok(v) => parse_size(&v).map_err(|range| Error::OutOfRange {
                field: ENV.into(),
                value: v,
                range,
            }),
            Err(_) => Ok(DEFAULT_MAX_MEMORY),
        },
        n => Ok(n),
    }
}

/// Parses a size: bytes, or a number with K, M, G or T (powers of 1024;
/// `B`, `iB` allowed after the letter), e.g. `12G`, `1.5GiB`, `800M`.
///
/// # Errors
/// What a size looks like.
pub fn parse_size(text: &str) -> std::result::Result<u64, String> {
    const HELP: &str = "a size such as 12G, 1.5GiB or 800M";
    let t = text.trim();
    let t = t
        .strip_suffix("iB")
        .or_else(|| t.strip_suffix('B'))
        .unwrap_or(t);
    let (num, unit) = match t.char_indices().last() {
        Some((i, c)) if c.is_ascii_alphabetic() => (&t[..i], c.to_ascii_uppercase()),
        _ => (t, ' '),
    };
    let scale = match unit {
        ' ' => 1u64,
        'K' => 1 << 10,
        'M' => 1 << 20,
        'G' => 1 << 30,
        'T' => 1 << 40,
        _ => return Err(HELP.into()),
    };
    let v: f64 = num.trim().parse().map_err(|_| HELP.to_string())?;
    if !(v.is_finite() && v > 0.0 && v * (scale as f64) < u64::MAX as f64) {
        return Err(HELP.into());
    }
    Ok((v * scale as f64).round() as u64)
}

/// Peak memory of a run with a time-lapse per photo pixel, besides the
/// frames an animation keeps: the run's layers, the photo with the shared
/// rainfalls composited once (13 B/px), the dust carried between frames
/// and a frame's own layers and composite (BENCHMARKS.md, "Time-lapse
/// (issue 15)").
pub const TIMELAPSE_BYTES_PER_PIXEL: u64 = 118;

/// Estimated peak memory of ageing a `w` x `h` photo.
pub fn estimate(w: u32, h: u32) -> u64 {
    w as u64 * h as u64 * BYTES_PER_PIXEL
}

/// Estimated peak memory of ageing a `w` x `h` photo with a time-lapse
/// that keeps `frames` RGBA frames of longest side `max_side` (0 = the
/// photo's) until it writes them (an animation; a folder keeps none).
pub fn estimate_timelapse(w: u32, h: u32, frames: u64, max_side: u32) -> u64 {
    let scale = match max_side {
        0 => 1.0,
        s => (s as f64 / w.max(h).max(1) as f64).min(1.0),
    };
    let frame = (w as f64 * scale).ceil() * (h as f64 * scale).ceil() * 4.0;
    w as u64 * h as u64 * TIMELAPSE_BYTES_PER_PIXEL + frames * frame as u64
}

/// Refuses a photo whose run would need more than [`max_memory`].
///
/// # Errors
/// [`Error::MemoryLimit`] with the estimate and a limit that would do.
pub fn check(path: &Path, w: u32, h: u32) -> Result<()> {
    check_needing(path, w, h, estimate(w, h))
}

/// Refuses a `w` x `h` photo when `needed` bytes are more than [`max_memory`].
///
/// # Errors
/// [`Error::MemoryLimit`] with the estimate and a limit that would do.
pub fn check_needing(path: &Path, w: u32, h: u32, needed: u64) -> Result<()> {
    let limit = max_memory()?;
    if needed <= limit {
        return Ok(());
    }
    Err(Error::MemoryLimit {
        path: path.to_path_buf(),
        width: w,
        height: h,
        needed: super::human_bytes(needed),
        limit: super::human_bytes(limit),
        suggest: format!("{}G", needed.div_ceil(1 << 30)),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse() {
        assert_eq!(parse_size("12G"), Ok(12 << 30));
        assert_eq!(parse_size("1.5GiB"), Ok(3 << 29));
        assert_eq!(parse_size("800m"), Ok(800 << 20));
        assert_eq!(parse_size("4096"), Ok(4096));
        assert!(parse_size("lots").is_err());
        assert!(parse_size("-1G").is_err());
        assert!(parse_size("9e30T").is_err());
    }

    #[test]
    fn a_16k_square_photo_is_refused_with_the_estimate() {
        let err = check(Path::new("big.png"), 16000, 16000)
            .unwrap_err()
            .to_string();
        assert!(err.contains("about 8.8 GiB"), "{err}");
        assert!(err.contains("--max-memory 9G"), "{err}");
        assert!(check(Path::new("a.png"), 4000, 3000).is_ok());
    }

    #[test]
    fn a_timelapse_counts_its_frames_and_the_shared_layers() {
        let run = estimate(4000, 3000);
        let folder = estimate_timelapse(4000, 3000, 0, 1024);
        assert!(folder > 2 * run, "{folder} vs {run}");
        // 31 GIF frames of 1024 x 768.
        let gif = estimate_timelapse(4000, 3000, 31, 1024);
        assert_eq!(gif - folder, 31 * 1024 * 768 * 4);
        // Frames at the photo's size when it is smaller than the frame size.
        assert_eq!(
            estimate_timelapse(100, 50, 2, 1024) - estimate_timelapse(100, 50, 0, 1024),
            2 * 100 * 50 * 4
        );
        // A 12 MP photo whose run fits 1 GiB is refused with a time-lapse.
        let limit = 1u64 << 30;
        assert!(run < limit && gif > limit);
    }
}
