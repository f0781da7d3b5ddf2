//! One entry point for every shell that runs a dataset: a [`RunRequest`] (the input,
//! the end time and output step, the integrator and its settings, the probes) goes into
//! [`run`], which checks it, reads the command file ([`super::acf`]) and the dataset,
//! builds the [`Simulation`], runs its segments and hands each output row to a
//! [`RunObserver`]. Out comes a [`RunDone`] (the header, the [`Summary`], why 2D or 3D),
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

use super::acf::{self, Commands};
use super::files::read_dataset;
use super::prepared;
use super::report;
use super::run::{Engine, Method, RunFailure, RunSpec, Segment, Simulation, Summary, TableRow};
use super::DimRequest;
use crate::diag::{render, Code, Diagnostic, Severity, SourceFile};
use crate::mbd::dynamics::integrator::Interrupt;
use crate::mbd::dynamics::DynError;
use crate::mbd::system::Dimension;
use crate::model::command_changes::ModelChange;
use crate::model::commands::Step;
use crate::model::linear_command::Linear;
use crate::model::overrides::Settings;
use std::cell::RefCell;
use std::fmt;
use std::io;
use std::path::PathBuf;

/// The name of the source the request's own errors point into (a bad number, a probe
/// without a name): they have no text, only a message.
pub const COMMAND_LINE: &str = "command line";

/// What to run.
#[derive(Clone, Debug, PartialEq)]
pub enum Input {
    /// A file: an Adams command file when its extension is `.acf` (any case; it names
    /// the dataset and may say how long to run), else a dataset.
    Path(PathBuf),
    /// A dataset's text, and the name messages give it.
    Dataset {
        /// The name diagnostics show (a file name, `<string>`).
        name: String,
        /// The dataset (`.adm` text).
        text: String,
    },
}

/// A run, as `mbfx run` takes it: every field is one of its options, and
/// [`RunRequest::new`] gives their defaults.
#[derive(Clone, Debug, PartialEq)]
pub struct RunRequest {
    /// The dataset or command file.
    pub input: Input,
    /// End time (`--end`): required for a dataset; for a command file, it replaces its
    /// SIMULATE commands by one stretch to it.
    pub end: Option<f64>,
    /// Output step (`--output-step`): None takes the command file's DTOUT, else END/100.
    pub output_step: Option<f64>,
    /// The integrator (`--integrator`): None takes the dataset's INTEGRATOR (with a
    /// command file's INTEGRATOR commands over it), else GSTIFF, as Adams.
    pub method: Option<Method>,
    /// ERROR (`--error`): None takes the INTEGRATOR statement's, else 1e-3.
    pub error: Option<f64>,
    /// HMAX (`--hmax`): None takes the statement's, else the output step.
    pub hmax: Option<f64>,
    /// HINIT (`--hinit`): None takes the statement's, else HMAX/20.
    pub hinit: Option<f64>,
    /// HMIN (`--hmin`): None takes the statement's, else 1e-6·HMAX.
    pub hmin: Option<f64>,
    /// ERROR bounds the whole run's error rather than each step's (`--error-per run`).
    pub error_per_run: bool,
    /// dopri853 keeps to the Cartesian index-1 form on a planar tree (`--cartesian`).
    pub cartesian: bool,
    /// Output rows from each method's continuous extension (`--interpolate`, as
    /// INTEGRATOR/INTERPOLATE = ON); false leaves it to the statement.
    pub interpolate: bool,
    /// Estimate the answer's error from a second run at ERROR/10 and warn when it
    /// exceeds 10·ERROR (`--estimate-error`, [`super::run::Estimate`]).
    pub estimate_error: bool,
    /// Fixed steps of at most this (`--fixed-step`): no error control.
    pub fixed_step: Option<f64>,
    /// HHT's ALPHA in [−1/3, 0] (`--alpha`): None takes the statement's, else −0.3.
    pub alpha: Option<f64>,
    /// The BDF formulation (`--formulation`): None takes the statement's, else I3.
    pub formulation: Option<Formulation>,
    /// The highest BDF order, 1 to 6 (`--kmax`): None takes the statement's, else 6.
    pub kmax: Option<u32>,
    /// Generalized-α's ρ∞ in [0, 1] (`--rho-inf`): None is 0.9.
    pub rho_inf: Option<f64>,
    /// 2D, 3D, or 2D when the scene is planar (`--dim`).
    pub dim: DimRequest,
    /// Which back end evaluates the model's expressions (`--engine`).
    pub engine: Engine,
    /// Output columns after `time`, in order: (name, expression of the model's scope)
    /// (`--probe NAME=EXPR`, see [`parse_probe`]). A name must not be blank.
    pub probes: Vec<(String, String)>,
    /// Values set in the dataset before it is read (`--set KIND/ID.FIELD=VALUE`, see
    /// [`crate::model::overrides`]).
    pub set: Vec<String>,
    /// Find the static equilibrium first (`--statics`, as SIMULATE/STATICS): the run
    /// starts from it; without an end time it is the whole run.
    pub statics: bool,
    /// Solve a fully driven model from its constraints at each output time instead of
    /// integrating (`--kinematics`, as SIMULATE/KINEMATICS).
    pub kinematics: bool,
    /// A linear analysis where the run ends (`--linear[=FILE]`, as LINEAR/EIGENSOL): the
    /// modes printed, and written to FILE_modes.csv and FILE_shapes.csv when FILE is
    /// given. Without an end time (and no static equilibrium), at the assembled start.
    pub linear: Option<LinearRequest>,
}

