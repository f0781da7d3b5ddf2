//! A dynamic simulation of a dataset, the library side of `mbfx run`: read and assemble
//! the model ([`super::analyze_model`]), build its forces and the equations of motion,
//! solve consistent accelerations at t = 0, then integrate to the end time, producing one
//! row of output columns at every output time. The columns are the `--probe`
//! expressions, then each REQUEST's components (`REQ<id>.F<k>`, k = 1..8), all compiled
//! in one batch by the chosen engine; interpreter and JIT give the same bits.

use super::lifted::Lifted;
use super::plan::Plan;
use super::plant::Plant;
use super::{analyze_model_with, DimRequest, Failure};
use crate::check::{Expect, Variables};
use crate::diag::{Code, Diagnostic};
use crate::ir::Function;
use crate::mbd::dynamics::integrator::{simulate, Interrupt, OutputTimes, RowState};
use crate::mbd::dynamics::{DynError, Dynamics, Stats};
use crate::mbd::error::MbdError;
use crate::mbd::expr::ExprCompiler as _;
use crate::mbd::expr::FusedFn;
use crate::mbd::output_slot::OutputSlot;
use crate::mbd::rewind::StartState;
use crate::model::command_changes::ModelChange;
use crate::model::commands::Analysis;
use crate::model::elements::{Expr, RequestKind};
use crate::model::equilibrium_settings::EquilibriumStatement;
use crate::model::integrator_settings::{Formulation, IntegratorStatement};
use crate::model::linear_command::Linear;
use crate::model::{read_model, ModelRead};
use std::time::Instant;

mod estimate;
mod rebuild;

pub use estimate::Estimate;

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
    /// Estimate the answer's error from a second run at a looser ERROR
    /// (`--estimate-error`, [`Estimate`]) and warn when it exceeds 10·ERROR.
    pub estimate_error: bool,
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
        }
    }
}

/// Where a run stopped before integrating.
pub enum RunFailure {
    /// The dataset (or a probe) has errors; the diagnostics say where. `probe` names the
    /// probe whose text the spans point into.
    Diagnostics {
        /// The probe whose text the spans point into (None: the dataset).
        probe: Option<String>,
        /// The diagnostics, errors and warnings.
        diagnostics: Vec<Diagnostic>,
    },
    /// Reading went well; building, assembly or the redundancy analysis did not.
    Analysis(Failure),
    /// The model cannot be simulated (a force element, a massless part, t = 0 state).
    Dynamics(DynError),
}

impl From<DynError> for RunFailure {
    fn from(e: DynError) -> Self {
        RunFailure::Dynamics(e)
    }
}

impl From<MbdError> for RunFailure {
    fn from(e: MbdError) -> Self {
        RunFailure::Dynamics(DynError::Model(e))
    }
}

/// One output column: its header and its expression.
struct Column {
    name: String,
    function: Function,
    /// The expression as written, its VARIABLEs not inlined (a command file that gives
    /// a VARIABLE a new expression inlines it again).
    source: Expr,
}

/// The summary `mbfx run` prints.
#[derive(Clone, Debug)]
pub struct Summary {
    /// The integrator's name.
    pub integrator: &'static str,
    /// Counters of the whole run.
    pub stats: Stats,
    /// Seconds spent integrating (wall clock).
    pub cpu_seconds: f64,
    /// Largest scaled residual of the kept constraint rows at the output times.
    pub max_residual: f64,
    /// Kinetic plus gravitational energy at the start and the end, when the model has
    /// no other forces and no drives (None otherwise).
    pub energy: Option<(f64, f64)>,
    /// Notes for the user (settings not honoured, substitutions).
    pub notes: Vec<String>,
    /// Why the run was 2D or 3D, in words.
    pub dim: String,
    /// What the run's own monitors say went wrong although it reached its end (fixed
    /// steps whose local error estimate left ERROR far behind, constraint drift), after
    /// the physics the model leaves out ([`crate::model::report::not_modelled`], added by
    /// [`super::request::run`]): a run that reports success on a wrong answer must at
    /// least say so.
    pub warnings: Vec<String>,
    /// The run reused the simulation of an earlier run on this thread (nothing was read,
    /// built or compiled: [`super::prepared`]).
    pub reused: bool,
    /// The static equilibria it found, in order.
    pub equilibria: Vec<crate::mbd::statics::Report>,
    /// The linear analyses it ran, in order.
    pub linear: Vec<super::linear::LinearReport>,
    /// The global error estimate, when one was asked for and made.
    pub estimate: Option<Estimate>,
}

impl Summary {
    /// The end-of-run summary `mbfx run` prints (and Python's `Run.summary` holds).
    pub fn text(&self) -> String {
        let s = self;
        let st = &s.stats;
        let mut out = format!(
            "{}: {} steps ({} rejected), {} Newton iterations, {} Jacobian evaluations, {} factorizations, {} expression evaluations, {:.6} s CPU{}\nlargest constraint residual {:.3e}\n",
            s.integrator,
            st.steps,
            st.rejected,
            st.newton_iterations,
            st.jacobian_evaluations,
            st.factorizations,
            st.expression_evaluations,
            s.cpu_seconds,
            // Runs with contact switches say how many were located; others print as before.
            match st.events {
                0 => String::new(),
                n => format!(", {n} force switches located"),
            },
            s.max_residual
        );
        if st.interpolated > 0 {
            out += &format!(
                "{} rows interpolated inside steps (largest position-constraint residual there {:.3e}, {} projected)\n",
                st.interpolated, st.interpolation_residual, st.projected
            );
        }
        if let Some((e0, e1)) = s.energy {
            out += &format!(
                "energy (kinetic + gravity): {e0:.9e} at the start, {e1:.9e} at the end (change {:.3e})\n",
                e1 - e0
            );
        }
        out += &equilibria_text(&s.equilibria);
        for l in &s.linear {
            out += &l.text();
        }
        if let Some(e) = &s.estimate {
            // Three digits whatever the size: an accurate run's estimate is often far
            // below one ERROR.
            let g = |x: f64| match x {
                x if x == 0.0 || (1e-2..1e5).contains(&x) => format!("{x:.3}"),
                x => format!("{x:.2e}"),
            };
            out += &format!(
                "error estimate: {}×ERROR (a second run at {}×ERROR, {:.6} s CPU, differs by {}×ERROR)\n",
                g(e.error),
                e.ratio,
                e.cpu_seconds,
                g(e.difference)
            );
        }
        for n in &s.notes {
            out += &format!("note: {n}\n");
        }
        for w in &s.warnings {
            out += &format!("warning: {w}\n");
        }
        out
    }
}

