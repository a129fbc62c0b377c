//! grime ages photos of buildings: rain streaks that run down from ledges and
//! darken over the years, as editable layers.
//!
//! The crate is a pure core (effects on buffers, seeded, no I/O) with thin
//! front ends (the `grime` CLI and GUI). Data flows
//! photo + region + preset → [`pipeline::run`] → [`stack::Stack`] →
//! composite or layered export.
//!
//! ```
//! use grime::{pipeline, preset::Preset, progress::Progress};
//! let demo = grime::demo::facade(96, 72);
//! let scene = pipeline::Scene::new(demo.photo, demo.region).unwrap();
//! let mut preset = Preset::default();
//! preset.rain.layers = 2;
//! let out = pipeline::run(&scene, &preset, &Progress::none()).unwrap();
//! // 2 rainfalls and the runs they washed, then moss, dust film and
//! // dust granules.
//! assert_eq!(out.stack.layers.len(), 6);
//! ```
#![deny(missing_docs)]
#![forbid(unsafe_code)]

pub mod age;
pub mod analysis;
pub mod batch;
pub mod clock;
pub mod demo;
pub mod effects;
pub mod error;
pub mod export;
pub mod field;
pub mod grid;
#[cfg(feature = "gui")]
pub mod gui;
pub mod io;
pub mod masks;
pub mod perspective;
pub mod photo;
pub mod pipeline;
pub mod preset;
pub mod progress;
pub mod random;
pub mod recipe;
pub mod round;
pub mod say;
pub mod shrink;
pub mod stack;
pub mod timelapse;

pub use error::{Error, Result};
