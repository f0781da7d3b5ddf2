//! DOP853, the explicit Dormand–Prince 8(5,3) Runge–Kutta pair (Hairer, Nørsett & Wanner,
//! *Solving ODEs I*, §II.10), on the index-1 form of the equations of motion: at every
//! stage the consistent accelerations of [`Dynamics::solve_accelerations`],
//!
//! ```text
//! [M/UCF  Φ_qᵀ] [a]   [Q]
//! [Φ_q     0  ] [λ] = [γ],
//! ```
//!
//! make the state (positions, velocities) an ODE whose right-hand side is (v, a). The
//! positions are integrated in a chart around the step's starting pose: the increment x
//! of [`Dynamics::set_state`] (δr, and per part a global rotation vector θ with
//! R = exp(\[θ\]×)·R₀), whose rate is ṙ = v and θ̇ = J_l(θ)⁻¹·ω, SO(3)'s inverse left
//! Jacobian (in 2D the chart is linear: θ̇ = ω). So every stage is a plain vector sum and
//! rotations stay rotations.
//!
//! Index 1 keeps the accelerations consistent but lets positions and velocities drift off
//! the constraints by the local error. After each step that error control accepts,
//! positions are projected back onto Φ(q, t) = 0 ([`Dynamics::project_positions`]) and
//! velocities onto the velocity constraints ([`Dynamics::reconcile`]), both closest in the
//! mass metric; the error estimate has already seen the unprojected solution, and the
//! projected step keeps its order (Hairer & Wanner, *Solving ODEs II*, §VII.2). Reconcile
//! leaves the consistent accelerations at the projected state: they are the next step's
//! first stage, as the published code reuses its last stage (FSAL), which the projection
//! invalidates.
//!
//! The error estimate is the published one, the fifth-order estimate e₅ = O(h⁶) damped by
//! the third-order e₃ = O(h⁴): err = h·|e₅|²/√(|e₅|² + 0.01·|e₃|²) = O(h⁸), with max norms
//! over positions and velocities each scaled per column as the Newmark family scales its
//! estimate (ERROR × model length for translations, ERROR for rotations, and the same per
//! unit time for their velocities). An explicit method: for smooth, non-stiff models at
//! tight ERROR, where it takes long steps at a dozen solves each; stiff springs, contact
//! or high damping limit its step by stability instead, where the implicit methods are
//! the choice.
//!
//! The state elements are extra components of the ODE, in the Cartesian form (`states`);
//! a model with any keeps to that form.
//!
//! One job a file: this one the integrator and its Cartesian form; `tableau` (the
//! coefficients), `error_estimate` (the combined error estimate), `dense_output` (the
//! order-7 continuous extension), `tree` (a planar tree's joint coordinates) and
//! `joints` (the integrator on them, its joint-coordinate mode), `articulated` (their
//! accelerations in O(N)) and `states` (the state elements' components).

mod articulated;
mod dense_output;
mod error_estimate;
mod joints;
mod states;
mod tableau;
pub mod tree;

use super::failure::DynError;
use super::integrator::{Attempt, Integrator, Settings};
use super::rotation_chart::rotation_vector_rate;
use super::setup::Dynamics;
use super::state::Snapshot;
use crate::mbd::system::Dimension;
use crate::vocab::math::{DVec, Vec3};
use dense_output::{Extension, A_EXTRA, C_EXTRA, END, EXTENDED};
use error_estimate::estimate;
use joints::Joints;
use states::StateStages;
use tableau::{A, B, C, STAGES};
use tree::JointTree;

/// The projection's target on the largest scaled position residual, in units of the
/// coordinates' rounding (ε times their size over the model length): a few tens of
/// ulps, which the Newton iteration reaches in one or two corrections from a local error.
const PROJECTION_ULPS: f64 = 64.0;

/// A stage turning a part by more than this (radians) is rejected as diverged: the
/// chart's inverse Jacobian is singular at 2π, and a step turning a part by half a turn is
/// far too long for the error estimate to trust anyway.
const LARGEST_TURN: f64 = std::f64::consts::PI;

