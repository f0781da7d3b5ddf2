//! Backward-difference formulas of variable order (1 to KMAX ≤ 6) and variable step on
//! the DAE of [`super`]: Adams' GSTIFF (fixed leading coefficient) and WSTIFF (variable
//! coefficients), in the index-3 (I3) or stabilized index-2 (SI2) formulation.
//!
//! Positions x (in the chart of the last accepted state: the `history` module) and
//! velocities v are each integrated by the order-k formula, written in predictor form:
//! with p the polynomial through the last k + 1 accepted values,
//!
//! ```text
//! y₁ = p(t₁) + g·(ẏ₁ − ṗ(t₁)),    g = h / Σⱼ₌₁..ₖ 1/j        (GSTIFF)
//!                                  g = 1 / Σₘ₌₀..ₖ₋₁ 1/(t₁ − tₙ₋ₘ)  (WSTIFF)
//! ```
//!
//! GSTIFF keeps the leading coefficient of the constant-step formula whatever the steps
//! were (as DASSL does), so the Newton matrix depends on h alone and survives order
//! changes; WSTIFF is the exact variable-step formula. So v₁ = b_v + g·a₁ and
//! x₁ = b_x + g·ẋ₁, with ẋ = v for translations and ẋ = dexp⁻¹(θ)·ω for rotation vectors.
//! Newton solves for the accelerations a₁ and multipliers λ:
//!
//! ```text
//! M·a₁/UCF + Φ_qᵀλ − Q = 0,   Φ(x₁)/g² = 0  (I3)   or   (Φ_q·v₁ + Φ_t)/g = 0  (SI2),
//! ```
//!
//! the Newton matrix being the Newmark family's with w_k = g², w_c = g. SI2 adds the
//! Gear–Gupta–Leimkuhler correction: positions move by x₁ += N⁻¹·Φ_qᵀ·μ so that Φ(x₁) = 0
//! too, solved with the same factorization N (a metric choice that leaves the method
//! unchanged where the constraints hold); its velocities are then exact on the velocity
//! constraints and go under error control with the positions.
//!
//! The state elements' states ([`crate::mbd::states`]) are integrated by the same
//! formula, x₁ = p(t₁) + g·(ẋ₁ − ṗ(t₁)), with the same order, steps and history: each
//! evaluation solves their equations for ẋ₁ with x₁ so tied to it, the Newton step is
//! the one of the matrix bordered by their coupling (`states_border`), and
//! their own corrector–predictor difference, over ERROR·max(1, |x|), joins the error
//! norm (and the order selection) beside the positions'.
//!
//! The local error is estimated from the corrector–predictor difference,
//! h/(t₁ − tₙ₋ₖ)·|y₁ − p(t₁)| (the constant-step factor 1/(k + 1)), per column over
//! ERROR in model units, as Adams takes it (scaled down for models under a unit length). After each step the orders k − 1, k and, when
//! k + 1 steps have gone by at order k, k + 1 (from the difference of the last two
//! corrector–predictor differences) are compared for the step each would allow, as DASSL
//! does; the step grows only when it can double, and shrinks to at most 0.9 of itself.
//! Repeated error failures drop the order to 1, and so does a located force-law switch
//! ([`super::events`]): a restart, never a step over it.

mod history;
mod variation;

use super::blocks::Weights;
use super::failure::DynError;
use super::integrator::{Attempt, Integrator, Settings};
use super::reuse::{self, Reuse};
use super::rotation_chart::rotation_vector_rate;
use super::setup::Dynamics;
use super::state::{copy_into, largest_magnitude, Snapshot};
use super::states_border::StateBorder;
use crate::mbd::states::StateSet;
use crate::mbd::system::Dimension;
use crate::vocab::math::{DVec, Vec3};
use history::{lagrange, lagrange_weights, History};

/// How the formula's coefficients follow the steps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Coefficients {
    /// The constant-step leading coefficient, always (GSTIFF).
    FixedLeading,
    /// The variable-step formula's (WSTIFF).
    Variable,
}

/// Which equations hold the constraints.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Formulation {
    /// Position constraints (index 3); positions under error control.
    #[default]
    I3,
    /// Velocity constraints with the positions projected (stabilized index 2); positions
    /// and velocities under error control.
    Si2,
}

/// The fraction of the tolerance a converged corrector may still move a variable by.
const NEWTON_FRACTION: f64 = 1e-3;

/// The local error no variable is held below, in ulps of the largest coordinate or
/// velocity.
const ROUNDING_FLOOR: f64 = 256.0;

