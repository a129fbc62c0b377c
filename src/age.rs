//! The one way to age files, used by `grime run`, `grime batch` and the
//! GUI's export: check the outputs against the inputs ([`guard`]), load the
//! inputs, run [`pipeline::run`], write every output atomically.
//!
//! The guard runs before anything is loaded or simulated, so a bad output
//! path costs nothing and never touches a file:
//! - no output (image, report, or a file the layers folder would hold) is
//!   any input (photo, mask, normal map);
//! - no two outputs are the same file;
//! - every output's folder exists, unless the caller creates folders.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::error::{Error, Result};
use crate::export;
use crate::io::{self, Format, folder_of};
use crate::perspective::Quad;
use crate::pipeline::{self, Outcome, Scene, Site};
use crate::preset::Preset;
use crate::progress::Progress;
use crate::recipe::Recipe;
use crate::stack::Stack;
use crate::timelapse::{self, Timelapse};

/// Where the photo comes from.
#[derive(Debug, Clone)]
pub enum Source {
    /// A photo file (PNG, JPEG, TIFF, WebP).
    File(PathBuf),
    /// An embedded sample ([`crate::demo::load`]); its region and ledges
    /// come with it (a `mask` replaces the region; the preset's own source
    /// lines replace the ledges).
    Demo(String),
    /// A scene already in memory (the GUI's document), and the files it was
    /// loaded from, which no output may overwrite.
    Loaded {
        /// The photo, region, normals and quad.
        scene: Scene,
        /// The files behind it.
        from: Vec<PathBuf>,
    },
}

/// Where the wall is when no mask is given.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RegionMode {
    /// Found by the scene analysis ([`crate::analysis`]): not the sky,
    /// vegetation, glass or ground.
    #[default]
    Auto,
    /// Every pixel is wall.
    Full,
}

/// Where rain water starts when the preset names no source lines.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SourcesMode {
    /// The ledges the scene analysis finds (sills, cornices, copings, the
    /// roof line); the region's top edge only when it finds none.
    #[default]
    Auto,
    /// Only the region's top edge.
    Top,
}

/// Everything one ageing reads.
#[derive(Debug, Clone)]
pub struct Inputs {
    /// The photo.
    pub source: Source,
    /// Region mask file: greyscale, photo-sized, white = wall.
    pub mask: Option<PathBuf>,
    /// Tangent-space normal map file, photo-sized.
    pub normal_map: Option<PathBuf>,
    /// The wall plane, photo pixels.
    pub quad: Option<Quad>,
    /// How a photo file without a mask finds its wall.
    pub region: RegionMode,
    /// How a photo file finds where water starts.
    pub sources: SourcesMode,
    /// The wall's width in metres, if known (overrides the scale estimate).
    pub wall_width_m: Option<f32>,
}

impl Inputs {
    /// Ageing the photo file at `path`, nothing else given.
    pub fn file(path: impl Into<PathBuf>) -> Inputs {
        Inputs {
            source: Source::File(path.into()),
            mask: None,
            normal_map: None,
            quad: None,
            region: RegionMode::Auto,
            sources: SourcesMode::Auto,
            wall_width_m: None,
        }
    }

    /// The input files (which no output may be).
    pub fn paths(&self) -> Vec<&Path> {
        let mut out: Vec<&Path> = match &self.source {
            Source::File(p) => vec![p.as_path()],
            Source::Demo(_) => Vec::new(),
            Source::Loaded { from, .. } => from.iter().map(PathBuf::as_path).collect(),
        };
        out.extend(self.mask.as_deref());
        out.extend(self.normal_map.as_deref());
        out
    }
}

/// Everything one ageing writes.
#[derive(Debug, Clone, Default)]
pub struct Outputs {
    /// Flattened or layered images; each extension picks the format.
    pub images: Vec<PathBuf>,
    /// Folder for every layer as a PNG plus `manifest.json`.
    pub layers_dir: Option<PathBuf>,
    /// JSON report of what happened.
    pub report: Option<PathBuf>,
    /// Create missing output folders (batch) instead of refusing (run).
    pub create_dirs: bool,
    /// A time-lapse of the ageing, up to the preset's `age.years`.
    pub timelapse: Option<Timelapse>,
}

/// Checks `outputs` against `inputs` and each other, before any work.
///
/// # Errors
/// [`Error::WouldOverwriteInput`] when an output is an input,
/// [`Error::OutputClash`] when two outputs are one file,
/// [`Error::OutputFolderMissing`] for a missing folder (unless
/// `create_dirs`), [`Error::UnknownFormat`] for an image output whose
/// extension names no format.
pub fn guard(inputs: &Inputs, outputs: &Outputs) -> Result<()> {
    let named = named_outputs(outputs)?;
    guard_paths(
        &inputs.paths(),
        &named,
        outputs.layers_dir.as_deref(),
        outputs.create_dirs,
    )
}