/// The explicit DOP853 integrator.
pub struct Dopri853 {
    /// The last accepted state, its velocities, accelerations and multipliers.
    base: Option<Snapshot>,
    v0: DVec,
    a0: DVec,
    lambda0: DVec,
    /// The stages' slopes: of the chart increment and of the velocities.
    kx: Vec<Vec<f64>>,
    kv: Vec<Vec<f64>>,
    /// Scratch: a stage's chart increment and velocities.
    x: Vec<f64>,
    v: DVec,
    /// Per-column error scales and the ERROR they are for.
    tol: (f64, Vec<f64>),
    /// Integrate the Cartesian index-1 form even where joint coordinates would do.
    cartesian: bool,
    /// The last accepted step's start and its velocities, and the last attempt's size:
    /// what its continuous extension starts from.
    start: Option<Snapshot>,
    start_v: DVec,
    h: f64,
    /// The continuous extension of the last accepted step with an output inside it
    /// ([`dense_output`]): of the chart increment, and of the velocities.
    dense_x: Extension,
    dense_v: Extension,
    /// The joint-coordinate form, when the model is a planar tree ([`JointTree`]).
    joint: Option<Joints>,
    /// The state elements' components.
    states: StateStages,
}

impl Default for Dopri853 {
    fn default() -> Self {
        Dopri853::new()
    }
}

impl Dopri853 {
    /// An integrator before its first step.
    pub fn new() -> Dopri853 {
        Dopri853 {
            base: None,
            v0: DVec::zeros(0),
            a0: DVec::zeros(0),
            lambda0: DVec::zeros(0),
            kx: Vec::new(),
            kv: Vec::new(),
            x: Vec::new(),
            v: DVec::zeros(0),
            tol: (f64::NAN, Vec::new()),
            cartesian: false,
            joint: None,
            start: None,
            start_v: DVec::zeros(0),
            h: 0.0,
            dense_x: Extension::default(),
            dense_v: Extension::default(),
            states: StateStages::default(),
        }
    }

    /// An integrator that keeps to the Cartesian form on every model.
    pub fn cartesian() -> Dopri853 {
        Dopri853 {
            cartesian: true,
            ..Dopri853::new()
        }
    }

    /// How many joint coordinates it integrates (None: the Cartesian form).
    pub fn joint_coordinates(&self) -> Option<usize> {
        self.joint.as_ref().map(|j| j.tree.coordinates())
    }

    /// Sizes the buffers for `n` columns.
    fn size(&mut self, n: usize) {
        // (The stages of the continuous extension too: a step keeps its slopes.)
        if self.x.len() != n || self.kx.len() != EXTENDED {
            self.kx = vec![vec![0.0; n]; EXTENDED];
            self.kv = vec![vec![0.0; n]; EXTENDED];
            self.x = vec![0.0; n];
            self.v = DVec::zeros(n);
        }
    }

    /// `self.x` = h·Σⱼ wⱼ·kxⱼ and `self.v` = v₀ + h·Σⱼ wⱼ·kvⱼ over the sparse weights `w`.
    fn combine(&mut self, w: &[(usize, f64)], h: f64) {
        for k in 0..self.x.len() {
            let (mut dx, mut dv) = (0.0, 0.0);
            for &(j, a) in w {
                dx += a * self.kx[j][k];
                dv += a * self.kv[j][k];
            }
            self.x[k] = h * dx;
            self.v[k] = self.v0[k] + h * dv;
        }
    }