/// The summary's lines about the equilibria: each in full when there are at most
/// three; else their count, iterations and largest imbalance, and the last in full.
fn equilibria_text(reports: &[crate::mbd::statics::Report]) -> String {
    match reports {
        [] => String::new(),
        few if few.len() <= 3 => few.iter().map(|r| r.text()).collect(),
        [.., last] => {
            let iterations: usize = reports.iter().map(|r| r.iterations).sum();
            let worst = reports.iter().map(|r| r.imbalance).fold(0.0, f64::max);
            format!(
                "{} static equilibria (quasi-static): {iterations} Newton iterations, largest imbalance {worst:.3e}; the last:\n{}",
                reports.len(),
                last.text()
            )
        }
    }
}

/// The output columns compiled, and the measure slots they read.
struct Outputs {
    columns: Vec<Column>,
    /// None: the slot reads an element the command file switched off (it holds 0).
    slots: Vec<(u32, Option<OutputSlot>)>,
    /// Some column reads velocities, accelerations or forces: each row reconciles.
    reconcile: bool,
    /// Every column's value from one call ([`crate::ir::fuse`]), the slots filled once.
    code: Option<Box<dyn FusedFn>>,
    measures: Vec<f64>,
    /// The compiler all of the model's expressions went through.
    exprs: crate::mbd::compiled::CompiledExprs,
    /// A 2D run's 3D shadow for the reactions ([`Lifted`]).
    lifted: Option<Lifted>,
    /// The last row (time, then the columns), kept to be filled again.
    row: Vec<f64>,
}

/// A 2D run's reactions come from a 3D shadow, which holds the out-of-plane loads: the
/// shadow of `dynamics` (built from `model`) for the reaction slots among `slots`, when
/// the run is 2D and reads any (a note says why when it cannot be built).
fn shadow(
    model: &crate::model::Model,
    exprs: &crate::mbd::compiled::CompiledExprs,
    dynamics: &Dynamics,
    slots: &[(u32, Option<OutputSlot>)],
    notes: &mut Vec<String>,
) -> Option<Lifted> {
    let reactions: Vec<u32> = slots
        .iter()
        .filter(|(_, o)| o.is_some_and(|o| o.reads_reaction()))
        .map(|&(s, _)| s)
        .collect();
    if dynamics.sys.dim != crate::mbd::Dimension::Two || reactions.is_empty() {
        return None;
    }
    match Lifted::new(model, exprs, dynamics, &reactions) {
        Ok(l) => Some(l),
        Err(why) => {
            let note = format!(
                "out-of-plane reaction components are left at 0: the 3D system that gives them cannot be built ({why})"
            );
            if !notes.contains(&note) {
                notes.push(note);
            }
            None
        }
    }
}

/// Whether an output slot reads velocities, accelerations or forces: each row then
/// reconciles.
fn reads_reconciled(slots: &[(u32, Option<OutputSlot>)], dynamics: &Dynamics) -> bool {
    slots
        .iter()
        .any(|(_, s)| s.is_some_and(|s| s.reads_reconciled(&dynamics.sys)))
}

/// Why [`Simulation::rewind`] refused.
#[derive(Debug)]
pub enum RewindError {
    /// A constraint reads this design variable.
    ConstraintReads(i64),
    /// The dynamics could not be made again.
    Dynamics(DynError),
    /// A command file changed the model during the last run: its start is another
    /// system's, so a new build is needed.
    ModelChanged,
}

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
    /// The dataset's plant inputs and outputs, for LINEAR/STATEMAT.
    plant: Plant,
    /// The parts' poses at each integrated row, while a run records them for its error
    /// estimate ([`estimate`]).
    trace: Option<Vec<Vec<f64>>>,
}

/// The expression text of component k (1..8) of a standard REQUEST, if it has one.
fn standard_component(kind: RequestKind, i: u32, j: u32, rm: u32, k: usize) -> Option<String> {
    let (mag, vec, amag, avec) = match kind {
        RequestKind::Displacement => ("DM", "D", None, None),
        RequestKind::Velocity => ("VM", "V", Some("WM"), Some("W")),
        RequestKind::Acceleration => ("ACCM", "ACC", Some("WDTM"), Some("WDT")),
        RequestKind::Force => ("FM", "F", Some("TM"), Some("T")),
    };
    let xyz = ["X", "Y", "Z"];
    Some(match k {
        1 => format!("{mag}({i},{j})"),
        2..=4 => format!("{vec}{}({i},{j},{rm})", xyz[k - 2]),
        5 => format!("{}({i},{j})", amag?),
        6..=8 => match avec {
            Some(w) => format!("{w}{}({i},{j},{rm})", xyz[k - 6]),
            None => format!("{}({i},{j})", ["PSI", "THETA", "PHI"][k - 6]),
        },
        _ => return None,
    })
}

impl Simulation {
    /// Reads, assembles and prepares `text` for `spec`, with `probes` as (name,
    /// expression) columns.
    pub fn new(
        text: &str,
        spec: RunSpec,
        probes: &[(String, String)],
    ) -> Result<Simulation, RunFailure> {
        Self::with_changes(text, spec, probes, &[])
    }

