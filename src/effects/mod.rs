//! The weathering effects. Each is pure: buffers, parameters and a seed in,
//! maps or layers out; no file I/O, no clock, no threads beyond rayon.

pub mod dust;
pub mod moss;
pub mod patches;
pub mod percentile;
pub mod rain;
pub mod region;
pub mod roughness;
