//! `--layers-dir`: one RGBA PNG per layer at photo size (transparent where the
//! layer has no effect) and a `manifest.json` listing them in stacking order,
//! bottom first, starting with the original photo (`00-photo.png`, at the
//! photo's bit depth). The layers composite with the formulas of
//! [`crate::stack`]. When the stack has a region, it is written as
//! `region.png` (greyscale, white = wall) and named by the manifest's
//! `region` field; it is not a layer of the picture.
//!
//! Writing into a folder that holds an earlier run's layers removes the
//! files that run's `manifest.json` listed and this run did not write (a
//! run with fewer layers leaves no stale `rain-05..12`). Only names grime
//! gives (`NN-name.png`, `region.png`) are removed; other files stay.

use std::path::Path;

use image::DynamicImage;
use serde::Serialize;

use crate::error::{Error, Result};
use crate::io::{self, Format};
use crate::stack::{BlendMode, Stack};

/// One entry of `manifest.json`.
#[derive(Debug, Serialize)]
pub struct ManifestLayer {
    /// Layer name.
    pub name: String,
    /// File name inside the folder.
    pub file: String,
    /// Blend mode.
    pub blend: BlendMode,
    /// Opacity, 0..1.
    pub opacity: f32,
    /// Visibility.
    pub visible: bool,
}

/// `manifest.json`.
#[derive(Debug, Serialize)]
pub struct Manifest {
    /// Photo width.
    pub width: u32,
    /// Photo height.
    pub height: u32,
    /// Layers bottom to top; the first is the original photo.
    pub layers: Vec<ManifestLayer>,
    /// File of the region mask (white = wall), when there is one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub region: Option<String>,
}

/// File-name-safe form of a layer name.
pub fn slug(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '-'
            }
        })
        .collect()
}

/// Whether `name` is a file name the layers folder writes: those of
/// [`is_grime_name`] and `manifest.json`.
pub fn is_own_file(name: &str) -> bool {
    is_grime_name(name) || name == "manifest.json"
}

/// Writes the photo, every layer and `manifest.json` into `dir` (created if
/// missing). Every file is written atomically.
///
/// # Errors
/// I/O and encoding errors, naming the file.
pub fn write(stack: &Stack, dir: &Path) -> Result<Manifest> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let mut layers = Vec::with_capacity(stack.layers.len() + 1);
    let photo_file = "00-photo.png".to_string();
    io::save_image(
        stack.base.image(),
        stack.base.icc.as_deref(),
        &dir.join(&photo_file),
    )?;
    layers.push(ManifestLayer {
        name: "photo".into(),
        file: photo_file,
        blend: BlendMode::Normal,
        opacity: 1.0,
        visible: true,
    });
    for (i, layer) in stack.layers.iter().enumerate() {
        let file = format!("{:02}-{}.png", i + 1, slug(&layer.name));
        let path = dir.join(&file);
        let img = DynamicImage::ImageRgba8(layer.to_rgba());
        io::write_atomic(&path, |out| io::encode(&img, None, Format::Png, &path, out))?;
        layers.push(ManifestLayer {
            name: layer.name.clone(),
            file,
            blend: layer.blend,
            opacity: layer.opacity,
            visible: layer.visible,
        });
    }
    let region = match stack.region.as_deref() {
        Some(mask) => {
            let file = "region.png".to_string();
            let path = dir.join(&file);
            let img = DynamicImage::ImageLuma8(mask.clone());
            io::write_atomic(&path, |out| io::encode(&img, None, Format::Png, &path, out))?;
            Some(file)
        }
        None => None,
    };
    let manifest = Manifest {
        width: stack.base.width(),
        height: stack.base.height(),
        layers,
        region,
    };
    let path = dir.join("manifest.json");
    let stale = listed_files(&path);
    let text = serde_json::to_string_pretty(&manifest).map_err(|e| Error::Encode {
        path: path.clone(),
        reason: e.to_string(),
    })?;
    io::write_atomic(&path, |out| {
        std::io::Write::write_all(out, text.as_bytes()).map_err(|e| Error::io(&path, e))
    })?;
    let written: Vec<&str> = manifest
        .layers
        .iter()
        .map(|l| l.file.as_str())
        .chain(manifest.region.as_deref())
        .collect();
    for file in stale.iter().filter(|f| !written.contains(&f.as_str())) {
        let old = dir.join(file);
        match std::fs::remove_file(&old) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(Error::io(old, e)),
            _ => {}
        }
    }
    Ok(manifest)
}

/// The files an existing `manifest.json` lists, keeping only names grime
/// writes (`NN-slug.png`, `region.png`); none when there is no readable
/// manifest.
fn listed_files(manifest: &Path) -> Vec<String> {
    let Ok(text) = std::fs::read_to_string(manifest) else {
        return Vec::new();
    };
    let Ok(value) = serde_json::from_str::<serde_json::Value>(&text) else {
        return Vec::new();
    };
    let layers = value["layers"].as_array().into_iter().flatten();
    layers
        .map(|l| &l["file"])
        .chain([&value["region"]])
        .filter_map(|f| f.as_str())
        .filter(|f| is_grime_name(f))
        .map(str::to_string)
        .collect()
}

/// True for the names [`write`] gives: `region.png` and `NN-slug.png`
/// (two digits, a slug of lowercase letters, digits and `-`).
pub fn is_grime_name(file: &str) -> bool {
    if file == "region.png" {
        return true;
    }
    let Some(stem) = file.strip_suffix(".png") else {
        return false;
    };
    let b = stem.as_bytes();
    b.len() > 3
        && b[..2].iter().all(u8::is_ascii_digit)
        && b[2] == b'-'
        && b[3..]
            .iter()
            .all(|&c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == b'-')
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grime_names() {
        for ok in [
            "00-photo.png",
            "12-rain-12.png",
            "region.png",
            "03-moss.png",
        ] {
            assert!(is_grime_name(ok), "{ok}");
        }
        for no in [
            "photo.png",
            "1-rain.png",
            "05-Rain.png",
            "05-rain.jpg",
            "../05-rain.png",
            "05-a/b.png",
            "manifest.json",
        ] {
            assert!(!is_grime_name(no), "{no}");
        }
    }
}