    /// [`Simulation::new`] for a command file whose changes `initial`, written before
    /// its first SIMULATE, make the model the run starts from (Adams View writes the
    /// elements switched off in a model as DEACTIVATE commands there). A change that does
    /// not resolve is left out here; [`Simulation::check_changes`] reports it.
    pub fn with_changes(
        text: &str,
        spec: RunSpec,
        probes: &[(String, String)],
        initial: &[ModelChange],
    ) -> Result<Simulation, RunFailure> {
        let mut read = read_model(text);
        if read.has_errors() {
            return Err(RunFailure::Diagnostics {
                probe: None,
                diagnostics: read.diagnostics,
            });
        }
        let mut inactive = super::changes::Inactive::new();
        for c in initial {
            if let Ok((r, _)) = super::changes::resolve(&mut read, c) {
                r.apply(&mut read.model, &mut inactive);
            }
        }
        // The model built: the dataset without the elements switched off (the dataset
        // itself, not a copy, when none is).
        let switched_off =
            (!inactive.is_empty()).then(|| super::changes::effective(&read.model, &inactive));
        let interpret = spec.engine == Engine::Interp;
        let analysis = analyze_model_with(
            switched_off.as_ref().unwrap_or(&read.model),
            spec.dim,
            interpret,
        )
        .map_err(RunFailure::Analysis)?;
        let mut columns = Vec::new();
        let mut probe_warnings = Vec::new();
        for (name, text) in probes {
            let fail = |diagnostics| RunFailure::Diagnostics {
                probe: Some(name.clone()),
                diagnostics,
            };
            let checked = read
                .compile(text, &Variables::new(), Expect::Scalar)
                .map_err(fail)?;
            if !checked.warnings.is_empty() {
                probe_warnings.push((name.clone(), text.clone(), checked.warnings));
            }
            let e = Expr {
                span: 0..text.len(),
                function: checked.function,
            };
            let function = read.model.inline_variables(&e).map_err(|why| {
                fail(vec![Diagnostic::error(
                    Code::Unsupported,
                    0..text.len(),
                    why,
                )])
            })?;
            columns.push(Column {
                name: name.clone(),
                function: function.function,
                source: e,
            });
        }
        let mut notes = Vec::new();
        for r in read.model.requests.clone() {
            for k in 1..=8 {
                let name = format!("REQ{}.F{k}", r.el.id);
                let expr = if let Some((kind, i, j, rm)) = r.standard {
                    let Some(text) =
                        standard_component(kind, i, j.unwrap_or(0), rm.unwrap_or(0), k)
                    else {
                        continue;
                    };
                    match read.compile(&text, &Variables::new(), Expect::Scalar) {
                        Ok(c) => Expr {
                            span: r.el.span.clone(),
                            function: c.function,
                        },
                        Err(_) => {
                            notes.push(format!("{name} ({text}) left out: it does not check"));
                            continue;
                        }
                    }
                } else {
                    match r.functions.iter().find(|(n, _)| *n + 1 == k) {
                        Some((_, e)) => e.clone(),
                        None => continue,
                    }
                };
                match read.model.inline_variables(&expr) {
                    Ok(e) => columns.push(Column {
                        name,
                        function: e.function,
                        source: expr,
                    }),
                    Err(why) => notes.push(format!("{name} left out: {why}")),
                }
            }
        }
        let exprs = analysis.exprs;
        let mut system = analysis.system;
        // (The columns added their measures to the dataset's slots.)
        let switched_off = switched_off.map(|mut m| {
            m.measures.clone_from(&read.model.measures);
            m
        });
        let model = switched_off.as_ref().unwrap_or(&read.model);
        let forces = system.forces_from_model(model, &exprs)?;
        // Energy is conserved only without force elements and without rows that move
        // with time (MOTIONs, time-dependent GCONs) or do work through velocities
        // (non-holonomic GCONs).
        let conservative = forces.elements.is_empty()
            && system
                .rows()
                .all(|(e, q)| !system.row_reads_time(e, q) && !system.row_reads_velocity(e, q));
        // Every slot the columns read, resolved for the dynamics. A probe that reads what
        // the dynamics cannot give is an error; a REQUEST column, a note.
        let mut slots: Vec<(u32, Option<OutputSlot>)> = Vec::new();
        let mut kept = Vec::with_capacity(columns.len());
        for (k, c) in columns.into_iter().enumerate() {
            let mut ok = Ok(());
            for &s in &c.function.uses.measures {
                if slots.iter().any(|(x, _)| *x == s) {
                    continue;
                }
                match OutputSlot::resolve(&mut system, model, s) {
                    Ok(o) => slots.push((s, Some(o))),
                    // An element switched off: the column holds 0 while it is.
                    Err(_) if super::changes::reads_inactive(&read.model, s, &inactive) => {
                        slots.push((s, None));
                    }
                    Err(e) => {
                        ok = Err(e);
                        break;
                    }
                }
            }
            match ok {
                Ok(()) => kept.push(c),
                Err(e) if k < probes.len() => {
                    let text = &probes[k].1;
                    return Err(RunFailure::Diagnostics {
                        probe: Some(c.name),
                        diagnostics: vec![Diagnostic::error(
                            Code::Unsupported,
                            0..text.len(),
                            e.to_string(),
                        )],
                    });
                }
                Err(e) => notes.push(format!("{} left out: {e}", c.name)),
            }
        }
        let columns = kept;
        let redundant = analysis.redundancy.redundant.len();
        let dropped: Vec<usize> = match spec.keep_redundant {
            true => Vec::new(),
            false => analysis
                .redundancy
                .redundant
                .iter()
                .map(|r| r.row)
                .collect(),
        };
        let constraint_designs: Vec<i64> = read
            .model
            .constraint_designs()
            .into_iter()
            .map(i64::from)
            .collect();
        let plant = Plant::new(model, &exprs, &mut system, &constraint_designs);
        let start = system.start_state();
        let dynamics = Dynamics::new(system, forces, &dropped)?;
        let lifted = shadow(model, &exprs, &dynamics, &slots, &mut notes);
        // Every expression of the model is recorded now: constraints, forces, outputs.
        let functions: Vec<&crate::ir::Function> = columns.iter().map(|c| &c.function).collect();
        let code = match functions.is_empty() {
            true => None,
            false => exprs.fuse(&functions),
        };
        exprs.unify();
        if let Some(e) = exprs.jit_error() {
            notes.push(format!(
                "the JIT could not compile the model ({e}); the interpreter runs it"
            ));
        }
        let measures = vec![0.0; read.model.measures.len()];
        let reconcile = reads_reconciled(&slots, &dynamics);
        Ok(Simulation {
            read,
            dynamics,
            outputs: Outputs {
                columns,
                slots,
                reconcile,
                code,
                measures,
                exprs,
                lifted,
                row: Vec::new(),
            },
            spec,
            notes,
            conservative,
            redundant,
            dropped: dropped.clone(),
            start,
            constraint_designs,
            probe_warnings,
            plant,
            inactive,
            changed: false,
            trace: None,
        })
    }

