//! Listing the input folder and deciding every image's outputs, shard and
//! seed.

use std::collections::HashMap;
use std::ffi::OsString;
use std::path::{Component, Path, PathBuf};
use std::str::FromStr;

use serde::Serialize;

use crate::age::{RegionMode, SourcesMode};
use crate::error::{Error, Result};
use crate::io::Format;
use crate::random::mix;

/// One output format of a batch: a fixed format, or the input's own.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OutputFormat {
    /// The input's format and file name (`IMG_1.JPG` stays `IMG_1.JPG`).
    Keep,
    /// A fixed format; the output takes the input's stem and this format's
    /// extension.
    Fixed(Format),
}

impl OutputFormat {
    /// The extension written for a fixed format; `None` for [`Self::Keep`].
    pub fn extension(self) -> Option<&'static str> {
        match self {
            OutputFormat::Keep => None,
            OutputFormat::Fixed(f) => Some(match f {
                Format::Png => "png",
                Format::Jpeg => "jpg",
                Format::Tiff => "tif",
                Format::Webp => "webp",
                Format::Psd => "psd",
                Format::Ora => "ora",
            }),
        }
    }
}

impl FromStr for OutputFormat {
    type Err = String;

    /// `keep`, or an extension: `png`, `jpg`, `jpeg`, `tif`, `tiff`, `webp`,
    /// `psd`, `ora`.
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        let s = s.trim();
        if s.eq_ignore_ascii_case("keep") {
            return Ok(OutputFormat::Keep);
        }
        Format::from_path(Path::new(&format!("x.{s}")))
            .map(OutputFormat::Fixed)
            .map_err(|_| {
                format!("unknown output format {s:?}; use keep, png, jpg, tif, webp, psd or ora")
            })
    }
}

/// Shard `index` of `count` (1-based): the images whose stable index `i`
/// (position in the sorted listing of the whole folder, from 0) satisfies
/// `i % count == index - 1`. Parses from `"K/N"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// Which shard, 1 ..= count.
    pub index: usize,
    /// How many shards.
    pub count: usize,
}

impl Shard {
    /// True when the image at stable index `i` belongs to this shard.
    pub fn contains(self, i: usize) -> bool {
        i % self.count == self.index - 1
    }
}

impl FromStr for Shard {
    type Err = String;

