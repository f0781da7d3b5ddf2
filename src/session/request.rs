//! One entry point for every shell that runs a dataset: a [`RunRequest`] (the input,
//! the end time and output step, the integrator and its settings, the probes) goes into
//! [`run`], which checks it, reads the command file ([`super::acf`]) and the dataset,
//! builds the [`Simulation`](super::run::Simulation), runs its segments and hands each output row to a
//! [`RunObserver`]. Out comes a [`RunDone`] (the header, the [`Summary`](super::run::Summary), why 2D or 3D),
//! or a [`RunFailed`] that keeps what was computed before the failure (header and
//! summary once integration had started) and the failure as diagnostics with their code,
//! the source their spans point into, the time, the element and the cause; the rows
//! handed out before it stay with the caller.
//!
//! `mbfx run`, the Python module and the C API are layers over this call: none of them
//! checks arguments, reads command files or words failures itself. Its defaults are
//! `mbfx run`'s (the output step END/100, the dataset's INTEGRATOR else GSTIFF, ERROR per
//! step, the JIT, 2D when the scene is planar), and so are its messages: they name the
//! command line's options (`--end`, `--probe`), which the other shells' arguments mirror.
//!
//! ```
//! use mbfx::session::request::{run, RunRequest};
//!
//! let adm = "pendulum\nPART/1, GROUND\nMARKER/10, PART = 1\n\
//!            PART/2, MASS = 1, CM = 20, IP = 1, 1, 1\n\
//!            MARKER/20, PART = 2, QP = 1, 0, 0\nMARKER/21, PART = 2\n\
//!            JOINT/1, REVOLUTE, I = 21, J = 10\nACCGRAV/JGRAV = -9.81\nEND\n";
//! let mut request = RunRequest::dataset("pendulum.adm", adm);
//! request.end = Some(1.0);
//! request.probes.push(("y".into(), "DY(20, 10)".into()));
//! let mut rows = Vec::new();
//! let mut sink = |row: &[f64]| -> std::io::Result<()> {
//!     rows.push(row.to_vec());
//!     Ok(())
//! };
//! let done = run(&request, &mut sink, None).expect("the pendulum swings");
//! assert_eq!(done.header, ["time", "y"]);
//! assert_eq!(rows.len(), 101); // END/100 apart, from 0 to END
//! assert!(rows[100][1] < 0.0);
//! ```
//!
//! This module holds [`run`] itself; `options` the request and its checks,
//! `outcome` what a run hands out and ends with, and `prepare` the simulation it
//! runs (a kept one reused, or one built); `built` the simulation a request would
//! run, for a shell that steps it itself.

use super::acf::{self, Commands};
use super::animation;
use super::prepared;
use super::report;
use super::run::{Segment, TableRow};
use crate::diag::{Code, Diagnostic, SourceFile};
use crate::mbd::dynamics::integrator::Interrupt;
use crate::model::command_changes::ModelChange;
use crate::model::commands::Step;
use crate::session::stopped::Stopped;
use std::cell::RefCell;

pub mod built;
mod options;
mod outcome;
mod prepare;

use options::asked_analyses;
pub use options::{parse_probe, Formulation, Input, LinearRequest, RunRequest, COMMAND_LINE};
pub use outcome::{Built, RunDone, RunFailed, RunObserver, Started};
pub use prepare::set_values;
use prepare::{copy, read_file, simulation_for};