/// The highest order there are coefficients for.
pub const MAX_ORDER: usize = 6;

/// What one step predicts: the polynomial values at t₁ and the formula's b and g.
#[derive(Default)]
struct Prediction {
    /// p_x(t₁), p_v(t₁), ṗ_v(t₁) (the predicted accelerations).
    xp: Vec<f64>,
    vp: DVec,
    ap: DVec,
    /// y₁ = b + g·ẏ₁ for positions and velocities.
    bx: Vec<f64>,
    bv: DVec,
    g: f64,
    /// The error factor h/(t₁ − tₙ₋ₖ).
    c_err: f64,
    /// The state elements' p(t₁) and b = p(t₁) − g·ṗ(t₁).
    sp: Vec<f64>,
    sb: Vec<f64>,
}

/// A BDF integrator.
pub struct Bdf {
    coefficients: Coefficients,
    formulation: Formulation,
    kmax: usize,
    /// The order of the next attempt, and the steps taken at it.
    k: usize,
    at_order: usize,
    hist: Option<History>,
    pred: Prediction,
    // The candidate: chart positions, velocities, and SI2's position correction.
    x: Vec<f64>,
    v1: DVec,
    shift: Vec<f64>,
    /// Corrector minus predictor of the candidate (positions, then velocities under
    /// SI2) and of the last accepted step, for the order-raising estimate.
    diff: Vec<f64>,
    last_diff: Option<Vec<f64>>,
    /// The candidate's state elements (x, ẋ), and their corrector minus predictor over
    /// their tolerances, the candidate's and the last accepted step's.
    sx: Vec<f64>,
    sr: Vec<f64>,
    sdiff: Vec<f64>,
    last_sdiff: Vec<f64>,
    /// The candidate's scaled error estimates at orders k − 1 and k.
    err_lower: f64,
    err: f64,
    /// Consecutive error-test failures.
    failures: usize,
    /// The step factor the integrator asks for after the last accept or reject.
    factor: Option<f64>,
    tol: (f64, Vec<f64>),
    res: DVec,
    rhs: Vec<f64>,
    proj: Vec<f64>,
    /// Scratch of the order-(k − 1) predictor: positions, velocities, their rate.
    lower: (Vec<f64>, DVec, DVec),
    /// When the factorization is reused (its weight: g).
    reuse: Reuse,
    /// The state elements' border of the Newton matrix.
    border: StateBorder,
    /// The order of the last attempt, and the interpolating polynomial of the last
    /// accepted step with an output time inside it.
    k_step: usize,
    dense: Dense,
    /// Whether the steps carry a global error estimate (`variation`), and the
    /// candidate's (positions, then velocities); empty once a variation failed.
    carry: bool,
    variation: Vec<f64>,
    /// The last converged corrector's contraction (0 after one iteration): how far the
    /// matrix it used is from the step's Jacobian.
    newton_rate: f64,
    scratch: variation::Scratch,
}

/// The polynomial an accepted step of order k interpolates: its k + 1 newest points
/// (times, chart positions, velocities), the chart's origin being the newest.
#[derive(Default)]
struct Dense {
    base: Option<Snapshot>,
    /// The times, relative to the newest.
    ts: Vec<f64>,
    x: Vec<Vec<f64>>,
    v: Vec<DVec>,
    /// The state elements' x at each point.
    s: Vec<Vec<f64>>,
    /// Scratch: weights, and the interpolated positions, velocities and states.
    l: Vec<f64>,
    xs: Vec<f64>,
    vs: DVec,
    ss: Vec<f64>,
}

impl Bdf {
    /// A BDF with the given coefficients and formulation, of order at most `kmax`
    /// (clamped to 1..=6), starting at order 1.
    pub fn new(coefficients: Coefficients, formulation: Formulation, kmax: usize) -> Bdf {
        Bdf {
            coefficients,
            formulation,
            kmax: kmax.clamp(1, MAX_ORDER),
            k: 1,
            at_order: 0,
            hist: None,
            pred: Prediction::default(),
            x: Vec::new(),
            v1: DVec::zeros(0),
            shift: Vec::new(),
            diff: Vec::new(),
            last_diff: None,
            sx: Vec::new(),
            sr: Vec::new(),
            sdiff: Vec::new(),
            last_sdiff: Vec::new(),
            err_lower: f64::INFINITY,
            err: 0.0,
            failures: 0,
            factor: None,
            tol: (f64::NAN, Vec::new()),
            res: DVec::zeros(0),
            rhs: Vec::new(),
            proj: Vec::new(),
            lower: (Vec::new(), DVec::zeros(0), DVec::zeros(0)),
            reuse: Reuse::refreshing(),
            border: StateBorder::default(),
            k_step: 1,
            dense: Dense::default(),
            carry: true,
            variation: Vec::new(),
            newton_rate: 0.0,
            scratch: variation::Scratch::default(),
        }
    }

