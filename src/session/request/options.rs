//! What a run is asked: the [`RunRequest`] with `mbfx run`'s defaults and its checks,
//! the linear analysis and formulation it may ask for, the probes' `NAME=EXPR`, and the
//! segments changed as `--statics`, `--kinematics` and `--linear` ask.

use crate::diag::{Code, Diagnostic};
use crate::model::linear_command::Linear;
use crate::session::run::{Engine, Method, RunSpec, Segment};
use crate::session::DimRequest;
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
    /// exceeds 10·ERROR (`--estimate-error`, [`crate::session::run::Estimate`]).
    pub estimate_error: bool,
    /// Carry a global error estimate through the steps (`--estimate-error=steps`).
    pub carry_error: bool,
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
    /// Record the run's animation (`--animate`): frames, glyphs, meshes for EXTERNAL
    /// graphics ([`crate::session::animation`]); the rows are the same with or without.
    pub animation: Option<crate::session::animation::AnimationRequest>,
    /// Meshes for EXTERNAL graphics (`--geometry GRAPHICS/ID=FILE`): the geometry of the
    /// CONTACTs that name them, with or without an animation (one it records draws them
    /// too).
    pub geometry: Vec<(u32, PathBuf)>,
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
    pub(super) fn command(&self) -> Linear {
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
            carry_error: false,
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
            animation: None,
            geometry: Vec::new(),
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
            ("--interpolate", self.animation.as_ref().and_then(|a| a.fps)),
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

    /// The probes' names checked, as `mbfx run` checks them before reading the dataset:
    /// each names a column of its own (not `time`, not another's), and none is blank. The
    /// first one wrong is an E0503 error.
    pub(super) fn check_probes(&self) -> Result<(), Diagnostic> {
        for (k, (name, expr)) in self.probes.iter().enumerate() {
            // Each probe is a column of its own: a second `x` (or one named `time`) would
            // leave two columns no reader can tell apart.
            let taken = name == "time" || self.probes[..k].iter().any(|(n, _)| n == name);
            if taken && !name.trim().is_empty() {
                let first = match name.as_str() {
                    "time" => "the time column is named time".to_string(),
                    _ => format!("another --probe is named {name}"),
                };
                return Err(Diagnostic::error(
                    Code::CommandLine,
                    0..0,
                    format!("--probe {name}={expr}: {first}; give each probe a name of its own"),
                ));
            }
            if name.trim().is_empty() {
                let written = match name.is_empty() {
                    true => expr.clone(),
                    false => format!("{name}={expr}"),
                };
                return Err(Diagnostic::error(
                    Code::CommandLine,
                    0..0,
                    format!("--probe {written}: expected NAME=EXPR, e.g. --probe x=DX(2,1)"),
                ));
            }
        }
        Ok(())
    }

    /// The name messages give the input.
    pub(super) fn input_name(&self) -> String {
        match &self.input {
            Input::Path(p) => p.display().to_string(),
            Input::Dataset { name, .. } => name.clone(),
        }
    }

    /// The simulation's settings (its end and output step are the segments').
    pub(super) fn spec(&self) -> RunSpec {
        // Replaced by the segments' own end and output step.
        let mut spec = RunSpec::new(self.end.unwrap_or(1.0), self.output_step.unwrap_or(1.0));
        spec.method = self.method;
        spec.kmax = self.kmax;
        spec.error_per_run = self.error_per_run;
        spec.cartesian = self.cartesian;
        spec.interpolate = self.interpolate;
        spec.estimate_error = self.estimate_error;
        spec.carry_error = self.carry_error;
        // The request's meshes, then any the animation alone was given (a caller that
        // set only the animation's): the contacts use the same files the drawing does.
        spec.geometry.clone_from(&self.geometry);
        for (id, file) in self.animation.iter().flat_map(|a| &a.geometry) {
            if !spec.geometry.iter().any(|(g, _)| g == id) {
                spec.geometry.push((*id, file.clone()));
            }
        }
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
pub(super) fn asked_analyses(
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
pub(super) const MAX_ROWS: f64 = 4_503_599_627_370_496.0;

/// `NAME=EXPR` (`--probe`) as (name, expression): split at the first `=`, the name
/// trimmed. Text without `=`, or with a blank name, comes back whole as ("", text), which
/// [`run`](super::run) refuses with E0503 quoting it.
pub fn parse_probe(text: &str) -> (String, String) {
    match text.split_once('=') {
        Some((n, e)) if !n.trim().is_empty() => (n.trim().to_string(), e.to_string()),
        _ => (String::new(), text.to_string()),
    }
}
