//! The document the GUI edits: which image, the wall mask, source lines,
//! perspective quad, preset and layer settings. It is plain data, saved as a
//! project file; everything at runtime (textures, workers) lives elsewhere.
//!
//! A project is a JSON file (conventionally `NAME.grime.json`) plus the
//! mask as a PNG next to it (`NAME.mask.png`). Paths are stored relative to
//! the project file when they can be.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use image::{DynamicImage, GrayImage, Luma};
use serde::{Deserialize, Serialize};

use crate::demo;
use crate::error::Error;
use crate::io;
use crate::perspective::Quad;
use crate::photo::Photo;
use crate::preset::{Preset, SourceLine};
use crate::stack::Stack;

/// Where the photo comes from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ImageSource {
    /// A file on disk.
    File(PathBuf),
    /// A built-in sample (`grime::demo`), by name.
    Demo(String),
}

impl ImageSource {
    /// A short name for titles and messages.
    pub fn display_name(&self) -> String {
        match self {
            ImageSource::File(p) => p
                .file_name()
                .map_or_else(|| p.display().to_string(), |n| n.to_string_lossy().into()),
            ImageSource::Demo(n) => format!("sample: {n}"),
        }
    }
}

/// The user's setting for one layer, by layer name.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LayerSetting {
    /// Whether the layer is shown and exported.
    pub visible: bool,
    /// Opacity, overriding the preset's; `None` = the preset's.
    pub opacity: Option<f32>,
}

impl Default for LayerSetting {
    fn default() -> Self {
        LayerSetting {
            visible: true,
            opacity: None,
        }
    }
}

/// Everything the user has made: the project.
#[derive(Debug, Clone, PartialEq)]
pub struct Document {
    /// The photo's origin.
    pub source: ImageSource,
    /// Wall region at photo size, 255 = wall.
    pub mask: GrayImage,
    /// Source lines (sills, cornices) in photo pixels.
    pub lines: Vec<SourceLine>,
    /// Optional perspective quad in photo pixels.
    pub quad: Option<Quad>,
    /// Effect parameters. Its `rain.source_lines` is ignored: [`Document::lines`]
    /// are used instead (see [`Document::run_preset`]).
    pub preset: Preset,
    /// Per-layer visibility and opacity, by layer name.
    pub layers: BTreeMap<String, LayerSetting>,
}

impl Document {
    /// A new document for a photo: the whole photo is wall.
    pub fn new(source: ImageSource, width: u32, height: u32, preset: Preset) -> Document {
        Document {
            source,
            mask: GrayImage::from_pixel(width, height, Luma([255])),
            lines: preset.rain.source_lines.clone(),
            quad: None,
            preset,
            layers: BTreeMap::new(),
        }
    }

    /// The preset a run uses: the document's preset with its source lines.
    pub fn run_preset(&self) -> Preset {
        let mut p = self.preset.clone();
        p.rain.source_lines = self.lines.clone();
        p
    }

    /// The preset as it is saved to TOML: with the source lines, so
    /// `grime run IMAGE --preset FILE` draws from the same ledges.
    pub fn preset_toml(&self) -> String {
        self.run_preset().to_commented_toml()
    }

    /// Applies the layer settings to a stack (visibility and opacity).
    pub fn apply_layer_settings(&self, stack: &mut Stack) {
        apply_layer_settings(&self.layers, stack);
    }

    /// Saves the project: JSON at `path` and the mask as PNG next to it.
    ///
    /// # Errors
    /// [`ProjectError`] when a file cannot be written.
    pub fn save_project(&self, path: &Path) -> Result<(), ProjectError> {
        let dir = path
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        let mask_name = mask_file_name(path);
        let image = match &self.source {
            ImageSource::File(p) => ImageSource::File(relative_to(p, dir)),
            other => other.clone(),
        };
        let file = ProjectFile {
            format: FORMAT.into(),
            version: 1,
            image,
            mask: mask_name.clone(),
            lines: self.lines.clone(),
            quad: self.quad,
            preset: self.preset.clone(),
            layers: self.layers.clone(),
        };
        let text = serde_json::to_string_pretty(&file).map_err(|e| ProjectError::Format {
            path: path.to_path_buf(),
            reason: e.to_string(),
        })?;
        io::save_image(
            &DynamicImage::ImageLuma8(self.mask.clone()),
            None,
            &dir.join(&mask_name),
        )?;
        io::write_atomic(path, |out| {
            std::io::Write::write_all(out, text.as_bytes()).map_err(|e| Error::io(path, e))
        })?;
        Ok(())
    }

