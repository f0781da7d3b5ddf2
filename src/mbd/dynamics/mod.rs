//! Equations of motion of the constrained system, the index-3 DAE (multibody spec §6.1)
//!
//! ```text
//! (1/UCF)·M(q)·a + Φ_qᵀ·λ = Q(q, v, t),     Φ(q, t) = 0,
//! ```
//!
//! over the core's velocity-level columns: per moving part the CM velocity and the
//! angular velocity, global axes (6 columns in 3D, 3 in 2D), so M is block diagonal,
//! diag(m·I, R·J·Rᵀ), and Q holds gravity, the force elements and the gyroscopic moment
//! −ω × (J·ω). [`Dynamics`] owns the system and its forces, the kept constraint rows
//! (rows the redundancy analysis dropped stay out, as in Adams, and are watched for
//! drift), the Newton matrix on one sparse pattern with a sparse LU, and the state's
//! accelerations and multipliers. Integrators ([`integrator`]) drive it.

pub mod bdf;
mod dense;
pub mod dopri853;
pub mod events;
mod fill;
mod gamma;
pub mod integrator;
pub mod jacobian;
pub mod newmark;
pub mod outputs;
mod reuse;
pub mod schur;
mod stiffness;
pub mod tree;

use super::constraints::Primitive;
use super::error::{element_name, MbdError};
use super::forces::{ForceSet, Generalized};
use super::rows::Row;
use super::sparse::{FactorError, Pattern, SparseLu};
use super::system::{Dimension, PartHandle, System};
use crate::vocab::elements::ElementRef;
use crate::vocab::math::{DVec, Mat3, Quat, Vec3};
use std::fmt;

/// Counters of a run: what the work-precision charts plot against accuracy.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    /// Accepted steps.
    pub steps: usize,
    /// Rejected step attempts.
    pub rejected: usize,
    /// Corrector (Newton) iterations, all attempts.
    pub newton_iterations: usize,
    /// Evaluations of a Newton or saddle-point matrix.
    pub jacobian_evaluations: usize,
    /// Sparse LU factorizations of the Newton matrix.
    pub factorizations: usize,
    /// Evaluations of compiled expressions (force magnitudes, GCON and MOTION
    /// functions), values and gradients alike.
    pub expression_evaluations: usize,
    /// Force-law switches (contact on or off, clamp on or off) located by the step
    /// control ([`events`]).
    pub events: usize,
    /// The size of the last accepted step, and the integrator's order on it (the step
    /// table of `mbfx run --verbose`).
    pub last_step: f64,
    /// The order used on the last accepted step (None for a fixed-order method).
    pub order: Option<u32>,
    /// Accepted steps at each order 1…6 of a variable-order method (index k − 1).
    pub steps_at_order: [usize; 6],
    /// The largest local error estimate of an accepted step, in units of ERROR: at most
    /// 1 under error control; with fixed steps, how far the run strayed from ERROR.
    pub worst_error: f64,
    /// When that step ended.
    pub worst_error_time: f64,
    /// The accepted steps' local error estimates added up, in units of ERROR: about
    /// what the answer's error can reach when the dynamics neither damp nor amplify
    /// errors (at most 1 when ERROR is per run).
    pub error_sum: f64,
    /// Output rows made from a continuous extension inside a step (INTERPOLATE = ON).
    pub interpolated: usize,
    /// The largest scaled residual of the position constraints at those rows, before
    /// any projection: how far the extension strays from the constraints.
    pub interpolation_residual: f64,
    /// Those of them projected back onto the constraints (their residual exceeded the
    /// run's drift tolerance).
    pub projected: usize,
}

/// What a failure points at: an element, or a part (by Adams id).
#[derive(Clone, Debug, PartialEq)]
pub enum Culprit {
    /// A constraint or force element.
    Element(ElementRef),
    /// A part, by Adams id.
    Part(u32),
}

impl fmt::Display for Culprit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Culprit::Element(e) => write!(f, "{}", element_name(e)),
            Culprit::Part(id) => write!(f, "PART/{id}"),
        }
    }
}

/// ", at X" when there is a culprit.
fn at(c: &Option<Culprit>) -> String {
    c.as_ref().map_or(String::new(), |c| format!(" (at {c})"))
}

/// Sweeps of the consistent accelerations when forces read them (or reactions), and the
/// relative change at which they have settled.
const SOLUTION_SWEEPS: usize = 200;
const SOLUTION_TOL: f64 = 1e-14;

/// Why the dynamics stopped.
#[derive(Clone, Debug, PartialEq)]
pub enum DynError {
    /// An element or expression could not be evaluated.
    Model(MbdError),
    /// The Newton matrix is singular, for the reason `why`.
    Singular {
        /// Simulation time.
        time: f64,
        /// The reason.
        why: Singularity,
        /// What the singular direction points at, when found.
        culprit: Option<Culprit>,
    },
    /// A force or the Newton matrix became NaN or infinite; `element` is the force
    /// element when one is to blame.
    NotFinite {
        /// Simulation time.
        time: f64,
        /// Which quantity became non-finite.
        what: NonFinite,
        /// The force element to blame, when one is.
        element: Option<ElementRef>,
    },
    /// The corrector did not converge even at the smallest step.
    Newton {
        /// Simulation time.
        time: f64,
        /// The step size that failed.
        step: f64,
        /// What the largest correction points at, when found.
        culprit: Option<Culprit>,
    },
    /// Error control asked for a step below HMIN.
    StepTooSmall {
        /// Simulation time.
        time: f64,
        /// The step size asked for.
        step: f64,
        /// The smallest step allowed.
        hmin: f64,
        /// What dominates the error estimate, when found.
        culprit: Option<Culprit>,
    },
    /// A constraint the redundancy analysis dropped is violated: the constraints are
    /// conflicting, not redundant.
    DroppedViolated {
        /// Simulation time.
        time: f64,
        /// The element the equation belongs to.
        element: ElementRef,
        /// The equation's Adams label.
        equation: &'static str,
        /// Its scaled residual.
        residual: f64,
    },
    /// A part free to move in `directions` directions that have no mass or inertia.
    Massless {
        /// The part, as messages name it.
        part: String,
        /// How many directions lack mass or inertia.
        directions: usize,
    },
    /// The Newton matrix's pattern is not one faer can factor.
    Structure,
    /// An output row could not be written (the I/O error, worded).
    Output(String),
    /// The caller's interrupt flag was set: the run stopped before its next step
    /// ([`integrator::simulate`] asks before every step attempt).
    Interrupted {
        /// Simulation time of the last accepted step.
        time: f64,
    },
    /// No static equilibrium came out ([`super::statics`]).
    Statics(Box<super::statics::Failure>),
    /// A command file's change to the model could not be made at `time` (the changed
    /// model does not build or assemble), for the reason `why`.
    Change {
        /// Simulation time of the change.
        time: f64,
        /// What went wrong, in words.
        why: String,
        /// The changes' commands in the command file.
        at: crate::diag::Span,
    },
    /// A kinematic analysis asked of a model with degrees of freedom left
    /// ([`super::kinematics`]): how many, and each named.
    FreeDegrees {
        /// The degrees of freedom.
        count: usize,
        /// Each one, named.
        free: Vec<super::freedom::Freedom>,
    },
}

/// Why the Newton matrix is singular.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Singularity {
    /// The factorization broke down: dependent constraints, or no mass along a free
    /// direction.
    Dependent,
    /// A kept row's Jacobian vanished: it constrains nothing any more.
    VanishedRow,
    /// The solve gave non-finite values: numerically singular (a lock-up position).
    Numerical,
    /// The run could not go on where the kept constraints are nearly dependent: the
    /// mechanism is at or next to a singular position (a dead centre, a lock-up), where
    /// it cannot move as driven or its branch is not unique.
    LockUp,
}

