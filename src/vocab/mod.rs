//! The shared vocabulary: the words several layers speak, in leaf modules that import
//! nothing from the rest of the crate, so every layer may use them and no dependency runs
//! back up the pipeline (syntax → ir → check → model → mbd → session).
//!
//! [`math`] holds the nalgebra aliases of the reader and the core.

pub mod math;
