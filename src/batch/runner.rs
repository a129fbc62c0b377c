//! Ageing the planned images on a thread pool, each through
//! [`crate::age::age`], and summing up what happened.

use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Instant;

use serde::Serialize;

use super::plan::{Job, ListingError, Plan, derive_seed, rel_string};
use crate::age::{self, Inputs, Outputs};
use crate::error::{Error, Result};
use crate::perspective::{self, Quad};
use crate::preset::Preset;
use crate::progress::Progress;

/// How one image ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    /// Aged and written.
    Ok,
    /// Not written; see the error.
    Failed,
    /// Its outputs already existed.
    Skipped,
}

/// One image in the summary.
#[derive(Debug, Clone, Serialize)]
pub struct FileReport {
    /// Path relative to the input folder, `/`-separated.
    pub path: String,
    /// Stable index in the whole folder's listing.
    pub index: usize,
    /// Outcome.
    pub status: Status,
    /// The image's seed ([`derive_seed`]).
    pub seed: u64,
    /// Output files.
    pub outputs: Vec<PathBuf>,
    /// Why it failed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// Wall time for this image, in milliseconds.
    pub ms: f64,
}

/// What a batch did (`--json`).
#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    /// Input folder.
    pub input: PathBuf,
    /// Output folder.
    pub output: PathBuf,
    /// The shard, as `K/N`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shard: Option<String>,
    /// Images found in the whole folder.
    pub found: usize,
    /// Images aged and written.
    pub succeeded: usize,
    /// Images that failed, plus folders that could not be listed.
    pub failed: usize,
    /// Images skipped because their outputs existed.
    pub skipped: usize,
    /// Every image of this shard, by stable index.
    pub files: Vec<FileReport>,
    /// Folders that could not be listed.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub listing_errors: Vec<ListingError>,
    /// Wall time, in seconds.
    pub seconds: f64,
}

impl Summary {
    /// `N succeeded, M failed, K skipped`.
    pub fn line(&self) -> String {
        format!(
            "{} succeeded, {} failed, {} skipped",
            self.succeeded, self.failed, self.skipped
        )
    }
}

/// The reason in an error's message, without the leading `path: ` when the
/// error names the file itself.
fn reason(err: &Error, input: &Path) -> String {
    let text = err.to_string();
    let prefix = format!("{}: ", input.display());
    text.strip_prefix(&prefix)
        .map(str::to_string)
        .unwrap_or(text)
}

/// Ages every job of `plan` with `jobs` threads (0 = all cores). `preset`'s
/// seed is the batch seed; each image runs with [`derive_seed`]. A failing
/// image is recorded and the rest go on. `on_done` sees each finished image
/// (from worker threads) in completion order. Once `cancel` is set, images
/// not yet started are left out.
///
/// At most `jobs` images are in memory at once: each pool thread takes the
/// next image only when its current one is written (the pipeline's own
/// parallel loops share the same threads).
///
/// # Errors
/// [`Error::Io`] if the output folder cannot be created or the thread pool
/// cannot be built.
pub fn run(
    plan: &Plan,
    preset: &Preset,
    jobs: usize,
    on_done: &(dyn Fn(&FileReport) + Sync),
    cancel: Option<&AtomicBool>,
) -> Result<Summary> {
    let start = Instant::now();
    std::fs::create_dir_all(&plan.output).map_err(|e| Error::io(&plan.output, e))?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs)
        .thread_name(|i| format!("grime-batch-{i}"))
        .build()
        .map_err(|e| Error::io(&plan.input, std::io::Error::other(e.to_string())))?;
    let next = AtomicUsize::new(0);
    let done: Mutex<Vec<FileReport>> = Mutex::new(Vec::with_capacity(plan.jobs.len()));
    pool.broadcast(|_| {
        loop {
            if cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
                break;
            }
            let Some(job) = plan.jobs.get(next.fetch_add(1, Ordering::Relaxed)) else {
                break;
            };
            let report = run_job(plan, job, preset, cancel);
            on_done(&report);
            if let Ok(mut d) = done.lock() {
                d.push(report);
            }
        }
    });
    let mut files = done.into_inner().unwrap_or_else(|p| p.into_inner());
    files.extend(plan.skipped.iter().map(|job| FileReport {
        path: rel_string(&job.rel),
        index: job.index,
        status: Status::Skipped,
        seed: derive_seed(preset.seed, &job.rel),
        outputs: job.outputs.clone(),
        error: None,
        ms: 0.0,
    }));
    files.sort_by_key(|f| f.index);
    let count = |s: Status| files.iter().filter(|f| f.status == s).count();
    Ok(Summary {
        input: plan.input.clone(),
        output: plan.output.clone(),
        shard: plan.shard.map(|s| s.to_string()),
        found: plan.found,
        succeeded: count(Status::Ok),
        failed: count(Status::Failed) + plan.listing_errors.len(),
        skipped: count(Status::Skipped),
        listing_errors: plan.listing_errors.clone(),
        files,
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// Ages one job's image through the one entry point, creating output
/// folders. A wall plane comes from the image's sidecar `<image>.quad`.
fn age_job(plan: &Plan, job: &Job, preset: &Preset, progress: &Progress) -> crate::Result<()> {
    if let Some(mask) = job.mask.as_ref().filter(|m| !m.exists()) {
        return Err(Error::MaskMissing {
            image: job.input.clone(),
            mask: mask.clone(),
        });
    }
    let inputs = Inputs {
        mask: job.mask.clone(),
        quad: sidecar_quad(&job.input)?,
        region: plan.seeing.region,
        sources: plan.seeing.sources,
        wall_width_m: plan.seeing.wall_width_m,
        ..Inputs::file(&job.input)
    };
    let outputs = Outputs {
        images: job.outputs.clone(),
        layers_dir: job.layers_dir.clone(),
        report: None,
        create_dirs: true,
        timelapse: None,
    };
    age::age(&inputs, preset, &outputs, progress).map(drop)
}

/// The quad in `<image>.quad` beside `image` (`x1,y1,...,x4,y4`, photo
/// pixels, as `grime run --quad`), if there is one.
///
/// # Errors
/// The file cannot be read or does not hold a valid quad.
pub fn sidecar_quad(image: &Path) -> crate::Result<Option<Quad>> {
    let mut name = image.as_os_str().to_owned();
    name.push(".quad");
    let path = PathBuf::from(name);
    if !path.is_file() {
        return Ok(None);
    }
    let text = std::fs::read_to_string(&path).map_err(|e| Error::io(&path, e))?;
    perspective::parse_quad(text.trim())
        .map(Some)
        .map_err(|e| Error::Preset(format!("{}: {e}", path.display())))
}

fn run_job(plan: &Plan, job: &Job, preset: &Preset, cancel: Option<&AtomicBool>) -> FileReport {
    let t = Instant::now();
    let seed = derive_seed(preset.seed, &job.rel);
    let result = match &job.problem {
        Some(p) => Err(p.clone()),
        None => {
            let mut preset = preset.clone();
            preset.seed = seed;
            age_job(plan, job, &preset, &Progress::new(None, cancel))
                .map_err(|e| reason(&e, &job.input))
        }
    };
    FileReport {
        path: rel_string(&job.rel),
        index: job.index,
        status: if result.is_ok() {
            Status::Ok
        } else {
            Status::Failed
        },
        seed,
        outputs: job.outputs.clone(),
        error: result.err(),
        ms: t.elapsed().as_secs_f64() * 1000.0,
    }
}
