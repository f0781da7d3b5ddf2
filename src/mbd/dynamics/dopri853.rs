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

mod dense;
mod tableau;

use super::integrator::{Attempt, Integrator, Settings};
use super::tree::JointTree;
use super::{DynError, Dynamics, Snapshot};
use crate::mbd::system::Dimension;
use crate::vocab::math::{DVec, Vec3};
use dense::{Extension, A_EXTRA, C_EXTRA, END, EXTENDED};
use tableau::{A, B, BHH, C, ER, STAGES};

/// The weight of the third-order estimate in the combined one (the published value):
/// small enough that e₅ decides once it is resolved, large enough to damp it when e₅ is
/// accidentally small.
const E3_WEIGHT: f64 = 0.01;

/// The projection's target on the largest scaled position residual, in units of the
/// coordinates' rounding (ε times their size over the model length): a few tens of
/// ulps, which the Newton iteration reaches in one or two corrections from a local error.
const PROJECTION_ULPS: f64 = 64.0;

/// A stage turning a part by more than this (radians) is rejected as diverged: the
/// chart's inverse Jacobian is singular at 2π, and a step turning a part by half a turn is
/// far too long for the error estimate to trust anyway.
const LARGEST_TURN: f64 = std::f64::consts::PI;

/// |θ|² below which the inverse Jacobian's coefficient is the series: the closed form
/// loses digits to cancellation there (two and a half at the bound), and the series'
/// first omitted term is below rounding.
const SERIES_BELOW: f64 = 0.04;

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
    /// ([`dense`]): of the chart increment, and of the velocities.
    dense_x: Extension,
    dense_v: Extension,
    /// The joint-coordinate form, when the model is a planar tree ([`JointTree`]).
    joint: Option<Joints>,
}

/// DOP853 on the joint coordinates of a planar tree: the ODE y = (θ, θ̇), ẏ = (θ̇, θ̈).
struct Joints {
    tree: JointTree,
    /// The accepted y and θ̈ there; the candidate's. (The Cartesian accelerations and
    /// multipliers of `Dynamics` are solved before outputs only.)
    y0: Vec<f64>,
    a0: Vec<f64>,
    y1: Vec<f64>,
    a1: Vec<f64>,
    /// The stages' slopes, a stage's y, and per-coordinate error scales.
    k: Vec<Vec<f64>>,
    y: Vec<f64>,
    /// Per-coordinate error scales and the ERROR they are for.
    tol: Vec<f64>,
    tol_error: f64,
    /// The continuous extension of the last step with an output inside it (or of the
    /// last candidate across a switch), and the y it starts from.
    dense: Extension,
    dense_from: Vec<f64>,
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
        let (err, worst) = estimate(
            2 * n,
            |i| self.tol.1[i % n],
            |j, i| match i < n {
                true => self.kx[j][i],
                false => self.kv[j][i - n],
            },
            h,
        );
        (err, worst % n)
    }
}

/// The coefficient c(φ) = (1 − (φ/2)·cot(φ/2))/φ² of \[θ\]×² in SO(3)'s inverse left
/// Jacobian J_l(θ)⁻¹ = I − ½\[θ\]× + c(φ)·\[θ\]×², φ = |θ|, from `phi2` = φ². From the
/// Bernoulli series of x·cot x, c = Σ |B₂ₖ|·φ²ᵏ⁻²/(2k)! = 1/12 + φ²/720 + φ⁴/30240 + …
fn inverse_jacobian_coefficient(phi2: f64) -> f64 {
    if phi2 < SERIES_BELOW {
        // Through φ⁸; the next term, 691·φ¹⁰/(2730·12!), is below 6e-17 here.
        1.0 / 12.0
            + phi2
                * (1.0 / 720.0
                    + phi2 * (1.0 / 30240.0 + phi2 * (1.0 / 1209600.0 + phi2 / 47900160.0)))
    } else {
        let half = 0.5 * phi2.sqrt();
        (1.0 - half / half.tan()) / phi2
    }
}