/// The linear analysis a [`RunRequest`] asks for where the run ends: LINEAR/EIGENSOL
/// with every default but these.
#[derive(Clone, Debug, PartialEq)]
pub struct LinearRequest {
    /// The modes are also written to FILE_modes.csv and FILE_shapes.csv (`--linear=FILE`).
    pub file: Option<String>,
    /// The damping is kept (false: NODAMPIN).
    pub damping: bool,
}

impl LinearRequest {
    /// LINEAR/EIGENSOL with every default, written to `file` when given (`--linear`).
    pub fn eigensol(file: Option<String>) -> LinearRequest {
        LinearRequest {
            file,
            damping: true,
        }
    }

    /// The LINEAR command it stands for.
    fn command(&self) -> Linear {
        let mut command = Linear::eigensol(self.file.clone());
        command.damping = self.damping;
        command
    }
}

/// The BDF formulation a [`RunRequest`] asks for (`--formulation`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Formulation {
    /// Index 3 (Adams' I3).
    I3,
    /// Stabilized index 2 (Adams' SI2).
    Si2,
}

impl From<Formulation> for crate::model::integrator_settings::Formulation {
    fn from(f: Formulation) -> Self {
        match f {
            Formulation::I3 => Self::I3,
            Formulation::Si2 => Self::Si2,
        }
    }
}

/// `text` with `values` (`KIND/ID.FIELD=VALUE`, as `--set` takes them) set in it; the
/// refusal points into the values, one a line (the text returned with it).
pub fn set_values(values: &[String], text: &str) -> Result<String, (String, Vec<Diagnostic>)> {
    let settings = Settings::parse(values)?;
    settings
        .apply(text)
        .map_err(|d| (settings.text().to_string(), d))
}

impl RunRequest {
    /// A run of `input` with every option at `mbfx run`'s default (no end time yet: a
    /// dataset needs one).
    pub fn new(input: Input) -> RunRequest {
        RunRequest {
            input,
            end: None,
            output_step: None,
            method: None,
            error: None,
            hmax: None,
            hinit: None,
            hmin: None,
            error_per_run: false,
            cartesian: false,
            interpolate: false,
            estimate_error: false,
            fixed_step: None,
            alpha: None,
            formulation: None,
            kmax: None,
            rho_inf: None,
            dim: DimRequest::Auto,
            engine: Engine::Jit,
            probes: Vec::new(),
            set: Vec::new(),
            statics: false,
            kinematics: false,
            linear: None,
        }
    }

    /// A run of the dataset or command file at `path` ([`Input::Path`]).
    pub fn file(path: impl Into<PathBuf>) -> RunRequest {
        RunRequest::new(Input::Path(path.into()))
    }

    /// A run of the dataset `text`, called `name` in messages ([`Input::Dataset`]).
    pub fn dataset(name: impl Into<String>, text: impl Into<String>) -> RunRequest {
        RunRequest::new(Input::Dataset {
            name: name.into(),
            text: text.into(),
        })
    }

    /// The request's numbers checked, as `mbfx run` checks its options before reading
    /// anything: a positive end time, positive steps and tolerance, ALPHA in [−1/3, 0],
    /// ρ∞ in [0, 1], KMAX from 1 to 6. The first one wrong is an E0503 error.
    pub fn validate(&self) -> Result<(), Diagnostic> {
        let error = |msg: String| Err(Diagnostic::error(Code::CommandLine, 0..0, msg));
        if self.statics && self.kinematics {
            return error(
                "--statics and --kinematics exclude each other: a fully driven model has no equilibrium to find".into(),
            );
        }
        if let Some(end) = self.end {
            if !(end.is_finite() && end > 0.0) {
                return error(format!("--end {end} must be a positive time"));
            }
        }
        for (name, x) in [
            ("--output-step", self.output_step),
            ("--error", self.error),
            ("--hmax", self.hmax),
            ("--hinit", self.hinit),
            ("--hmin", self.hmin),
            ("--fixed-step", self.fixed_step),
        ] {
            if let Some(x) = x {
                if !(x.is_finite() && x > 0.0) {
                    return error(format!("{name} {x} must be a positive number"));
                }
            }
        }
        if let Some(alpha) = self.alpha {
            if !(-1.0 / 3.0..=0.0).contains(&alpha) {
                return error(format!("--alpha {alpha} must lie in [-1/3, 0]"));
            }
        }
        if let Some(rho) = self.rho_inf {
            if !(0.0..=1.0).contains(&rho) {
                return error(format!("--rho-inf {rho} must lie in [0, 1]"));
            }
        }
        if let Some(k) = self.kmax {
            if !(1..=6).contains(&k) {
                return error(format!("--kmax {k} must be an order from 1 to 6"));
            }
        }
        if let (Some(end), Some(dt)) = (self.end, self.output_step) {
            // Past 2^52 rows, neighbouring output times are no longer distinct doubles.
            let rows = end / dt;
            if rows > MAX_ROWS {
                return error(format!(
                    "--output-step {dt:e} over --end {end:e} makes {rows:.3e} rows: times that \
                     close cannot be told apart (at most {MAX_ROWS:.3e} rows); take a longer step"
                ));
            }
        }
        Ok(())
    }