    /// The design variables the model's expressions read (constant VARIABLEs, read by
    /// VARVAL), with their values (the build's, or the last rewind's).
    pub fn designs(&self) -> &[(i64, f64)] {
        self.dynamics.sys.measures.designs()
    }

    /// Makes the simulation ready to run again from t = 0 with the design values
    /// `values` (VARIABLE id, value; the others keep the values it was built with): the
    /// next run gives the bits a simulation built from the dataset with those values
    /// would. Refuses (with the VARIABLE's id) a value of a design variable a constraint
    /// reads, which moves the assembled configuration: that needs a new build.
    pub fn rewind(&mut self, values: &[(i64, f64)]) -> Result<(), RewindError> {
        if let Some(&(id, _)) = values
            .iter()
            .find(|(id, _)| self.constraint_designs.contains(id))
        {
            return Err(RewindError::ConstraintReads(id));
        }
        if self.changed {
            return Err(RewindError::ModelChanged);
        }
        let sys = &mut self.dynamics.sys;
        sys.rewind_to(&self.start);
        for &(id, v) in values {
            sys.measures.set_design(id, v);
        }
        self.dynamics
            .restart(&self.dropped)
            .map_err(RewindError::Dynamics)?;
        if let Some(lifted) = &mut self.outputs.lifted {
            lifted.rewind(values).map_err(RewindError::Dynamics)?;
        }
        Ok(())
    }

    /// How many JIT modules hold the model's compiled expressions: 1 with the JIT (every
    /// GCON, MOTION, force component and output column in one), 0 interpreted.
    pub fn jit_modules(&self) -> usize {
        self.outputs.exprs.modules()
    }

    /// The column headers: `time`, then the probes, then the request components.
    pub fn header(&self) -> Vec<String> {
        std::iter::once("time".to_string())
            .chain(self.outputs.columns.iter().map(|c| c.name.clone()))
            .collect()
    }
}

impl Outputs {
    /// The output row of a state solved already (an equilibrium, a kinematic solution):
    /// its velocities, accelerations and multipliers are the solution's, not reconciled.
    fn solved_row(&mut self, d: &mut Dynamics) -> Result<&[f64], DynError> {
        d.refresh_outputs()?;
        self.fill_row(d)
    }

    /// The output row at the state of `d`; `last` says it is the run's final row, which
    /// the summary's energy and residual read.
    fn row(&mut self, d: &mut Dynamics, last: bool, state: RowState) -> Result<&[f64], DynError> {
        // The integrator's accelerations and multipliers are its own (HHT's are shifted
        // by α and only first-order accurate), and index 3 lets velocities drift: outputs
        // get velocities projected onto the velocity constraints and the consistent a
        // and λ of that state, M·a/UCF + Φ_qᵀλ = Q with Φ_q·a = γ (spec §6.1 phase 3), as
        // Adams reconciles at output steps. The integrator keeps its own state. Columns
        // that read positions only skip it (compute only what the outputs read).
        if self.reconcile || last {
            d.reconcile()?;
            d.refresh_outputs()?;
        } else if state == RowState::Stepped {
            // Φ at this state, for the summary's largest constraint residual (an
            // interpolated row's was measured where it was made).
            d.eval_constraints(false)?;
        }
        self.fill_row(d)
    }

    /// The columns at the state of `d` as it stands (evaluated for outputs).
    fn fill_row(&mut self, d: &mut Dynamics) -> Result<&[f64], DynError> {
        for &(s, slot) in &self.slots {
            self.measures[s as usize] = slot.map_or(0.0, |o| o.value(d));
        }
        if let Some(lifted) = &mut self.lifted {
            lifted.fill(d, &mut self.measures)?;
        }
        let t = d.sys.time;
        let row = &mut self.row;
        row.clear();
        row.push(t);
        row.resize(self.columns.len() + 1, 0.0);
        if let Some(code) = &self.code {
            code.eval_into(t, &self.measures, &mut row[1..]);
        }
        Ok(row)
    }
}

impl Simulation {
    /// Kinetic plus gravitational potential energy (model units, /UCF).
    fn energy(&self) -> f64 {
        let sys = &self.dynamics.sys;
        let g = sys.gravity;
        let potential: f64 = sys
            .parts
            .iter()
            .filter(|p| p.index.is_some())
            .map(|p| -p.mass * g.dot(&p.r))
            .sum();
        kinetic(sys) + potential / sys.ucf
    }

    /// Runs to the end time, handing each output row to `out` (the first at t = 0). The
    /// summary comes with the failure that stopped the run, if one did; the rows before
    /// it have been handed out.
    pub fn run(
        &mut self,
        out: &mut dyn FnMut(&[f64]) -> std::io::Result<()>,
    ) -> (Summary, Option<DynError>) {
        let segment = Segment::dynamic(
            self.spec.end,
            self.spec.output_step,
            self.read.model.integrator.clone(),
        );
        self.run_segments(&[segment], out, None)
    }