/// θ̇ = J_l(θ)⁻¹·ω: the rate of the rotation vector θ of R = exp(\[θ\]×)·R₀ that turns with
/// the global angular velocity ω (Ṙ·Rᵀ = \[ω\]×).
pub(super) fn rotation_vector_rate(theta: Vec3, w: Vec3) -> Vec3 {
    let tw = theta.cross(&w);
    w - 0.5 * tw + inverse_jacobian_coefficient(theta.norm_squared()) * theta.cross(&tw)
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
        if !self.cartesian {
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
    }

    fn reject(&mut self, d: &mut Dynamics) {
        let base = self.base.as_ref().expect("started");
        d.restore(base);
        d.a.clone_from(&self.a0);
        d.lambda.clone_from(&self.lambda0);
    }
}

impl Joints {
    /// The joint form of `tree` from `d`'s consistent state (at the tree's origin).
    fn start(mut tree: JointTree, d: &mut Dynamics) -> Result<Joints, DynError> {
        let f = tree.coordinates();
        let mut y0 = vec![0.0; 2 * f];
        let mut a0 = vec![0.0; f];
        let (theta, rate) = y0.split_at_mut(f);
        tree.rates_at_start(d, rate)?;
        tree.accelerations(d, (theta, rate, d.sys.time), &mut a0, false)?;
        // The Cartesian accelerations and multipliers at the start, for the outputs.
        d.solve_accelerations()?;
        Ok(Joints {
            tree,
            y1: y0.clone(),
            a1: a0.clone(),
            y0,
            a0,
            k: vec![vec![0.0; 2 * f]; EXTENDED],
            y: vec![0.0; 2 * f],
            tol: Vec::new(),
            tol_error: f64::NAN,
            dense: Extension::default(),
            dense_from: Vec::new(),
        })
    }

    /// The continuous extension of the step of `h` from `t0` just accepted (its start in
    /// `y1` now, its end in `y0`): the end's slope, the three extra stages, the rows.
    fn extend(&mut self, d: &mut Dynamics, h: f64, t0: f64) -> Result<(), DynError> {
        let f = self.tree.coordinates();
        let (dy, dv) = self.k[END].split_at_mut(f);
        dy.copy_from_slice(&self.y0[f..]);
        dv.copy_from_slice(&self.a0);
        // The stages start from the step's start: y0 and y1 trade places meanwhile.
        std::mem::swap(&mut self.y0, &mut self.y1);
        let mut full = true;
        let mut outcome = Ok(());
        for (e, s) in (END + 1..EXTENDED).enumerate() {
            if !self.combine(A_EXTRA[e], h) {
                full = false;
                break;
            }
            outcome = self.slope(d, s, t0 + C_EXTRA[e] * h);
            if outcome.is_err() {
                break;
            }
        }
        std::mem::swap(&mut self.y0, &mut self.y1);
        outcome?;
        let (y0, y1, k) = (&self.y0, &self.y1, &self.k);
        self.dense
            .fill(2 * f, h, full, |i| y0[i] - y1[i], |j, i| k[j][i]);
        self.dense_from.clone_from(&self.y1);
        Ok(())
    }

    /// The continuous extension of the candidate just attempted, a step of `h` from `t0`
    /// that error control accepted (its end in `y1`, θ̈ there in `a1`); false when a
    /// stage could not be evaluated.
    fn extend_candidate(&mut self, d: &mut Dynamics, h: f64, t0: f64) -> bool {
        let f = self.tree.coordinates();
        let (dy, dv) = self.k[END].split_at_mut(f);
        dy.copy_from_slice(&self.y1[f..]);
        dv.copy_from_slice(&self.a1);
        for (e, s) in (END + 1..EXTENDED).enumerate() {
            if !self.combine(A_EXTRA[e], h) || self.slope(d, s, t0 + C_EXTRA[e] * h).is_err() {
                return false;
            }
        }
        let (y0, y1, k) = (&self.y0, &self.y1, &self.k);
        self.dense
            .fill(2 * f, h, true, |i| y1[i] - y0[i], |j, i| k[j][i]);
        self.dense_from.clone_from(&self.y0);
        true
    }

