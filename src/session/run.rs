//! A dynamic simulation of a dataset, the library side of `mbfx run`: read and assemble
//! the model ([`super::analyze_model`]), build its forces and the equations of motion,
//! solve consistent accelerations at t = 0, then integrate to the end time, producing one
//! row of output columns at every output time. The columns are the `--probe`
//! expressions, then each REQUEST's components (`REQ<id>.F<k>`, k = 1..8), all compiled
//! in one batch by the chosen engine; interpreter and JIT give the same bits.
//!
//! This module holds the [`Simulation`] every part works on; `spec` what a run is
//! asked to do, `simulation` building one, `columns` its output columns, `segments`
//! the run loop, `summary` what it ends with, `warnings` the lock-up diagnosis and
//! the accuracy monitors, `estimate` the error estimate from a second run, and
//! `rebuild` a command file's changes to the model during a run, and `stepped` what a
//! caller stepping a simulation itself needs of it.

use super::plan::Plan;
use super::plant::Plant;
use crate::diag::Diagnostic;
use crate::mbd::dynamics::Dynamics;
use crate::mbd::rewind::StartState;
use crate::model::ModelRead;

mod columns;
mod contact_meshes;
mod cpu_clock;
mod estimate;
mod friction_columns;
mod rebuild;
mod segments;
mod simulation;
mod spec;
mod stepped;
mod summary;
mod warnings;

use columns::{reads_reconciled, shadow, standard_component, Column, Outputs};
pub use contact_meshes::contact_meshes;
pub use estimate::Estimate;
pub use simulation::{RewindError, RunFailure};
pub use spec::{Engine, Method, RunSpec, Segment, TableRow};
pub use summary::Summary;
pub use warnings::ACCUMULATED_WARNING;
use warnings::{monitors, sum_warning};

/// A model ready to run.
pub struct Simulation {
    /// The dataset as read.
    pub read: ModelRead,
    /// The system in motion.
    pub dynamics: Dynamics,
    outputs: Outputs,
    /// What to run.
    pub spec: RunSpec,
    notes: Vec<String>,
    conservative: bool,
    /// How many equations the redundancy analysis found redundant.
    pub redundant: usize,
    /// The rows left out of the equations of motion as redundant.
    dropped: Vec<usize>,
    /// The state the run starts from, to run again from it ([`Simulation::rewind`]).
    start: StartState,
    /// The elements a command file switched off ([`super::changes`]).
    inactive: super::changes::Inactive,
    /// A command file rebuilt the system during a run ([`Simulation::rewind`] refuses).
    changed: bool,
    /// The design variables the constraints read: changing one needs a new build.
    constraint_designs: Vec<i64>,
    /// The checker's warnings about each probe that has some (units of measure, ...):
    /// (name, expression, warnings with spans into the expression).
    pub probe_warnings: Vec<(String, String, Vec<Diagnostic>)>,
    /// The CONTACT geometries' warnings (an EXTERNAL without a mesh: its placeholder).
    pub contact_warnings: Vec<Diagnostic>,
    /// The dataset's plant inputs and outputs, for LINEAR/STATEMAT.
    plant: Plant,
    /// The parts' poses at each integrated row, while a run records them for its error
    /// estimate (`estimate`).
    trace: Option<Vec<Vec<f64>>>,
    /// What records the run's animation frames, while a run is asked for one
    /// ([`super::animation`]).
    pub(crate) recorder: Option<super::animation::Recorder>,
}

#[cfg(test)]
mod tests;