/// What became NaN or infinite.
#[derive(Clone, Debug, PartialEq)]
pub enum NonFinite {
    /// A force element's load (the element is the error's).
    Force,
    /// A gyroscopic or gravity term (no element to blame).
    Inertial,
    /// An entry of the Newton matrix (a force Jacobian or the mass matrix).
    NewtonMatrix,
}

impl DynError {
    /// The simulation time of the failure, when it has one (an expression that
    /// evaluated to NaN or infinity says when).
    pub fn time(&self) -> Option<f64> {
        match self {
            DynError::Model(MbdError::Expression(
                _,
                super::expr::ExprError::NotFinite { time, .. },
            )) => Some(*time),
            DynError::Singular { time, .. }
            | DynError::NotFinite { time, .. }
            | DynError::Newton { time, .. }
            | DynError::StepTooSmall { time, .. }
            | DynError::DroppedViolated { time, .. }
            | DynError::Interrupted { time }
            | DynError::Change { time, .. } => Some(*time),
            DynError::Statics(f) => Some(f.time()),
            DynError::Model(_)
            | DynError::FreeDegrees { .. }
            | DynError::Massless { .. }
            | DynError::Structure
            | DynError::Output(_) => None,
        }
    }

    /// The element or part the failure is about, when there is one.
    pub fn culprit(&self) -> Option<Culprit> {
        match self {
            DynError::Singular { culprit, .. }
            | DynError::Newton { culprit, .. }
            | DynError::StepTooSmall { culprit, .. } => culprit.clone(),
            DynError::Statics(f) => f.culprit(),
            DynError::FreeDegrees { free, .. } => free.iter().find_map(|f| f.culprit.clone()),
            _ => self.element().cloned().map(Culprit::Element),
        }
    }

    /// The element the failure is about, when there is one.
    pub fn element(&self) -> Option<&ElementRef> {
        match self {
            DynError::DroppedViolated { element, .. } => Some(element),
            DynError::NotFinite { element, .. } => element.as_ref(),
            DynError::Singular {
                culprit: Some(Culprit::Element(e)),
                ..
            }
            | DynError::Newton {
                culprit: Some(Culprit::Element(e)),
                ..
            }
            | DynError::StepTooSmall {
                culprit: Some(Culprit::Element(e)),
                ..
            } => Some(e),
            DynError::Model(MbdError::Expression(e, _))
            | DynError::Model(MbdError::NoSecondDerivative(e, _, _))
            | DynError::Model(MbdError::SamePart(e))
            | DynError::Model(MbdError::Floating(e, _))
            | DynError::Model(MbdError::SolutionLoop { element: e, .. }) => Some(e),
            DynError::Model(MbdError::ForceCycle(circle)) => circle.first(),
            DynError::Statics(f) => match f.as_ref() {
                super::statics::Failure::Unstable { freedom, .. } => match &freedom.culprit {
                    Some(Culprit::Element(e)) => Some(e),
                    _ => None,
                },
                _ => None,
            },
            DynError::FreeDegrees { free, .. } => free.iter().find_map(|f| match &f.culprit {
                Some(Culprit::Element(e)) => Some(e),
                _ => None,
            }),
            _ => None,
        }
    }
}

impl From<MbdError> for DynError {
    fn from(e: MbdError) -> Self {
        DynError::Model(e)
    }
}

impl fmt::Display for DynError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DynError::Model(e) => write!(f, "{e}"),
            DynError::Singular { time, why, culprit } => write!(
                f,
                "at time {time}: the equations of motion are singular{}: {}",
                at(culprit),
                match why {
                    Singularity::Dependent => "the constraints are dependent here, or a part has no mass along a free direction",
                    Singularity::VanishedRow => "this constraint's Jacobian vanishes: it no longer constrains anything",
                    Singularity::Numerical => "the Newton matrix is numerically singular (dependent constraints or a lock-up position)",
                    Singularity::LockUp => "the mechanism is at a singular position (a dead centre or lock-up): its constraints are nearly dependent here, so it cannot move on as driven (named: the drive, else the element whose equation depends on the others)",
                }
            ),
            DynError::NotFinite {
                time,
                what,
                element,
            } => match (what, element) {
                (NonFinite::Force, Some(e)) => {
                    write!(f, "at time {time}: the force of {} is not finite", element_name(e))
                }
                (NonFinite::Force | NonFinite::Inertial, _) => write!(
                    f,
                    "at time {time}: the force of a gyroscopic or gravity term is not finite"
                ),
                (NonFinite::NewtonMatrix, _) => write!(
                    f,
                    "at time {time}: the Newton matrix holds a NaN or infinite value (a force Jacobian or the mass matrix)"
                ),
            },
            DynError::Newton { time, step, culprit } => write!(
                f,
                "at time {time}: the corrector does not converge (Newton diverges even at step {step:e}){}",
                culprit.as_ref().map_or(String::new(), |c| format!("; the largest constraint error is in {c}"))
            ),
            DynError::StepTooSmall {
                time,
                step,
                hmin,
                culprit,
            } => write!(
                f,
                "at time {time}: error control needs a step of {step:e}, below HMIN = {hmin:e}{}",
                culprit.as_ref().map_or(String::new(), |c| format!("; the largest error estimate is {c}'s"))
            ),
            DynError::DroppedViolated {
                time,
                element,
                equation,
                residual,
            } => write!(
                f,
                "at time {time}: conflicting, not redundant: {equation} of {}, dropped as redundant at assembly, is off by {residual:.3e}",
                element_name(element)
            ),
            DynError::Massless { part, directions } => write!(
                f,
                "{part} can move in {directions} direction(s) that have no mass or inertia and that no constraint holds: give it MASS and IP, or constrain it"
            ),
            DynError::Structure => f.write_str("the Newton matrix has no valid structure"),
            DynError::Change { time, why, .. } => {
                write!(f, "the command file's change to the model at t = {time}: {why}")
            }
            DynError::Output(why) => write!(f, "the output could not be written: {why}"),
            DynError::Interrupted { time } => write!(f, "at time {time}: the run was interrupted"),
            DynError::Statics(failure) => write!(f, "{failure}"),
            DynError::FreeDegrees { count, free } => {
                write!(
                    f,
                    "a kinematic analysis needs a model without degrees of freedom, and this one has {count}: "
                )?;
                let named: Vec<String> = free.iter().map(|x| x.to_string()).collect();
                write!(f, "{} (drive each with a MOTION, or run SIMULATE/DYNAMIC)", named.join("; "))
            }
        }
    }
}

impl std::error::Error for DynError {}

/// A saved configuration: each part's pose, and the velocities.
#[derive(Clone, Debug)]
pub struct Snapshot {
    poses: Vec<(Vec3, Quat, f64)>,
    v: DVec,
    time: f64,
}

/// Weights of the Newton matrix [[w_m·M/UCF − w_k·∂Q/∂q − w_c·∂Q/∂v, w_l·Φ_qᵀ], [Φ_q, 0]].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Weights {
    /// Weight of the mass matrix.
    pub w_m: f64,
    /// Weight of the stiffness ∂Q/∂q.
    pub w_k: f64,
    /// Weight of the damping ∂Q/∂v.
    pub w_c: f64,
    /// Weight of the constraint forces Φ_qᵀ.
    pub w_l: f64,
}