    /// The name messages give the input.
    fn input_name(&self) -> String {
        match &self.input {
            Input::Path(p) => p.display().to_string(),
            Input::Dataset { name, .. } => name.clone(),
        }
    }

    /// The simulation's settings (its end and output step are the segments').
    fn spec(&self) -> RunSpec {
        // Replaced by the segments' own end and output step.
        let mut spec = RunSpec::new(self.end.unwrap_or(1.0), self.output_step.unwrap_or(1.0));
        spec.method = self.method;
        spec.kmax = self.kmax;
        spec.error_per_run = self.error_per_run;
        spec.cartesian = self.cartesian;
        spec.interpolate = self.interpolate;
        spec.estimate_error = self.estimate_error;
        spec.formulation = self.formulation.map(Into::into);
        (spec.error, spec.hmax, spec.hinit, spec.hmin) =
            (self.error, self.hmax, self.hinit, self.hmin);
        (spec.fixed_step, spec.alpha, spec.rho_inf) = (self.fixed_step, self.alpha, self.rho_inf);
        spec.dim = self.dim;
        spec.engine = self.engine;
        spec
    }
}

/// The segments changed as `--statics`, `--kinematics` and `--linear` ask: an
/// equilibrium first (unless the first segment is one), every stretch of dynamics made
/// kinematic, a linear analysis last. Every
/// segment without EQUILIBRIUM settings takes the dataset's `equilibrium`.
fn asked_analyses(
    request: &RunRequest,
    segments: &mut Vec<Segment>,
    equilibrium: Option<&crate::model::equilibrium_settings::EquilibriumStatement>,
) {
    use crate::model::commands::Analysis;
    let point = |s: &Segment| s.kind == Analysis::Statics && s.output_step == 0.0;
    if request.statics && !segments.first().is_some_and(point) {
        let mut start = Segment::dynamic(0.0, 0.0, None);
        start.kind = Analysis::Statics;
        // The command file's changes before its first SIMULATE come before this too.
        if let Some(first) = segments.first_mut() {
            start.changes = std::mem::take(&mut first.changes);
        }
        segments.insert(0, start);
    }
    if let Some(command) = &request.linear {
        let at = segments.last().map_or(0.0, |s| s.end);
        segments.push(Segment::linear(at, command.command()));
    }
    for s in segments.iter_mut() {
        if request.kinematics && s.kind == Analysis::Dynamic {
            s.kind = Analysis::Kinematics;
        }
        if s.equilibrium.is_none() {
            s.equilibrium = equilibrium.cloned();
        }
    }
}

/// The most output rows a run may ask for: 2^52, beyond which neighbouring output times
/// round to the same double.
const MAX_ROWS: f64 = 4_503_599_627_370_496.0;

/// `NAME=EXPR` (`--probe`) as (name, expression): split at the first `=`, the name
/// trimmed. Text without `=`, or with a blank name, comes back whole as ("", text), which
/// [`run`] refuses with E0503 quoting it.
pub fn parse_probe(text: &str) -> (String, String) {
    match text.split_once('=') {
        Some((n, e)) if !n.trim().is_empty() => (n.trim().to_string(), e.to_string()),
        _ => (String::new(), text.to_string()),
    }
}

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
    /// Steps, work, residuals, notes (a command file's output files among them) and the
    /// accuracy warnings of the run's own monitors.
    pub summary: Summary,
    /// Why the run was 2D or 3D, in words.
    pub dim_reason: String,
}

/// A run that failed: what it had computed, and why it stopped.
pub struct RunFailed {
    /// The column names, once the model was built.
    pub header: Option<Vec<String>>,
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
    /// The dynamics failure itself, when it is one (match [`DynError::Interrupted`]).
    pub error: Option<DynError>,
}

impl RunFailed {
    /// A failure made of `diagnostics` about `source`, nothing computed yet.
    fn new(source: SourceFile, diagnostics: Vec<Diagnostic>) -> Box<RunFailed> {
        let first = diagnostics
            .iter()
            .find(|d| d.is_error())
            .or(diagnostics.first());
        Box::new(RunFailed {
            header: None,
            summary: None,
            code: first.map_or(Code::CannotSimulate, |d| d.code),
            cause: first.map_or_else(String::new, |d| d.message.clone()),
            diagnostics,
            source,
            time: None,
            element: None,
            probe: None,
            error: None,
        })
    }

    /// A failure of the request itself (E0503 and friends, no text to point into).
    fn command_line(d: Diagnostic) -> Box<RunFailed> {
        RunFailed::new(SourceFile::textless(COMMAND_LINE), vec![d])
    }

    /// A dynamics failure, at the element it names in `model` (read from `source`).
    fn dynamics(e: DynError, source: SourceFile, model: &crate::model::Model) -> Box<RunFailed> {
        let mut f = RunFailed::new(source, vec![report::failure_diagnostic(&e, model)]);
        f.time = e.time();
        f.element = e.culprit().map(|c| c.to_string());
        f.error = Some(e);
        f
    }