/// [`guard`] for any command's files: `named` are the output files with
/// the flag that writes each (`-o`, `--report`, ...), `layers_dir` a folder
/// the layers go into.
///
/// # Errors
/// As [`guard`], but for the format check (the caller's).
pub fn guard_paths(
    inputs: &[&Path],
    named: &[(PathBuf, String)],
    layers_dir: Option<&Path>,
    create_dirs: bool,
) -> Result<()> {
    for (i, (path, what)) in named.iter().enumerate() {
        if inputs.iter().any(|input| same_path(input, path)) {
            return Err(Error::WouldOverwriteInput { path: path.clone() });
        }
        if let Some((_, first)) = named[..i].iter().find(|(p, _)| same_path(p, path)) {
            return Err(Error::OutputClash {
                path: path.clone(),
                first: first.clone(),
                second: what.clone(),
            });
        }
    }
    if let Some(dir) = layers_dir {
        let clash = |p: &Path| layer_file_in(dir, p);
        if let Some(input) = inputs.iter().find(|p| clash(p)) {
            return Err(Error::WouldOverwriteInput {
                path: input.to_path_buf(),
            });
        }
        if let Some((path, what)) = named.iter().find(|(p, _)| clash(p)) {
            return Err(Error::OutputClash {
                path: path.clone(),
                first: what.clone(),
                second: "--layers-dir".into(),
            });
        }
    }
    if !create_dirs {
        for (path, _) in named {
            let dir = folder_of(path);
            if !dir.is_dir() {
                return Err(Error::OutputFolderMissing { path: dir });
            }
        }
    }
    Ok(())
}

/// The image and report outputs with what writes them, formats checked.
fn named_outputs(outputs: &Outputs) -> Result<Vec<(PathBuf, String)>> {
    let mut named = Vec::new();
    for p in &outputs.images {
        Format::from_path(p)?;
        named.push((p.clone(), "-o".to_string()));
    }
    if let Some(r) = &outputs.report {
        named.push((r.clone(), "--report".to_string()));
    }
    if let Some(t) = &outputs.timelapse {
        for p in t.files(None)? {
            named.push((p, "--timelapse".to_string()));
        }
    }
    Ok(named)
}

/// Whether `path` is in `dir` under a name the layers folder writes.
fn layer_file_in(dir: &Path, path: &Path) -> bool {
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
    same_path(&folder_of(path), dir) && export::layers_dir::is_own_file(name)
}

/// Whether two paths name the same file, existing or not: the folder part
/// is resolved (links, `..`), the name compared as is.
fn same_path(a: &Path, b: &Path) -> bool {
    fn resolved(p: &Path) -> PathBuf {
        if let Ok(real) = p.canonicalize() {
            return real;
        }
        match (folder_of(p).canonicalize(), p.file_name()) {
            (Ok(dir), Some(name)) => dir.join(name),
            _ => p.to_path_buf(),
        }
    }
    resolved(a) == resolved(b)
}

/// Loads the inputs into a scene, with the preset the demo adds its ledges to.
///
/// # Errors
/// Decoding errors naming the file, and the scene's size checks.
pub fn load(inputs: &Inputs, preset: &Preset) -> Result<(Scene, Preset)> {
    load_needing(inputs, preset, &io::limits::estimate)
}

/// [`load`], checking a photo file against the memory limit with `need`
/// (the bytes its work needs at its size).
fn load_needing(
    inputs: &Inputs,
    preset: &Preset,
    need: &dyn Fn(u32, u32) -> u64,
) -> Result<(Scene, Preset)> {
    let mut preset = preset.clone();
    let (photo, region, site) = match &inputs.source {
        Source::File(path) => (Arc::new(io::load_photo_needing(path, need)?), None, None),
        Source::Demo(name) => {
            let d = crate::demo::load(name)?;
            if preset.rain.source_lines.is_empty() && !d.source_lines.is_empty() {
                // The demo's cornice is its roof line: no top edge besides.
                preset.rain.source_lines = d.source_lines;
                preset.rain.top_edge = false;
            }
            (Arc::new(d.photo), d.region.map(Arc::new), Some(d.site))
        }
        Source::Loaded { scene, .. } => (
            Arc::clone(&scene.photo),
            scene.region.clone(),
            Some(scene.site.clone()),
        ),
    };
    let region = match &inputs.mask {
        Some(m) => Some(Arc::new(io::load_mask(m, photo.width(), photo.height())?)),
        None => region,
    };
    let (region, site) = match &inputs.source {
        Source::File(path) => see(inputs, path, &photo, region, &mut preset)?,
        _ => (region, site),
    };
    let mut scene = Scene::shared(photo, region)?;
    if let Some(site) = site {
        scene = scene.with_site(site)?;
    }
    if let Source::Loaded { scene: given, .. } = &inputs.source {
        scene.normals = given.normals.clone();
        scene.quad = given.quad;
    }
    if let Some(path) = &inputs.normal_map {
        let normals = io::load_photo(path)?.into_image().to_rgb8();
        scene = scene.with_normals(normals)?;
    }
    if inputs.quad.is_some() {
        scene = scene.with_quad(inputs.quad)?;
    }
    Ok((scene, preset))
}

