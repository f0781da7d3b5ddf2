//! The shared vocabulary: the words several layers speak, in leaf modules that import
//! nothing from the rest of the crate, so every layer may use them and no dependency runs
//! back up the pipeline (syntax → ir → check → model → mbd → session).
//!
//! [`builtins`] is the table of the language's names (arity, argument kinds, result type,
//! meaning) and [`func`] the runtime functions they stand for; [`elements`] holds the joint,
//! primitive and element kinds with the one table of their names; [`math`] holds the
//! nalgebra aliases of the reader and the core.

pub mod builtins;
pub mod elements;
pub mod func;
pub mod math;