    /// Places `d` at the continuous extension's state at `s` (of the step), time `t`.
    fn dense_state(&mut self, d: &mut Dynamics, s: f64, t: f64) {
        let f = self.tree.coordinates();
        for i in 0..2 * f {
            self.y[i] = self.dense_from[i] + self.dense.at(i, s);
        }
        let (theta, rate) = self.y.split_at(f);
        self.tree.place(d, theta, rate, t);
    }

    /// Sets stage `s`'s slope from the state in `self.y` at time `t`.
    fn slope(&mut self, d: &mut Dynamics, s: usize, t: f64) -> Result<(), DynError> {
        let f = self.tree.coordinates();
        let (theta, rate) = self.y.split_at(f);
        let (dy, dv) = self.k[s].split_at_mut(f);
        dy.copy_from_slice(rate);
        self.tree.accelerations(d, (theta, rate, t), dv, true)
    }

    /// `self.y` = y₀ + h·Σⱼ wⱼ·kⱼ; false when it is not finite.
    fn combine(&mut self, w: &[(usize, f64)], h: f64) -> bool {
        for i in 0..self.y.len() {
            let sum: f64 = w.iter().map(|&(j, a)| a * self.k[j][i]).sum();
            self.y[i] = self.y0[i] + h * sum;
        }
        self.y.iter().all(|x| x.is_finite())
    }

    /// One step of `h` from the accepted state: the stages, the estimate, and θ̈ at a
    /// candidate error control accepts (the next step's first stage). The Cartesian
    /// accelerations and multipliers are not solved: an output row that reads them
    /// reconciles, which solves them afresh (`session::run`'s `Outputs::row`).
    fn attempt(&mut self, d: &mut Dynamics, h: f64, st: &Settings) -> Result<Attempt, DynError> {
        let f = self.tree.coordinates();
        if self.tol_error != st.error || self.tol.len() != 2 * f {
            self.tol_error = st.error;
            self.tol = (0..2 * f)
                .map(|i| match self.tree.rotational(i % f) {
                    true => st.error,
                    false => st.error * d.sys.length,
                })
                .collect();
        }
        let t0 = d.sys.time;
        let (dy, dv) = self.k[0].split_at_mut(f);
        dy.copy_from_slice(&self.y0[f..]);
        dv.copy_from_slice(&self.a0);
        for s in 1..STAGES {
            if !self.combine(A[s], h) {
                return Ok(Attempt::Diverged);
            }
            self.slope(d, s, t0 + C[s] * h)?;
        }
        if !self.combine(&B, h) {
            return Ok(Attempt::Diverged);
        }
        let (err, worst) = estimate(self.tol.len(), |i| self.tol[i], |j, i| self.k[j][i], h);
        // The column of the part the worst coordinate moves, for a step-size failure.
        let worst = 3 * self.tree.child(worst % f) + 2;
        self.y1.copy_from_slice(&self.y);
        let (theta, rate) = self.y1.split_at(f);
        if err <= 1.0 || st.fixed_step.is_some() {
            // θ̈ at the candidate: the next step's first stage.
            self.tree
                .accelerations(d, (theta, rate, t0 + h), &mut self.a1, false)?;
        } else {
            // The state alone, for the switches the driver reads.
            self.tree.place(d, theta, rate, t0 + h);
        }
        Ok(Attempt::Converged { err, worst })
    }
}