    fn hist(&self) -> &History {
        self.hist.as_ref().expect("started")
    }

    /// The order-`k` predictor polynomial at t₀ + h through the newest k + 1 points:
    /// position value into `xp`, velocity value and derivative into `vp`, `ap`, position
    /// derivative into `xd` (any of them skipped when None).
    fn interpolate(
        hist: &History,
        k: usize,
        h: f64,
        xp: &mut [f64],
        mut xd: Option<&mut [f64]>,
        v: Option<(&mut DVec, &mut DVec)>,
    ) {
        let (l, dl) = predictor_weights(hist, k, h);
        xp.fill(0.0);
        if let Some(xd) = xd.as_deref_mut() {
            xd.fill(0.0);
        }
        for j in 0..=k {
            let p = hist.point(j);
            for (c, &x) in p.x.iter().enumerate() {
                xp[c] += l[j] * x;
            }
            if let Some(xd) = xd.as_deref_mut() {
                for (c, &x) in p.x.iter().enumerate() {
                    xd[c] += dl[j] * x;
                }
            }
        }
        if let Some((vp, ap)) = v {
            vp.fill(0.0);
            ap.fill(0.0);
            for j in 0..=k {
                let p = hist.point(j);
                vp.axpy(l[j], &p.v, 1.0);
                ap.axpy(dl[j], &p.v, 1.0);
            }
        }
    }

    /// The order-`k` predictor polynomial of the state elements at t₀ + h through the
    /// newest k + 1 points: value into `sp`, derivative into `sd` (when given).
    fn interpolate_states(
        hist: &History,
        k: usize,
        h: f64,
        sp: &mut Vec<f64>,
        mut sd: Option<&mut Vec<f64>>,
    ) {
        let (l, dl) = predictor_weights(hist, k, h);
        let ns = hist.newest().states.len();
        sp.clear();
        sp.resize(ns, 0.0);
        if let Some(sd) = sd.as_deref_mut() {
            sd.clear();
            sd.resize(ns, 0.0);
        }
        for j in 0..=k {
            let p = &hist.point(j).states;
            for (c, &x) in p.iter().enumerate() {
                sp[c] += l[j] * x;
                if let Some(sd) = sd.as_deref_mut() {
                    sd[c] += dl[j] * x;
                }
            }
        }
    }

    /// Fills [`Prediction`] for a step of `h` at the current order.
    fn predict(&mut self, n: usize, h: f64) {
        let k = self.k;
        let hist = self.hist.as_mut().expect("started");
        hist.seed_for(h);
        let p = &mut self.pred;
        if p.xp.len() != n {
            *p = Prediction {
                xp: vec![0.0; n],
                vp: DVec::zeros(n),
                ap: DVec::zeros(n),
                bx: vec![0.0; n],
                bv: DVec::zeros(n),
                g: 0.0,
                c_err: 0.0,
                sp: Vec::new(),
                sb: Vec::new(),
            };
        }
        let mut xd = std::mem::take(&mut p.bx);
        xd.resize(n, 0.0);
        Self::interpolate(
            hist,
            k,
            h,
            &mut p.xp,
            Some(&mut xd),
            Some((&mut p.vp, &mut p.ap)),
        );
        let t0 = hist.newest().t;
        p.g = match self.coefficients {
            Coefficients::FixedLeading => h / (1..=k).map(|j| 1.0 / j as f64).sum::<f64>(),
            Coefficients::Variable => {
                1.0 / (0..k)
                    .map(|m| 1.0 / (t0 + h - hist.point(m).t))
                    .sum::<f64>()
            }
        };
        p.c_err = h / (t0 + h - hist.point(k).t);
        // b = p − g·ṗ.
        for (b, &x) in xd.iter_mut().zip(&p.xp) {
            *b = x - p.g * *b;
        }
        p.bx = xd;
        p.bv.copy_from(&p.vp);
        p.bv.axpy(-p.g, &p.ap, 1.0);
        // The state elements: b = p − g·ṗ too.
        Self::interpolate_states(hist, k, h, &mut p.sp, Some(&mut p.sb));
        for (b, &x) in p.sb.iter_mut().zip(&p.sp) {
            *b = x - p.g * *b;
        }
    }