    /// `K/N` with `1 <= K <= N`.
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        let bad = || format!("shard {s:?}: write K/N with 1 <= K <= N, e.g. 3/8 (shard 3 of 8)");
        let (k, n) = s.split_once('/').ok_or_else(bad)?;
        let index: usize = k.trim().parse().map_err(|_| bad())?;
        let count: usize = n.trim().parse().map_err(|_| bad())?;
        if index == 0 || index > count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// The bytes of a relative path with `/` between components, the same on
/// every platform (for names that are valid Unicode).
fn rel_bytes(rel: &Path) -> Vec<u8> {
    let mut out = Vec::new();
    for (i, c) in rel.components().enumerate() {
        if i > 0 {
            out.push(b'/');
        }
        out.extend_from_slice(c.as_os_str().as_encoded_bytes());
    }
    out
}

/// A relative path as text with `/` separators (lossy for names that are not
/// valid Unicode), as shown in reports.
pub fn rel_string(rel: &Path) -> String {
    String::from_utf8_lossy(&rel_bytes(rel)).into_owned()
}

/// The seed of one image of a batch: a SplitMix64 hash of the preset's seed
/// and the image's path relative to the input folder (`/`-separated bytes,
/// so the same on every platform). The result has 63 bits, so it can be
/// written into a TOML preset.
///
/// `grime run IMAGE --seed <this>` with the same preset reproduces the
/// image's batch output.
pub fn derive_seed(seed: u64, rel: &Path) -> u64 {
    const BATCH: u64 = u64::from_be_bytes(*b"grimebat");
    let bytes = rel_bytes(rel);
    let mut h = mix(mix(seed) ^ BATCH ^ bytes.len() as u64);
    for chunk in bytes.chunks(8) {
        let mut word = [0u8; 8];
        word[..chunk.len()].copy_from_slice(chunk);
        h = mix(h ^ u64::from_le_bytes(word));
    }
    // 63 bits: TOML integers (presets, `--set seed=`) are signed 64-bit.
    h >> 1
}

/// True for grime's own temporary files (`.NAME.grime-PID-N.tmp`), left
/// behind only when a run is killed mid-write.
pub fn is_temp_file(name: &str) -> bool {
    name.starts_with('.') && name.ends_with(".tmp") && name.contains(".grime-")
}

/// A folder or file that could not be listed.
#[derive(Debug, Clone, Serialize)]
pub struct ListingError {
    /// The path, relative to the input folder.
    pub path: String,
    /// What went wrong.
    pub error: String,
}

/// Lists the images under `input` (extensions as [`Format::is_input`], any
/// case), as paths relative to `input`, sorted. `exclude` (an absolute,
/// canonical folder, e.g. the output folder) is not entered. Symbolic links
/// to files are followed, links to folders are not. Folders that cannot be
/// read are returned as errors; the listing goes on without them.
///
/// # Errors
/// [`Error::Io`] when `input` itself cannot be read.
pub fn discover(
    input: &Path,
    recursive: bool,
    exclude: Option<&Path>,
) -> Result<(Vec<PathBuf>, Vec<ListingError>)> {
    let mut files = Vec::new();
    let mut errors = Vec::new();
    let mut stack = vec![PathBuf::new()];
    while let Some(rel_dir) = stack.pop() {
        let dir = input.join(&rel_dir);
        let entries = match std::fs::read_dir(&dir) {
            Ok(e) => e,
            Err(e) if rel_dir.as_os_str().is_empty() => return Err(Error::io(input, e)),
            Err(e) => {
                errors.push(ListingError {
                    path: rel_string(&rel_dir),
                    error: e.to_string(),
                });
                continue;
            }
        };
        for entry in entries {
            let entry = match entry {
                Ok(e) => e,
                Err(e) => {
                    errors.push(ListingError {
                        path: rel_string(&rel_dir),
                        error: e.to_string(),
                    });
                    continue;
                }
            };
            let name = entry.file_name();
            let rel = rel_dir.join(&name);
            let Ok(kind) = entry.file_type() else {
                continue;
            };
            if kind.is_dir() {
                let skip =
                    exclude.is_some_and(|ex| entry.path().canonicalize().is_ok_and(|p| p == ex));
                if recursive && !skip {
                    stack.push(rel);
                }
                continue;
            }
            if kind.is_symlink() && !entry.path().is_file() {
                continue;
            }
            if name.to_str().is_some_and(is_temp_file) || !Format::is_input(&rel) {
                continue;
            }
            files.push(rel);
        }
    }
    files.sort_by_cached_key(|p| rel_bytes(p));
    errors.sort_by(|a, b| a.path.cmp(&b.path));
    Ok((files, errors))
}

/// The absolute form of `path` with symbolic links resolved as far as the
/// path exists (the missing rest is appended as written, `..` folded).
fn resolve(path: &Path) -> Result<PathBuf> {
    let abs = std::path::absolute(path).map_err(|e| Error::io(path, e))?;
    let mut norm = PathBuf::new();
    for c in abs.components() {
        match c {
            Component::ParentDir => {
                norm.pop();
            }
            Component::CurDir => {}
            other => norm.push(other),
        }
    }
    let mut missing: Vec<OsString> = Vec::new();
    let mut base = norm.as_path();
    loop {
        if let Ok(real) = base.canonicalize() {
            let mut out = real;
            out.extend(missing.iter().rev());
            return Ok(out);
        }
        match (base.file_name(), base.parent()) {
            (Some(name), Some(parent)) => {
                missing.push(name.to_os_string());
                base = parent;
            }
            _ => return Ok(norm),
        }
    }
}

/// What to do, besides the preset.
#[derive(Debug, Clone)]
pub struct Options {
    /// Descend into sub-folders.
    pub recursive: bool,
    /// Formats to write for every image (at least one).
    pub formats: Vec<OutputFormat>,
    /// Only this shard of the images.
    pub shard: Option<Shard>,
    /// Skip an image when all its outputs exist.
    pub skip_existing: bool,
    /// Allow the output folder inside the input folder (never equal to it).
    pub allow_inside_input: bool,
    /// Region masks: `DIR/<relative path with .png>` for every image.
    pub masks: Option<PathBuf>,
    /// Also write every image's layers (PNGs + manifest.json) to
    /// `<output>/<relative path without extension>.layers/`.
    pub layers_dirs: bool,
    /// How each image without a mask finds its wall, its ledges and its
    /// scale (`Inputs::region`, `sources`, `wall_width_m`).
    pub seeing: Seeing,
}

/// How an image finds its wall, its ledges and its scale.
#[derive(Debug, Clone, Copy, Default)]
pub struct Seeing {
    /// Where the wall is without a mask.
    pub region: RegionMode,
    /// Where water starts without source lines in the preset.
    pub sources: SourcesMode,
    /// The wall's width in metres, if known.
    pub wall_width_m: Option<f32>,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            recursive: false,
            formats: vec![OutputFormat::Keep],
            shard: None,
            skip_existing: false,
            allow_inside_input: false,
            masks: None,
            layers_dirs: false,
            seeing: Seeing::default(),
        }
    }
}

