//! A modelling session: the whole job for a dataset in one call, for every shell (the
//! CLI, the REPL, Python and C). It sequences the core's pipeline
//! ([`crate::mbd::pipeline`]: build, assemble, redundancy) and everything after it;
//! its public types are its own (plain figures, words, rows), so a shell needs nothing
//! beyond `session` and `diag`. [`report`] words the pipeline's result for `mbfx check`.
//!
//! Beside it: [`files`] reads input files as text, [`loaded`] keeps a dataset loaded for
//! questions, [`evaluate`] takes one expression from text to value (`mbfx eval` and the
//! REPL), [`expression`] compiles one over named variables for evaluation at many points
//! (the Python module and the C API), [`run`] simulates a dataset (`mbfx run`) and [`plan`] decides which integrator and
//! settings each stretch of a run gets; [`analyses`] runs the stretches that integrate
//! nothing (static equilibria, kinematic analysis). [`request`] is the one call every shell runs a
//! dataset with (a request in; the rows out as they come, then a result or a failure that
//! keeps what it computed), reading command files with [`acf`]. [`check`] reads, analyses
//! and words a dataset as `mbfx check` prints it, [`linearization`] gives a linear
//! analysis as plain numbers and [`graphics`] lists a model's GRAPHICS statements: with
//! them, the Python module and the C API need nothing beyond `session` and `diag`.

pub mod acf;
pub mod analyses;
pub mod animation;
pub mod changes;
pub mod check;
pub mod evaluate;
pub mod expression;
pub mod files;
pub mod fmu_settings;
pub mod graphics;
pub mod lifted;
pub mod linear;
pub mod linearization;
pub mod loaded;
pub mod plan;
pub mod plant;
pub mod prepared;
pub mod report;
pub mod request;
pub mod run;
pub mod stepping;
pub mod stopped;

pub use crate::mbd::pipeline::DimRequest;
use crate::mbd::pipeline::{analyze_model, Analysis, Failure};