/// DOP853's combined error estimate of a step `h` over `components` components, from
/// stage j's slope of component i, `slope(j, i)`, relative to the scales `scale(i)`;
/// and the component where it is largest.
fn estimate(
    components: usize,
    scale: impl Fn(usize) -> f64,
    slope: impl Fn(usize, usize) -> f64,
    h: f64,
) -> (f64, usize) {
    let (mut e5, mut e3, mut worst) = (0.0f64, 0.0f64, 0);
    for i in 0..components {
        let scale = scale(i);
        let dot = |w: &[(usize, f64)]| w.iter().map(|&(j, x)| x * slope(j, i)).sum::<f64>();
        let (s5, s3) = (
            (dot(&ER) / scale).abs(),
            ((dot(&B) - dot(&BHH)) / scale).abs(),
        );
        if s5 > e5 {
            (e5, worst) = (s5, i);
        }
        e3 = e3.max(s3);
    }
    let denominator = (e5 * e5 + E3_WEIGHT * e3 * e3).sqrt();
    match denominator > 0.0 {
        true => (h.abs() * e5 * e5 / denominator, worst),
        false => (0.0, worst),
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
        for s in 1..STAGES {
            self.combine(A[s], h);
            if !self.place(d, base, t0 + C[s] * h) {
                return Ok(Attempt::Diverged);
            }
            d.solve_accelerations()?;
            self.kv[s].copy_from_slice(d.a.as_slice());
            self.chart_rates(d, s);
        }
        self.combine(&B, h);
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
        for (e, s) in (END + 1..EXTENDED).enumerate() {
            self.combine(A_EXTRA[e], h);
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
        }
        std::mem::swap(&mut self.v0, &mut self.start_v);
        outcome?;
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
        for (e, s) in (END + 1..EXTENDED).enumerate() {
            self.combine(A_EXTRA[e], h);
            if !self.place(d, base, base.time + C_EXTRA[e] * h) || d.solve_accelerations().is_err()
            {
                return false;
            }
            self.kv[s].copy_from_slice(d.a.as_slice());
            self.chart_rates(d, s);
        }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vocab::math::{Mat3, Quat};

    #[test]
    fn series_and_closed_form_of_the_coefficient_meet() {
        let phi2 = SERIES_BELOW;
        let half = 0.5 * phi2.sqrt();
        let closed = (1.0 - half / half.tan()) / phi2;
        let series = inverse_jacobian_coefficient(phi2 * (1.0 - 1e-15));
        assert!((closed - series).abs() < 1e-14, "{closed} vs {series}");
        assert_eq!(inverse_jacobian_coefficient(0.0), 1.0 / 12.0);
    }

    /// The global angular velocity of R(t) = exp([θ(t)]×)·R₀ by central differences.
    fn omega_by_differences(theta: Vec3, rate: Vec3) -> Vec3 {
        let r = |t: f64| -> Mat3 {
            Quat::from_scaled_axis(theta + t * rate)
                .to_rotation_matrix()
                .into_inner()
        };
        let dt = 1e-5;
        let dr = (r(dt) - r(-dt)) / (2.0 * dt);
        let wx = dr * r(0.0).transpose();
        Vec3::new(
            wx[(2, 1)] - wx[(1, 2)],
            wx[(0, 2)] - wx[(2, 0)],
            wx[(1, 0)] - wx[(0, 1)],
        ) / 2.0
    }

    #[test]
    fn the_rate_turns_the_chart_with_the_angular_velocity() {
        // θ̇ from the formula, fed back through R(t) = exp([θ(t)]×)·R₀, must give ω back:
        // small angles (the series), large ones (the closed form), near half a turn.
        let w = Vec3::new(0.3, -1.2, 0.7);
        for theta in [
            Vec3::new(1e-9, 0.0, 0.0),
            Vec3::new(0.05, -0.02, 0.03),
            Vec3::new(0.2, 0.3, -0.1),
            Vec3::new(0.9, -0.4, 1.1),
            Vec3::new(-2.0, 1.5, 1.2),
        ] {
            let rate = rotation_vector_rate(theta, w);
            let back = omega_by_differences(theta, rate);
            assert!((back - w).norm() < 1e-8, "θ = {theta:?}: ω back {back:?}");
        }
    }
}