    /// Moves `d` to the candidate the accelerations `a1` give at `t1`.
    fn place(&mut self, d: &mut Dynamics, a1: &DVec, t1: f64) {
        let p = &self.pred;
        let g = p.g;
        self.v1.copy_from(&p.bv);
        self.v1.axpy(g, a1, 1.0);
        for c in 0..self.x.len() {
            self.x[c] = p.bx[c] + g * self.v1[c] + self.shift[c];
        }
        if d.sys.dim == Dimension::Three {
            // θ₁ = b + g·dexp⁻¹(θ₁)·ω₁ (+ shift): a contraction of factor about g·|ω|/2.
            for i in 0..self.x.len() / 6 {
                let r = i * 6 + 3..i * 6 + 6;
                let w = Vec3::from_column_slice(&self.v1.as_slice()[r.clone()]);
                let base = Vec3::from_column_slice(&p.bx[r.clone()])
                    + Vec3::from_column_slice(&self.shift[r.clone()]);
                let mut th = Vec3::from_column_slice(&self.x[r.clone()]);
                for _ in 0..20 {
                    let next = base + g * rotation_vector_rate(th, w);
                    let moved = (next - th).amax();
                    th = next;
                    if moved <= 1e-16 * (1.0 + th.amax()) {
                        break;
                    }
                }
                self.x[r].copy_from_slice(th.as_slice());
            }
        }
        let base = &self.hist().newest().snap;
        d.set_state(base, &self.x, &self.v1, t1);
    }

    fn weights(g: f64) -> Weights {
        Weights {
            w_m: 1.0,
            w_k: g * g,
            w_c: g,
            w_l: 1.0,
        }
    }

    /// The constraint rows' Newton right-hand side (I3: −Φ/g²; SI2: −(Φ_q·v + Φ_t)/g;
    /// a row on velocities: −f/g) into `rhs[n..]`.
    fn constraint_rhs(&self, d: &Dynamics, rhs: &mut [f64]) -> Result<(), DynError> {
        let (n, g) = (d.n, self.pred.g);
        if self.formulation == Formulation::Si2 {
            rhs[n..].fill(0.0);
            d.jac.add_times(self.v1.as_slice(), &mut rhs[n..]);
        }
        for (r, &(e, q)) in d.rows.iter().enumerate() {
            rhs[n + r] = if d.sys.row_reads_velocity(e, q) {
                -d.phi[r] / g
            } else {
                match self.formulation {
                    Formulation::I3 => -d.phi[r] / (g * g),
                    Formulation::Si2 => -(rhs[n + r] + d.sys.row_dt(e, q)?) / g,
                }
            };
        }
        Ok(())
    }

    /// SI2's position projection with the current factorization: δy with
    /// N·[δy; ν] = [0; −Φ], added to the shift; returns max |δy|/tol.
    fn project(&mut self, d: &mut Dynamics, tol: &[f64]) -> Result<f64, DynError> {
        let n = d.n;
        self.proj.clear();
        self.proj.resize(n + d.m, 0.0);
        for (r, &(e, q)) in d.rows.iter().enumerate() {
            if !d.sys.row_reads_velocity(e, q) {
                self.proj[n + r] = -d.phi[r];
            }
        }
        d.solve(&mut self.proj)?;
        let mut size: f64 = 0.0;
        for ((s, dy), t) in self.shift.iter_mut().zip(&self.proj[..n]).zip(tol) {
            *s += dy;
            size = size.max(dy.abs() / t);
        }
        Ok(size)
    }

    /// Newton on a step of `h`.
    fn iterate(&mut self, d: &mut Dynamics, h: f64, st: &Settings) -> Result<Attempt, DynError> {
        let (n, m) = (d.n, d.m);
        let t1 = self.hist().newest().t + h;
        self.predict(n, h);
        if self.x.len() != n {
            (self.x, self.v1, self.res) = (vec![0.0; n], DVec::zeros(n), DVec::zeros(n));
        }
        self.shift.clear();
        self.shift.resize(n, 0.0);
        let g = self.pred.g;
        if !self.pred.sb.is_empty() {
            d.forces.states.set_formula(&self.pred.sb, g);
        }
        let mut a1 = self.pred.ap.clone();
        let mut lambda = {
            let hist = self.hist();
            let l0 = &hist.newest().lambda;
            match hist.len() > 1 {
                true => {
                    let p1 = hist.point(1);
                    l0 + (l0 - &p1.lambda) * (h / (hist.newest().t - p1.t))
                }
                false => l0.clone(),
            }
        };
        self.reuse.begin_step(g, d.factor_generation);
        let tol = std::mem::take(&mut self.tol.1);
        let mut rhs = std::mem::take(&mut self.rhs);
        rhs.resize(n + m, 0.0);
        let outcome = self.newton(d, &mut a1, &mut lambda, t1, st, &tol, &mut rhs);
        (self.tol.1, self.rhs) = (tol, rhs);
        let converged = outcome?;
        if !converged {
            self.reuse.invalidate();
            return Ok(Attempt::Diverged);
        }
        self.place(d, &a1, t1);
        d.a = a1;
        d.lambda = lambda;
        if !self.pred.sb.is_empty() {
            // The states at the converged candidate (the last evaluation was one
            // correction before it).
            d.solve_states()?;
            d.forces.states.current(&d.sys, &mut self.sx, &mut self.sr);
        }
        Ok(self.estimate(d, h, st))
    }