/// The system in motion.
pub struct Dynamics {
    /// The assembled system at the current state.
    pub sys: System,
    /// The applied forces and gravity.
    pub forces: ForceSet,
    /// Kept constraint rows (element, equation), in multiplier order.
    pub rows: Vec<(usize, usize)>,
    /// Rows the redundancy analysis dropped: checked, not solved.
    pub dropped: Vec<(usize, usize)>,
    /// Velocity-level columns and kept rows.
    pub n: usize,
    /// Kept constraint rows (length of λ).
    pub m: usize,
    /// Accelerations (v̇, ω̇ per part, the velocity layout) and multipliers.
    pub a: DVec,
    /// Lagrange multipliers, one per kept row.
    pub lambda: DVec,
    /// Counters of the run.
    pub stats: Stats,
    /// The Newton matrix's factors, and the saddle-point matrix's of the outputs'
    /// reconciliation: separate, so an output does not cost the integrator its
    /// factorization.
    factors: Vec<Factors>,
    /// Counts factorizations, so an integrator can tell whether the factors it reuses
    /// are still its own.
    pub factor_generation: u64,
    /// Scratch: generalized forces and their Jacobians.
    pub(crate) gen: Generalized,
    /// Φ and Φ_q of the kept rows at the last evaluation.
    pub(crate) phi: DVec,
    pub(crate) jac: jacobian::Jacobian,
    /// Per kept row, its primitive equation resolved, with the Jacobian slots of its I
    /// and J parts (None for ground): the rows evaluated without looking anything up.
    prims: Vec<stiffness::ResolvedRow>,
    /// The geometric stiffness of the last Newton factorization ([`stiffness`]).
    geo: Vec<(usize, usize, f64)>,
    /// Scratch of the geometric stiffness: one rotational block per moving part.
    geo_blocks: Vec<Mat3>,
    /// The rows whose Jacobian can vanish (all but the `Along` primitives, whose
    /// direction is a unit vector), and the Jacobian's largest entry at the last
    /// factorization, their scale.
    may_vanish: Vec<usize>,
    jac_top: f64,
    /// The mass blocks when they never change: in 2D, and in 3D when every moving
    /// part's inertia is isotropic.
    constant_mass: Option<Vec<Mat3Block>>,
    /// Buffers of one row's evaluation, reused.
    row_scratch: super::constraints::RowEval,
    /// Where the Newton matrix's entries go ([`fill::Fill`]).
    fill: fill::Fill,
    /// Every moving part's inertia is isotropic (the 3D mass blocks then never change).
    isotropic: bool,
    /// Scratch of the saddle-point solves.
    scratch: Scratch,
}

/// `x` made a copy of `from`, reallocated only when the length differs (nalgebra's
/// resize always reallocates).
pub(super) fn copy_into(x: &mut DVec, from: &[f64]) {
    if x.len() == from.len() {
        x.copy_from_slice(from);
    } else {
        *x = DVec::from_column_slice(from);
    }
}

/// `x` made `n` zeros, reallocated only when the length differs.
fn zero_into(x: &mut DVec, n: usize) {
    if x.len() == n {
        x.fill(0.0);
    } else {
        *x = DVec::zeros(n);
    }
}

/// The dense saddle-point matrix is factored without regularisation while its smallest
/// pivot is at least this fraction of its largest; nearer singular (a dead centre), it
/// is regularised and its solves refined ([`Dynamics::solve_saddle`]).
const EXACT_PIVOT_RATIO: f64 = 1e-8;

/// Reused buffers of the saddle-point solves.
#[derive(Default)]
struct Scratch {
    rhs: Vec<f64>,
    residual: Vec<f64>,
    /// M·a + Φ_qᵀ·λ, and Φ_q·a.
    product: DVec,
    row_product: Vec<f64>,
    /// γ and the solution (a; λ) of [`Dynamics::accelerations_factored`].
    gamma: DVec,
    solution: Vec<f64>,
}

/// Which factorization: the integrator's Newton matrix or the outputs' saddle point.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Which {
    Newton = 0,
    Saddle = 1,
}

/// One factorization of the Newton matrix: the full LU on the pattern and, when no
/// force element couples two parts, the Schur-complement solver; `via_schur` says which
/// one holds the last factors.
pub(crate) struct Factors {
    lu: SparseLu,
    values: Vec<f64>,
    schur: Option<schur::Schur>,
    via_schur: bool,
    /// The factors are of the regularised matrix (a solve must refine).
    regularised: bool,
    /// The Schur path declined a matrix that never changes (the saddle point's, with
    /// constant mass blocks): it is not tried again.
    schur_declined: bool,
}

impl Dynamics {
    /// Sets up the dynamics of an assembled `sys` (velocities consistent) with its
    /// forces; `dropped` lists the rows (in [`System::rows`] order) the redundancy
    /// analysis removed.
    pub fn new(sys: System, mut forces: ForceSet, dropped: &[usize]) -> Result<Dynamics, DynError> {
        forces.prepare(&sys)?;
        Self::with_prepared(sys, forces, dropped)
    }

    /// [`Dynamics::new`] with `forces` prepared for `sys` already ([`ForceSet::prepare`]:
    /// it checks every element's parts fit its duals, which a rerun of the same system
    /// need not do again).
    pub fn with_prepared(
        sys: System,
        forces: ForceSet,
        dropped: &[usize],
    ) -> Result<Dynamics, DynError> {
        Self::with_factors(sys, forces, dropped, Vec::new())
    }

    /// [`Dynamics::with_prepared`] taking the LU solvers of `reuse` (another dynamics'
    /// [`Dynamics::take_factors`]) when their pattern is this system's: their symbolic
    /// analysis is kept, everything else made anew ([`SparseLu::forget`]).
    pub(crate) fn with_factors(
        sys: System,
        forces: ForceSet,
        dropped: &[usize],
        reuse: Vec<Factors>,
    ) -> Result<Dynamics, DynError> {
        let all: Vec<(usize, usize)> = sys.rows().collect();
        let (mut rows, mut drop) = (Vec::new(), Vec::new());
        for (k, r) in all.into_iter().enumerate() {
            if dropped.contains(&k) {
                drop.push(r);
            } else {
                rows.push(r);
            }
        }
        let (n, m) = (sys.ncols(), rows.len());
        let index = |p: PartHandle| sys.part(p).index;
        let row_parts: Vec<Vec<usize>> = rows
            .iter()
            .map(|&(e, q)| {
                row_parts(&sys, e, q)
                    .into_iter()
                    .filter_map(index)
                    .collect()
            })
            .collect();
        let pattern = Self::pattern(&sys, &forces, &row_parts);
        let jac = jacobian::Jacobian::new(sys.dim.cols(), &row_parts);
        let mut prims: Vec<stiffness::ResolvedRow> = rows
            .iter()
            .enumerate()
            .map(|(r, &(e, q))| {
                let p = sys.resolved_primitive(e, q)?;
                let (pi, pj) = p.parts();
                let slot = |h: PartHandle| index(h).and_then(|i| jac.slot_of(r, i));
                Some((p, [slot(pi), slot(pj)]))
            })
            .collect();
        stiffness::freeze_point_rows(&sys, &rows, &mut prims);
        let factors = |pattern: Pattern| -> Result<Factors, DynError> {
            Ok(Factors {
                values: vec![0.0; pattern.nnz()],
                lu: SparseLu::new(pattern).map_err(|_| DynError::Structure)?,
                schur: None,
                via_schur: false,
                regularised: true,
                schur_declined: false,
            })
        };
        let factors = match reuse.len() == 2 && reuse.iter().all(|f| *f.lu.pattern() == pattern) {
            true => reuse
                .into_iter()
                .map(|f| {
                    let mut lu = f.lu;
                    lu.forget();
                    Factors {
                        values: vec![0.0; pattern.nnz()],
                        lu,
                        schur: None,
                        via_schur: false,
                        regularised: true,
                        schur_declined: false,
                    }
                })
                .collect(),
            false => vec![factors(pattern.clone())?, factors(pattern)?],
        };
        let mut d = Dynamics {
            sys,
            forces,
            rows,
            dropped: drop,
            n,
            m,
            a: DVec::zeros(n),
            lambda: DVec::zeros(m),
            stats: Stats::default(),
            factors,
            factor_generation: 0,
            gen: Generalized::new(n),
            phi: DVec::zeros(m),
            may_vanish: (0..m)
                .filter(|&r| {
                    !matches!(
                        prims[r],
                        Some((Primitive::Along(_) | Primitive::Fixed(_), _))
                    )
                })
                .collect(),
            jac_top: 0.0,
            jac,
            prims,
            geo: Vec::new(),
            geo_blocks: Vec::new(),
            row_scratch: Default::default(),
            constant_mass: None,
            fill: fill::Fill::default(),
            isotropic: false,
            scratch: Scratch::default(),
        };
        d.fill = fill::Fill::new(&d.factors[0].lu, &d.sys, &d.jac);
        for f in 0..2 {
            d.factors[f].schur = d.schur_solver();
        }
        let isotropic = d
            .sys
            .parts
            .iter()
            .all(|p| p.index.is_none() || p.isotropic());
        d.isotropic = isotropic;
        if d.mass_is_constant() {
            d.constant_mass = Some(d.mass_blocks().into_owned());
        }
        d.check_massless()?;
        Ok(d)
    }