    /// The combined error estimate of the step `h` from its stages' slopes, relative to
    /// the per-column scales, and the column where it is largest (positions' and
    /// velocities' alike).
    fn error(&self, h: f64) -> (f64, usize) {
        let n = self.tol.1.len();
        let error = self.tol.0;
        let (err, worst) = estimate(
            2 * n + self.states.len(),
            |i| match i < 2 * n {
                true => self.tol.1[i % n],
                false => self.states.tolerance(i - 2 * n, error),
            },
            |j, i| match i {
                i if i < n => self.kx[j][i],
                i if i < 2 * n => self.kv[j][i - n],
                i => self.states.k[j][i - 2 * n],
            },
            h,
        );
        (err, if worst < 2 * n { worst % n } else { 0 })
    }
}

impl Integrator for Dopri853 {
    fn name(&self) -> &'static str {
        "dopri853"
    }

    fn error_order(&self) -> f64 {
        // The combined estimate scales as h·(h⁵)²/h³ = h⁸ (the published code's 1/8).
        8.0
    }

    fn order(&self) -> Option<u32> {
        Some(8)
    }

    fn max_growth(&self) -> f64 {
        // The published code's bound (FAC2): an eighth-order estimate grows the step
        // 2× at an error of 1/256 of the tolerance; free flight after a contact would
        // otherwise climb back from the contact's steps in many doublings.
        6.0
    }

    fn start(&mut self, d: &mut Dynamics) -> Result<(), DynError> {
        d.commit_states()?;
        self.states = StateStages::default();
        self.states.take_committed(d);
        // The joint form carries no state elements.
        if !self.cartesian && d.forces.states.is_empty() {
            self.joint = match JointTree::of(d) {
                Some(tree) => Some(Joints::start(tree, d)?),
                None => None,
            };
        }
        self.base = Some(d.snapshot());
        self.v0 = d.sys.v();
        self.a0 = d.a.clone();
        self.lambda0 = d.lambda.clone();
        Ok(())
    }

    fn attempt(&mut self, d: &mut Dynamics, h: f64, st: &Settings) -> Result<Attempt, DynError> {
        self.h = h;
        if let Some(j) = &mut self.joint {
            return j.attempt(d, h, st);
        }
        let n = d.n;
        self.size(n);
        if self.tol.0 != st.error || self.tol.1.len() != n {
            self.tol = (st.error, d.tolerances(st.error));
        }
        let base = self.base.take().expect("started");
        let outcome = self.stages(d, &base, h, st);
        self.base = Some(base);
        outcome
    }

    fn dense(&self) -> bool {
        true
    }

    fn extend(&mut self, d: &mut Dynamics) -> Result<(), DynError> {
        let Some(start) = self.start.take() else {
            return Ok(());
        };
        let extended = match &mut self.joint {
            Some(j) => j.extend(d, self.h, start.time),
            None => self.extend_cartesian(d, &start),
        };
        self.start = Some(start);
        extended
    }

    fn dense_state(&mut self, d: &mut Dynamics, t: f64) {
        let Some(start) = self.start.take() else {
            return;
        };
        let s = ((t - start.time) / self.h).clamp(0.0, 1.0);
        match &mut self.joint {
            Some(j) => j.dense_state(d, s, t),
            None => {
                for i in 0..self.x.len() {
                    self.x[i] = self.dense_x.at(i, s);
                    self.v[i] = self.start_v[i] + self.dense_v.at(i, s);
                }
                d.set_state(&start, &self.x, &self.v, t);
                self.states.dense_state(d, s);
            }
        }
        self.start = Some(start);
    }

    fn dense_on_constraints(&self) -> bool {
        self.joint.is_some()
    }

    fn extend_candidate(&mut self, d: &mut Dynamics) -> bool {
        let Some(base) = self.base.take() else {
            return false;
        };
        let extended = match &mut self.joint {
            Some(j) => j.extend_candidate(d, self.h, base.time),
            None => self.extend_candidate_cartesian(d, &base),
        };
        // The extension starts from the accepted state (`accept` moves it on again).
        self.start = Some(base.clone());
        self.start_v.clone_from(&self.v0);
        self.base = Some(base);
        extended
    }

    fn formulation(&self) -> Option<String> {
        self.joint_coordinates()
            .map(|f| format!("a planar tree of joints: integrated in its {f} joint coordinates"))
    }

    fn accept(&mut self, d: &mut Dynamics) {
        if let Some(j) = &mut self.joint {
            std::mem::swap(&mut j.y0, &mut j.y1);
            std::mem::swap(&mut j.a0, &mut j.a1);
        }
        self.start = self.base.replace(d.snapshot());
        std::mem::swap(&mut self.start_v, &mut self.v0);
        self.v0 = d.sys.v();
        self.a0.clone_from(&d.a);
        self.lambda0.clone_from(&d.lambda);
        self.states.take_committed(d);
    }

    fn reject(&mut self, d: &mut Dynamics) {
        d.forces.states.hold();
        let base = self.base.as_ref().expect("started");
        d.restore(base);
        d.a.clone_from(&self.a0);
        d.lambda.clone_from(&self.lambda0);
    }
}