    /// An observer's error: the run stopped because its output could not be written.
    fn output(e: io::Error) -> Box<RunFailed> {
        let e = DynError::Output(e.to_string());
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

/// The `--set` values as [`Settings::parse`] read them, or its refusal.
type Parsed = Result<Settings, (String, Vec<Diagnostic>)>;

/// `text` with the `--set` values (`parsed`) applied; a refusal points into the settings,
/// shown as a source named `--set`, one a line.
fn apply_settings(parsed: Parsed, text: String) -> Result<String, Box<RunFailed>> {
    let refused = |t: &str, diagnostics: Vec<Diagnostic>| {
        RunFailed::new(SourceFile::new("--set", t), diagnostics)
    };
    let settings = parsed.map_err(|(t, d)| refused(&t, d))?;
    if settings.is_empty() {
        return Ok(text);
    }
    settings
        .apply(&text)
        .map_err(|d| refused(settings.text(), d))
}

/// A copy of `source` (its name and text) to keep in a failure.
fn copy(source: &SourceFile) -> SourceFile {
    source.duplicate()
}

/// Runs `request`: checks it, reads the command file and the dataset, builds the model,
/// integrates its segments and hands each output row to `observer` (the first at t = 0),
/// with warnings, the built model, the start and the step table as they come (see
/// [`RunObserver`]). When `interrupt` is given, it is asked before every integration step
/// (a relaxed load of a flag, say): once it answers true, the run stops within a step with E0804
/// ([`DynError::Interrupted`]), however far apart the output times are.
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
    for (k, (name, expr)) in request.probes.iter().enumerate() {
        // Each probe is a column of its own: a second `x` (or one named `time`) would
        // leave two columns no reader can tell apart.
        let taken = name == "time" || request.probes[..k].iter().any(|(n, _)| n == name);
        if taken && !name.trim().is_empty() {
            let first = match name.as_str() {
                "time" => "the time column is named time".to_string(),
                _ => format!("another --probe is named {name}"),
            };
            return Err(RunFailed::command_line(Diagnostic::error(
                Code::CommandLine,
                0..0,
                format!("--probe {name}={expr}: {first}; give each probe a name of its own"),
            )));
        }
        if name.trim().is_empty() {
            let written = match name.is_empty() {
                true => expr.clone(),
                false => format!("{name}={expr}"),
            };
            return Err(RunFailed::command_line(Diagnostic::error(
                Code::CommandLine,
                0..0,
                format!("--probe {written}: expected NAME=EXPR, e.g. --probe x=DX(2,1)"),
            )));
        }
    }
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
    let result = match failed {
        None => Ok(RunDone {
            header,
            summary,
            dim_reason,
        }),
        Some(e) => {
            let mut f = match (&e, &commands) {
                // A change to the model that could not be made: at its commands.
                (DynError::Change { at, .. }, Some(c)) => {
                    let d = Diagnostic::error(report::code_of(&e), at.clone(), e.to_string());
                    let mut f = RunFailed::new(copy(&c.source), vec![d]);
                    (f.time, f.error) = (e.time(), Some(e));
                    f
                }
                _ => RunFailed::dynamics(e, source, &sim.read.model),
            };
            (f.header, f.summary) = (Some(header), Some(summary));
            Err(f)
        }
    };
    if let Some(key) = key.filter(|_| keepable) {
        prepared::keep(key, sim);
    }
    result
}

/// Whether `sim`'s expressions read design variable `id` as an input: setting it then
/// needs no new build. (A design variable only a MOTION reads is compiled in, and one
/// nothing reads changes nothing; either way the run builds the edited dataset.)
fn reads_design(sim: &Simulation, id: i64) -> bool {
    sim.designs().iter().any(|&(d, _)| d == id)
}

/// The simulation for `request` on the dataset `text`, its source, whether it may be
/// kept for the next run of `key` ([`prepared`]) and whether it is a kept one. When the settings only give design
/// variables numbers, the simulation kept for `key` runs again with those values, or one
/// is built from `text` as written and given them; otherwise the settings are applied to
/// the text (refusals as E0611) and the edited text is built.
fn simulation_for(
    request: &RunRequest,
    key: Option<&RunRequest>,
    name: String,
    text: String,
    initial: &[ModelChange],
) -> Result<(Simulation, SourceFile, bool, bool), Box<RunFailed>> {
    let parsed = Settings::parse(&request.set);
    let design = parsed.as_ref().ok().filter(|s| s.only_design());
    if let (Some(key), Some(settings)) = (key, design) {
        if let Some(mut sim) = prepared::take(key) {
            match settings.design_values(|id| reads_design(&sim, id)) {
                Some(values) if sim.rewind(&values).is_ok() => {
                    return Ok((sim, SourceFile::new(name, text), true, true));
                }
                // Not design values of this dataset: kept for other runs.
                _ => prepared::keep(key.clone(), sim),
            }
        }
        let source = SourceFile::new(name.clone(), text.clone());
        let mut sim = build(request, &text, &source, initial)?;
        match settings.design_values(|id| reads_design(&sim, id)) {
            Some(values) if values.is_empty() => return Ok((sim, source, true, false)),
            Some(values) if sim.rewind(&values).is_ok() => return Ok((sim, source, true, false)),
            _ => {}
        }
    }
    let text = apply_settings(parsed, text)?;
    let source = SourceFile::new(name, text);
    let sim = build(request, source.text.as_str(), &source, initial)?;
    Ok((sim, source, false, false))
}

/// Reads the dataset at `path`: its name, its text and the warnings of its encoding.
fn read_file(path: &std::path::Path) -> Result<(String, String, Vec<Diagnostic>), Box<RunFailed>> {
    match read_dataset(path) {
        Ok((text, warnings)) => Ok((path.display().to_string(), text, warnings)),
        Err(u) => Err(RunFailed::new(u.source, vec![u.diagnostic])),
    }
}

/// The simulation of `text` (the text of `source`) for `request`, or why it cannot be
/// built: the reader's diagnostics, a probe's, the analysis' (all errors), or a dynamics
/// failure at its element. `initial` are the command file's changes before its first
/// SIMULATE ([`Simulation::with_changes`]).
fn build(
    request: &RunRequest,
    text: &str,
    source: &SourceFile,
    initial: &[ModelChange],
) -> Result<Simulation, Box<RunFailed>> {
    match Simulation::with_changes(text, request.spec(), &request.probes, initial) {
        Ok(sim) => Ok(sim),
        Err(RunFailure::Diagnostics {
            probe: None,
            diagnostics,
        }) => Err(RunFailed::new(copy(source), diagnostics)),
        Err(RunFailure::Diagnostics {
            probe: Some(p),
            diagnostics,
        }) => {
            let expr = request
                .probes
                .iter()
                .find(|(n, _)| *n == p)
                .map_or("", |(_, e)| e.as_str());
            let probe = SourceFile::new(format!("--probe {p}"), expr);
            let mut f = RunFailed::new(probe, diagnostics);
            f.probe = Some(p);
            Err(f)
        }
        Err(RunFailure::Analysis(failure)) => {
            let model = crate::model::read_model(text).model;
            let mut diagnostics = report::diagnostics(&failure, &model);
            for d in &mut diagnostics {
                d.severity = Severity::Error;
            }
            Err(RunFailed::new(copy(source), diagnostics))
        }
        Err(RunFailure::Dynamics(e)) => {
            // Simulation::new kept its model to itself: read it again for the span.
            let model = crate::model::read_model(text).model;
            Err(RunFailed::dynamics(e, copy(source), &model))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mbd::dynamics::integrator::{simulate, Attempt, Integrator, OutputTimes, Settings};
    use crate::mbd::dynamics::Dynamics;
    use crate::session::plan::Plan;
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::Mutex;
    use std::time::{Duration, Instant};

    /// A 1 kg pendulum of length 1 swinging from the horizontal under gravity −y.
    const PENDULUM: &str = "pendulum\nPART/1, GROUND\nMARKER/10, PART = 1\n\
        PART/2, MASS = 1, CM = 20, IP = 1, 1, 1\nMARKER/20, PART = 2, QP = 1, 0, 0\n\
        MARKER/21, PART = 2\nJOINT/1, REVOLUTE, I = 21, J = 10\nACCGRAV/JGRAV = -9.81\nEND\n";

    /// A 1 kg slider on a rail along x, pulled by a SPRINGDAMPER to the origin.
    const OSCILLATOR: &str = "oscillator\nPART/1, GROUND\nMARKER/10, PART = 1\n\
        MARKER/11, PART = 1, REULER = 90D, 90D, 0\n\
        PART/2, MASS = 1, CM = 20, IP = 1, 1, 1, QG = 1.2, 0, 0\n\
        MARKER/20, PART = 2\nMARKER/21, PART = 2, REULER = 90D, 90D, 0\n\
        JOINT/1, TRANSLATIONAL, I = 21, J = 11\n\
        SPRINGDAMPER/1, TRANSLATION, I = 20, J = 10, K = 100, C = 4, LENGTH = 1\nEND\n";

    /// A slider whose SFORCE/1 becomes the square root of a negative number at t = 0.5
    /// (tests/models/failures/nan_in_force.adm).
    const NAN_AT_HALF: &str = "nan\nPART/1, GROUND\nMARKER/101, PART = 1\n\
        MARKER/102, PART = 1, REULER = 90D, 90D, -90D\n\
        PART/2, MASS = 1, CM = 201, IP = 1, 1, 1\nMARKER/201, PART = 2\n\
        MARKER/202, PART = 2, REULER = 90D, 90D, -90D\n\
        JOINT/1, TRANSLATIONAL, I = 102, J = 202\nACCGRAV/KGRAV = -9.80665\n\
        SFORCE/1, TRANSLATIONAL, ACTIONONLY, I = 201, J = 102, \
        FUNCTION = IF(TIME - 0.5: 0, 0, SQRT(-1 - DX(201,101)**2))\nEND\n";

    /// Runs `r`, collecting its rows.
    fn rows_of(r: &RunRequest) -> (Vec<Vec<f64>>, Result<RunDone, Box<RunFailed>>) {
        let mut rows = Vec::new();
        let result = run(
            r,
            &mut |row: &[f64]| -> io::Result<()> {
                rows.push(row.to_vec());
                Ok(())
            },
            None,
        );
        (rows, result)
    }

    /// The failure of `r`, which must fail before running.
    fn refusal(r: &RunRequest) -> Box<RunFailed> {
        let (rows, result) = rows_of(r);
        assert!(rows.is_empty());
        match result {
            Ok(_) => panic!("the request is refused"),
            Err(f) => f,
        }
    }

    #[test]
    fn the_defaults_are_mbfx_runs() {
        let mut r = RunRequest::dataset("pendulum.adm", PENDULUM);
        r.end = Some(2.0);
        let (rows, result) = rows_of(&r);
        let done = result.expect("the pendulum runs");
        // A row every END/100, the last exactly at END; GSTIFF without an INTEGRATOR.
        assert_eq!(rows.len(), 101);
        for (k, row) in rows.iter().enumerate() {
            assert!(
                (row[0] - k as f64 * 0.02).abs() < 1e-12,
                "row {k}: {}",
                row[0]
            );
        }
        assert_eq!(rows[100][0], 2.0);
        assert_eq!(done.header, ["time"]);
        assert_eq!(done.summary.integrator, "gstiff");
        assert!(done.dim_reason.starts_with("2D"), "{}", done.dim_reason);
        // The dataset's INTEGRATOR when the request names none; the request's over it.
        let hht = PENDULUM.replace("END\n", "INTEGRATOR/HHT\nEND\n");
        r.input = Input::Dataset {
            name: "hht.adm".into(),
            text: hht,
        };
        assert_eq!(rows_of(&r).1.expect("runs").summary.integrator, "hht");
        r.method = Some(Method::Wstiff);
        assert_eq!(rows_of(&r).1.expect("runs").summary.integrator, "wstiff");
    }

    #[test]
    fn a_command_file_gives_the_segments_and_its_note() {
        let dir = std::env::temp_dir().join(format!("mbfx-request-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("scratch folder");
        std::fs::write(dir.join("pendulum.adm"), PENDULUM).expect("write");
        let acf = dir.join("swing.acf");
        std::fs::write(&acf, "pendulum\nswing_out\nsim/dyn, end=0.5, dtout=0.1\n").expect("write");
        let (rows, result) = rows_of(&RunRequest::file(&acf));
        let done = result.expect("the command file runs");
        let times: Vec<f64> = rows.iter().map(|r| r[0]).collect();
        assert_eq!(times.len(), 6, "{times:?}");
        assert!(done
            .summary
            .notes
            .iter()
            .any(|n| n.contains("swing_out.req")));
        // The request's end replaces the SIMULATE commands (the first DTOUT kept).
        let mut r = RunRequest::file(&acf);
        r.end = Some(0.3);
        let (rows, result) = rows_of(&r);
        assert!(result.is_ok());
        assert_eq!(rows.len(), 4);
        // Without SIMULATE, the command file needs an end time.
        std::fs::write(&acf, "pendulum\nswing_out\n").expect("write");
        let f = refusal(&RunRequest::file(&acf));
        assert_eq!(
            (f.code, f.cause.as_str()),
            (Code::MissingArgument, acf::NO_SIMULATION)
        );
        assert_eq!(f.source.name, acf.display().to_string());
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn arguments_are_refused_with_the_command_lines_messages() {
        let base = || {
            let mut r = RunRequest::dataset("pendulum.adm", PENDULUM);
            r.end = Some(1.0);
            r
        };
        type Change = fn(&mut RunRequest);
        let cases: [(Change, &str); 11] = [
            (|r| r.end = Some(-1.0), "--end -1 must be a positive time"),
            (|r| r.end = Some(f64::NAN), "--end NaN must be a positive time"),
            (|r| r.hmax = Some(0.0), "--hmax 0 must be a positive number"),
            (|r| r.alpha = Some(0.5), "--alpha 0.5 must lie in [-1/3, 0]"),
            (|r| r.rho_inf = Some(2.0), "--rho-inf 2 must lie in [0, 1]"),
            (|r| r.kmax = Some(7), "--kmax 7 must be an order from 1 to 6"),
            (
                |r| (r.end, r.output_step) = (Some(1e9), Some(1e-9)),
                "--output-step 1e-9 over --end 1e9 makes 1.000e18 rows: times that close cannot be told apart (at most 4.504e15 rows); take a longer step",
            ),
            (
                |r| r.end = None,
                "--end is required to run a dataset (pendulum.adm); a command file (.acf) may give it instead, and --statics alone needs none",
            ),
            (
                |r| r.probes.push(parse_probe("DX(20)")),
                "--probe DX(20): expected NAME=EXPR, e.g. --probe x=DX(2,1)",
            ),
            (
                |r| {
                    r.probes.push(parse_probe("x=DX(20)"));
                    r.probes.push(parse_probe("x=DY(20)"));
                },
                "--probe x=DY(20): another --probe is named x; give each probe a name of its own",
            ),
            (
                |r| r.probes.push(parse_probe("time=TIME")),
                "--probe time=TIME: the time column is named time; give each probe a name of its own",
            ),
        ];
        for (change, message) in cases {
            let mut r = base();
            change(&mut r);
            let f = refusal(&r);
            assert_eq!((f.code, f.cause.as_str()), (Code::CommandLine, message));
            assert_eq!(f.source.name, COMMAND_LINE);
            assert!(f.header.is_none() && f.summary.is_none());
        }
        // A probe that does not compile points into its own text.
        let mut r = base();
        r.probes.push(("p".into(), "DX(20) + NOPE(1)".into()));
        let f = refusal(&r);
        assert_eq!(f.code, Code::UnknownFunction);
        assert_eq!(
            (f.source.name.as_str(), f.probe.as_deref()),
            ("--probe p", Some("p"))
        );
        assert_eq!(&f.source.text[f.diagnostics[0].span.clone()], "NOPE");
    }

    #[test]
    fn probes_split_at_the_first_equals_sign() {
        assert_eq!(parse_probe(" x = DX(2)=1"), ("x".into(), " DX(2)=1".into()));
        assert_eq!(parse_probe(" =DX(2)"), (String::new(), " =DX(2)".into()));
        assert_eq!(parse_probe("DX(2)"), (String::new(), "DX(2)".into()));
    }

    /// The oscillator with its stiffness as design variable 1 in an SFORCE.
    fn design_oscillator() -> String {
        OSCILLATOR.replace(
            "SPRINGDAMPER/1, TRANSLATION, I = 20, J = 10, K = 100, C = 4, LENGTH = 1",
            "VARIABLE/1, FUNCTION = 100\n\
                 SFORCE/1, TRANSLATION, I = 20, J = 10, FUNCTION = -VARVAL(1)*(DM(20, 10) - 1)",
        )
    }

    fn reused(result: &Result<RunDone, Box<RunFailed>>) -> bool {
        result.as_ref().expect("the run").summary.reused
    }

    #[test]
    fn a_run_again_reuses_the_simulation_and_gives_its_bits() {
        prepared::forget();
        let mut r = RunRequest::dataset("osc", design_oscillator());
        r.end = Some(1.0);
        r.probes = vec![("x".into(), "DX(20, 10)".into())];
        let (first, done) = rows_of(&r);
        assert!(!reused(&done));
        let (again, done) = rows_of(&r);
        assert!(reused(&done));
        assert_eq!(first, again);
        // A design variable's number: the kept simulation, with the bits of the edited
        // dataset built afresh.
        r.set = vec!["VARIABLE/1.FUN=400".into()];
        let (stiff, done) = rows_of(&r);
        assert!(reused(&done));
        prepared::forget();
        let mut edited = r.clone();
        edited.set.clear();
        edited.input = Input::Dataset {
            name: "osc".into(),
            text: design_oscillator().replace("FUNCTION = 100", "FUNCTION = 400"),
        };
        let (fresh, done) = rows_of(&edited);
        assert!(!reused(&done));
        assert_eq!(stiff, fresh);
        assert_ne!(stiff, first);
        // Any other setting or dataset builds again, and leaves the kept one alone.
        prepared::forget();
        r.set = vec!["VARIABLE/1.FUNCTION=-2.5E2".into()];
        assert!(!reused(&rows_of(&r).1));
        r.set = vec!["PART/2.MASS=2".into()];
        assert!(!reused(&rows_of(&r).1));
        r.set = vec!["VARIABLE/1.FUNCTION=250".into()];
        let (softer, done) = rows_of(&r);
        assert!(reused(&done));
        assert_ne!(softer, first);
        r.set = vec!["VARIABLE/1.FUNCTION=2*PI".into()];
        assert!(!reused(&rows_of(&r).1));
        r.set.clear();
        r.end = Some(0.5);
        assert!(!reused(&rows_of(&r).1));
    }

    #[test]
    fn a_failure_keeps_its_rows_and_names_time_element_and_code() {
        let mut r = RunRequest::dataset("nan.adm", NAN_AT_HALF);
        (r.end, r.output_step, r.fixed_step) = (Some(1.0), Some(0.01), Some(1e-3));
        r.dim = DimRequest::Three;
        r.probes.push(("x".into(), "DX(201,101)".into()));
        let (rows, result) = rows_of(&r);
        let Err(f) = result else {
            panic!("the force becomes NaN")
        };
        assert_eq!(f.code, Code::NonFiniteForce);
        let t = f.time.unwrap_or_else(|| panic!("a time: {f:?}"));
        assert!((0.5..=0.51).contains(&t), "failed at {t}");
        assert!(
            f.element
                .as_deref()
                .is_some_and(|e| e.starts_with("SFORCE/1")),
            "{:?}",
            f.element
        );
        assert!(f.cause.contains(&format!("at time {t}")), "{}", f.cause);
        let span = f.diagnostics[0].span.clone();
        assert!(f.source.text[span].starts_with("SFORCE/1"));
        assert_eq!(f.source.name, "nan.adm");
        // Every row before the failure was handed out, on the grid, and the summary kept.
        assert_eq!(
            f.header.as_deref(),
            Some(&["time".to_string(), "x".into()][..])
        );
        assert_eq!(rows.len(), 51);
        assert!(rows
            .iter()
            .enumerate()
            .all(|(k, r)| (r[0] - k as f64 * 0.01).abs() < 1e-12));
        let summary = f.summary.as_ref().expect("a summary");
        assert!(summary.stats.steps >= 500);
        assert!(f.to_string().starts_with("[E0803] SFORCE/1: "), "{f}");
    }

    /// Delegates to `inner`, setting `flag` at its `at`-th accepted step.
    struct Tripwire<'a> {
        inner: Box<dyn Integrator>,
        flag: &'a AtomicBool,
        at: usize,
        accepted: usize,
    }

    impl Integrator for Tripwire<'_> {
        fn name(&self) -> &'static str {
            self.inner.name()
        }
        fn error_order(&self) -> f64 {
            self.inner.error_order()
        }
        fn order(&self) -> Option<u32> {
            self.inner.order()
        }
        fn max_growth(&self) -> f64 {
            self.inner.max_growth()
        }
        fn monitored_error(&self, err: f64) -> f64 {
            self.inner.monitored_error(err)
        }
        fn formulation(&self) -> Option<String> {
            self.inner.formulation()
        }
        fn step_factor(&self) -> Option<f64> {
            self.inner.step_factor()
        }
        fn first_step(&self, d: &Dynamics, hinit: f64, s: &Settings) -> f64 {
            self.inner.first_step(d, hinit, s)
        }
        fn restart(&mut self, d: &mut Dynamics) {
            self.inner.restart(d)
        }
        fn start(&mut self, d: &mut Dynamics) -> Result<(), DynError> {
            self.inner.start(d)
        }
        fn attempt(&mut self, d: &mut Dynamics, h: f64, s: &Settings) -> Result<Attempt, DynError> {
            self.inner.attempt(d, h, s)
        }
        fn accept(&mut self, d: &mut Dynamics) {
            self.inner.accept(d);
            self.accepted += 1;
            if self.accepted == self.at {
                self.flag.store(true, Ordering::Relaxed);
            }
        }
        fn reject(&mut self, d: &mut Dynamics) {
            self.inner.reject(d)
        }
    }

    #[test]
    fn the_interrupt_is_read_before_every_step() {
        // One output time at the end: a check at output times only would run to it.
        let spec = RunSpec::new(10.0, 10.0);
        let Ok(mut sim) = Simulation::new(OSCILLATOR, spec.clone(), &[]) else {
            panic!("the oscillator builds")
        };
        sim.dynamics
            .solve_accelerations()
            .expect("consistent at t = 0");
        let plan = Plan::new(None, &spec, 10.0);
        let flag = AtomicBool::new(false);
        let mut tripwire = Tripwire {
            inner: plan.integrator().0,
            flag: &flag,
            at: 7,
            accepted: 0,
        };
        let d = &mut sim.dynamics;
        let stopped = simulate(
            d,
            &mut tripwire,
            &plan.settings,
            &OutputTimes::new(0.0, 10.0, 10.0),
            &mut |_, _| Ok(()),
            Some(&|| flag.load(Ordering::Relaxed)),
        );
        assert_eq!(stopped, Err(DynError::Interrupted { time: d.sys.time }));
        assert_eq!(d.stats.steps, 7);
        assert!(d.sys.time > 0.0 && d.sys.time < 10.0);
    }

    #[test]
    fn an_interrupt_from_another_thread_stops_a_run_promptly() {
        // Ten million fixed steps and no output between the first row and the last.
        let mut r = RunRequest::dataset("oscillator.adm", OSCILLATOR);
        (r.end, r.output_step, r.fixed_step) = (Some(100.0), Some(100.0), Some(1e-5));
        r.method = Some(Method::Hht);
        let (flag, started) = (AtomicBool::new(false), AtomicBool::new(false));
        let set_at: Mutex<Option<Instant>> = Mutex::new(None);
        let mut rows = Vec::new();
        let (result, returned) = std::thread::scope(|s| {
            s.spawn(|| {
                while !started.load(Ordering::Acquire) {
                    std::thread::sleep(Duration::from_millis(1));
                }
                std::thread::sleep(Duration::from_millis(50));
                flag.store(true, Ordering::Relaxed);
                *set_at.lock().expect("lock") = Some(Instant::now());
            });
            let mut sink = |row: &[f64]| -> io::Result<()> {
                rows.push(row.to_vec());
                started.store(true, Ordering::Release);
                Ok(())
            };
            let result = run(&r, &mut sink, Some(&|| flag.load(Ordering::Relaxed)));
            (result, Instant::now())
        });
        let Err(f) = result else {
            panic!("the run is interrupted")
        };
        let set_at = set_at.lock().expect("lock").expect("the flag was set");
        let took = returned.saturating_duration_since(set_at);
        assert!(
            took < Duration::from_millis(100),
            "stopped {took:?} after the flag"
        );
        assert_eq!(f.code, Code::Interrupted);
        assert!(matches!(f.error, Some(DynError::Interrupted { .. })));
        let t = f.time.expect("a time");
        assert!(t > 0.0 && t < 100.0, "stopped at {t}");
        // The row at t = 0 was delivered, the summary counts the steps taken.
        assert_eq!(rows.len(), 1);
        let steps = f.summary.as_ref().expect("a summary").stats.steps;
        assert!(
            (t / 1e-5 - steps as f64).abs() < 2.0,
            "{steps} steps to {t}"
        );
    }
}