    /// Moves the measures' unwrapping references (angles past ±π) to the current state,
    /// an accepted one: a step, an equilibrium, a kinematic solution.
    pub fn commit_measures(&mut self) {
        let mut measures = std::mem::take(&mut self.sys.measures);
        measures.commit(&self.sys);
        self.sys.measures = measures;
    }

    /// Kept row `r`'s primitive joint equation, resolved to its parts (None for a
    /// MOTION, GCON or other measured row).
    pub(crate) fn primitive(&self, r: usize) -> Option<Primitive> {
        self.prims[r].map(|(p, _)| p)
    }

    /// The LU solvers, for a new dynamics of the same system
    /// ([`Dynamics::with_factors`]); this one is left without any and must not solve again.
    pub(crate) fn take_factors(&mut self) -> Vec<Factors> {
        std::mem::take(&mut self.factors)
    }

    /// The Newton matrix's pattern: each part's mass block, the blocks force elements
    /// couple, and the constraint rows over the columns of every part they read
    /// (`row_parts`, velocity-layout part indices).
    fn pattern(sys: &System, forces: &ForceSet, row_parts: &[Vec<usize>]) -> Pattern {
        let n = sys.ncols();
        let bs = sys.dim.cols();
        let block = |p: PartHandle| sys.part(p).index.map(|i| i * bs);
        let mut pos = Vec::new();
        let dense = |pos: &mut Vec<(usize, usize)>, r0: usize, nr: usize, c0: usize| {
            for r in r0..r0 + nr {
                for c in c0..c0 + bs {
                    pos.push((r, c));
                }
            }
        };
        for i in 0..sys.moving_parts() {
            dense(&mut pos, i * bs, bs, i * bs);
        }
        for el in &forces.elements {
            let applied = [Some(sys.marker(el.i).part), Some(sys.frame(el.j).part)];
            for p in applied.into_iter().flatten().filter_map(block) {
                for q in el.slots.parts.into_iter().flatten().filter_map(block) {
                    dense(&mut pos, p, bs, q);
                }
            }
        }
        for (r, parts) in row_parts.iter().enumerate() {
            // The multiplier's diagonal holds the regularisation (Dynamics::factor).
            pos.push((n + r, n + r));
            for &i in parts {
                for c in i * bs..(i + 1) * bs {
                    pos.push((n + r, c));
                    pos.push((c, n + r));
                }
            }
        }
        Pattern::new(n + row_parts.len(), pos)
    }

    /// The Schur-complement solver, when the effective mass is block diagonal: no force
    /// element reads or loads more than one moving part.
    fn schur_solver(&self) -> Option<schur::Schur> {
        let sys = &self.sys;
        let index = |p: PartHandle| sys.part(p).index;
        for el in &self.forces.elements {
            let mut touched = [Some(sys.marker(el.i).part), Some(sys.frame(el.j).part)]
                .into_iter()
                .chain(el.slots.parts)
                .flatten()
                .filter_map(index);
            let first = touched.next();
            if touched.any(|i| Some(i) != first) {
                return None;
            }
        }
        Some(schur::Schur::new(&self.jac, sys.moving_parts()))
    }

    /// A part must not have a direction of motion that is massless and free: one along
    /// which its mass matrix vanishes and no constraint row it is in changes. (A point
    /// mass on a pendulum rod is fine: its rotation has no inertia but moves the pin.)
    fn check_massless(&mut self) -> Result<(), DynError> {
        self.eval_constraints(true)?;
        let bs = self.sys.dim.cols();
        let blocks = self.mass_blocks();
        let part_slots = self.jac.part_slots(self.sys.moving_parts());
        for (h, p) in self.sys.parts.iter().enumerate() {
            let Some(i) = p.index else { continue };
            // Mass in every direction (relative to the largest): nothing to check.
            let (lo, hi) = match blocks[i] {
                Mat3Block::Three(m, j) => {
                    let eig = j.symmetric_eigenvalues();
                    (m.min(eig.min()), m.max(eig.max()))
                }
                Mat3Block::Two(m, j) => (m.min(j), m.max(j)),
            };
            if lo > 1e-9 * hi {
                continue;
            }
            // Otherwise the mass block stacked on the rows that read the part must have
            // full rank: each massless direction held by a constraint.
            let slots = &part_slots[i];
            let mut stack = crate::vocab::math::DMat::zeros(bs + slots.len(), bs);
            match blocks[i] {
                Mat3Block::Three(m, j) => {
                    for c in 0..3 {
                        stack[(c, c)] = m;
                        for r in 0..3 {
                            stack[(3 + r, 3 + c)] = j[(r, c)];
                        }
                    }
                }
                Mat3Block::Two(m, j) => {
                    (stack[(0, 0)], stack[(1, 1)], stack[(2, 2)]) = (m, m, j);
                }
            }
            let top = stack.amax();
            if top > 0.0 {
                stack /= top;
            }
            for (row, &k) in slots.iter().enumerate() {
                for (c, &x) in self.jac.block(k).iter().enumerate() {
                    stack[(bs + row, c)] = x;
                }
                let top = stack.row(bs + row).amax();
                if top > 0.0 {
                    stack.row_mut(bs + row).scale_mut(1.0 / top);
                }
            }
            let sv = stack.singular_values();
            let rank = sv.iter().filter(|&&s| s > 1e-9).count();
            if rank < bs {
                let name = p.id.map_or(format!("part {h}"), |id| format!("PART/{id}"));
                return Err(DynError::Massless {
                    part: name,
                    directions: bs - rank,
                });
            }
        }
        Ok(())
    }

    /// Φ over the kept rows (into `self.phi`) and, with `jacobian`, Φ_q (into
    /// `self.jac`; a non-holonomic row holds ∂f/∂v).
    pub fn eval_constraints(&mut self, jacobian: bool) -> Result<(), MbdError> {
        // Every GCON in one call at this state; the rows read it, and only they.
        self.sys.eval_fused_rows(jacobian);
        let rows = self.eval_rows(jacobian);
        self.sys.forget_fused_rows();
        rows
    }