/// The region, ledges and site of a photo file from the scene analysis, as
/// `inputs` asks: the wall when there is no mask (`RegionMode::Auto`), the
/// ledges as source lines when the preset has none (`SourcesMode::Auto`),
/// or only the top edge (`SourcesMode::Top`). The site (scale, ground,
/// shelter) comes from the analysis whenever it runs.
///
/// # Errors
/// [`Error::NoWall`] when the analysis finds no wall.
fn see(
    inputs: &Inputs,
    path: &Path,
    photo: &Arc<crate::photo::Photo>,
    region: Option<Arc<image::GrayImage>>,
    preset: &mut Preset,
) -> Result<(Option<Arc<image::GrayImage>>, Option<Site>)> {
    if inputs.sources == SourcesMode::Top {
        preset.rain.source_lines.clear();
        preset.rain.top_edge = true;
    }
    let wants_region = region.is_none() && inputs.region == RegionMode::Auto;
    let wants_ledges = inputs.sources == SourcesMode::Auto && preset.rain.source_lines.is_empty();
    let opts = crate::analysis::Options {
        wall_width_m: inputs.wall_width_m,
        name: path.display().to_string(),
        ..crate::analysis::Options::default()
    };
    // The analysis always runs on a photo file: its scale sizes every
    // effect, so a re-run from a recipe (which pins region and ledges)
    // gets the same metres per pixel. Without a wall in sight, a run that
    // needs neither region nor ledges goes on at the assumed scale.
    let seen = match crate::analysis::analyse(photo, &opts) {
        Ok(seen) => seen,
        Err(Error::NoWall { .. }) if !wants_region && !wants_ledges => {
            let mut site = Site::assumed(photo.width());
            if let Some(m) = inputs.wall_width_m {
                site.metres_per_pixel = m / photo.width().max(1) as f32;
            }
            return Ok((region, Some(site)));
        }
        Err(e) => return Err(e),
    };
    if wants_region && seen.matte.as_raw().iter().all(|&v| v == 0) {
        return Err(Error::NoWall { name: opts.name });
    }
    if wants_ledges && !seen.ledges.is_empty() {
        preset.rain.source_lines = seen.source_lines();
        preset.rain.top_edge = false;
    }
    let site = Site::seen(&seen);
    let region = match wants_region {
        true => Some(Arc::new(seen.matte)),
        false => region,
    };
    Ok((region, Some(site)))
}

/// Ages `inputs` with `preset` and writes `outputs`.
///
/// # Errors
/// [`guard`]'s errors (before any work), then loading, pipeline and
/// writing errors, each naming its file.
pub fn age(
    inputs: &Inputs,
    preset: &Preset,
    outputs: &Outputs,
    progress: &Progress,
) -> Result<Outcome> {
    age_adjusted(inputs, preset, outputs, progress, &|_| {})
}

/// [`age`], with `adjust` applied to the layer stack before it is written
/// (the GUI's layer visibility and opacity).
///
/// # Errors
/// As [`age`].
pub fn age_adjusted(
    inputs: &Inputs,
    preset: &Preset,
    outputs: &Outputs,
    progress: &Progress,
    adjust: &dyn Fn(&mut Stack),
) -> Result<Outcome> {
    guard(inputs, outputs)?;
    let need = |w, h| match &outputs.timelapse {
        Some(t) => t.memory(w, h, preset.age.years.unwrap_or(0)),
        None => io::limits::estimate(w, h),
    };
    let (scene, preset) = load_needing(inputs, preset, &need)?;
    let recipe = Recipe::new(inputs, &preset)?;
    let span = progress.span(0.0, 0.95);
    let mut outcome = match &outputs.timelapse {
        None => pipeline::run(&scene, &preset, &span)?,
        Some(t) => timelapse::run(&scene, &preset, t, &recipe, &span)?,
    };
    adjust(&mut outcome.stack);
    progress.update("writing", 0.95);
    write(&outcome, outputs, Some(&recipe))?;
    progress.update("done", 1.0);
    Ok(outcome)
}

