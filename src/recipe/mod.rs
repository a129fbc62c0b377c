//! The recipe inside every output: the full preset, the seed, grime's
//! version and the SHA-256 of the input files, so the file alone says how
//! it was made and `grime run … --recipe-from FILE` makes it again.
//!
//! Where it is stored: PNG (an `iTXt` chunk, keyword `grime-recipe`), JPEG
//! (`COM` segments), WebP (an `XMP ` chunk), TIFF (the XMP tag, 700), PSD
//! (the XMP image resource, 1060), ORA (`recipe.toml` in the archive, named
//! by `stack.xml`'s `grime:recipe` attribute). [`embed`] writes them,
//! [`read`] finds them again.

pub mod embed;
pub mod read;

use std::path::Path;

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::age::{Inputs, RegionMode, Source, SourcesMode};
use crate::error::{Error, Result};
use crate::perspective::Quad;
use crate::preset::Preset;

/// How an output was made.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Recipe {
    /// grime's version.
    pub grime: String,
    /// The master seed (also in the preset).
    pub seed: u64,
    /// The input's file name, or `demo:NAME`.
    pub input: String,
    /// SHA-256 of the input file (of the photo's pixels for an image in
    /// memory); none for a demo.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub input_sha256: Option<String>,
    /// SHA-256 of the mask file, if one was given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mask_sha256: Option<String>,
    /// SHA-256 of the normal map file, if one was given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub normal_map_sha256: Option<String>,
    /// `auto` (the wall was found) or `full`.
    pub region: String,
    /// `auto` (ledges found) or `top`.
    pub sources: String,
    /// The wall's width in metres, if given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wall_width_m: Option<f32>,
    /// The wall plane, if given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub quad: Option<Quad>,
    /// The preset as run: the clock applied, detected ledges included.
    pub preset: Preset,
}

/// The first line of a recipe's text.
const HEADER: &str =
    "# grime recipe: `grime run PHOTO -o OUT --recipe-from THIS` makes the output again\n";

impl Recipe {
    /// The recipe of ageing `inputs` with `preset` (as loaded and run).
    ///
    /// # Errors
    /// [`Error::Io`] when an input file cannot be read.
    pub fn new(inputs: &Inputs, preset: &Preset) -> Result<Recipe> {
        let (input, input_sha256) = match &inputs.source {
            Source::File(p) => (file_name(p), Some(sha256_file(p)?)),
            Source::Demo(name) => (format!("demo:{name}"), None),
            Source::Loaded { scene, from } => match from.first() {
                Some(p) => (file_name(p), Some(sha256_file(p)?)),
                None => ("image".into(), Some(sha256(scene.photo.image().as_bytes()))),
            },
        };
        Ok(Recipe {
            grime: env!("CARGO_PKG_VERSION").into(),
            seed: preset.seed,
            input,
            input_sha256,
            mask_sha256: inputs.mask.as_deref().map(sha256_file).transpose()?,
            normal_map_sha256: inputs.normal_map.as_deref().map(sha256_file).transpose()?,
            region: match inputs.region {
                RegionMode::Auto => "auto",
                RegionMode::Full => "full",
            }
            .into(),
            sources: match inputs.sources {
                SourcesMode::Auto => "auto",
                SourcesMode::Top => "top",
            }
            .into(),
            wall_width_m: inputs.wall_width_m,
            quad: inputs.quad,
            preset: preset.clone(),
        })
    }

    /// This recipe with another preset (a time-lapse frame's).
    pub fn with_preset(&self, preset: &Preset) -> Recipe {
        Recipe {
            seed: preset.seed,
            preset: preset.clone(),
            ..self.clone()
        }
    }

    /// The recipe as TOML, with a first line saying what it is.
    pub fn to_text(&self) -> String {
        format!("{HEADER}{}", toml::to_string(self).unwrap_or_default())
    }

    /// Parses [`Recipe::to_text`]'s output.
    ///
    /// # Errors
    /// [`Error::Preset`] for bad TOML; the preset's validation errors.
    pub fn from_text(text: &str) -> Result<Recipe> {
        let recipe: Recipe =
            toml::from_str(text).map_err(|e| Error::Preset(format!("recipe: {}", e.message())))?;
        recipe.preset.validate()?;
        Ok(recipe)
    }

    /// The inputs to age again with this recipe: `inputs`' files, with the
    /// recipe's region, sources, wall width and plane.
    ///
    /// # Errors
    /// [`Error::RecipeMismatch`] when an input is not the recipe's (unless
    /// `force`), or the recipe had a mask and none is given.
    pub fn apply(&self, inputs: &Inputs, force: bool) -> Result<Inputs> {
        let again = Recipe::new(inputs, &self.preset)?;
        let mismatch = |what: &str, ok: bool| match ok || force {
            true => Ok(()),
            false => Err(Error::RecipeMismatch(format!(
                "{what} is not the recipe's ({}): pass --force to use the recipe anyway",
                self.input
            ))),
        };
        mismatch(
            &format!("the input {}", again.input),
            again.input_sha256 == self.input_sha256
                && (self.input_sha256.is_some() || again.input == self.input),
        )?;
        if self.mask_sha256.is_some() && inputs.mask.is_none() {
            return Err(Error::RecipeMismatch(
                "the recipe was made with a mask: pass it with --mask".into(),
            ));
        }
        mismatch("the mask", again.mask_sha256 == self.mask_sha256)?;
        mismatch(
            "the normal map",
            again.normal_map_sha256 == self.normal_map_sha256,
        )?;
        Ok(Inputs {
            quad: self.quad,
            region: match self.region.as_str() {
                "full" => RegionMode::Full,
                _ => RegionMode::Auto,
            },
            sources: match self.sources.as_str() {
                "top" => SourcesMode::Top,
                _ => SourcesMode::Auto,
            },
            wall_width_m: self.wall_width_m,
            ..inputs.clone()
        })
    }
}

fn file_name(p: &Path) -> String {
    p.file_name().map_or_else(
        || p.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

/// SHA-256 of `bytes`, lower-case hex.
pub fn sha256(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// SHA-256 of a file's bytes, read in pieces.
///
/// # Errors
/// [`Error::Io`] naming the file.
pub fn sha256_file(path: &Path) -> Result<String> {
    let mut file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let mut hasher = Sha256::new();
    std::io::copy(&mut file, &mut hasher).map_err(|e| Error::io(path, e))?;
    Ok(hasher
        .finalize()
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_round_trips_and_names_what_it_is() {
        let mut p = Preset::default();
        p.age.years = Some(30);
        p.rain.source_lines = vec![vec![[1.5, 2.0], [40.0, 2.5]]];
        let r = Recipe::new(
            &Inputs {
                source: Source::Demo("facade".into()),
                ..Inputs::file("unused")
            },
            &p,
        )
        .unwrap();
        let text = r.to_text();
        assert!(text.starts_with("# grime recipe"), "{text}");
        assert!(text.contains("input = \"demo:facade\""), "{text}");
        assert_eq!(Recipe::from_text(&text).unwrap(), r);
    }

    #[test]
    fn sha256_of_abc() {
        assert_eq!(
            sha256(b"abc"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
    }
}