    /// [`Dynamics::eval_constraints`]' rows.
    fn eval_rows(&mut self, jacobian: bool) -> Result<(), MbdError> {
        let bs = self.sys.dim.cols();
        let comps = self.sys.column_components();
        for (r, &(e, q)) in self.rows.iter().enumerate() {
            // The primitives (nearly every row of a jointed model) write their blocks
            // directly.
            if let Some((p, slots)) = &self.prims[r] {
                let (mut si, mut sj) = ([0.0; 6], [0.0; 6]);
                if bs == 6 {
                    // 3D: the columns are the six components in order, written in place
                    let (gi, gj) = match jacobian {
                        true => self.jac.six_blocks_mut(slots[0], slots[1]),
                        false => (None, None),
                    };
                    self.phi[r] = self.sys.eval_primitive_into(
                        p,
                        gi.unwrap_or(&mut si),
                        gj.unwrap_or(&mut sj),
                    );
                    continue;
                }
                self.phi[r] = self.sys.eval_primitive_into(p, &mut si, &mut sj);
                if jacobian {
                    // 2D: each part's columns gather their components. The two slots are
                    // distinct parts (a row within one part reads it once).
                    for (g, k) in [&si, &sj].into_iter().zip(slots) {
                        let Some(k) = *k else { continue };
                        for (b, &c) in self.jac.block_at_mut(k).iter_mut().zip(&comps[..bs]) {
                            *b = g[c];
                        }
                    }
                }
                continue;
            }
            if matches!(
                self.sys.elements[e].eqs[q].row,
                Row::Gcon { .. } | Row::Measured { drive: Some(_), .. }
            ) {
                self.stats.expression_evaluations += 1;
            }
            let ev = &mut self.row_scratch;
            self.sys.eval_row_into(e, q, jacobian, ev)?;
            self.phi[r] = ev.value;
            if jacobian {
                let entries = if self.sys.row_reads_velocity(e, q) {
                    &ev.dv
                } else {
                    &ev.dq
                };
                self.jac.clear_row(r);
                for &(c, x) in entries {
                    let read = self.jac.add(r, c, x);
                    debug_assert!(read, "row {r} reads column {c} outside its parts");
                }
            }
        }
        Ok(())
    }

    /// Q (gravity, force elements, gyroscopic moments) into `self.gen`, with ∂Q/∂q and
    /// ∂Q/∂v when `jacobians`.
    pub fn eval_forces(&mut self, jacobians: bool) -> Result<(), MbdError> {
        self.gen.clear();
        let bs = self.sys.dim.cols();
        let g = self.sys.gravity / self.sys.ucf;
        for p in &self.sys.parts {
            let Some(i) = p.index else { continue };
            let b = i * bs;
            match self.sys.dim {
                Dimension::Three => {
                    for c in 0..3 {
                        self.gen.q[b + c] += p.mass * g[c];
                    }
                    // −ω × (J ω), with ∂/∂ω = −([ω]× J − [J ω]×) and, through J = R J Rᵀ
                    // turning with δR = [δθ]× R, ∂/∂θ = [ω]× ([J ω]× − J [ω]×). All
                    // three vanish when J is isotropic.
                    if p.isotropic() {
                        continue;
                    }
                    let j = self.inertia_over_ucf(p);
                    let jw = j * p.w;
                    let gyro = -p.w.cross(&jw);
                    for c in 0..3 {
                        self.gen.q[b + 3 + c] += gyro[c];
                    }
                    if jacobians && p.w.norm() > 0.0 {
                        let wx = p.w.cross_matrix();
                        let dw = -(wx * j - jw.cross_matrix());
                        let dth = wx * (jw.cross_matrix() - j * wx);
                        for r in 0..3 {
                            for c in 0..3 {
                                self.gen.dv.push((b + 3 + r, b + 3 + c, dw[(r, c)]));
                                self.gen.dq.push((b + 3 + r, b + 3 + c, dth[(r, c)]));
                            }
                        }
                    }
                }
                Dimension::Two => {
                    let (x, y, _) = self.sys.plane_axes();
                    self.gen.q[b] += p.mass * g[x];
                    self.gen.q[b + 1] += p.mass * g[y];
                }
            }
        }
        self.stats.expression_evaluations += self.forces.expression_count();
        if !self.forces.reads_solution() {
            return self.forces.eval(&self.sys, &mut self.gen, jacobians);
        }
        // Each element after the forces it reads, its solution values read just before
        // it: accelerations and multipliers as they stand (`a`, `lambda`, the parts'),
        // forces as this pass left them.
        for o in 0..self.forces.order.len() {
            let k = self.forces.order[o];
            for r in 0..self.forces.reads[k].len() {
                let s = self.forces.reads[k][r];
                self.forces.solved[s] = self.forces.solution[s].value(self);
            }
            self.forces
                .eval_element(k, &self.sys, &mut self.gen, jacobians)?;
        }
        Ok(())
    }

    /// R·J·Rᵀ of part `p` divided by UCF (1 in SI models: then not divided, nine
    /// divisions saved a part, the same bits).
    #[inline(always)]
    fn inertia_over_ucf(&self, p: &super::system::Part) -> Mat3 {
        match self.sys.ucf {
            1.0 => p.inertia_global(),
            u => p.inertia_global() / u,
        }
    }

    /// The mass matrix block of moving part `i` over its columns, divided by UCF.
    #[inline(always)]
    pub fn mass_block(&self, p: &super::system::Part) -> Mat3Block {
        let u = self.sys.ucf;
        match self.sys.dim {
            Dimension::Three => Mat3Block::Three(p.mass / u, self.inertia_over_ucf(p)),
            Dimension::Two => {
                // n·(R·J·Rᵀ)·n = (Rᵀn)·J·(Rᵀn).
                let n = p
                    .rot
                    .inverse_transform_vector(&Vec3::ith(self.sys.normal, 1.0));
                Mat3Block::Two(p.mass / u, n.dot(&(p.inertia * n)) / u)
            }
        }
    }

    /// Whether the mass blocks never change: in 2D, and in 3D when every moving part's
    /// inertia is isotropic.
    fn mass_is_constant(&self) -> bool {
        self.sys.dim == Dimension::Two || self.isotropic
    }