impl Dopri853 {
    /// The step `h` from `base`: the stages, the estimate, the projection.
    fn stages(
        &mut self,
        d: &mut Dynamics,
        base: &Snapshot,
        h: f64,
        st: &Settings,
    ) -> Result<Attempt, DynError> {
        let t0 = base.time;
        // The first stage is the accepted state: x = 0, where the chart's rate is ω.
        self.kx[0].copy_from_slice(self.v0.as_slice());
        self.kv[0].copy_from_slice(self.a0.as_slice());
        self.states.first();
        for s in 1..STAGES {
            self.combine(A[s], h);
            self.states.combine(d, A[s], h, false);
            if !self.place(d, base, t0 + C[s] * h) {
                return Ok(Attempt::Diverged);
            }
            d.solve_accelerations()?;
            self.kv[s].copy_from_slice(d.a.as_slice());
            self.chart_rates(d, s);
            self.states.slope(d, s);
        }
        self.combine(&B, h);
        // The candidate's states: the evaluations at its end (the projection's, the
        // commit's) solve their rates there.
        self.states.combine(d, &B, h, false);
        if !self.place(d, base, t0 + h) {
            return Ok(Attempt::Diverged);
        }
        // With fixed steps the estimate only feeds the run's monitors.
        let (err, worst) = self.error(h);
        if err > 1.0 && st.fixed_step.is_none() {
            // The driver rejects it: no projection to spend on it.
            return Ok(Attempt::Converged { err, worst });
        }
        // Rounding of the coordinates, over the model length: the projection's floor.
        let target = PROJECTION_ULPS * f64::EPSILON * d.reach() / d.sys.length;
        match d.project_positions(target) {
            // Too far off the constraints for Newton: the step was too long.
            Err(DynError::Newton { .. }) => return Ok(Attempt::Diverged),
            other => other?,
        }
        d.reconcile()?;
        Ok(Attempt::Converged { err, worst })
    }

    /// The continuous extension of the step just accepted from `start` (the end is the
    /// accepted state): the end's chart increment and slope, the three extra stages from
    /// the start, then the rows of positions and of velocities.
    fn extend_cartesian(&mut self, d: &mut Dynamics, start: &Snapshot) -> Result<(), DynError> {
        let h = self.h;
        let Some(end) = self.base.as_ref() else {
            return Ok(());
        };
        d.increment(start, end, &mut self.x);
        let dx = self.x.clone();
        self.v.copy_from(&self.v0);
        self.kv[END].copy_from_slice(self.a0.as_slice());
        self.chart_rates(d, END);
        // The stages combine from the start's velocities: v0 and start_v trade places.
        std::mem::swap(&mut self.v0, &mut self.start_v);
        let mut full = true;
        let mut outcome = Ok(());
        // (The states' end slope first: the extra stages read it.)
        self.states.extend(h, false);
        for (e, s) in (END + 1..EXTENDED).enumerate() {
            self.combine(A_EXTRA[e], h);
            self.states.combine(d, A_EXTRA[e], h, true);
            if !self.place(d, start, start.time + C_EXTRA[e] * h) {
                full = false;
                break;
            }
            outcome = d.solve_accelerations();
            if outcome.is_err() {
                break;
            }
            self.kv[s].copy_from_slice(d.a.as_slice());
            self.chart_rates(d, s);
            self.states.slope(d, s);
        }
        std::mem::swap(&mut self.v0, &mut self.start_v);
        outcome?;
        self.states.extend(h, full);
        let (kx, kv) = (&self.kx, &self.kv);
        let (v0, v1) = (&self.start_v, &self.v0);
        let n = dx.len();
        self.dense_x.fill(n, h, full, |i| dx[i], |j, i| kx[j][i]);
        self.dense_v
            .fill(n, h, full, |i| v1[i] - v0[i], |j, i| kv[j][i]);
        Ok(())
    }