    /// Runs the segments one after the other from t = 0, handing each output row to
    /// `out` (the first at t = 0, none twice where two segments meet) and, when `table`
    /// is given, a step-table line at each. The integrator starts afresh at each segment
    /// from the reconciled state where the last one ended, as Adams restarts at each
    /// SIMULATE command. The command line's `spec` overrides each segment's statement.
    pub fn run_segments(
        &mut self,
        segments: &[Segment],
        out: &mut dyn FnMut(&[f64]) -> std::io::Result<()>,
        table: Option<&mut dyn FnMut(&TableRow)>,
    ) -> (Summary, Option<DynError>) {
        self.run_interruptible(segments, out, table, None)
    }

    /// [`Simulation::run_segments`], stopped with [`DynError::Interrupted`] before the
    /// first step attempt at which `interrupt` answers true. When the spec asks for an
    /// error estimate, a run that finished is made again at a looser ERROR afterwards
    /// ([`Estimate`]); the simulation is then left at that run's end.
    pub fn run_interruptible(
        &mut self,
        segments: &[Segment],
        out: &mut dyn FnMut(&[f64]) -> std::io::Result<()>,
        table: Option<&mut dyn FnMut(&TableRow)>,
        interrupt: Option<Interrupt<'_>>,
    ) -> (Summary, Option<DynError>) {
        let error = self.start_trace(segments);
        let (mut summary, failed) = self.run_once(segments, out, table, interrupt);
        match (error, &failed) {
            (Some(error), None) => self.add_estimate(segments, error, &mut summary, interrupt),
            _ => self.trace = None,
        }
        (summary, failed)
    }

    /// One run of `segments` ([`Simulation::run_interruptible`] without the estimate).
    fn run_once(
        &mut self,
        segments: &[Segment],
        out: &mut dyn FnMut(&[f64]) -> std::io::Result<()>,
        mut table: Option<&mut dyn FnMut(&TableRow)>,
        interrupt: Option<Interrupt<'_>>,
    ) -> (Summary, Option<DynError>) {
        let clock = Instant::now();
        // Energy is watched over runs of dynamics alone (an equilibrium changes it).
        // (A command file that changes the model changes its energy too.)
        let integrates_only = segments
            .iter()
            .all(|s| s.kind == Analysis::Dynamic && s.changes.is_empty());
        let e0 = (self.conservative && integrates_only).then(|| self.energy());
        let mut max_residual: f64 = 0.0;
        let mut name = match segments.iter().find(|s| s.kind != Analysis::Dynamic) {
            Some(s) if s.kind == Analysis::Kinematics => "kinematics",
            Some(s) if s.kind == Analysis::Linear => "linear",
            Some(_) => "statics",
            None => "hht",
        };
        let mut error: f64 = 0.0;
        let mut notes = self.notes.clone();
        let mut equilibria = Vec::new();
        let mut linear = Vec::new();
        let conservative = self.conservative;
        let mut kinetic_max: f64 = 0.0;
        let mut trace = self.trace.take();
        // A row of the integrated state (`Some((last, state))`: reconciled when the
        // columns need it or it is a segment's last) or of a state solved already (None).
        let mut emit = |outputs: &mut Outputs,
                        d: &mut Dynamics,
                        row: Option<(bool, RowState)>|
         -> Result<(), DynError> {
            if conservative {
                kinetic_max = kinetic_max.max(kinetic(&d.sys));
            }
            let row = match row {
                Some((last, state)) => outputs.row(d, last, state)?,
                None => outputs.solved_row(d)?,
            };
            if let Some(t) = trace.as_mut() {
                t.push(row.to_vec());
            }
            max_residual = max_residual.max(residual(d));
            if let Some(table) = table.as_mut() {
                table(&TableRow {
                    time: d.sys.time,
                    step: d.stats.last_step,
                    steps: d.stats.steps,
                    newton_iterations: d.stats.newton_iterations,
                    order: d.stats.order,
                    cpu_seconds: clock.elapsed().as_secs_f64(),
                });
            }
            out(row).map_err(|e| DynError::Output(e.to_string()))
        };
        // The row at the start belongs to the first segment: the dynamics' consistent
        // state, or the first equilibrium or kinematic solution. The command file's
        // changes before its first SIMULATE come before it.
        let mut first_row = true;
        let mut result = match segments.first() {
            Some(s) => self.change_model(&s.changes),
            None => Ok(()),
        };
        if result.is_ok() && segments.first().is_none_or(|s| s.kind == Analysis::Dynamic) {
            let (dynamics, outputs) = (&mut self.dynamics, &mut self.outputs);
            result = dynamics.solve_accelerations().and_then(|()| {
                emit(
                    outputs,
                    dynamics,
                    Some((segments.is_empty(), RowState::Stepped)),
                )
            });
            first_row = false;
        }
        let mut after_solved = false;
        for (k, seg) in segments.iter().enumerate() {
            if result.is_err() {
                break;
            }
            if k > 0 && !seg.changes.is_empty() {
                // The stretch starts from the changed model, assembled where the last
                // one stopped: its velocities and accelerations are reconciled below.
                result = self.change_model(&seg.changes);
                if result.is_err() {
                    break;
                }
                after_solved = true;
            }
            let last = k + 1 == segments.len();
            let (dynamics, outputs, plant) = (&mut self.dynamics, &mut self.outputs, &self.plant);
            if seg.kind != Analysis::Dynamic {
                let mut solved_emit = |d: &mut Dynamics| emit(outputs, d, None);
                result = super::analyses::run(
                    dynamics,
                    plant,
                    seg,
                    (first_row, last),
                    &mut solved_emit,
                    (&mut equilibria, &mut linear),
                    interrupt,
                );
                (first_row, after_solved) = (false, true);
                continue;
            }
            // From an equilibrium (velocities zero), a kinematic state or a changed
            // model: velocities consistent with the constraints, then the accelerations.
            if after_solved {
                result = dynamics.reconcile();
                if result.is_err() {
                    break;
                }
            }
            after_solved = false;
            let plan = Plan::new(seg.integrator.as_ref(), &self.spec, seg.output_step);
            let (mut integrator, note) = plan.integrator();
            name = integrator.name();
            error = error.max(plan.settings.error);
            if let Some(n) = note.filter(|n| !notes.contains(n)) {
                notes.push(n);
            }
            let (t0, dt, end) = (dynamics.sys.time, seg.output_step, seg.end);
            let times = OutputTimes::new(t0, dt, end);
            // Each segment's last row reconciles: the next segment starts from it.
            let mut segment_emit =
                |d: &mut Dynamics, state| emit(outputs, d, Some((d.sys.time >= end, state)));
            result = simulate(
                dynamics,
                integrator.as_mut(),
                &plan.settings,
                &times,
                &mut segment_emit,
                interrupt,
            );
            if let Some(n) = integrator.formulation().filter(|n| !notes.contains(n)) {
                notes.push(n);
            }
        }
        self.trace = trace;
        // Notes the changes to the model added.
        for n in &self.notes {
            if !notes.contains(n) {
                notes.push(n.clone());
            }
        }
        let result = result.map_err(|e| self.diagnose_lock_up(e));
        let summary = Summary {
            integrator: name,
            equilibria,
            linear,
            stats: self.dynamics.stats,
            cpu_seconds: clock.elapsed().as_secs_f64(),
            max_residual,
            energy: e0.map(|e| (e, self.energy())),
            notes,
            dim: self.dynamics.sys.dim_reason.clone(),
            warnings: Vec::new(),
            estimate: None,
            reused: false,
        };
        let summary = Summary {
            warnings: monitors(
                &summary,
                (
                    self.spec.fixed_step.is_some(),
                    self.dynamics.m >= self.dynamics.n,
                    self.trace.is_some(),
                ),
                error,
                kinetic_max,
            ),
            ..summary
        };
        (summary, result.err())
    }
}