    /// Every moving part's mass block (divided by UCF) at the current state, in part
    /// order. In 2D (and for isotropic parts) they never change and are computed once.
    pub fn mass_blocks(&self) -> std::borrow::Cow<'_, [Mat3Block]> {
        if let Some(b) = &self.constant_mass {
            return std::borrow::Cow::Borrowed(b);
        }
        // sized up front: a filtered collect grows by reallocation, a copy each time
        let mut blocks = Vec::with_capacity(self.sys.parts.len());
        blocks.extend(
            self.sys
                .parts
                .iter()
                .filter(|p| p.index.is_some())
                .map(|p| self.mass_block(p)),
        );
        std::borrow::Cow::Owned(blocks)
    }

    /// w·M·x added to `out` (x in the velocity layout), M given by its `blocks`.
    pub fn add_blocks_times(&self, blocks: &[Mat3Block], w: f64, x: &[f64], out: &mut DVec) {
        let bs = self.sys.dim.cols();
        for (i, blk) in blocks.iter().enumerate() {
            let b = i * bs;
            match *blk {
                Mat3Block::Three(m, j) => {
                    for c in 0..3 {
                        out[b + c] += w * m * x[b + c];
                    }
                    let t = j * Vec3::new(x[b + 3], x[b + 4], x[b + 5]);
                    for c in 0..3 {
                        out[b + 3 + c] += w * t[c];
                    }
                }
                Mat3Block::Two(m, j) => {
                    out[b] += w * m * x[b];
                    out[b + 1] += w * m * x[b + 1];
                    out[b + 2] += w * j * x[b + 2];
                }
            }
        }
    }

    /// M·x / UCF added to `out` (x in the velocity layout), M at the current state.
    pub fn add_mass_times(&self, x: &[f64], out: &mut DVec) {
        self.add_blocks_times(&self.mass_blocks(), 1.0, x, out);
    }

    /// w·M / UCF added to the top-left n × n of the dense matrix `a`, M at the current
    /// state (the static Newton matrix and the linearization want it whole).
    pub fn add_mass_matrix(&self, w: f64, a: &mut crate::vocab::math::DMat) {
        let bs = self.sys.dim.cols();
        for (i, b) in self.mass_blocks().iter().enumerate() {
            let c = i * bs;
            match *b {
                Mat3Block::Three(mass, j) => {
                    for r in 0..3 {
                        a[(c + r, c + r)] += w * mass;
                        for k in 0..3 {
                            a[(c + 3 + r, c + 3 + k)] += w * j[(r, k)];
                        }
                    }
                }
                Mat3Block::Two(mass, j) => {
                    a[(c, c)] += w * mass;
                    a[(c + 1, c + 1)] += w * mass;
                    a[(c + 2, c + 2)] += w * j;
                }
            }
        }
    }

    /// Φ_qᵀ·λ added to `out`, with the Φ_q of the last [`Dynamics::eval_constraints`].
    pub fn add_constraint_forces(&self, lambda: &DVec, out: &mut DVec) {
        self.jac.add_transpose_times(lambda.as_slice(), 1.0, out);
    }

    /// Fills and factors the Newton matrix with weights `w` from the last evaluations of
    /// constraints (with Jacobian) and forces (with Jacobians).
    /// Factors the Newton matrix with weights `w` at the current state and multipliers
    /// `lambda` (their geometric stiffness enters with w_k).
    pub fn factor(&mut self, w: Weights, lambda: &DVec) -> Result<(), DynError> {
        if w.w_k != 0.0 {
            self.geometric_stiffness(lambda);
        } else {
            self.geo.clear();
        }
        self.factor_into(Which::Newton, w)
    }

    fn factor_into(&mut self, which: Which, w: Weights) -> Result<(), DynError> {
        // Where the constraints lose rank for an instant (a four-bar passing its dead
        // centre), the saddle-point matrix is singular although the motion goes on. A
        // regularisation −ε·I on the multipliers' block, ε = 1e-10 of the Schur complement's
        // scale |Φ_q|²/m, keeps it factorable; it changes the Newton matrix only, so a
        // converged step still solves the equations exactly. A row whose Jacobian has
        // vanished altogether constrains nothing any more: that is reported.
        let top = self.jac.amax();
        self.jac_top = top;
        self.check_rows()?;
        // (Constant blocks are lent out for the factorization rather than copied.)
        let blocks = match self.constant_mass.take() {
            Some(b) => b,
            None => self.mass_blocks().into_owned(),
        };
        let factored = self.factor_blocks(which, w, &blocks, top);
        if self.mass_is_constant() {
            self.constant_mass = Some(blocks);
        }
        factored
    }

    /// [`Dynamics::factor_into`] with the mass blocks `blocks` and the Jacobian's
    /// largest entry `top`.
    fn factor_blocks(
        &mut self,
        which: Which,
        w: Weights,
        blocks: &[Mat3Block],
        top: f64,
    ) -> Result<(), DynError> {
        let time = self.sys.time;
        let heaviest = blocks
            .iter()
            .map(|b| match b {
                Mat3Block::Three(m, j) => m.max(j.amax()),
                Mat3Block::Two(m, j) => m.max(*j),
            })
            .fold(0.0f64, f64::max);
        let eps = 1e-10 * w.w_l * top * top / heaviest.max(f64::MIN_POSITIVE);
        self.stats.factorizations += 1;
        if which == Which::Newton {
            self.factor_generation += 1;
        }
        let constant = self.mass_is_constant();
        let f = &mut self.factors[which as usize];
        f.via_schur = false;
        f.regularised = true;
        // A NaN or infinity in the matrix makes the Schur path decline (its block
        // inverses and factorizations check); the full LU then reports it.
        if let (Some(schur), false) = (&mut f.schur, f.schur_declined) {
            match schur.factor(&self.jac, blocks, &self.gen, &self.geo, w, eps) {
                Ok(true) => {
                    f.via_schur = true;
                    return Ok(());
                }
                // The saddle point's blocks are the mass's: when that never changes, a
                // block the Schur path cannot invert never will be.
                Ok(false) if which == Which::Saddle && constant => {
                    f.schur_declined = true;
                }
                _ => {}
            }
        }
        // The saddle point's dense matrix is factored as it is unless it is nearly
        // singular: its solves then need no refinement.
        if which == Which::Saddle && f.lu.pivot_ratio().is_some() {
            let f = &mut self.factors[which as usize];
            if self
                .fill
                .factor(f, blocks, &self.jac, &self.gen, &self.geo, w, 0.0)
                .is_ok()
                && f.lu.pivot_ratio().is_some_and(|r| r >= EXACT_PIVOT_RATIO)
            {
                f.regularised = false;
                return Ok(());
            }
        }
        let f = &mut self.factors[which as usize];
        let factored = self
            .fill
            .factor(f, blocks, &self.jac, &self.gen, &self.geo, w, eps);
        let culprit = if factored.is_err() {
            self.singular_culprit()
        } else {
            None
        };
        factored.map_err(|e| match e {
            FactorError::NotFinite => DynError::NotFinite {
                time,
                what: NonFinite::NewtonMatrix,
                element: None,
            },
            FactorError::Singular => DynError::Singular {
                time,
                why: Singularity::Dependent,
                culprit,
            },
        })
    }

    /// A kept row whose Jacobian vanished at the last evaluation constrains nothing any
    /// more: the Newton matrix is singular there, even while an older factorization
    /// still converges.
    pub fn check_rows(&self) -> Result<(), DynError> {
        match self.vanished_row() {
            Some(r) => Err(DynError::Singular {
                time: self.sys.time,
                why: Singularity::VanishedRow,
                culprit: Some(self.row_culprit(r)),
            }),
            None => Ok(()),
        }
    }

    /// Solves the factored Newton matrix in place.
    pub fn solve(&mut self, rhs: &mut [f64]) -> Result<(), DynError> {
        self.solve_with(Which::Newton, rhs)
    }

    fn solve_with(&mut self, which: Which, rhs: &mut [f64]) -> Result<(), DynError> {
        let time = self.sys.time;
        let f = &mut self.factors[which as usize];
        let solved = match (&mut f.schur, f.via_schur) {
            (Some(schur), true) => schur.solve(rhs),
            _ => f.lu.solve(rhs),
        };
        let solved = solved.and_then(|()| match rhs.iter().all(|x| x.is_finite()) {
            true => Ok(()),
            false => Err(FactorError::Singular),
        });
        let culprit = if solved.is_err() {
            self.singular_culprit()
        } else {
            None
        };
        solved.map_err(|_| DynError::Singular {
            time,
            why: Singularity::Numerical,
            culprit,
        })
    }

    /// The element of the kept row with the largest residual at the last constraint
    /// evaluation (translational rows over the model length).
    pub fn worst_row(&self) -> Option<Culprit> {
        (0..self.m)
            .max_by(|&a, &b| self.scaled_residual(a).total_cmp(&self.scaled_residual(b)))
            .map(|r| self.row_culprit(r))
    }

    /// |Φ| of kept row `r` at the last evaluation, translational rows over the model
    /// length.
    pub fn scaled_residual(&self, r: usize) -> f64 {
        let (e, q) = self.rows[r];
        self.phi[r].abs() * self.sys.row_scale(e, q)
    }

    fn row_culprit(&self, r: usize) -> Culprit {
        Culprit::Element(self.sys.elements[self.rows[r].0].elref.clone())
    }

    /// A kept row whose Jacobian (the last evaluation's) has vanished: it constrains
    /// nothing any more.
    fn vanished_row(&self) -> Option<usize> {
        let floor = 1e-12 * self.jac_top;
        self.may_vanish
            .iter()
            .copied()
            .find(|&r| !self.jac.row_exceeds(r, floor))
    }

    /// Names what makes the Newton matrix singular: a kept row whose Jacobian vanishes
    /// (the constraint no longer constrains anything), else the row with the largest
    /// residual.
    pub fn singular_culprit(&self) -> Option<Culprit> {
        self.vanished_row()
            .map(|r| self.row_culprit(r))
            .or_else(|| self.worst_row())
    }

    /// The part whose velocity-layout column is `col`.
    pub fn part_of_column(&self, col: usize) -> Option<Culprit> {
        let i = col / self.sys.dim.cols();
        self.sys
            .parts
            .iter()
            .find(|p| p.index == Some(i))
            .and_then(|p| p.id)
            .map(Culprit::Part)
    }

    /// The current poses, velocities and time.
    pub fn snapshot(&self) -> Snapshot {
        Snapshot {
            poses: self.sys.snapshot(),
            v: self.sys.v(),
            time: self.sys.time,
        }
    }

    /// Returns to a [`Snapshot`].
    pub fn restore(&mut self, s: &Snapshot) {
        self.sys.restore(&s.poses);
        self.sys.set_v(&s.v);
        self.sys.time = s.time;
    }

    /// Sets the configuration to `base` moved by the increment `dx` (velocity layout:
    /// δr and a rotation vector, global), and the velocities to `v`.
    pub fn set_state(&mut self, base: &Snapshot, dx: &[f64], v: &DVec, time: f64) {
        self.sys.set_moved(&base.poses, dx);
        self.sys.set_v(v);
        self.sys.time = time;
    }

    /// The increment that takes `from` to `to` (velocity layout: δr and the global
    /// rotation vector of R_to·R_fromᵀ in 3D, δx, δy, δθ in 2D) into `out`: the inverse
    /// of [`Dynamics::set_state`]'s move, the chart the multistep methods work in.
    pub fn increment(&self, from: &Snapshot, to: &Snapshot, out: &mut [f64]) {
        let bs = self.sys.dim.cols();
        let (a, b, _) = self.sys.plane_axes();
        for (p, (f, t)) in self.sys.parts.iter().zip(from.poses.iter().zip(&to.poses)) {
            let Some(i) = p.index else { continue };
            let d = &mut out[i * bs..(i + 1) * bs];
            let dr = t.0 - f.0;
            match self.sys.dim {
                Dimension::Three => {
                    let th = (t.1 * f.1.inverse()).scaled_axis();
                    d.copy_from_slice(&[dr[0], dr[1], dr[2], th[0], th[1], th[2]]);
                }
                Dimension::Two => d.copy_from_slice(&[dr[a], dr[b], t.2 - f.2]),
            }
        }
    }

    /// The size of the coordinates: the largest part position component, at least the
    /// model length (their rounding is the floor of every Newton correction).
    pub fn reach(&self) -> f64 {
        self.sys
            .parts
            .iter()
            .map(|p| newmark::largest_magnitude(p.r.as_slice()))
            .fold(self.sys.length, f64::max)
    }

    /// Per-column scale of the local error: ERROR × the model length for translations,
    /// ERROR for rotations.
    pub fn tolerances(&self, error: f64) -> Vec<f64> {
        let bs = self.sys.dim.cols();
        let trans = self.sys.dim.axes();
        (0..self.n)
            .map(|c| match c % bs < trans {
                true => error * self.sys.length,
                false => error,
            })
            .collect()
    }

    /// Consistent accelerations and multipliers at the current state (spec §6.1 phase
    /// 3): M·a/UCF + Φ_qᵀλ = Q, Φ_q·a = γ.
    pub fn solve_accelerations(&mut self) -> Result<(), DynError> {
        self.eval_constraints(true)?;
        self.factor_saddle()?;
        self.accelerations_factored()
    }

    /// Reconciles the state for output (as Adams does at output steps): velocities
    /// projected onto the velocity constraints, closest in the mass metric
    /// ([[M, Φ_qᵀ], [Φ_q, 0]]·[δv; μ] = [0; −(Φ_q·v + Φ_t)]), then the consistent
    /// accelerations and multipliers, both from one factorization. The index-3 integrators
    /// keep positions on the constraints but let velocities drift by their error.
    pub fn reconcile(&mut self) -> Result<(), DynError> {
        self.eval_constraints(true)?;
        self.factor_saddle()?;
        let v = self.sys.v();
        let mut rhs = vec![0.0; self.n + self.m];
        let mut jv = vec![0.0; self.m];
        self.jac.add_times(v.as_slice(), &mut jv);
        for (r, x) in jv.iter().enumerate() {
            rhs[self.n + r] -= x;
        }
        for (r, &(e, q)) in self.rows.iter().enumerate() {
            if self.sys.row_reads_velocity(e, q) {
                // A non-holonomic row holds ∂f/∂v: its velocity residual is f itself.
                rhs[self.n + r] = -self.phi[r];
            } else {
                rhs[self.n + r] -= self.sys.row_dt(e, q)?;
            }
        }
        self.solve_saddle(&mut rhs)?;
        let v = v + DVec::from_column_slice(&rhs[..self.n]);
        self.sys.set_v(&v);
        self.accelerations_factored()
    }

    /// Projects the positions onto the position constraints Φ(q, t) = 0, closest in the
    /// mass metric (the coordinate projection of an explicit method's step): Newton with
    /// [[M/UCF, Φ_qᵀ], [Φ_q, 0]]·[δq; μ] = [0; −Φ], δq applied as a velocity-layout
    /// increment (rotations compose). The factorization at the first iterate serves the
    /// next ones while they contract (what they correct is a step's local error, so the
    /// frozen Jacobian is exact to about that); one that does not contract refactors.
    /// Stops with the largest scaled residual of the position rows within `tol`, or at
    /// the rounding floor, where a fresh factorization no longer contracts (having
    /// improved on the start); fails with [`DynError::Newton`] when neither happens in a
    /// few iterations. Non-holonomic rows constrain velocities only and are left out.
    /// Velocities, accelerations and multipliers are left as they are:
    /// [`Dynamics::reconcile`] follows.
    pub fn project_positions(&mut self, tol: f64) -> Result<(), DynError> {
        const ITERATIONS: usize = 8;
        let (n, m) = (self.n, self.m);
        let positional: Vec<bool> = self
            .rows
            .iter()
            .map(|&(e, q)| !self.sys.row_reads_velocity(e, q))
            .collect();
        let worst = |d: &Dynamics| {
            (0..m)
                .filter(|&r| positional[r])
                .map(|r| d.scaled_residual(r))
                .fold(0.0, f64::max)
        };
        self.eval_constraints(true)?;
        let first = worst(self);
        let mut residual = first;
        // Whether the factorization is the current iterate's.
        let mut fresh = false;
        let mut factored = false;
        let mut rhs = vec![0.0; n + m];
        for _ in 0..ITERATIONS {
            if residual <= tol {
                return Ok(());
            }
            if !factored {
                self.factor_saddle()?;
                (factored, fresh) = (true, true);
            }
            rhs.fill(0.0);
            for r in (0..m).filter(|&r| positional[r]) {
                rhs[n + r] = -self.phi[r];
            }
            self.solve_saddle(&mut rhs)?;
            self.stats.newton_iterations += 1;
            self.sys.apply_increment(&rhs[..n]);
            // The Jacobian stays the factorization's: the refinement in the solve uses it.
            self.eval_constraints(false)?;
            let next = worst(self);
            if !next.is_finite() {
                break;
            }
            if next > 0.5 * residual {
                if fresh && next < first {
                    // Newton with the exact Jacobian stalls only at rounding.
                    return Ok(());
                }
                if fresh {
                    break;
                }
                self.eval_constraints(true)?;
                factored = false;
            }
            (residual, fresh) = (next, false);
        }
        Err(DynError::Newton {
            time: self.sys.time,
            step: 0.0,
            culprit: self.worst_row(),
        })
    }

    /// Solves [[M/UCF, Φ_qᵀ], [Φ_q, 0]]·x = b in place with the factorization of
    /// [`Dynamics::factor_saddle`]: its regularisation is taken back out by iterative
    /// refinement against the exact matrix (a direct solve, unlike a Newton step, would
    /// keep the regularisation's bias).
    fn solve_saddle(&mut self, b: &mut [f64]) -> Result<(), DynError> {
        let n = self.n;
        let mut s = std::mem::take(&mut self.scratch);
        s.rhs.clear();
        s.rhs.extend_from_slice(b);
        let mut solved = self.solve_with(Which::Saddle, b);
        if solved.is_ok() && self.factors[Which::Saddle as usize].regularised {
            for _ in 0..3 {
                // r = rhs − [[M, Φ_qᵀ], [Φ_q, 0]]·b.
                zero_into(&mut s.product, n);
                let (a, lambda) = b.split_at(n);
                self.add_mass_times(a, &mut s.product);
                self.jac.add_transpose_times(lambda, 1.0, &mut s.product);
                s.residual.clear();
                s.residual.extend((0..n).map(|k| s.rhs[k] - s.product[k]));
                s.residual.extend_from_slice(&s.rhs[n..]);
                s.row_product.clear();
                s.row_product.resize(self.m, 0.0);
                self.jac.add_times(a, &mut s.row_product);
                for (x, y) in s.residual[n..].iter_mut().zip(&s.row_product) {
                    *x -= y;
                }
                let size = b.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                solved = self.solve_with(Which::Saddle, &mut s.residual);
                if solved.is_err() {
                    break;
                }
                let step = s.residual.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                for (x, d) in b.iter_mut().zip(&s.residual) {
                    *x += d;
                }
                if step <= 1e-15 * size {
                    break;
                }
            }
        }
        self.scratch = s;
        solved
    }

    /// Factors [[M/UCF, Φ_qᵀ], [Φ_q, 0]] from the last constraint evaluation.
    fn factor_saddle(&mut self) -> Result<(), DynError> {
        self.stats.jacobian_evaluations += 1;
        self.factor_into(
            Which::Saddle,
            Weights {
                w_m: 1.0,
                w_k: 0.0,
                w_c: 0.0,
                w_l: 1.0,
            },
        )
    }

    /// The accelerations and multipliers with the saddle-point matrix factored. Forces
    /// that read accelerations or reactions make this a fixed point: solved by repeating
    /// the solve with the forces at the last accelerations and multipliers until they
    /// settle (at the loop's gain per sweep).
    fn accelerations_factored(&mut self) -> Result<(), DynError> {
        // (Buffers taken out of the scratch are put back on success; a failure ends the
        // attempt, and a lost buffer is only allocated again.)
        let mut gamma = std::mem::take(&mut self.scratch.gamma);
        gamma::gamma(self, &mut gamma)?;
        let mut rhs = std::mem::take(&mut self.scratch.solution);
        let looped = self.forces.reads_solution();
        let mut last_change = f64::INFINITY;
        let mut stalled = 0;
        for _ in 0..SOLUTION_SWEEPS {
            self.eval_forces(false)?;
            self.check_forces()?;
            rhs.clear();
            rhs.extend_from_slice(self.gen.q.as_slice());
            rhs.extend_from_slice(gamma.as_slice());
            self.solve_saddle(&mut rhs)?;
            let (a, lambda) = rhs.split_at(self.n);
            let change = if looped && self.a.len() == self.n && self.lambda.len() == self.m {
                let diff = |x: &[f64], y: &DVec| {
                    x.iter()
                        .zip(y.iter())
                        .fold(0.0f64, |m, (p, q)| m.max((p - q).abs()))
                };
                let size = rhs.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                diff(a, &self.a).max(diff(lambda, &self.lambda)) / (size + f64::MIN_POSITIVE)
            } else {
                f64::INFINITY
            };
            copy_into(&mut self.a, a);
            copy_into(&mut self.lambda, lambda);
            self.store_accelerations();
            if !looped || change <= SOLUTION_TOL {
                (self.scratch.gamma, self.scratch.solution) = (gamma, rhs);
                return Ok(());
            }
            stalled = if change < 0.9 * last_change {
                0
            } else {
                stalled + 1
            };
            if stalled >= 5 {
                break;
            }
            last_change = change;
        }
        Err(self.solution_loop())
    }

    /// The failure of a force–solution loop that does not settle: names the first force
    /// reading an acceleration or a reaction, and what it reads.
    fn solution_loop(&self) -> DynError {
        let f = &self.forces;
        // Forces that read only forces settle in one ordered pass: the loop that did not
        // runs through an acceleration or a reaction (any read, should that ever not be).
        let reads = |motion: bool| {
            f.reads.iter().enumerate().find_map(|(k, reads)| {
                reads
                    .iter()
                    .find(|&&s| !motion || f.solution[s].reads_motion())
                    .map(|&s| (k, s))
            })
        };
        let (k, s) = reads(true).or_else(|| reads(false)).unwrap_or((0, 0));
        DynError::Model(MbdError::SolutionLoop {
            element: f.elements[k].elref.clone(),
            reads: f.names.get(s).cloned().unwrap_or_default(),
        })
    }

    /// NaN or infinity in the generalized forces: names the element.
    pub fn check_forces(&self) -> Result<(), DynError> {
        if self.gen.q.iter().all(|x| x.is_finite()) {
            return Ok(());
        }
        let element = self
            .forces
            .loads
            .iter()
            .zip(&self.forces.elements)
            .find(|(l, _)| {
                ![l.on_i.0, l.on_i.1, l.on_j.0, l.on_j.1]
                    .iter()
                    .all(|v| v.iter().all(|x| x.is_finite()))
            })
            .map(|(_, e)| e.elref.clone());
        Err(DynError::NotFinite {
            time: self.sys.time,
            what: match element {
                Some(_) => NonFinite::Force,
                None => NonFinite::Inertial,
            },
            element,
        })
    }

    /// Copies the accelerations into the parts (for acceleration measures and outputs).
    pub fn store_accelerations(&mut self) {
        for h in 1..self.sys.parts.len() {
            let ph = PartHandle(h as u32);
            let mut acc = [0.0; 6];
            for (c, x) in acc.iter_mut().enumerate() {
                if let Some(col) = self.sys.col(ph, c) {
                    *x = self.a[col];
                }
            }
            let p = self.sys.part_mut(ph);
            p.acc = Vec3::new(acc[0], acc[1], acc[2]);
            p.alpha = Vec3::new(acc[3], acc[4], acc[5]);
        }
    }

    /// The largest residual of the kept rows (model units) and of the dropped rows, the
    /// latter checked against `tol`: a violated dropped row is a conflict.
    pub fn check_dropped(&self, tol: f64) -> Result<f64, DynError> {
        let mut worst: f64 = 0.0;
        for &(e, q) in &self.dropped {
            let scaled = self.sys.row_value(e, q)? * self.sys.row_scale(e, q);
            if scaled.abs() > tol || scaled.is_nan() {
                return Err(DynError::DroppedViolated {
                    time: self.sys.time,
                    element: self.sys.elements[e].elref.clone(),
                    equation: self.sys.elements[e].eqs[q].label.label(),
                    residual: scaled.abs(),
                });
            }
            worst = worst.max(scaled.abs());
        }
        Ok(worst)
    }
}

/// One part's mass block divided by UCF: 3D (m, R·J·Rᵀ) or 2D (m, J about the normal).
#[derive(Clone, Copy, Debug)]
pub enum Mat3Block {
    /// 3D: mass and the inertia tensor in global axes.
    Three(f64, Mat3),
    /// 2D: mass and the inertia about the plane's normal.
    Two(f64, f64),
}

/// The parts a constraint row reads (its markers', or its measures' markers').
pub fn row_parts(sys: &System, e: usize, q: usize) -> Vec<PartHandle> {
    let mut out = Vec::new();
    let mut add = |m: Option<super::system::MarkerHandle>| {
        let p = sys.frame(m).part;
        if !out.contains(&p) {
            out.push(p);
        }
    };
    match &sys.elements[e].eqs[q].row {
        Row::Along { i, j, .. } | Row::Dot { i, j, .. } => {
            add(Some(*i));
            add(Some(*j));
        }
        Row::Measured { terms, .. } => {
            for &(_, m) in terms {
                for mk in sys.measures.list[m].markers() {
                    add(mk);
                }
            }
        }
        Row::Gcon { map, .. } => {
            for &m in map {
                for mk in sys.measures.list[m].markers() {
                    add(mk);
                }
            }
        }
    }
    out
}