    /// Loads a project, its photo, and the path of its mask file.
    ///
    /// # Errors
    /// [`ProjectError`] for an unreadable or malformed project, a photo that
    /// cannot be loaded or a mask of the wrong size.
    pub fn load_project(path: &Path) -> Result<(Document, Photo, PathBuf), ProjectError> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
        let file: ProjectFile = serde_json::from_str(&text).map_err(|e| ProjectError::Format {
            path: path.to_path_buf(),
            reason: e.to_string(),
        })?;
        if file.format != FORMAT {
            return Err(ProjectError::Format {
                path: path.to_path_buf(),
                reason: format!("format is {:?}, expected {FORMAT:?}", file.format),
            });
        }
        file.preset.validate()?;
        if let Some(q) = &file.quad {
            crate::perspective::validate(q)?;
        }
        let dir = path
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        let (source, photo) = match &file.image {
            ImageSource::File(p) => {
                let full = if p.is_absolute() {
                    p.clone()
                } else {
                    dir.join(p)
                };
                let photo = io::load_photo(&full)?;
                (ImageSource::File(full), photo)
            }
            ImageSource::Demo(name) => (ImageSource::Demo(name.clone()), demo::load(name)?.photo),
        };
        let mask_path = dir.join(&file.mask);
        let mask = io::load_mask(&mask_path, photo.width(), photo.height())?;
        let doc = Document {
            source,
            mask,
            lines: file.lines,
            quad: file.quad,
            preset: file.preset,
            layers: file.layers,
        };
        Ok((doc, photo, mask_path))
    }
}

/// Applies layer settings, by name, to a stack.
pub fn apply_layer_settings(settings: &BTreeMap<String, LayerSetting>, stack: &mut Stack) {
    for layer in &mut stack.layers {
        if let Some(s) = settings.get(&layer.name) {
            layer.visible = s.visible;
            if let Some(o) = s.opacity {
                layer.opacity = o.clamp(0.0, 1.0);
            }
        }
    }
}

const FORMAT: &str = "grime-project";

#[derive(Serialize, Deserialize)]
struct ProjectFile {
    format: String,
    version: u32,
    image: ImageSource,
    mask: String,
    #[serde(default)]
    lines: Vec<SourceLine>,
    #[serde(default)]
    quad: Option<Quad>,
    #[serde(default)]
    preset: Preset,
    #[serde(default)]
    layers: BTreeMap<String, LayerSetting>,
}

/// `dir/NAME.grime.json` → `NAME.mask.png`.
fn mask_file_name(project: &Path) -> String {
    let name = project
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let stem = name
        .strip_suffix(".grime.json")
        .or_else(|| name.strip_suffix(".json"))
        .unwrap_or(&name);
    format!("{stem}.mask.png")
}

fn relative_to(path: &Path, dir: &Path) -> PathBuf {
    let (Ok(p), Ok(d)) = (path.canonicalize(), dir.canonicalize()) else {
        return path.to_path_buf();
    };
    p.strip_prefix(&d).map(Path::to_path_buf).unwrap_or(p)
}

/// Why a project could not be saved or loaded.
#[derive(Debug, thiserror::Error)]
pub enum ProjectError {
    /// Reading or writing a file, or the photo or mask in it, failed.
    #[error(transparent)]
    Grime(#[from] Error),
    /// The file is not a grime project.
    #[error("{path}: not a grime project file ({reason})")]
    Format {
        /// The file involved.
        path: PathBuf,
        /// What was wrong.
        reason: String,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn project_round_trips_with_its_mask() {
        let dir = tempfile::tempdir().unwrap();
        let img_path = dir.path().join("wall.png");
        let d = demo::facade(64, 48);
        io::save_image(d.photo.image(), None, &img_path).unwrap();
        let mut doc = Document::new(
            ImageSource::File(img_path.clone()),
            64,
            48,
            Preset::default(),
        );
        doc.mask = d.region.unwrap();
        doc.lines = vec![vec![[1.0, 10.0], [60.0, 12.0]]];
        doc.quad = Some([[2.0, 2.0], [60.0, 3.0], [61.0, 45.0], [1.0, 44.0]]);
        doc.preset.rain.k_a = 0.25;
        doc.layers.insert(
            "rain 01".into(),
            LayerSetting {
                visible: false,
                opacity: Some(0.5),
            },
        );
        let project = dir.path().join("facade.grime.json");
        doc.save_project(&project).unwrap();
        assert!(dir.path().join("facade.mask.png").exists());
        let text = std::fs::read_to_string(&project).unwrap();
        assert!(
            text.contains("\"wall.png\""),
            "image path is relative: {text}"
        );
        let (back, photo, mask) = Document::load_project(&project).unwrap();
        assert_eq!(mask, dir.path().join("facade.mask.png"));
        assert_eq!((photo.width(), photo.height()), (64, 48));
        assert_eq!(back.mask, doc.mask);
        assert_eq!(back.lines, doc.lines);
        assert_eq!(back.quad, doc.quad);
        assert_eq!(back.preset, doc.preset);
        assert_eq!(back.layers, doc.layers);
    }

    #[test]
    fn bad_projects_give_clear_errors() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("x.grime.json");
        std::fs::write(&p, "{ not json").unwrap();
        let e = Document::load_project(&p).unwrap_err().to_string();
        assert!(e.contains("not a grime project"), "{e}");
        let e = Document::load_project(&dir.path().join("missing.json"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("missing.json"), "{e}");
    }
}
