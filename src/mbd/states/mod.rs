//! The state elements in the core (issue 40 §3): DIFF, LSE and TFSISO as one block of
//! first-order states x with ẋ = f(x, q, v, t) (or, for an IMPLICIT DIFF, 0 = f(ẋ, x, q,
//! v, t)), whose values the expressions read through [`Measure::State`] (DIF, DIF1, and
//! ARYVAL of an X, U or Y array).
//!
//! **How the integrators carry them.** The states are components of each integrator's
//! own state vector: the integrator says, for the evaluations of a step, how x follows
//! from ẋ in its formula, x = b + g·ẋ ([`StateSet::set_formula`]: a BDF's predictor form
//! with its own g, the Newmark family's γ-rule, an explicit stage's sum with g = 0), and
//! every evaluation of the forces solves the block's equations for ẋ under that formula
//! at the current (q, v, t) ([`StateSet::solve`]: Newton on ẋ with a finite-difference
//! Jacobian of the small block, or the rates directly when g = 0 and no DIFF is
//! IMPLICIT). The integrator keeps the states' history, their error estimate and their
//! continuous extension beside its own. The accepted step commits the states
//! ([`StateSet::commit`]); between steps, and after a rejection ([`StateSet::hold`]),
//! the evaluations hold x at the committed values.
//!
//! **Statics** ([`Mode::Static`]) solves ẋ = 0 for the states without STATIC_HOLD and
//! keeps the others at their current values.
//!
//! **What the expressions read.** Kinematic measures, time and state values through
//! the system's measures; and, as force expressions do ([`Source::Solution`]), what only
//! the dynamics gives: a joint's or primitive's reaction, a force element's value, the
//! net load FX…TM between two markers, an acceleration. Those are listed in
//! [`StateSet::solution`] and their values ([`StateSet::solved`]) are filled in by the
//! dynamics before every solve (`Dynamics::fill_state_inputs`), at the current
//! iterate's multipliers and accelerations: the state block is then solved with them
//! held, and the integrators' bordered Newton matrix carries ∂Rₛ/∂λ and ∂Rₛ/∂a
//! (`dynamics::states_border`), so a loop force → reaction → state → force converges
//! as Newton. An applied force's value is the one of the evaluation before (the
//! states are solved before the forces): exact once the iteration has settled.
//!
//! The block also carries joint friction's stiction deformations (the `stiction`
//! file): states of the same kind whose values the friction reads.
//!
//! [`Measure::State`]: crate::mbd::measure_set::Measure::State
//! [`Source::Solution`]: crate::mbd::forces::Source::Solution

mod solve;
mod stiction;

use super::error::MbdError;
use super::expr::ExprFn;
use super::forces::Source;
use super::output_slot::OutputSlot;
use crate::model::states::{LinearSystem, Statement};

/// How the states are solved at an evaluation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Mode {
    /// x = b + g·ẋ in the integrator's formula (a run).
    #[default]
    Dynamic,
    /// ẋ = 0, STATIC_HOLD states held (statics).
    Static,
}

/// An expression of the states with the values its slots read.
pub(crate) struct StateExpr {
    /// The compiled expression.
    pub(crate) f: Box<dyn ExprFn>,
    /// Where each of its slots is read from, in the order of [`ExprFn::slots`]: a
    /// system measure, or a solution value (an index into [`StateSet::solution`]).
    pub(crate) map: Vec<Source>,
}

/// A DIFF in the core.
pub(crate) struct DiffState {
    /// `DIFF/3`.
    pub(crate) label: String,
    /// The same, as a place for diagnostics.
    pub(crate) statement: Statement,
    /// FUNCTION.
    pub(crate) f: StateExpr,
    /// IMPLICIT.
    pub(crate) implicit: bool,
    /// STATIC_HOLD.
    pub(crate) static_hold: bool,
    /// IC: x and (IMPLICIT) the first guess of ẋ.
    pub(crate) ic: (f64, f64),
}