/// Relative distance of a kept row to the span of the others below which a failed run's
/// configuration counts as singular (a lock-up): the redundancy analysis' own
/// tolerance is 1e-8, for exact dependence; a run fails a little before that.
const LOCK_UP_DISTANCE: f64 = 1e-3;

impl Simulation {
    /// A failure of the step control (the corrector diverging, the step below HMIN) at
    /// a configuration where the kept constraints are nearly dependent becomes a
    /// lock-up naming the element whose equation depends on the others; any other
    /// failure is returned as it is.
    fn diagnose_lock_up(&self, e: DynError) -> DynError {
        use crate::mbd::redundancy::{analyze, Options, Problem};
        use crate::vocab::elements::ElementKind;
        let time = match e {
            DynError::Newton { time, .. } | DynError::StepTooSmall { time, .. } => time,
            _ => return e,
        };
        let sys = &self.dynamics.sys;
        let Ok(jacobian) = sys.jacobian(true) else {
            return e;
        };
        let (labels, elements) = (sys.labels(), sys.element_refs());
        let dim = sys.dim.axes();
        let options = Options {
            tolerance: LOCK_UP_DISTANCE,
            conflict_tolerance: f64::INFINITY,
        };
        // The first kept row nearly dependent on the others, with the rows `skip` says
        // to leave out (indices of the full Jacobian), if any.
        let dependent = |skip: &dyn Fn(usize) -> bool| -> Option<usize> {
            let rows: Vec<usize> = (0..labels.len()).filter(|&r| !skip(r)).collect();
            let mut new_index = vec![u32::MAX; labels.len()];
            for (k, &r) in rows.iter().enumerate() {
                new_index[r] = k as u32;
            }
            let mut jac = crate::mbd::sparse::Triplets::new(rows.len(), jacobian.ncols);
            for &(r, c, v) in &jacobian.entries {
                let k = new_index[r as usize];
                if k != u32::MAX {
                    jac.push(k as usize, c as usize, v);
                }
            }
            let sub: Vec<_> = rows.iter().map(|&r| labels[r]).collect();
            let problem = Problem::new(&jac, &sub, &elements, sys.moving_parts(), dim);
            let report = analyze(&problem, &options).ok()?;
            report
                .redundant
                .iter()
                .map(|d| rows[d.row])
                .find(|r| !self.dropped.contains(r))
        };
        let Some(row) = dependent(&|_| false) else {
            return e;
        };
        // A drive whose rows, left out, leave the rest independent is what cannot move
        // the mechanism any further: name it rather than a joint of its loop.
        let drives = (0..elements.len()).filter(|&el| elements[el].kind == ElementKind::Motion);
        let culprit = drives
            .into_iter()
            .find(|&el| dependent(&|r| labels[r].element == el).is_none())
            .unwrap_or(labels[row].element);
        DynError::Singular {
            time,
            why: crate::mbd::dynamics::Singularity::LockUp,
            culprit: Some(crate::mbd::dynamics::Culprit::Element(
                elements[culprit].clone(),
            )),
        }
    }
}

/// Past this many ERRORs, a fixed-step run's local error estimate makes it a warning.
const FIXED_STEP_WARNING: f64 = 10.0;

/// Past this many ERRORs (relative to the largest kinetic energy), the energy change of
/// a conservative model makes it a warning.
const ENERGY_WARNING: f64 = 10.0;

/// Past this many ERRORs, the sum of a run's local errors makes it a warning, unless the
/// run's error is estimated.
pub const ACCUMULATED_WARNING: f64 = 10.0;