/// One image's work.
#[derive(Debug, Clone)]
pub struct Job {
    /// Stable index: position in the sorted listing of the whole folder.
    pub index: usize,
    /// Path relative to the input folder.
    pub rel: PathBuf,
    /// The image file.
    pub input: PathBuf,
    /// Its region mask, if masks were asked for.
    pub mask: Option<PathBuf>,
    /// Output files, one per format.
    pub outputs: Vec<PathBuf>,
    /// Folder for its layers, if asked for.
    pub layers_dir: Option<PathBuf>,
    /// Set when the job cannot run (e.g. two inputs would write one output).
    pub problem: Option<String>,
}

impl Job {
    /// True when every output (and the layers manifest, if asked for) exists.
    pub fn done(&self) -> bool {
        self.outputs.iter().all(|p| p.is_file())
            && self
                .layers_dir
                .as_ref()
                .is_none_or(|d| d.join("manifest.json").is_file())
    }
}

/// The images of this run and where their results go.
#[derive(Debug, Clone)]
pub struct Plan {
    /// Input folder, as given.
    pub input: PathBuf,
    /// Output folder, as given.
    pub output: PathBuf,
    /// Images found in the whole folder (all shards).
    pub found: usize,
    /// This shard's images, by stable index.
    pub jobs: Vec<Job>,
    /// Jobs skipped because their outputs exist (`skip_existing`).
    pub skipped: Vec<Job>,
    /// Folders that could not be listed.
    pub listing_errors: Vec<ListingError>,
    /// The shard, if any.
    pub shard: Option<Shard>,
    /// How images find their wall.
    pub seeing: Seeing,
}

/// Output file names for `rel` (relative), one per format, before clashes
/// between inputs are resolved. Formats naming the same file are merged.
fn output_names(rel: &Path, formats: &[OutputFormat]) -> Vec<PathBuf> {
    let mut names: Vec<PathBuf> = Vec::new();
    for f in formats {
        let name = match *f {
            OutputFormat::Keep => rel.to_path_buf(),
            // Same format as the input: keep its name (`.JPEG` stays `.JPEG`).
            OutputFormat::Fixed(fmt) if Format::from_path(rel).ok() == Some(fmt) => {
                rel.to_path_buf()
            }
            OutputFormat::Fixed(_) => rel.with_extension(f.extension().unwrap_or_default()),
        };
        if !names.iter().any(|n| lower(n) == lower(&name)) {
            names.push(name);
        }
    }
    names
}