/// Writes every output of `outcome`, each atomically, the images with
/// `recipe` inside (the time-lapse is written as it runs).
///
/// # Errors
/// Writing errors naming the file.
pub fn write(outcome: &Outcome, outputs: &Outputs, recipe: Option<&Recipe>) -> Result<()> {
    let text = recipe.map(Recipe::to_text);
    for out in &outputs.images {
        if outputs.create_dirs {
            let dir = folder_of(out);
            std::fs::create_dir_all(&dir).map_err(|e| Error::io(dir, e))?;
        }
        export::save_with(&outcome.stack, out, text.as_deref())?;
    }
    if let Some(dir) = &outputs.layers_dir {
        export::layers_dir::write(&outcome.stack, dir)?;
    }
    if let Some(path) = &outputs.report {
        let text = serde_json::to_string_pretty(&outcome.report).map_err(|e| Error::Encode {
            path: path.clone(),
            reason: e.to_string(),
        })?;
        io::write_atomic(path, |out| {
            std::io::Write::write_all(out, text.as_bytes()).map_err(|e| Error::io(path, e))
        })?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn outputs(images: &[&Path]) -> Outputs {
        Outputs {
            images: images.iter().map(|p| p.to_path_buf()).collect(),
            ..Outputs::default()
        }
    }

    #[test]
    fn refuses_an_output_that_is_an_input_in_another_spelling() {
        let dir = tempfile::tempdir().unwrap();
        let photo = dir.path().join("p.png");
        std::fs::write(&photo, b"x").unwrap();
        let other = dir.path().join("sub/../p.png");
        std::fs::create_dir(dir.path().join("sub")).unwrap();
        let err = guard(&Inputs::file(&photo), &outputs(&[&other])).unwrap_err();
        assert!(matches!(err, Error::WouldOverwriteInput { .. }), "{err}");
    }

    #[test]
    fn refuses_a_mask_even_for_the_demo() {
        let dir = tempfile::tempdir().unwrap();
        let mask = dir.path().join("m.png");
        std::fs::write(&mask, b"x").unwrap();
        let inputs = Inputs {
            source: Source::Demo("facade".into()),
            mask: Some(mask.clone()),
            ..Inputs::file("unused")
        };
        assert!(guard(&inputs, &outputs(&[&mask])).is_err());
    }

    #[test]
    fn refuses_report_on_image_and_on_input() {
        let dir = tempfile::tempdir().unwrap();
        let photo = dir.path().join("p.png");
        std::fs::write(&photo, b"x").unwrap();
        let out = dir.path().join("aged.png");
        let mut o = outputs(&[&out]);
        o.report = Some(out.clone());
        let err = guard(&Inputs::file(&photo), &o).unwrap_err();
        assert!(matches!(err, Error::OutputClash { .. }), "{err}");
        o.report = Some(photo.clone());
        let err = guard(&Inputs::file(&photo), &o).unwrap_err();
        assert!(matches!(err, Error::WouldOverwriteInput { .. }), "{err}");
    }

    #[test]
    fn refuses_a_layers_folder_holding_an_input_named_like_a_layer() {
        let dir = tempfile::tempdir().unwrap();
        let photo = dir.path().join("00-photo.png");
        std::fs::write(&photo, b"x").unwrap();
        let mut o = outputs(&[&dir.path().join("out.png")]);
        o.layers_dir = Some(dir.path().to_path_buf());
        assert!(guard(&Inputs::file(&photo), &o).is_err());
        // An input with another name may sit there.
        let other = dir.path().join("facade.png");
        std::fs::write(&other, b"x").unwrap();
        assert!(guard(&Inputs::file(&other), &o).is_ok());
    }

    #[test]
    fn refuses_a_missing_folder_unless_asked_to_create_it() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("no/such/aged.png");
        let mut o = outputs(&[&out]);
        let err = guard(&Inputs::file(dir.path().join("p.png")), &o).unwrap_err();
        assert!(matches!(err, Error::OutputFolderMissing { .. }), "{err}");
        o.create_dirs = true;
        assert!(guard(&Inputs::file(dir.path().join("p.png")), &o).is_ok());
    }
}