/// The warnings of a finished run (see [`Summary::warnings`]): fixed steps whose local
/// error estimate exceeded ERROR more than tenfold, local errors that add up to more than
/// ten ERRORs, a conservative model whose energy changed by more than ten ERRORs of its
/// largest kinetic energy, and a constraint residual larger than the drift the run
/// allows dropped rows (10·ERROR, at least 1e-6). When the run's error is estimated
/// (`estimated`, [`Estimate`]) the estimate judges it instead of the local errors' sum,
/// which over the work-precision bench warned 71 % of the accurate runs.
fn monitors(
    s: &Summary,
    (fixed, driven, estimated): (bool, bool, bool),
    error: f64,
    kinetic_max: f64,
) -> Vec<String> {
    // Fully driven: the constraints fix every coordinate at every time, so no local
    // error of the integrator is the answer's (nothing is left to integrate).
    let mut w = match driven {
        true => Vec::new(),
        false => integration_warnings(s, fixed, estimated, error, kinetic_max),
    };
    let drift = (10.0 * error).max(1e-6);
    if s.max_residual > drift {
        w.push(format!(
            "the constraints drifted: residual {:.1e} exceeds {drift:.0e}",
            s.max_residual
        ));
    }
    w
}

/// The warnings about the integration's accuracy: energy, fixed steps, local errors.
fn integration_warnings(
    s: &Summary,
    fixed: bool,
    estimated: bool,
    error: f64,
    kinetic_max: f64,
) -> Vec<String> {
    let mut w = Vec::new();
    if let Some((e0, e1)) = s.energy {
        // Against the largest kinetic energy seen at the output times: what the motion
        // trades back and forth, whatever the potential's datum.
        let scale = kinetic_max.max(e0.abs());
        if scale > 0.0 && (e1 - e0).abs() > ENERGY_WARNING * error * scale {
            w.push(format!(
                "the energy changed by {:.1e} in a conservative model, {:.1e} of the largest kinetic energy ({scale:.3e}): more than {ENERGY_WARNING}·ERROR ({error:e}), so the answer is not accurate to ERROR",
                e1 - e0,
                (e1 - e0).abs() / scale
            ));
        }
    }
    if fixed && s.stats.worst_error > FIXED_STEP_WARNING {
        w.push(format!(
            "fixed steps: the local error estimate reached {:.1e} × ERROR ({error:e}) at time {}; the results are not accurate to ERROR (use error control or a smaller step)",
            s.stats.worst_error, s.stats.worst_error_time
        ));
    }
    if fixed || !estimated {
        w.extend(sum_warning(s, fixed, error));
    }
    w
}

/// The warning of a run whose steps' local errors add up to more than
/// [`ACCUMULATED_WARNING`] ERRORs, if they do.
fn sum_warning(s: &Summary, fixed: bool, error: f64) -> Option<String> {
    let remedy = if fixed {
        "use error control or a smaller step"
    } else {
        "ERROR bounds each step, as in Adams; --estimate-error estimates the answer's error"
    };
    (s.stats.error_sum > ACCUMULATED_WARNING).then(|| {
        format!(
            "the steps' local error estimates add up to {:.0}×ERROR ({error:e}): the answer may be off by that much ({remedy})",
            s.stats.error_sum
        )
    })
}

/// Kinetic energy (model units, /UCF).
fn kinetic(sys: &crate::mbd::system::System) -> f64 {
    sys.parts
        .iter()
        .filter(|p| p.index.is_some())
        .map(|p| {
            let w = p.w;
            0.5 * p.mass * p.v.norm_squared() + 0.5 * w.dot(&(p.inertia_global() * w))
        })
        .sum::<f64>()
        / sys.ucf
}