    /// The continuous extension of the candidate just attempted from `base` (error
    /// control accepted it: `self.x` and `self.v` hold its end before the projection,
    /// `d.a` the accelerations after it), as [`Dopri853::extend_cartesian`] makes an
    /// accepted step's; false when an extra stage could not be evaluated.
    fn extend_candidate_cartesian(&mut self, d: &mut Dynamics, base: &Snapshot) -> bool {
        let h = self.h;
        let (dx, v1) = (self.x.clone(), self.v.clone());
        self.kv[END].copy_from_slice(d.a.as_slice());
        self.chart_rates(d, END);
        // The states' end: the candidate's sum, its rates as the last evaluation left them.
        let end = self.states.y.clone();
        self.states.slope(d, END);
        for (e, s) in (END + 1..EXTENDED).enumerate() {
            self.combine(A_EXTRA[e], h);
            self.states.combine(d, A_EXTRA[e], h, false);
            if !self.place(d, base, base.time + C_EXTRA[e] * h) || d.solve_accelerations().is_err()
            {
                return false;
            }
            self.kv[s].copy_from_slice(d.a.as_slice());
            self.chart_rates(d, s);
            self.states.slope(d, s);
        }
        self.states.extend_candidate(h, &end);
        let (kx, kv, v0) = (&self.kx, &self.kv, &self.v0);
        let n = dx.len();
        self.dense_x.fill(n, h, true, |i| dx[i], |j, i| kx[j][i]);
        self.dense_v
            .fill(n, h, true, |i| v1[i] - v0[i], |j, i| kv[j][i]);
        true
    }

    /// Moves `d` to `base` moved by the stage increment `self.x`, with velocities
    /// `self.v` at `time`; false when the stage is not finite or turns a part too far.
    fn place(&self, d: &mut Dynamics, base: &Snapshot, time: f64) -> bool {
        let finite = self.x.iter().chain(self.v.iter()).all(|x| x.is_finite());
        if !finite || !self.turns_within_chart(d) {
            return false;
        }
        d.set_state(base, &self.x, &self.v, time);
        true
    }

    /// Whether every part's rotation vector in `self.x` stays where the chart is regular.
    fn turns_within_chart(&self, d: &Dynamics) -> bool {
        if d.sys.dim != Dimension::Three {
            return true;
        }
        self.x
            .chunks_exact(6)
            .all(|c| Vec3::new(c[3], c[4], c[5]).norm() < LARGEST_TURN)
    }

    /// Stage `s`'s chart slopes from its increment `self.x` and velocities `self.v`.
    fn chart_rates(&mut self, d: &Dynamics, s: usize) {
        let k = &mut self.kx[s];
        k.copy_from_slice(self.v.as_slice());
        if d.sys.dim != Dimension::Three {
            return;
        }
        for (rate, x) in k.chunks_exact_mut(6).zip(self.x.chunks_exact(6)) {
            let theta = Vec3::new(x[3], x[4], x[5]);
            let w = Vec3::new(rate[3], rate[4], rate[5]);
            rate[3..6].copy_from_slice(rotation_vector_rate(theta, w).as_slice());
        }
    }
}
