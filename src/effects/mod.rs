//! The weathering effects. Each is pure: buffers, parameters and a seed in,
//! maps or layers out; no file I/O, no clock, no threads beyond rayon.

pub mod rain;