    /// The Newton loop proper; true when it converged.
    #[allow(clippy::too_many_arguments)]
    fn newton(
        &mut self,
        d: &mut Dynamics,
        a1: &mut DVec,
        lambda: &mut DVec,
        t1: f64,
        st: &Settings,
        tol: &[f64],
        rhs: &mut [f64],
    ) -> Result<bool, DynError> {
        let (n, m, g) = (d.n, d.m, self.pred.g);
        let reach = d.reach();
        let (mut prev_norm, mut first) = (f64::INFINITY, 0.0);
        for iter in 1..=st.maxit {
            self.place(d, a1, t1);
            let w = (g, Self::weights(g));
            let refactor = reuse::evaluate(d, &mut self.reuse, (iter, w.0, w.1), lambda, |a| {
                copy_into(a, a1.as_slice())
            })?;
            let r1 = &mut self.res;
            d.motion_residual(a1.as_slice(), lambda, r1);
            for (x, &r) in rhs[..n].iter_mut().zip(r1.as_slice()) {
                *x = -r;
            }
            self.constraint_rhs(d, rhs)?;
            d.solve(rhs)?;
            if !d.forces.states.is_empty() {
                // The step of the matrix bordered by the state elements.
                let mut border = std::mem::take(&mut self.border);
                let mut place = |d: &mut Dynamics, a: &DVec| self.place(d, a, t1);
                let bordered = border.correct(d, rhs, (a1, 1.0), &mut place);
                self.border = border;
                bordered?;
            }
            // The test is on what the corrections do to the integrated variables: the
            // velocities move by g·δa (the positions by g²·δa, less), each against a
            // fraction of its tolerance, above the rounding floor: in I3 the positions'
            // (ε·|q|, a velocity of that over g, as the velocities follow from them); in
            // SI2 the velocities' own, since they meet their constraints directly.
            // Accelerations and reactions themselves are reconciled at the outputs.
            let floor = match self.formulation {
                Formulation::I3 => 10.0 * f64::EPSILON * reach / g,
                Formulation::Si2 => 10.0 * f64::EPSILON * largest_magnitude(self.v1.as_slice()),
            };
            let mut norm = rhs[..n]
                .iter()
                .zip(tol)
                .map(|(da, t)| g * da.abs() / (NEWTON_FRACTION * t + floor))
                .fold(0.0, f64::max);
            for (a, &x) in a1.as_mut_slice().iter_mut().zip(&rhs[..n]) {
                *a += x;
            }
            for (l, &x) in lambda.as_mut_slice().iter_mut().zip(&rhs[n..n + m]) {
                *l += x;
            }
            if self.formulation == Formulation::Si2 {
                let moved = self.project(d, tol)?;
                norm = norm.max(moved / NEWTON_FRACTION);
            }
            if !norm.is_finite() {
                return Ok(false);
            }
            let rate = norm / prev_norm;
            if iter == 1 {
                first = norm;
            }
            let left = match rate < 1.0 {
                true => norm * rate / (1.0 - rate),
                false => norm,
            };
            // Stalled at the rounding floor: no contraction left, the correction already
            // within the tolerance (rounding in a singular position's Newton matrix).
            let stalled = iter > 2 && rate > 0.5 && norm <= 1000.0;
            if iter > 1 && norm.min(left) <= 1.0 || norm <= 1e-3 || stalled {
                self.reuse.converged(iter, first, rate);
                self.newton_rate = if iter > 1 { rate } else { 0.0 };
                return Ok(true);
            }
            prev_norm = norm;
            if self.reuse.after_iteration(iter, rate, refactor) {
                break;
            }
        }
        Ok(false)
    }

