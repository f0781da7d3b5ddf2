//! What a run hands out as it goes ([`RunObserver`]: warnings, the built model, the
//! start, the rows, the step table) and what it ends with: a [`RunDone`], or a
//! [`RunFailed`] that keeps what it computed and words why it stopped.

use super::COMMAND_LINE;
use crate::diag::{render, Code, Diagnostic, SourceFile};
use crate::mbd::dynamics::DynError;
use crate::mbd::system::Dimension;
use crate::session::animation::Animation;
use crate::session::report;
use crate::session::run::{Segment, Summary, TableRow};
use crate::session::stopped::Stopped;
use std::fmt;
use std::io;

/// The model is built: what a run will write, before any warning about its INTEGRATOR.
pub struct Built<'a> {
    /// The column names: `time`, the probes, the REQUEST components.
    pub header: &'a [String],
    /// The dimension the system was built in.
    pub dim: Dimension,
    /// Why 2D or 3D, in words (`mbfx run` prints it when `--dim` is not given).
    pub dim_reason: &'a str,
}

/// The run is about to integrate.
pub struct Started<'a> {
    /// The column names, as in [`Built`].
    pub header: &'a [String],
    /// The stretches it runs, one after the other from t = 0.
    pub segments: &'a [Segment],
    /// Where the last one ends.
    pub end: f64,
}

/// What a run tells its caller as it goes. Only [`RunObserver::row`] is required; a
/// closure `FnMut(&[f64]) -> io::Result<()>` is an observer of rows alone. An error
/// returned by any method stops the run (a [`RunFailed`] with the output failure, E0801);
/// the caller, who knows what failed, reports it.
pub trait RunObserver {
    /// Warnings about `source` as they arise (the command file's, the dataset's
    /// encoding, its INTEGRATOR statement's); never called with an empty list.
    fn warnings(&mut self, _diagnostics: &[Diagnostic], _source: &SourceFile) -> io::Result<()> {
        Ok(())
    }
    /// The model is read, assembled and ready ([`Built`]).
    fn built(&mut self, _built: &Built<'_>) -> io::Result<()> {
        Ok(())
    }
    /// Integration starts ([`Started`]); rows follow.
    fn started(&mut self, _started: &Started<'_>) -> io::Result<()> {
        Ok(())
    }
    /// One output row: the time, then the columns of the header.
    fn row(&mut self, row: &[f64]) -> io::Result<()>;
    /// Whether [`RunObserver::table`] wants the step table.
    fn wants_table(&self) -> bool {
        false
    }
    /// A line of the step table (`mbfx run --verbose`), at each output time.
    fn table(&mut self, _row: &TableRow) {}
}

impl<F: FnMut(&[f64]) -> io::Result<()>> RunObserver for F {
    fn row(&mut self, row: &[f64]) -> io::Result<()> {
        self(row)
    }
}

/// A finished run.
#[derive(Clone, Debug)]
pub struct RunDone {
    /// The column names: `time`, the probes, the REQUEST components.
    pub header: Vec<String>,
    /// Each column's unit ([`Simulation::units`](crate::session::run::Simulation::units)).
    pub units: Vec<String>,
    /// Steps, work, residuals, notes (a command file's output files among them) and the
    /// accuracy warnings of the run's own monitors.
    pub summary: Summary,
    /// Why the run was 2D or 3D, in words.
    pub dim_reason: String,
    /// The animation, when the request asked for one ([`RunRequest::animation`](super::RunRequest::animation)).
    pub animation: Option<Animation>,
}

/// A run that failed: what it had computed, and why it stopped.
pub struct RunFailed {
    /// The column names, once the model was built.
    pub header: Option<Vec<String>>,
    /// Each column's unit, once the model was built (as [`RunDone::units`]).
    pub units: Option<Vec<String>>,
    /// The summary up to the failure, once integration had started.
    pub summary: Option<Summary>,
    /// The failure's code (its first error's).
    pub code: Code,
    /// What to show: the failure, with the warnings that came with it (a dataset's or
    /// command file's reader reports both), in order.
    pub diagnostics: Vec<Diagnostic>,
    /// What the spans point into: the dataset, the command file, a probe's expression
    /// (named `--probe NAME`), or nothing ([`COMMAND_LINE`]).
    pub source: SourceFile,
    /// The simulation time of a dynamics failure.
    pub time: Option<f64>,
    /// The element (`JOINT/3`, `SFORCE/1 'spring'`) or part (`PART/2`) it names.
    pub element: Option<String>,
    /// The probe whose expression failed to compile.
    pub probe: Option<String>,
    /// The failure in words (its first error's message).
    pub cause: String,
    /// The run's failure itself, when it is one (match [`DynError::Interrupted`] in
    /// [`Stopped::dynamics`]).
    pub error: Option<Stopped>,
    /// The animation recorded up to the failure, when the request asked for one and
    /// integration had started.
    pub animation: Option<Animation>,
}

impl RunFailed {
    /// A failure made of `diagnostics` about `source`, nothing computed yet.
    pub(super) fn new(source: SourceFile, diagnostics: Vec<Diagnostic>) -> Box<RunFailed> {
        let first = diagnostics
            .iter()
            .find(|d| d.is_error())
            .or(diagnostics.first());
        Box::new(RunFailed {
            header: None,
            units: None,
            summary: None,
            code: first.map_or(Code::CannotSimulate, |d| d.code),
            cause: first.map_or_else(String::new, |d| d.message.clone()),
            diagnostics,
            source,
            time: None,
            element: None,
            probe: None,
            error: None,
            animation: None,
        })
    }

    /// A failure of the request itself (E0503 and friends, no text to point into).
    pub(super) fn command_line(d: Diagnostic) -> Box<RunFailed> {
        RunFailed::new(SourceFile::textless(COMMAND_LINE), vec![d])
    }

    /// A dynamics failure, at the element it names in `model` (read from `source`).
    pub(super) fn dynamics(
        e: Stopped,
        source: SourceFile,
        model: &crate::model::Model,
    ) -> Box<RunFailed> {
        let mut f = RunFailed::new(source, vec![report::failure_diagnostic(&e, model)]);
        f.time = e.time();
        f.element = e.culprit().map(|c| c.to_string());
        f.error = Some(e);
        f
    }

    /// An observer's error: the run stopped because its output could not be written.
    pub(super) fn output(e: io::Error) -> Box<RunFailed> {
        let e = Stopped::from(DynError::Output(e.to_string()));
        let d = Diagnostic::error(report::code_of(&e), 0..0, e.to_string());
        let mut f = RunFailed::new(SourceFile::textless(COMMAND_LINE), vec![d]);
        f.error = Some(e);
        f
    }

    /// The diagnostics rendered against their source, as `mbfx run` prints them.
    pub fn render(&self, color: bool) -> String {
        render(&self.diagnostics, &self.source, color)
    }
}

impl fmt::Display for RunFailed {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "[{}] {}", self.code.as_str(), self.cause)
    }
}

impl fmt::Debug for RunFailed {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("RunFailed")
            .field("code", &self.code)
            .field("cause", &self.cause)
            .field("source", &self.source.name)
            .field("time", &self.time)
            .field("element", &self.element)
            .field("probe", &self.probe)
            .field("diagnostics", &self.diagnostics)
            .field("summary", &self.summary)
            .finish_non_exhaustive()
    }
}

impl std::error::Error for RunFailed {}
