//! What a run is asked to do: the engine and integrator, the stretches (segments) it
//! runs, its settings ([`RunSpec`]), and the step table's row.

use crate::model::command_changes::ModelChange;
use crate::model::commands::Analysis;
use crate::model::equilibrium_settings::EquilibriumStatement;
use crate::model::integrator_settings::{Formulation, IntegratorStatement};
use crate::model::linear_command::Linear;
use crate::session::DimRequest;

/// Which back end evaluates the model's expressions.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Engine {
    /// Cranelift JIT.
    #[default]
    Jit,
    /// The interpreter.
    Interp,
}

/// The integrators `mbfx run --integrator` names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Adams HHT (ALPHA, default −0.3).
    Hht,
    /// Generalized-α with ρ∞ (default 0.9, as Exudyn).
    Galpha,
    /// Plain Newmark with the INTEGRATOR statement's BETA and GAMMA (default 0.36, 0.7).
    Newmark,
    /// Adams GSTIFF: variable-order BDF with a fixed leading coefficient.
    Gstiff,
    /// Adams WSTIFF: variable-order BDF with variable coefficients.
    Wstiff,
    /// Explicit Dormand–Prince 8(5,3) on the index-1 equations, with projection.
    Dopri853,
}

/// One stretch of a run (a `SIMULATE` command of a command file): from where the last
/// one stopped to `end`, a row every `output_step` from its start and one at `end`,
/// under the INTEGRATOR statement `integrator` (None: Adams' defaults). A static
/// stretch ending where it starts is one equilibrium.
#[derive(Clone, Debug)]
pub struct Segment {
    /// Where the stretch stops.
    pub end: f64,
    /// Time between output rows.
    pub output_step: f64,
    /// The INTEGRATOR statement in force (None: Adams' defaults).
    pub integrator: Option<IntegratorStatement>,
    /// Dynamics, statics or kinematics.
    pub kind: Analysis,
    /// The EQUILIBRIUM statement in force for a static stretch (None: Adams' defaults).
    pub equilibrium: Option<EquilibriumStatement>,
    /// What a linear analysis asks for (kind [`Analysis::Linear`]).
    pub linear: Option<Box<Linear>>,
    /// The command file's changes to the model to make before the stretch, in order.
    pub changes: Vec<ModelChange>,
}

impl Segment {
    /// A stretch of dynamics to `end`, a row every `output_step`.
    pub fn dynamic(end: f64, output_step: f64, integrator: Option<IntegratorStatement>) -> Segment {
        Segment {
            end,
            output_step,
            integrator,
            kind: Analysis::Dynamic,
            equilibrium: None,
            linear: None,
            changes: Vec::new(),
        }
    }

    /// A linear analysis `command` at time `at`.
    pub fn linear(at: f64, command: Linear) -> Segment {
        Segment {
            kind: Analysis::Linear,
            linear: Some(Box::new(command)),
            ..Segment::dynamic(at, 0.0, None)
        }
    }
}

/// One line of the step table `mbfx run --verbose` prints at each output time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TableRow {
    /// Simulation time of the row.
    pub time: f64,
    /// The last accepted step (0 before the first).
    pub step: f64,
    /// Accepted steps so far.
    pub steps: usize,
    /// Corrector iterations so far.
    pub newton_iterations: usize,
    /// The integrator's order on its last step, when it has one.
    pub order: Option<u32>,
    /// Seconds spent integrating so far (wall clock).
    pub cpu_seconds: f64,
}

/// What to run.
#[derive(Clone, Debug)]
pub struct RunSpec {
    /// Where the run stops.
    pub end: f64,
    /// Time between output rows.
    pub output_step: f64,
    /// None: the dataset's INTEGRATOR statement, else GSTIFF (as Adams).
    pub method: Option<Method>,
    /// ERROR: the local error tolerance (None: the dataset's, else the method's default).
    pub error: Option<f64>,
    /// HMAX: the largest step.
    pub hmax: Option<f64>,
    /// HINIT: the first step.
    pub hinit: Option<f64>,
    /// HMIN: the smallest step.
    pub hmin: Option<f64>,
    /// A fixed step instead of error control.
    pub fixed_step: Option<f64>,
    /// HHT's ALPHA.
    pub alpha: Option<f64>,
    /// Generalized-α's ρ∞.
    pub rho_inf: Option<f64>,
    /// The BDF formulation (None: the INTEGRATOR statement's, else I3).
    pub formulation: Option<Formulation>,
    /// The highest BDF order (None: the INTEGRATOR statement's KMAX, else 6).
    pub kmax: Option<u32>,
    /// ERROR bounds the whole run's error instead of each step's (see
    /// [`crate::mbd::dynamics::integrator::Settings::error_per_run`]).
    pub error_per_run: bool,
    /// Keep the rows the redundancy analysis finds redundant in the equations of motion
    /// (a measurement of what dropping them is worth: the Newton matrix is singular).
    pub keep_redundant: bool,
    /// dopri853 keeps to the Cartesian index-1 form even on a planar tree of joints,
    /// which it otherwise integrates in joint coordinates.
    pub cartesian: bool,
    /// Output rows from each method's continuous extension, the steps left to error
    /// control (INTERPOLATE = ON); false leaves it to the INTEGRATOR statement (off
    /// unless it says ON).
    pub interpolate: bool,
    /// 2D, 3D or whichever the scene allows.
    pub dim: DimRequest,
    /// Which back end evaluates the expressions.
    pub engine: Engine,
    /// `--geometry GRAPHICS/ID=FILE`: the mesh of an EXTERNAL CONTACT geometry (one
    /// without a file gets its part's placeholder box).
    pub geometry: Vec<(u32, std::path::PathBuf)>,
    /// Estimate the answer's error from a second run at a looser ERROR
    /// (`--estimate-error`, [`super::Estimate`]) and warn when it exceeds 10·ERROR.
    pub estimate_error: bool,
    /// Carry an estimate of the global error through the steps, by the method's own
    /// linearization (`--estimate-error=steps`; the BDFs carry one, the other methods
    /// none yet): the summary's "estimated error" and its warning past
    /// 10·ERROR.
    pub carry_error: bool,
}

impl RunSpec {
    /// A run to `end` with a row every `output_step`, every setting left to the dataset or the defaults.
    pub fn new(end: f64, output_step: f64) -> RunSpec {
        RunSpec {
            end,
            output_step,
            method: None,
            error: None,
            hmax: None,
            hinit: None,
            hmin: None,
            fixed_step: None,
            alpha: None,
            rho_inf: None,
            formulation: None,
            kmax: None,
            error_per_run: false,
            keep_redundant: false,
            cartesian: false,
            interpolate: false,
            dim: DimRequest::Auto,
            engine: Engine::Jit,
            estimate_error: false,
            carry_error: false,
            geometry: Vec::new(),
        }
    }
}