    /// The error estimates of the converged candidate at orders k and k − 1.
    fn estimate(&mut self, d: &Dynamics, h: f64, st: &Settings) -> Attempt {
        let n = d.n;
        // SI2 controls velocities always, I3 while a contact is engaged.
        let si2 = self.formulation == Formulation::Si2 || st.in_contact;
        let width = if si2 { 2 * n } else { n };
        self.diff.resize(width, 0.0);
        for c in 0..n {
            self.diff[c] = self.x[c] - self.pred.xp[c];
            if si2 {
                self.diff[n + c] = self.v1[c] - self.pred.vp[c];
            }
        }
        if st.fixed_step.is_some() {
            (self.err, self.err_lower) = (0.0, f64::INFINITY);
            return Attempt::Converged { err: 0.0, worst: 0 };
        }
        let tol = &self.tol.1;
        // No variable is controlled below a few hundred ulps of the coordinates and
        // velocities: the predictor's differences carry that much rounding.
        let floor =
            ROUNDING_FLOOR * f64::EPSILON * d.reach().max(largest_magnitude(self.v1.as_slice()));
        let (mut err, mut worst) = (0.0, 0);
        for (c, e) in self.diff.iter().enumerate() {
            let e = self.pred.c_err * e.abs() / tol[c % n].max(floor);
            if e > err {
                (err, worst) = (e, c % n);
            }
        }
        // The state elements' own differences, over their tolerances.
        self.sdiff.clear();
        for (&x, &p) in self.sx.iter().zip(&self.pred.sp) {
            self.sdiff.push((x - p) / StateSet::tolerance(x, st.error));
        }
        let states = largest_magnitude(&self.sdiff) * self.pred.c_err;
        if states > err {
            (err, worst) = (states, 0);
        }
        self.err = err;
        self.err_lower = f64::INFINITY;
        let k = self.k;
        if k > 1 {
            // The order-(k − 1) predictor through the newest k points.
            let hist = self.hist.as_ref().expect("started");
            let t0 = hist.newest().t;
            let c_err = h / (t0 + h - hist.point(k - 1).t);
            let (xp, vp, ap) = &mut self.lower;
            if xp.len() != n {
                (*xp, *vp, *ap) = (vec![0.0; n], DVec::zeros(n), DVec::zeros(n));
            }
            let v = si2.then_some((&mut *vp, &mut *ap));
            Self::interpolate(hist, k - 1, h, xp, None, v);
            let mut e_low: f64 = 0.0;
            for c in 0..n {
                let t = tol[c].max(floor);
                e_low = e_low.max((self.x[c] - xp[c]).abs() / t);
                if si2 {
                    e_low = e_low.max((self.v1[c] - vp[c]).abs() / t);
                }
            }
            if !self.sx.is_empty() {
                let mut sp = Vec::new();
                Self::interpolate_states(hist, k - 1, h, &mut sp, None);
                for (&x, &p) in self.sx.iter().zip(&sp) {
                    e_low = e_low.max((x - p).abs() / StateSet::tolerance(x, st.error));
                }
            }
            self.err_lower = c_err * e_low;
        }
        Attempt::Converged { err, worst }
    }

    /// The step factor order `j` allows for a scaled error `e` (DASSL's safety of 2).
    fn allows(e: f64, j: usize) -> f64 {
        (2.0 * e).max(1e-12).powf(-1.0 / (j as f64 + 1.0))
    }
}

/// The Lagrange weights at the newest point's time + `h` of the order-`k` polynomial
/// through the newest k + 1 points (the seed standing in behind a lone one): the value's,
/// then the derivative's, in the first k + 1 places.
fn predictor_weights(hist: &History, k: usize, h: f64) -> PointWeights {
    let t0 = hist.newest().t;
    let mut ts = [0.0; MAX_ORDER + 2];
    for (j, t) in ts.iter_mut().enumerate().take(k + 1) {
        *t = hist.point(j).t - t0;
    }
    let (mut l, mut dl) = ([0.0; MAX_ORDER + 2], [0.0; MAX_ORDER + 2]);
    lagrange(&ts[..=k], h, &mut l[..=k], &mut dl[..=k]);
    (l, dl)
}

/// Weights per history point (value, derivative), at most `MAX_ORDER` + 2 of them.
type PointWeights = ([f64; MAX_ORDER + 2], [f64; MAX_ORDER + 2]);