fn lower(p: &Path) -> String {
    rel_string(p).to_lowercase()
}

/// Lists `input` and plans every image's outputs under `output`.
///
/// Outputs mirror the input's sub-folders. An output in the input's own
/// format keeps the input's name; a converted one takes the input's stem and
/// the format's extension, unless another input's output already has that
/// name (compared without regard to case, e.g. `a.jpg` and `a.png` both to
/// `a.png`): then it takes the input's full name plus the extension
/// (`a.jpg.png`). Names are decided over the whole folder, so every shard
/// agrees on them.
///
/// # Errors
/// [`Error::Io`] when `input` is not a readable folder, when `output` is the
/// input folder, or lies inside it without `allow_inside_input`;
/// [`Error::Preset`] for no formats.
pub fn plan(input: &Path, output: &Path, opts: &Options) -> Result<Plan> {
    if opts.formats.is_empty() {
        return Err(Error::Preset("give at least one output format".into()));
    }
    if !input.is_dir() {
        return Err(Error::io(
            input,
            std::io::Error::new(
                std::io::ErrorKind::NotADirectory,
                "not a folder; batch takes a folder of photos (use `grime run` for one photo)",
            ),
        ));
    }
    let in_real = input.canonicalize().map_err(|e| Error::io(input, e))?;
    let out_real = resolve(output)?;
    if out_real == in_real {
        return Err(Error::io(
            output,
            std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "the output folder is the input folder; choose another (outputs and inputs would mix)",
            ),
        ));
    }
    let inside = out_real.starts_with(&in_real);
    if inside && !opts.allow_inside_input {
        return Err(Error::io(
            output,
            std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "the output folder is inside the input folder; choose another, or pass --allow-inside-input",
            ),
        ));
    }
    let exclude = inside.then_some(out_real.as_path());
    let (files, listing_errors) = discover(input, opts.recursive, exclude)?;

    // Names over the whole listing (not just this shard), so every shard
    // agrees on them.
    let mut names: Vec<Vec<PathBuf>> = files
        .iter()
        .map(|r| output_names(r, &opts.formats))
        .collect();
    let mut owners: HashMap<String, Vec<usize>> = HashMap::new();
    for (i, list) in names.iter().enumerate() {
        for n in list {
            owners.entry(lower(n)).or_default().push(i);
        }
    }
    for (i, list) in names.iter_mut().enumerate() {
        for n in list.iter_mut() {
            let clash = owners[&lower(n)].iter().any(|&j| j != i);
            if clash && *n != files[i] {
                let mut full = files[i].clone().into_os_string();
                full.push(".");
                full.push(n.extension().unwrap_or_default());
                *n = PathBuf::from(full);
            }
        }
    }
    let mut count: HashMap<String, usize> = HashMap::new();
    for n in names.iter().flatten() {
        *count.entry(lower(n)).or_default() += 1;
    }

    let found = files.len();
    let mut jobs = Vec::new();
    let mut skipped = Vec::new();
    for (index, (rel, list)) in files.into_iter().zip(names).enumerate() {
        if opts.shard.is_some_and(|s| !s.contains(index)) {
            continue;
        }
        let problem = list.iter().find(|n| count[&lower(n)] > 1).map(|n| {
            format!(
                "another input also writes {}; rename one of them",
                rel_string(n)
            )
        });
        let job = Job {
            index,
            input: input.join(&rel),
            mask: opts
                .masks
                .as_ref()
                .map(|d| d.join(rel.with_extension("png"))),
            outputs: list.iter().map(|n| output.join(n)).collect(),
            layers_dir: opts.layers_dirs.then(|| {
                let mut d = output.join(&rel).into_os_string();
                d.push(".layers");
                PathBuf::from(d)
            }),
            rel,
            problem,
        };
        if opts.skip_existing && job.problem.is_none() && job.done() {
            skipped.push(job);
        } else {
            jobs.push(job);
        }
    }
    Ok(Plan {
        input: input.to_path_buf(),
        output: output.to_path_buf(),
        found,
        jobs,
        skipped,
        listing_errors,
        shard: opts.shard,
        seeing: opts.seeing,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seed_depends_on_seed_and_every_path_byte() {
        let a = derive_seed(7, Path::new("a/b.jpg"));
        assert_ne!(a, derive_seed(7, Path::new("a/c.jpg")));
        assert_ne!(a, derive_seed(7, Path::new("ab.jpg")));
        assert_ne!(a, derive_seed(8, Path::new("a/b.jpg")));
        // Trailing zero bytes of the last word must still count.
        assert_ne!(
            derive_seed(7, Path::new("abcdefgh")),
            derive_seed(7, Path::new("abcdefg"))
        );
        assert_eq!(a, derive_seed(7, &Path::new("a").join("b.jpg")));
        assert!((0..1000).all(|i| derive_seed(i, Path::new("x.png")) <= i64::MAX as u64));
    }

    #[test]
    fn shards_partition_the_indices() {
        let n = 8;
        for i in 0..100 {
            let owners = (1..=n)
                .filter(|&k| Shard { index: k, count: n }.contains(i))
                .count();
            assert_eq!(owners, 1);
        }
        assert!("0/3".parse::<Shard>().is_err());
        assert!("4/3".parse::<Shard>().is_err());
        assert!("x".parse::<Shard>().is_err());
        assert_eq!(
            "2/3".parse::<Shard>().unwrap(),
            Shard { index: 2, count: 3 }
        );
    }

    #[test]
    fn formats_parse() {
        assert_eq!("KEEP".parse::<OutputFormat>().unwrap(), OutputFormat::Keep);
        assert_eq!(
            "jpeg".parse::<OutputFormat>().unwrap(),
            OutputFormat::Fixed(Format::Jpeg)
        );
        assert!("bmp".parse::<OutputFormat>().is_err());
    }

    #[test]
    fn clashing_names_take_the_full_name() {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("in");
        std::fs::create_dir_all(input.join("sub")).unwrap();
        for f in [
            "a.jpg",
            "a.PNG",
            "b.tif",
            "sub/c.jpeg",
            "notes.txt",
            ".x.png.grime-1-2.tmp",
        ] {
            std::fs::write(input.join(f), b"").unwrap();
        }
        let opts = Options {
            formats: vec![OutputFormat::Fixed(Format::Png), OutputFormat::Keep],
            recursive: true,
            ..Options::default()
        };
        let plan = plan(&input, &dir.path().join("out"), &opts).unwrap();
        let outs: Vec<Vec<String>> = plan
            .jobs
            .iter()
            .map(|j| {
                j.outputs
                    .iter()
                    .map(|p| rel_string(p.strip_prefix(dir.path().join("out")).unwrap()))
                    .collect()
            })
            .collect();
        assert_eq!(
            outs,
            vec![
                vec!["a.PNG"],
                vec!["a.jpg.png", "a.jpg"],
                vec!["b.png", "b.tif"],
                vec!["sub/c.png", "sub/c.jpeg"],
            ]
        );
        assert!(plan.jobs.iter().all(|j| j.problem.is_none()));
    }

    #[test]
    fn output_inside_input_needs_permission_and_is_not_listed() {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path();
        std::fs::create_dir_all(input.join("aged")).unwrap();
        std::fs::write(input.join("a.png"), b"").unwrap();
        std::fs::write(input.join("aged/a.png"), b"").unwrap();
        let mut opts = Options {
            recursive: true,
            ..Options::default()
        };
        assert!(plan(input, &input.join("aged"), &opts).is_err());
        assert!(plan(input, input, &opts).is_err());
        assert!(plan(input, &input.join("sub/../."), &opts).is_err());
        opts.allow_inside_input = true;
        assert!(plan(input, input, &opts).is_err());
        let p = plan(input, &input.join("aged"), &opts).unwrap();
        assert_eq!(p.jobs.len(), 1);
        assert_eq!(p.jobs[0].rel, Path::new("a.png"));
    }
}