/// An LSE or TFSISO in the core: its matrices and its inputs' expressions.
pub(crate) struct LinearState {
    /// The matrices and sizes.
    pub(crate) sys: LinearSystem,
    /// The expression of each input (its VARIABLE's FUNCTION).
    pub(crate) inputs: Vec<StateExpr>,
    /// Its first state value ([`crate::model::states::StateElements::channel`]).
    pub(crate) base: usize,
}

/// The model's state elements and where their integration stands.
#[derive(Default)]
pub struct StateSet {
    pub(crate) diffs: Vec<DiffState>,
    pub(crate) linear: Vec<LinearState>,
    /// Joint friction's stiction deformations.
    pub(crate) stiction: Vec<stiction::StictionState>,
    /// How the next evaluations solve them.
    pub(crate) mode: Mode,
    /// The values the measures read: per DIFF x, ẋ; per linear system x, ẋ, u, y.
    pub(crate) channels: usize,
    /// The committed states and rates; None before the first solve.
    pub(crate) base: Option<Committed>,
    /// The integrator's formula x = b + g·ẋ for the evaluations of the current step:
    /// (b, g); None holds x at the committed values.
    pub(crate) formula: Option<(Vec<f64>, f64)>,
    /// The time of the last commit.
    pub(crate) committed_time: Option<f64>,
    /// The unknowns of the last solve (its warm start).
    pub(crate) z: Vec<f64>,
    /// Scratch: the model slot values the expressions read.
    pub(crate) slots: Vec<f64>,
    /// The solves leave the state values as they stand (a linearization's differences
    /// in the values the forces read).
    pub frozen: bool,
    /// The solution values the expressions read (reactions, forces, accelerations:
    /// [`Source::Solution`]), which only the dynamics can give.
    pub solution: Vec<OutputSlot>,
    /// Each as written (`JOINT(3, 0, 4, 7)`).
    pub names: Vec<String>,
    /// Their values for the next solves, filled in by the dynamics.
    pub solved: Vec<f64>,
}

/// The accepted states.
#[derive(Clone, Debug)]
pub(crate) struct Committed {
    pub(crate) x: Vec<f64>,
    pub(crate) rate: Vec<f64>,
}

impl StateSet {
    /// Whether the model has none (every evaluation then skips them at no cost).
    pub fn is_empty(&self) -> bool {
        self.diffs.is_empty() && self.linear.is_empty() && self.stiction.is_empty()
    }

    /// How many states.
    pub fn len(&self) -> usize {
        self.diffs.len() + self.linear.iter().map(|l| l.sys.n).sum::<usize>() + self.stiction_len()
    }

    /// Adds a DIFF; `label` names it in errors.
    pub(crate) fn add_diff(&mut self, d: DiffState) {
        self.diffs.push(d);
        self.channels += 2;
    }

    /// Adds a linear system; its values follow the ones before.
    pub(crate) fn add_linear(&mut self, sys: LinearSystem, inputs: Vec<StateExpr>) {
        let base = self.channels;
        self.channels += 2 * sys.n + sys.m + sys.p;
        self.linear.push(LinearState { sys, inputs, base });
    }

    /// How the next evaluations solve the states (statics switches to [`Mode::Static`]
    /// and back).
    pub fn set_mode(&mut self, mode: Mode) {
        if self.mode != mode {
            self.mode = mode;
            self.z.clear();
        }
    }

    /// How the evaluations solve the states now.
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// Forgets the integration: the next solve starts again from the initial conditions.
    pub fn forget_state(&mut self) {
        (self.base, self.formula, self.mode) = (None, None, Mode::Dynamic);
        self.committed_time = None;
        self.z.clear();
    }

    /// The committed states (x, then ẋ), in the order DIFFs then linear systems.
    pub fn committed(&self) -> Option<(&[f64], &[f64])> {
        self.base
            .as_ref()
            .map(|b| (b.x.as_slice(), b.rate.as_slice()))
    }

    /// The states' names, in order: `DIFF/3`, `LSE/2 x1`, `FRICTION/1 δ1`.
    pub fn names(&self) -> Vec<String> {
        let mut out: Vec<String> = self.diffs.iter().map(|d| d.label.clone()).collect();
        for l in &self.linear {
            out.extend((1..=l.sys.n).map(|j| format!("{} x{j}", l.sys.label)));
        }
        self.stiction_names(&mut out);
        out
    }