/// Per-column error scales: as Adams, ERROR in model units for every integrated
/// variable, and tighter in proportion for a model smaller than a unit length (the
/// Newmark family scales translations by the model size both ways).
fn tolerances(d: &Dynamics, error: f64) -> Vec<f64> {
    let mut tol = d.tolerances(error);
    tol.iter_mut().for_each(|t| *t = t.min(error));
    tol
}

impl Integrator for Bdf {
    fn name(&self) -> &'static str {
        match self.coefficients {
            Coefficients::FixedLeading => "gstiff",
            Coefficients::Variable => "wstiff",
        }
    }

    fn error_order(&self) -> f64 {
        self.k as f64 + 1.0
    }

    fn order(&self) -> Option<u32> {
        Some(self.k as u32)
    }

    fn step_factor(&self) -> Option<f64> {
        self.factor
    }

    fn first_step(&self, d: &Dynamics, hinit: f64, st: &Settings) -> f64 {
        // Order one's position error from rest is about ½·c·h²·|a| against the seed's
        // predictor (c = ½): the step that meets a tenth of ERROR in every column,
        // never below HMIN (error control takes over from there).
        let fit =
            d.a.iter()
                .zip(tolerances(d, st.error))
                .filter(|(a, _)| a.abs() > 0.0)
                .map(|(a, t)| (0.4 * t / a.abs()).sqrt())
                .fold(f64::INFINITY, f64::min);
        hinit.min(fit).max(st.hmin)
    }

    fn start(&mut self, d: &mut Dynamics) -> Result<(), DynError> {
        // The state elements' history starts from their committed values.
        d.commit_states()?;
        self.hist = Some(History::new(d, self.kmax + 2));
        (self.k, self.at_order, self.failures) = (1, 0, 0);
        self.last_diff = None;
        self.reuse.invalidate();
        self.factor = None;
        Ok(())
    }

    fn attempt(&mut self, d: &mut Dynamics, h: f64, st: &Settings) -> Result<Attempt, DynError> {
        if self.tol.0 != st.error || self.tol.1.len() != d.n {
            self.tol = (st.error, tolerances(d, st.error));
        }
        self.err = f64::NAN;
        self.k_step = self.k;
        self.iterate(d, h, st)
    }

    fn accept(&mut self, d: &mut Dynamics) {
        // The variation reads the history before the step joins it. One that fails (a
        // force not finite at the perturbed state) ends the estimate, not the run.
        if self.carry && self.vary(d).is_err() {
            (self.carry, self.variation) = (false, Vec::new());
        }
        let k = self.k;
        self.failures = 0;
        self.at_order += 1;
        // The order-(k + 1) estimate: the difference of the last two corrector–predictor
        // differences, over k + 2.
        let raise = match &self.last_diff {
            Some(last)
                if self.at_order > k
                    && k < self.kmax
                    && self.hist().len() > k
                    && last.len() == self.diff.len() =>
            {
                let n = d.n;
                let tol = &self.tol.1;
                let e = self
                    .diff
                    .iter()
                    .zip(last)
                    .enumerate()
                    .map(|(c, (a, b))| (a - b).abs() / tol[c % n])
                    .fold(0.0, f64::max);
                let states = (self.sdiff.iter().zip(&self.last_sdiff))
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max);
                Some(e.max(states) / (k as f64 + 2.0))
            }
            _ => None,
        };
        let mut best = (k, Self::allows(self.err, k));
        if k > 1 && Self::allows(self.err_lower, k - 1) >= best.1 {
            best = (k - 1, Self::allows(self.err_lower, k - 1));
        } else if let Some(e) = raise {
            if Self::allows(e, k + 1) > best.1 {
                best = (k + 1, Self::allows(e, k + 1));
            }
        }
        if best.0 != k {
            (self.k, self.at_order) = (best.0, 0);
        }
        self.factor = Some(if best.1 >= 2.0 {
            2.0
        } else if best.1 >= 1.0 {
            1.0
        } else {
            best.1.clamp(0.5, 0.9)
        });
        match &mut self.last_diff {
            Some(l) => l.clone_from(&self.diff),
            None => self.last_diff = Some(self.diff.clone()),
        }
        self.last_sdiff.clone_from(&self.sdiff);
        let hist = self.hist.as_mut().expect("started");
        hist.push(d);
        hist.newest_error_mut().clone_from(&self.variation);
        // The order can only use the points there are.
        self.k = self.k.min(hist.len().saturating_sub(1).max(1));
        d.store_accelerations();
    }

    fn reject(&mut self, d: &mut Dynamics) {
        let hist = self.hist.as_ref().expect("started");
        let p = hist.newest();
        d.restore(&p.snap);
        d.a.clone_from(hist.accelerations());
        d.lambda.clone_from(&p.lambda);
        d.forces.states.hold();
        self.factor = None;
        if self.err.is_nan() || self.err <= 1.0 {
            // A diverged corrector or a switch being located: the driver picks the step.
            return;
        }
        self.failures += 1;
        let k = self.k;
        // As DASSL, but with the estimate's own factor down to a tenth (a first step from
        // rest may be orders of magnitude too long), and order 1 from the third failure.
        let shrink = 0.9 * Self::allows(self.err, k);
        self.factor = Some(match self.failures {
            1 | 2 => {
                if k > 1 && self.err_lower <= self.err {
                    (self.k, self.at_order) = (k - 1, 0);
                }
                shrink.clamp(0.1, 0.9)
            }
            _ => {
                (self.k, self.at_order) = (1, 0);
                shrink.clamp(0.1, 0.25)
            }
        });
    }

    fn dense(&self) -> bool {
        true
    }

    fn carry_global_error(&mut self, on: bool) {
        self.carry = on;
    }

    fn global_error(&self) -> Option<&[f64]> {
        (self.carry && !self.variation.is_empty()).then_some(self.variation.as_slice())
    }

    fn extend(&mut self, _d: &mut Dynamics) -> Result<(), DynError> {
        // The polynomial of the order the step was taken at, through the step's end and
        // the k points before it (the corrector's own interpolant, as DASSL's output).
        let Some(hist) = self.hist.as_ref() else {
            return Ok(());
        };
        let k = self.k_step.min(hist.len().saturating_sub(1)).max(1);
        let dense = &mut self.dense;
        dense.base = Some(hist.newest().snap.clone());
        dense.ts.clear();
        dense.x.clear();
        dense.v.clear();
        dense.s.clear();
        let t1 = hist.newest().t;
        for j in 0..=k.min(hist.len() - 1) {
            let p = hist.point(j);
            dense.ts.push(p.t - t1);
            dense.x.push(p.x.clone());
            dense.v.push(p.v.clone());
            dense.s.push(p.states.clone());
        }
        Ok(())
    }

    fn dense_state(&mut self, d: &mut Dynamics, t: f64) {
        let dense = &mut self.dense;
        let Some(base) = dense.base.as_ref() else {
            return;
        };
        let n = d.n;
        dense.l.resize(dense.ts.len(), 0.0);
        lagrange_weights(&dense.ts, t - base.time, &mut dense.l);
        dense.xs.clear();
        dense.xs.resize(n, 0.0);
        if dense.vs.len() != n {
            dense.vs = DVec::zeros(n);
        }
        dense.vs.fill(0.0);
        dense.ss.clear();
        dense.ss.resize(dense.s.first().map_or(0, Vec::len), 0.0);
        for (j, &w) in dense.l.iter().enumerate() {
            for (x, &p) in dense.xs.iter_mut().zip(&dense.x[j]) {
                *x += w * p;
            }
            dense.vs.axpy(w, &dense.v[j], 1.0);
            for (x, &p) in dense.ss.iter_mut().zip(&dense.s[j]) {
                *x += w * p;
            }
        }
        d.set_state(base, &dense.xs, &dense.vs, t);
        d.place_states(&dense.ss);
    }

    fn extend_candidate(&mut self, d: &mut Dynamics) -> bool {
        // The corrector's polynomial through the candidate and the k points before it.
        let Some(hist) = self.hist.as_ref() else {
            return false;
        };
        let k = self.k_step.min(hist.len()).max(1);
        let newest = hist.newest();
        let dense = &mut self.dense;
        dense.base = Some(newest.snap.clone());
        dense.ts.clear();
        dense.x.clear();
        dense.v.clear();
        dense.s.clear();
        let mut x = vec![0.0; d.n];
        d.increment(&newest.snap, &d.snapshot(), &mut x);
        dense.ts.push(d.sys.time - newest.t);
        dense.x.push(x);
        dense.v.push(d.sys.v());
        dense.s.push(self.sx.clone());
        for j in 0..k {
            let p = hist.point(j);
            dense.ts.push(p.t - newest.t);
            dense.x.push(p.x.clone());
            dense.v.push(p.v.clone());
            dense.s.push(p.states.clone());
        }
        true
    }

    fn restart(&mut self, d: &mut Dynamics) {
        if let Some(h) = self.hist.as_mut() {
            h.restart(d);
        }
        (self.k, self.at_order) = (1, 0);
        self.last_diff = None;
    }
}