/// The largest scaled residual of the kept rows of `d` (translational rows over the
/// model length), from its last constraint evaluation.
fn residual(d: &Dynamics) -> f64 {
    (0..d.m).map(|r| d.scaled_residual(r)).fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 1 kg slider on a rail along global x, pulled by a SPRINGDAMPER (K = 100,
    /// C = 4, free length 1) to the ground origin, released at rest at x = 1.2.
    pub(super) const OSCILLATOR: &str = "oscillator\nPART/1, GROUND\nMARKER/10, PART = 1\n\
        MARKER/11, PART = 1, REULER = 90D, 90D, 0\n\
        PART/2, MASS = 1, CM = 20, IP = 1, 1, 1, QG = 1.2, 0, 0\n\
        MARKER/20, PART = 2\nMARKER/21, PART = 2, REULER = 90D, 90D, 0\n\
        JOINT/1, TRANSLATIONAL, I = 21, J = 11\n\
        SPRINGDAMPER/1, TRANSLATION, I = 20, J = 10, K = 100, C = 4, LENGTH = 1\nEND\n";

    #[test]
    fn every_expression_of_a_model_lands_in_one_module() {
        // A GCON (compiled for assembly first), a MOTION, an SFORCE, a GFORCE's six
        // components, a VARIABLE read by a force, a REQUEST's F1..F2 and a probe.
        let model = "one module\nPART/1, GROUND\nMARKER/10, PART = 1\n\
            PART/2, MASS = 1, CM = 20, IP = 1, 1, 1\nMARKER/20, PART = 2\n\
            MARKER/22, PART = 2, FLOATING\n\
            PART/3, MASS = 1, CM = 30, IP = 1, 1, 1, QG = 0, 0, 1\nMARKER/30, PART = 3\n\
            MARKER/31, PART = 3\nMARKER/11, PART = 1, QP = 0, 0, 1\n\
            JOINT/1, SPHERICAL, I = 20, J = 10\nJOINT/2, TRANSLATIONAL, I = 31, J = 11\n\
            GCON/1, I = 20, FUNCTION = AX(20, 10)\n\
            GCON/2, I = 20, FUNCTION = AY(20, 10) - 0.1*SIN(TIME)\n\
            MOTION/1, JOINT = 2, FUNCTION = 0.1*TIME\n\
            VARIABLE/1, FUNCTION = -2*WZ(20, 10)\n\
            SFORCE/1, ROTATION, I = 20, J = 10, FUNCTION = VARVAL(1)\n\
            GFORCE/1, I = 20, JFLOAT = 22, RM = 10, FX = 0\\ FY = 0\\ FZ = 1\\ TX = 0\\ TY = 0\\ TZ = 0.1\n\
            REQUEST/1, F1 = DZ(31, 11)\\ F2 = WZ(20, 10)\nEND\n";
        let probes = [("z".to_string(), "DZ(30)".to_string())];
        let build = |engine| {
            let mut spec = RunSpec::new(0.1, 0.05);
            spec.engine = engine;
            match Simulation::new(model, spec, &probes) {
                Ok(sim) => sim,
                Err(_) => panic!("the model builds"),
            }
        };
        if crate::jit::Jit::new().is_ok() {
            assert_eq!(build(Engine::Jit).jit_modules(), 1);
        }
        assert_eq!(build(Engine::Interp).jit_modules(), 0);
    }

    #[test]
    fn a_damped_spring_follows_its_closed_form() {
        // m ẍ = −k (x − 1) − c ẋ: ω = 10, ζ = c/(2√(k m)) = 0.2, ω_d = ω√(1 − ζ²);
        // x − 1 = 0.2·e^{−ζωt}(cos ω_d t + ζω/ω_d sin ω_d t).
        let probes = [
            ("x".to_string(), "DX(20,10)".to_string()),
            ("f".to_string(), "SPDP(1,0,2,0)".to_string()),
        ];
        for method in [Method::Hht, Method::Galpha] {
            let mut spec = RunSpec::new(2.0, 0.05);
            spec.method = Some(method);
            spec.error = Some(1e-11);
            let Ok(mut sim) = Simulation::new(OSCILLATOR, spec, &probes) else {
                panic!("the oscillator builds");
            };
            let mut rows = Vec::new();
            let (_, failed) = sim.run(&mut |r| {
                rows.push(r.to_vec());
                Ok(())
            });
            assert!(failed.is_none(), "{failed:?}");
            assert_eq!(rows.len(), 41);
            let (w, z) = (10.0f64, 0.2f64);
            let wd = w * (1.0 - z * z).sqrt();
            for r in &rows {
                let t = r[0];
                let e = (-z * w * t).exp();
                let x = 1.0 + 0.2 * e * ((wd * t).cos() + z * w / wd * (wd * t).sin());
                let v = -0.2 * e * (w * w / wd) * (wd * t).sin();
                assert!(
                    (r[1] - x).abs() < 1e-6,
                    "{method:?} t = {t}: x {} vs {x}",
                    r[1]
                );
                // The spring's force on I along x: −k(x − 1) − c·ẋ.
                let f = -100.0 * (x - 1.0) - 4.0 * v;
                assert!(
                    (r[2] - f).abs() < 1e-4,
                    "{method:?} t = {t}: force {} vs {f}",
                    r[2]
                );
            }
        }
    }

    #[test]
    fn plain_newmark_follows_its_amplification_matrix() {
        // Undamped x'' = −ω²x (ω = 10) in fixed steps h: Newmark's two-step recurrence
        // x_{n+1} − 2A₁x_n + A₂x_{n−1} = 0, Ω = ωh, D = 1 + βΩ²,
        // A₁ = 1 − Ω²(γ + ½)/(2D), A₂ = 1 − Ω²(γ − ½)/D (Hughes, The Finite Element
        // Method, §9.1), so x_n = ρⁿ(x₀ cos nθ + c sin nθ) with ρ = √A₂,
        // cos θ = A₁/ρ, and x₁ = x₀(1 − (½ − β)Ω²)/D from rest. β = ¼, γ = ½ keeps the
        // amplitude (ρ = 1) and only lengthens the period; Adams' defaults damp.
        let undamped = OSCILLATOR.replace("C = 4", "C = 0");
        let probes = [("x".to_string(), "DX(20,10)".to_string())];
        let h = 0.02;
        for (beta, gamma) in [(0.25, 0.5), (0.36, 0.7)] {
            let text = undamped.replace(
                "END\n",
                &format!("INTEGRATOR/NEWMARK, BETA = {beta}, GAMMA = {gamma}\nEND\n"),
            );
            let mut spec = RunSpec::new(2.0, h);
            (spec.fixed_step, spec.error) = (Some(h), Some(1e-10));
            let Ok(mut sim) = Simulation::new(&text, spec, &probes) else {
                panic!("the oscillator builds");
            };
            let mut rows = Vec::new();
            let (summary, failed) = sim.run(&mut |r| {
                rows.push(r.to_vec());
                Ok(())
            });
            assert!(failed.is_none(), "{failed:?}");
            assert_eq!(summary.integrator, "newmark");
            assert_eq!(summary.stats.order, Some(if gamma == 0.5 { 2 } else { 1 }));
            let big_omega = 10.0 * h;
            let d = 1.0 + beta * big_omega * big_omega;
            let a1 = 1.0 - big_omega * big_omega * (gamma + 0.5) / (2.0 * d);
            let a2 = 1.0 - big_omega * big_omega * (gamma - 0.5) / d;
            let rho = a2.sqrt();
            let theta = (a2 - a1 * a1).sqrt().atan2(a1);
            let x0 = 0.2;
            let x1 = x0 * (1.0 - (0.5 - beta) * big_omega * big_omega) / d;
            let c = (x1 / rho - x0 * theta.cos()) / theta.sin();
            assert_eq!(rows.len(), 101);
            for (n, r) in rows.iter().enumerate() {
                let nf = n as f64;
                let x = rho.powf(nf) * (x0 * (nf * theta).cos() + c * (nf * theta).sin());
                assert!(
                    (r[1] - 1.0 - x).abs() < 1e-9,
                    "β {beta} γ {gamma} step {n}: {} vs {x}",
                    r[1] - 1.0
                );
            }
        }
    }
}