    /// The state whose value (x) channel `channel` is, if any.
    pub fn state_of_channel(&self, channel: usize) -> Option<usize> {
        if channel < 2 * self.diffs.len() {
            return channel.is_multiple_of(2).then_some(channel / 2);
        }
        let mut k = self.diffs.len();
        for l in &self.linear {
            if (l.base..l.base + l.sys.n).contains(&channel) {
                return Some(k + channel - l.base);
            }
            k += l.sys.n;
        }
        self.stiction_state_of_channel(channel, k)
    }

    /// The integrator's formula for the evaluations that follow: x = b + g·ẋ, per state
    /// in the order of [`StateSet::names`].
    pub fn set_formula(&mut self, b: &[f64], g: f64) {
        match &mut self.formula {
            Some((fb, fg)) => {
                fb.clear();
                fb.extend_from_slice(b);
                *fg = g;
            }
            None => self.formula = Some((b.to_vec(), g)),
        }
    }

    /// The trapezoidal rule from the committed states to time `t`,
    /// x = xₙ + (t − tₙ)/2·(ẋₙ + ẋ), as the formula of the evaluations that follow: how
    /// the states follow a motion no integrator carries (kinematics, solved at its
    /// output times).
    pub fn trapezoidal_to(&mut self, t: f64) {
        let Some(c) = &self.base else {
            return;
        };
        let h = t - self.committed_time.unwrap_or(t);
        let b: Vec<f64> = (c.x.iter().zip(&c.rate))
            .map(|(x, r)| x + 0.5 * h * r)
            .collect();
        self.set_formula(&b, 0.5 * h);
    }

    /// Holds the states at `x` (their rates `rate` the next solve's start), as if
    /// committed there: a shadow of another system's run (the 3D system a 2D run reads
    /// its reactions from) takes that run's states.
    pub fn hold_at(&mut self, x: Vec<f64>, rate: Vec<f64>) {
        if x.len() != self.len() || rate.len() != x.len() {
            return;
        }
        self.z.clone_from(&rate);
        self.base = Some(Committed { x, rate });
        self.formula = None;
    }

    /// The evaluations that follow hold x at the committed values (after a rejected
    /// step, between steps).
    pub fn hold(&mut self) {
        self.formula = None;
    }

    /// The tolerance of state `x` at ERROR `error`: relative above a unit value,
    /// absolute below.
    pub fn tolerance(x: f64, error: f64) -> f64 {
        error * x.abs().max(1.0)
    }

    /// Moves committed state `k` by `dx` (a linearization's finite differences); the
    /// next solve at the committed time reads it.
    pub fn nudge(&mut self, k: usize, dx: f64) {
        if let Some(b) = &mut self.base {
            b.x[k] += dx;
        }
    }

    /// Whether an expression reads a solution value (the dynamics must fill them in).
    pub fn reads_solution(&self) -> bool {
        !self.solution.is_empty()
    }

    /// The error a state element's solve fails with.
    fn failure(&self, k: usize, why: &str) -> MbdError {
        MbdError::State(self.statement(k), format!("{}: {why}", self.label(k)))
    }

    /// The statement of the element state `k` belongs to.
    fn statement(&self, k: usize) -> Statement {
        if k < self.diffs.len() {
            return self.diffs[k].statement;
        }
        let mut j = k - self.diffs.len();
        for l in &self.linear {
            if j < l.sys.n {
                return l.sys.statement;
            }
            j -= l.sys.n;
        }
        Statement::new("DIFF", 0)
    }

    /// The element state `k` belongs to (`DIFF/3`, `LSE/2`).
    pub fn label(&self, k: usize) -> String {
        if k < self.diffs.len() {
            return self.diffs[k].label.clone();
        }
        let mut j = k - self.diffs.len();
        for l in &self.linear {
            if j < l.sys.n {
                return l.sys.label.clone();
            }
            j -= l.sys.n;
        }
        (self.stiction_label(j)).unwrap_or_else(|| "a state element".into())
    }
}