/// Runs `request`: checks it, reads the command file and the dataset, builds the model,
/// integrates its segments and hands each output row to `observer` (the first at t = 0),
/// with warnings, the built model, the start and the step table as they come (see
/// [`RunObserver`]). When `interrupt` is given, it is asked before every integration step
/// (a relaxed load of a flag, say): once it answers true, the run stops within a step
/// with E0804 ([`DynError::Interrupted`](crate::mbd::dynamics::DynError::Interrupted)),
/// however far apart the output times are.
///
/// The order of the checks is `mbfx run`'s: the numbers ([`RunRequest::validate`]), the
/// command file, the end time (E0503 for a dataset without one, E0604 for a command file
/// without SIMULATE), the probes' names, the dataset, the model.
pub fn run(
    request: &RunRequest,
    observer: &mut dyn RunObserver,
    interrupt: Option<Interrupt<'_>>,
) -> Result<RunDone, Box<RunFailed>> {
    request.validate().map_err(RunFailed::command_line)?;
    // A command file names the dataset and says how long to run; a dataset needs an end.
    let commands: Option<Commands> = match &request.input {
        Input::Path(path) if acf::is_command_file(path) => match acf::read(path) {
            Ok(c) => {
                if !c.file.diagnostics.is_empty() {
                    observer
                        .warnings(&c.file.diagnostics, &c.source)
                        .map_err(RunFailed::output)?;
                }
                Some(c)
            }
            Err(refused) => return Err(RunFailed::new(refused.source, refused.diagnostics)),
        },
        _ if request.end.is_none() && !request.statics && request.linear.is_none() => {
            return Err(RunFailed::command_line(Diagnostic::error(
                Code::CommandLine,
                0..0,
                format!(
                    "--end is required to run a dataset ({}); a command file (.acf) may give it instead, and --statics alone needs none",
                    request.input_name()
                ),
            )))
        }
        _ => None,
    };
    if let Some(c) = commands.as_ref().filter(|_| request.end.is_none()) {
        let analyses = c.file.steps.iter().any(|s| {
            matches!(
                s,
                crate::model::commands::Step::Simulate(_) | crate::model::commands::Step::Linear(_)
            )
        });
        if !analyses {
            let d = Diagnostic::error(Code::MissingArgument, 0..0, acf::NO_SIMULATION);
            return Err(RunFailed::new(copy(&c.source), vec![d]));
        }
    }
    request.check_probes().map_err(RunFailed::command_line)?;
    let (name, text, warnings) = match (&request.input, &commands) {
        (_, Some(c)) => read_file(&c.model)?,
        (Input::Path(path), None) => read_file(path)?,
        (Input::Dataset { name, text }, None) => (name.clone(), text.clone(), Vec::new()),
    };
    if !warnings.is_empty() {
        // The encoding's warnings point into the file as read, before any setting.
        observer
            .warnings(&warnings, &SourceFile::new(name.clone(), text.clone()))
            .map_err(RunFailed::output)?;
    }
    let key = commands
        .is_none()
        .then(|| prepared::key(request, &name, &text));
    // The changes a command file makes before its first SIMULATE: the model it starts from.
    let initial: Vec<ModelChange> = commands.as_ref().map_or(Vec::new(), |c| {
        (c.file.steps.iter())
            .take_while(|s| !matches!(s, Step::Simulate(_)))
            .filter_map(|s| match s {
                Step::Change(c) => Some((**c).clone()),
                _ => None,
            })
            .collect()
    });
    let (mut sim, source, keepable, reused) =
        simulation_for(request, key.as_ref(), name, text, &initial)?;
    // The scene is drawn before anything runs: a mesh file that cannot be read fails
    // the run at once.
    let drawn = request
        .animation
        .as_ref()
        .map(|a| animation::scene_of(a, &sim.read.model))
        .transpose()
        .map_err(RunFailed::command_line)?;
    let header = sim.header();
    let dim_reason = sim.dynamics.sys.dim_reason.clone();
    observer
        .built(&Built {
            header: &header,
            dim: sim.dynamics.sys.dim,
            dim_reason: &dim_reason,
        })
        .map_err(RunFailed::output)?;
    // Physics the model leaves out (a CONTACT, a FRICTION): never silently. A kept
    // simulation run again has shown them already.
    let ignored: Vec<Diagnostic> = (sim.read.model.ignored.iter())
        .filter(|i| i.physical && !reused)
        .map(crate::model::report::ignored_warning)
        .collect();
    let ignored: Vec<Diagnostic> = (ignored.into_iter())
        .chain(sim.contact_warnings.iter().filter(|_| !reused).cloned())
        .collect();
    if !ignored.is_empty() {
        observer
            .warnings(&ignored, &source)
            .map_err(RunFailed::output)?;
    }
    let dataset_integrator = sim.read.model.integrator.clone();
    if let Some(i) = dataset_integrator
        .as_ref()
        .filter(|i| !i.warnings.is_empty())
    {
        observer
            .warnings(&i.warnings, &source)
            .map_err(RunFailed::output)?;
    }
    // Units of measure that do not fit (W0312) are warnings: the run goes on. A kept
    // simulation run again has shown them already.
    let units: Vec<Diagnostic> = (sim.read.diagnostics.iter())
        .filter(|d| d.code == Code::UnitMismatch && !reused)
        .cloned()
        .collect();
    if !units.is_empty() {
        observer
            .warnings(&units, &source)
            .map_err(RunFailed::output)?;
    }
    // A probe's warnings point into its own text.
    for (name, text, warnings) in sim.probe_warnings.iter().filter(|_| !reused) {
        let probe = SourceFile::new(format!("--probe {name}"), text.clone());
        observer
            .warnings(warnings, &probe)
            .map_err(RunFailed::output)?;
    }
    let equilibrium = sim.read.model.equilibrium.clone();
    if let Some(e) = equilibrium.as_ref().filter(|e| !e.warnings.is_empty()) {
        observer
            .warnings(&e.warnings, &source)
            .map_err(RunFailed::output)?;
    }
    let mut segments = match &commands {
        None => request.end.map_or_else(Vec::new, |end| {
            vec![Segment::dynamic(
                end,
                request.output_step.unwrap_or(end / 100.0),
                dataset_integrator.clone(),
            )]
        }),
        Some(c) => acf::segments(
            &c.file,
            dataset_integrator.as_ref(),
            equilibrium.as_ref(),
            request.end,
            request.output_step,
        )
        .map_err(|msg| {
            let d = Diagnostic::error(Code::MissingArgument, 0..0, msg);
            RunFailed::new(copy(&c.source), vec![d])
        })?,
    };
    asked_analyses(request, &mut segments, equilibrium.as_ref());
    if let Some(c) = &commands {
        // The command file's changes to the model, checked against the dataset before
        // the first row: a bad one is an error at its place in the command file.
        let found = sim.check_changes(&segments);
        if crate::diag::has_errors(&found) {
            return Err(RunFailed::new(copy(&c.source), found));
        }
        if !found.is_empty() {
            observer
                .warnings(&found, &c.source)
                .map_err(RunFailed::output)?;
        }
    }
    let end = segments.last().map_or(0.0, |s| s.end);
    if let (Some(a), Some((_, scene))) = (&request.animation, &drawn) {
        sim.recorder = Some(animation::recorder(a, scene, &mut sim, end));
    }
    let started = Started {
        header: &header,
        segments: &segments,
        end,
    };
    if let Err(e) = observer.started(&started) {
        let mut f = RunFailed::output(e);
        f.header = Some(header);
        return Err(f);
    }
    let wants_table = observer.wants_table();
    let observer = RefCell::new(observer);
    let mut out = |row: &[f64]| observer.borrow_mut().row(row);
    let mut table = |r: &TableRow| observer.borrow_mut().table(r);
    let table: Option<&mut dyn FnMut(&TableRow)> = match wants_table {
        true => Some(&mut table),
        false => None,
    };
    let (mut summary, failed) = sim.run_interruptible(&segments, &mut out, table, interrupt);
    if let Some(note) = commands.as_ref().and_then(|c| acf::output_note(&c.file)) {
        summary.notes.push(note);
    }
    summary.reused = reused;
    if let Some(line) = crate::model::report::not_modelled(&sim.read.model.ignored) {
        summary.warnings.insert(0, line);
    }
    let recorded = (sim.recorder.take())
        .zip(drawn)
        .map(|(r, (options, scene))| animation::finish(r, options, scene, &sim.read.model));
    let result = match failed {
        None => Ok(RunDone {
            header,
            summary,
            dim_reason,
            animation: recorded,
        }),
        Some(e) => {
            let mut f = match (&e, &commands) {
                // A change to the model that could not be made: at its commands.
                (Stopped::Change { at, .. }, Some(c)) => {
                    let d = Diagnostic::error(report::code_of(&e), at.clone(), e.to_string());
                    let mut f = RunFailed::new(copy(&c.source), vec![d]);
                    (f.time, f.error) = (e.time(), Some(e));
                    f
                }
                _ => RunFailed::dynamics(e, source, &sim.read.model),
            };
            (f.header, f.summary) = (Some(header), Some(summary));
            f.animation = recorded;
            Err(f)
        }
    };
    if let Some(key) = key.filter(|_| keepable) {
        prepared::keep(key, sim);
    }
    result
}

#[cfg(test)]
mod tests;
