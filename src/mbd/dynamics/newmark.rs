//! The Newmark family on the index-3 DAE: Adams' HHT (Hilber–Hughes–Taylor, as Negrut et
//! al. 2007 and Chrono's `ChTimestepperHHT` state it for index-3 constraints),
//! generalized-α with algorithmic accelerations (Arnold & Brüls 2007, as Exudyn runs it,
//! spec §6.3) and Adams' plain NEWMARK (β, γ). All update positions and velocities from an acceleration-like ã:
//!
//! ```text
//! q₁ = q₀ ⊕ (h·v₀ + h²·((½ − β)·ã₀ + β·ã₁)),   v₁ = v₀ + h·((1 − γ)·ã₀ + γ·ã₁)
//! ```
//!
//! (⊕: rotations compose as R₁ = exp(\[Δθ\]×)·R₀), and solve for the accelerations a₁
//! and multipliers λ₁ by Newton on
//!
//! ```text
//! (s·M₁ − r·M₀)·a₁/UCF + s·(Φ_qᵀλ − Q)₁ − r·(Φ_qᵀλ − Q)₀ = 0,     Φ(q₁, t₁)/(β·h²·c) = 0.
//! ```
//!
//! HHT's a₁ is the acceleration at t₁ + α·h, so the mass matrix is shifted with the
//! forces: in 3D the rotational inertia R·J·Rᵀ changes with the configuration, and
//! M₁·a₁ alone leaves angular velocities first-order accurate.
//!
//! HHT: ã = a, s = 1 + α, r = α, γ = ½ − α, β = (1 − α)²/4, α ∈ [−⅓, 0].
//! Newmark: ã = a, s = 1, r = 0, β and γ as given (HHT with α = 0 when γ = ½, β = ¼);
//! γ > ½ damps, and makes the method first-order accurate.
//! Generalized-α: (1 − α_m)·ã₁ + α_m·ã₀ = (1 − α_f)·a₁ + α_f·a₀, s = 1, r = 0,
//! c = (1 − α_f)/(1 − α_m), all four from ρ∞.
//!
//! The state elements' states ([`crate::mbd::states`]) follow the first-order
//! generalized-α method (Jansen, Whiting & Hulbert 2000, in the algorithmic-rate form of
//! Arnold & Brüls 2007) with the same method's parameters: with w the algorithmic rate,
//!
//! ```text
//! x₁ = x₀ + h·((1 − γ)·w₀ + γ·w₁),   (1 − α_m)·w₁ + α_m·w₀ = (1 − α_f)·ẋ₁ + α_f·ẋ₀,
//! ```
//!
//! ẋ₁ = f(x₁, q₁, v₁, t₁) solved inside every evaluation of the same Newton iteration
//! (x₁ = b + g·ẋ₁ is linear in ẋ₁), whose step is the one of the matrix bordered by
//! their coupling (`states_border`). Generalized-α uses its own α_m, α_f, γ; HHT maps to
//! α_m = 0, α_f = −α, γ = ½ − α (its blend of the forces at t₀ and t₁); Newmark to
//! α_m = α_f = 0 with its γ. So the states are second order where the method is
//! (γ = ½ − α_m + α_f), A-stable, and damped at high frequency as the method damps. w
//! lags ẋ by (α_f − α_m)·h: when the step changes, w₀ is moved along by
//! (α_m − α_f)·Δh·ẍ₀ (ẍ₀ from the last step's rates), or a variable step would leave it
//! off by O(h·Δh) (at a start w₀ = ẋ₀).
//! Their local error, |γ − ½ + α_m − α_f|·h·|ẋ₁ − ẋ₀| + h³/12·|x⃛| with x⃛ from the divided
//! differences of ẋ over this step and the one before (on a first step h²/12·|ẋ₁ − ẋ₀|),
//! over ERROR·max(1, |x|), joins the step's estimate.
//!
//! Newton reuses its factorization across iterations and steps while it contracts, and
//! refactors when the step size moved or the contraction is poor. The local error
//! estimate is the Newmark position truncation error, (β − ⅙)·h²·(ã₁ − ã₀); while a
//! contact is engaged the run's monitors also watch the velocity one, (γ − ½)·h·(ã₁ − ã₀).

use super::blocks::{Mat3Block, Weights};
use super::failure::DynError;
use super::integrator::{Attempt, Integrator, Settings};
use super::reuse::{self, Reuse};
use super::setup::Dynamics;
use super::state::{copy_into, largest_magnitude, Snapshot};
use super::states_border::StateBorder;
use super::step_extension::Hermite;
use crate::mbd::states::StateSet;
use crate::vocab::math::DVec;

/// Relative size of the last Newton correction of accelerations and multipliers at
/// which the corrector has converged, as a fraction of ERROR, and its bounds: a loose
/// ERROR does not need accelerations to ten digits, a tight one needs them that close.
pub(super) const NEWTON_PER_ERROR: f64 = 1e-2;
pub(super) const NEWTON_TOL_MIN: f64 = 1e-10;
pub(super) const NEWTON_TOL_MAX: f64 = 1e-4;

/// Which member of the family.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Method {
    /// HHT with ALPHA ∈ [−1/3, 0].
    Hht {
        /// ALPHA.
        alpha: f64,
    },
    /// Generalized-α with spectral radius ρ∞ ∈ [0, 1].
    GeneralizedAlpha {
        /// ρ∞.
        rho_inf: f64,
    },
    /// Plain Newmark with β > 0, γ ≥ ½ (unconditionally stable for β ≥ γ/2).
    Newmark {
        /// β.
        beta: f64,
        /// γ.
        gamma: f64,
    },
}

/// An HHT or generalized-α integrator.
pub struct Newmark {
    method: Method,
    beta: f64,
    gamma: f64,
    alpha_m: f64,
    alpha_f: f64,
    /// Residual weights s and r.
    s: f64,
    r: f64,
    // The last accepted state.
    base: Option<Snapshot>,
    v0: DVec,
    a0: DVec,
    at0: DVec,
    lambda0: DVec,
    /// (Φ_qᵀλ − Q) at the last accepted state.
    f0: DVec,
    /// The accelerations before the last accepted step, and that step's size.
    a_prev: DVec,
    lambda_prev: DVec,
    h0: Option<f64>,
    /// The step of the current attempt.
    h1: f64,
    /// The mass blocks at the last accepted state.
    m0: Vec<Mat3Block>,
    // The candidate.
    at1: DVec,
    /// Scratch of [`Newmark::place`]: the position increment and the velocities.
    dx: Vec<f64>,
    v1: DVec,
    /// Scratch: the residual of the force balance, and the Newton right-hand side.
    res: DVec,
    rhs: Vec<f64>,
    /// The last attempt's error estimate for the run's monitors (the velocities' too
    /// while a contact is engaged).
    watched: f64,
    /// Per-column tolerance scales ([`Newmark::tolerances`]) and the ERROR they are for.
    tol: (f64, Vec<f64>),
    /// When the factorization is reused (its weight: the step size).
    reuse: Reuse,
    /// The state elements' border of the Newton matrix.
    border: StateBorder,
    /// The physical accelerations at the last accepted state (kept only when forces read
    /// accelerations: HHT's own are shifted in time).
    a_phys0: DVec,
    /// The last accepted step's start and its velocities, and its continuous extension
    /// when an output time falls inside it.
    start: Option<Snapshot>,
    start_v: DVec,
    hermite: Hermite,
    /// The state elements: x and ẋ committed at the last accepted state, ẋ before it,
    /// the candidate's x and ẋ, and the last accepted step's start (x, ẋ) for its
    /// continuous extension.
    states: StateHistory,
}

/// The state elements' values a Newmark step reads.
#[derive(Default)]
struct StateHistory {
    /// α_m, α_f and γ of the states' generalized-α (the module doc).
    alpha_m: f64,
    alpha_f: f64,
    gamma: f64,
    /// x, ẋ and the algorithmic rate w committed at the last accepted state.
    x0: Vec<f64>,
    r0: Vec<f64>,
    w0: Vec<f64>,
    /// The step w₀ belongs to (0 at a start), and w₀ moved to the current step's.
    w_step: f64,
    w: Vec<f64>,
    r_prev: Vec<f64>,
    x1: Vec<f64>,
    r1: Vec<f64>,
    start: (Vec<f64>, Vec<f64>),
    /// The extension is the candidate's (from x0 to x1), not the accepted step's.
    candidate: bool,
    /// Scratch: the formula's b, and the extension's states.
    b: Vec<f64>,
    at: Vec<f64>,
}

impl Newmark {
    /// An integrator of `method`, before its first step.
    pub fn new(method: Method) -> Newmark {
        let (alpha_m, alpha_f, gamma, beta, s, r) = match method {
            Method::Hht { alpha } => {
                let g = 0.5 - alpha;
                (0.0, 0.0, g, (1.0 - alpha).powi(2) / 4.0, 1.0 + alpha, alpha)
            }
            Method::GeneralizedAlpha { rho_inf } => {
                let am = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0);
                let af = rho_inf / (rho_inf + 1.0);
                let g = 0.5 - am + af;
                (am, af, g, 0.25 * (1.0 - am + af).powi(2), 1.0, 0.0)
            }
            Method::Newmark { beta, gamma } => (0.0, 0.0, gamma, beta, 1.0, 0.0),
        };
        Newmark {
            method,
            beta,
            gamma,
            alpha_m,
            alpha_f,
            s,
            r,
            base: None,
            v0: DVec::zeros(0),
            a0: DVec::zeros(0),
            at0: DVec::zeros(0),
            lambda0: DVec::zeros(0),
            f0: DVec::zeros(0),
            m0: Vec::new(),
            a_prev: DVec::zeros(0),
            lambda_prev: DVec::zeros(0),
            h0: None,
            h1: 0.0,
            at1: DVec::zeros(0),
            dx: Vec::new(),
            v1: DVec::zeros(0),
            res: DVec::zeros(0),
            rhs: Vec::new(),
            watched: 0.0,
            tol: (f64::NAN, Vec::new()),
            reuse: Reuse::default(),
            border: StateBorder::default(),
            a_phys0: DVec::zeros(0),
            start: None,
            start_v: DVec::zeros(0),
            hermite: Hermite::default(),
            states: StateHistory::default(),
        }
    }

    /// Adams HHT with its default ALPHA = −0.3.
    pub fn hht(alpha: f64) -> Newmark {
        Newmark::new(Method::Hht { alpha })
    }

    /// Generalized-α with Exudyn's default ρ∞ = 0.9 unless given.
    pub fn generalized_alpha(rho_inf: f64) -> Newmark {
        Newmark::new(Method::GeneralizedAlpha { rho_inf })
    }

    /// ∂ã₁/∂a₁.
    fn c(&self) -> f64 {
        (1.0 - self.alpha_f) / (1.0 - self.alpha_m)
    }

    /// ã₁ from a₁, into `self.at1`.
    fn algorithmic(&mut self, a1: &DVec) {
        if self.at1.len() != a1.len() {
            self.at1 = DVec::zeros(a1.len());
        }
        match self.method {
            Method::Hht { .. } | Method::Newmark { .. } => self.at1.copy_from(a1),
            Method::GeneralizedAlpha { .. } => {
                let (af, am) = (self.alpha_f, self.alpha_m);
                for k in 0..a1.len() {
                    self.at1[k] =
                        (a1[k] * (1.0 - af) + self.a0[k] * af - self.at0[k] * am) / (1.0 - am);
                }
            }
        }
    }

    /// Moves `d` to the state the accelerations `a1` give after a step `h` from the
    /// accepted state.
    fn place(&mut self, d: &mut Dynamics, a1: &DVec, h: f64, t1: f64) {
        self.algorithmic(a1);
        let n = a1.len();
        if self.dx.len() != n {
            (self.dx, self.v1) = (vec![0.0; n], DVec::zeros(n));
        }
        let (c0, c1) = ((0.5 - self.beta) * h * h, self.beta * h * h);
        let (g0, g1) = ((1.0 - self.gamma) * h, self.gamma * h);
        // (over slices: indexing nalgebra vectors checks bounds twice an entry)
        let (v0, at0, at1) = (self.v0.as_slice(), self.at0.as_slice(), self.at1.as_slice());
        let states = v0.iter().zip(at0).zip(at1);
        let outs = self.dx.iter_mut().zip(self.v1.as_mut_slice());
        for (((&v0, &at0), &at1), (dx, v1)) in states.zip(outs) {
            *dx = v0 * h + at0 * c0 + at1 * c1;
            *v1 = v0 + at0 * g0 + at1 * g1;
        }
        let base = self.base.as_ref().expect("started");
        d.set_state(base, &self.dx, &self.v1, t1);
    }

    fn weights(&self, h: f64) -> Weights {
        let c = self.c();
        Weights {
            w_m: 1.0,
            w_k: self.s * self.beta * h * h * c,
            w_c: self.s * self.gamma * h * c,
            w_l: self.s,
        }
    }

    /// Newton on the step `h` to `t1` with the per-column tolerance scales `tol`; `rhs`
    /// is scratch of n + m.
    fn iterate(
        &mut self,
        d: &mut Dynamics,
        h: f64,
        t1: f64,
        st: &Settings,
        tol: &[f64],
        rhs: &mut [f64],
    ) -> Result<Attempt, DynError> {
        let (n, m) = (d.n, d.m);
        let scale = self.beta * h * h * self.c();
        // Predictor: the accelerations extrapolated linearly from the last two steps.
        let mut a1 = match self.h0 {
            Some(h0) if self.a_prev.len() == n => &self.a0 + (&self.a0 - &self.a_prev) * (h / h0),
            _ => self.a0.clone(),
        };
        let mut lambda = match self.h0 {
            Some(h0) if self.lambda_prev.len() == m => {
                &self.lambda0 + (&self.lambda0 - &self.lambda_prev) * (h / h0)
            }
            _ => self.lambda0.clone(),
        };
        self.reuse.begin_step(h, d.factor_generation);
        // The states' generalized-α: x₁ = b + g·ẋ₁.
        let sh = &mut self.states;
        if !sh.x0.is_empty() {
            let (am, af, gm) = (sh.alpha_m, sh.alpha_f, sh.gamma);
            // w lags ẋ by (α_f − α_m)·h: moved to this step's h (ẍ₀ from the last
            // step's rates), as a change of step would leave it off by O(h·Δh).
            sh.w.clear();
            for k in 0..sh.x0.len() {
                let accel = match (sh.r_prev.get(k), self.h0) {
                    (Some(rp), Some(h0)) => (sh.r0[k] - rp) / h0,
                    _ => 0.0,
                };
                sh.w.push(sh.w0[k] + (am - af) * (h - sh.w_step) * accel);
            }
            sh.b.clear();
            for k in 0..sh.x0.len() {
                let (x, r, w) = (sh.x0[k], sh.r0[k], sh.w[k]);
                sh.b.push(x + h * (1.0 - gm) * w + h * gm * (af * r - am * w) / (1.0 - am));
            }
            d.forces
                .states
                .set_formula(&sh.b, h * gm * (1.0 - af) / (1.0 - am));
        }
        let reach = d.reach();
        let newton_tol = (NEWTON_PER_ERROR * st.error).clamp(NEWTON_TOL_MIN, NEWTON_TOL_MAX);
        let mut prev_norm = f64::INFINITY;
        if self.res.len() != n {
            self.res = DVec::zeros(n);
        }
        let mut first = 0.0;
        let tightest = tol.iter().fold(f64::INFINITY, |x, &y| x.min(y));
        let mut iter = 0;
        while iter < st.maxit {
            iter += 1;
            self.place(d, &a1, h, t1);
            let weights = self.weights(h);
            // (The reuse state is lent out: the closure reads the rest of `self`.)
            let mut reuse = std::mem::take(&mut self.reuse);
            let evaluated = reuse::evaluate(d, &mut reuse, (iter, h, weights), &lambda, |a| {
                self.physical_accelerations(&a1, a)
            });
            self.reuse = reuse;
            let refactor = evaluated?;
            // −R₁ = −(M a/UCF + s(Φ_qᵀλ − Q) − r f₀), −R₂ = −Φ/scale.
            let r1 = &mut self.res;
            r1.fill(0.0);
            d.add_constraint_forces(&lambda, r1);
            let (s, r) = (self.s, self.r);
            let forces = d.gen.q.as_slice().iter().zip(self.f0.as_slice());
            for (x, (&q, &f0)) in r1.as_mut_slice().iter_mut().zip(forces) {
                *x = s * (*x - q) - r * f0;
            }
            d.add_blocks_times(&d.mass_blocks(), self.s, a1.as_slice(), r1);
            if self.r != 0.0 {
                d.add_blocks_times(&self.m0, -self.r, a1.as_slice(), r1);
            }
            let (top, bottom) = rhs.split_at_mut(n);
            for (x, &r) in top.iter_mut().zip(r1.as_slice()) {
                *x = -r;
            }
            let inv_scale = 1.0 / scale;
            for (x, &phi) in bottom[..m].iter_mut().zip(d.phi.as_slice()) {
                *x = -phi * inv_scale;
            }
            d.solve(rhs)?;
            if !d.forces.states.is_empty() {
                // The step of the matrix bordered by the state elements.
                let mut border = std::mem::take(&mut self.border);
                let w_q = self.s;
                let mut place = |d: &mut Dynamics, a: &DVec| self.place(d, a, h, t1);
                let bordered = border.correct(d, rhs, (&a1, w_q), &mut place);
                self.border = border;
                bordered?;
            }
            // The index-3 Newton matrix has condition O(h⁻²): positions converged to a
            // tolerance still leave accelerations and multipliers (reactions) off by
            // that over β·h². So the test is on the accelerations and multipliers
            // themselves, relative to their size (with a floor where they vanish).
            // Positions carry rounding of ε·|q|; over β·h²·c that is an acceleration
            // Newton cannot resolve below. `norm` ≤ 1 is converged.
            let bh2 = h * h * self.beta * self.c();
            let a_scale = largest_magnitude(a1.as_slice()) + 1e-3 * tightest / bh2;
            let a_noise = 10.0 * f64::EPSILON * reach / bh2;
            let inv_tol = 1.0 / (newton_tol * a_scale + a_noise);
            // The test is on the accelerations: the multipliers follow them (and where the
            // constraints lose rank, at a four-bar's dead centre, part of them is not
            // determined at all). Reactions are reconciled at the outputs anyway.
            let norm = largest_magnitude(&rhs[..n]) * inv_tol;
            if !norm.is_finite() {
                return Ok(Attempt::Diverged);
            }
            for (a, &x) in a1.as_mut_slice().iter_mut().zip(&rhs[..n]) {
                *a += x;
            }
            for (l, &x) in lambda.as_mut_slice().iter_mut().zip(&rhs[n..n + m]) {
                *l += x;
            }
            let rate = norm / prev_norm;
            if iter == 1 {
                first = norm;
            }
            // Linear convergence: the error left is about rate/(1 − rate) of this step.
            let left = if rate < 1.0 {
                norm * rate / (1.0 - rate)
            } else {
                norm
            };
            // Converged; or stalled at the rounding floor of the linear solves (the
            // contraction is gone while the correction is already below 1e-6 relative).
            let stalled = iter > 2 && rate > 0.5 && norm * newton_tol <= 1e-6;
            if iter > 1 && norm.min(left) <= 1.0 || norm <= 1e-3 || stalled {
                self.reuse.converged(iter, first, rate);
                self.place(d, &a1, h, t1);
                d.a = a1;
                d.lambda = lambda;
                let coef = ((self.beta - 1.0 / 6.0) * h * h).abs();
                // While a contact is engaged, the velocities' error is watched too (not
                // controlled: their estimate is one order lower): a contact reverses them
                // in far less time than positions show it, and numerical damping eats
                // the bounce. (γ − ½)·h·(ã₁ − ã₀) is damping's term (γ = ½ − α for HHT);
                // at γ = ½ the trapezoid's h/12 scale stands in.
                let coef_v = match st.in_contact {
                    true => (self.gamma - 0.5).abs().max(1.0 / 12.0) * h,
                    false => 0.0,
                };
                let (mut err, mut worst, mut watched) = (0.0, 0, 0.0f64);
                // With fixed steps the estimate only feeds the run's monitors.
                let columns = self.at1.iter().zip(self.at0.iter()).zip(tol);
                for (k, ((a1, a0), tol)) in columns.enumerate() {
                    let e = coef * (a1 - a0).abs() / tol;
                    if e > err {
                        (err, worst) = (e, k);
                    }
                    watched = watched.max(coef_v * (a1 - a0).abs() / tol);
                }
                self.watched = err.max(watched);
                if !self.states.x0.is_empty() {
                    // The states at the converged candidate, and their own error.
                    d.solve_states()?;
                    let sh = &mut self.states;
                    d.forces.states.current(&d.sys, &mut sh.x1, &mut sh.r1);
                    let states = self.state_error(h, st.error);
                    if states > err {
                        (err, worst) = (states, 0);
                    }
                }
                return Ok(Attempt::Converged { err, worst });
            }
            // Slow or diverging with an old factorization: refactor here and go on.
            prev_norm = norm;
            if self.reuse.after_iteration(iter, rate, refactor) {
                break;
            }
        }
        self.reuse.invalidate();
        Ok(Attempt::Diverged)
    }
}

impl Newmark {
    /// The state elements' local error of the candidate after a step `h`, over their
    /// tolerances at ERROR `error` (the module doc's estimate).
    fn state_error(&self, h: f64, error: f64) -> f64 {
        let sh = &self.states;
        let first = (sh.gamma - 0.5 + sh.alpha_m - sh.alpha_f).abs() * h;
        let mut worst = 0.0f64;
        for k in 0..sh.x1.len() {
            let (r0, r1) = (sh.r0[k], sh.r1[k]);
            let third = match (sh.r_prev.get(k), self.h0) {
                (Some(&rp), Some(h0)) => 2.0 * ((r1 - r0) / h - (r0 - rp) / h0) / (h + h0),
                _ => (r1 - r0) / h,
            };
            let e = first * (r1 - r0).abs() + h.powi(3) / 12.0 * third.abs();
            worst = worst.max(e / StateSet::tolerance(sh.x1[k], error));
        }
        worst
    }

    /// Takes the committed state elements as the start of the next step, with their
    /// algorithmic rates (at a start, the rates themselves).
    fn take_committed_states(&mut self, d: &Dynamics) {
        let sh = &mut self.states;
        let Some((x, r)) = d.forces.states.committed() else {
            return;
        };
        let (am, af) = (sh.alpha_m, sh.alpha_f);
        let w1: Vec<f64> = match sh.w.len() == r.len() {
            true => (0..r.len())
                .map(|k| ((1.0 - af) * r[k] + af * sh.r0[k] - am * sh.w[k]) / (1.0 - am))
                .collect(),
            false => r.to_vec(),
        };
        sh.w_step = match sh.w.len() == r.len() {
            true => self.h1,
            false => 0.0,
        };
        let (x_old, r_old) = (std::mem::take(&mut sh.x0), std::mem::take(&mut sh.r0));
        sh.r_prev.clone_from(&r_old);
        sh.start = (x_old, r_old);
        (sh.x0, sh.r0, sh.w0) = (x.to_vec(), r.to_vec(), w1);
    }

    /// The physical accelerations at t₁ from the method's a₁ into `out`. HHT's a₁ solves
    /// (s·M₁ − r·M₀)·a₁ = s·F₁ − r·F₀ with F = M·a at each end, so a₁ is the blend
    /// s·a(t₁) − r·a(t₀) (exactly where the mass is constant, to O(h) where 3D inertia
    /// turns): forces that read accelerations must see a(t₁) = (a₁ + r·a(t₀))/s, or
    /// they would act at t₁ + α·h. Generalized-α's a₁ is physical (s = 1, r = 0).
    fn physical_accelerations(&self, a1: &DVec, out: &mut DVec) {
        copy_into(out, a1.as_slice());
        if self.r != 0.0 && self.a_phys0.len() == a1.len() {
            for (x, p) in out.iter_mut().zip(self.a_phys0.iter()) {
                *x = (*x + self.r * p) / self.s;
            }
        }
    }
}

impl Integrator for Newmark {
    fn name(&self) -> &'static str {
        match self.method {
            Method::Hht { .. } => "hht",
            Method::GeneralizedAlpha { .. } => "galpha",
            Method::Newmark { .. } => "newmark",
        }
    }

    fn order(&self) -> Option<u32> {
        // HHT and generalized-α are second order by construction (γ = ½ − α, resp.
        // ½ − α_m + α_f); a plain Newmark only with γ = ½.
        Some(match self.method {
            Method::Newmark { gamma, .. } if gamma != 0.5 => 1,
            _ => 2,
        })
    }

    fn monitored_error(&self, _err: f64) -> f64 {
        self.watched
    }

    fn error_order(&self) -> f64 {
        3.0
    }

    fn start(&mut self, d: &mut Dynamics) -> Result<(), DynError> {
        self.base = Some(d.snapshot());
        self.v0 = d.sys.v();
        self.a0 = d.a.clone();
        self.at0 = d.a.clone();
        self.lambda0 = d.lambda.clone();
        self.a_phys0 = d.a.clone();
        // (Φ_qᵀλ − Q)₀ = −M·a₀/UCF for consistent initial accelerations.
        let mut f0 = DVec::zeros(d.n);
        d.add_mass_times(self.a0.as_slice(), &mut f0);
        self.f0 = -f0;
        self.m0 = d.mass_blocks().into_owned();
        self.a_prev = DVec::zeros(0);
        self.h0 = None;
        self.reuse.invalidate();
        d.commit_states()?;
        let (alpha_m, alpha_f, gamma) = match self.method {
            Method::Hht { alpha } => (0.0, -alpha, 0.5 - alpha),
            _ => (self.alpha_m, self.alpha_f, self.gamma),
        };
        self.states = StateHistory {
            alpha_m,
            alpha_f,
            gamma,
            ..StateHistory::default()
        };
        self.take_committed_states(d);
        Ok(())
    }

    fn attempt(&mut self, d: &mut Dynamics, h: f64, st: &Settings) -> Result<Attempt, DynError> {
        let n = d.n;
        let t1 = self.base.as_ref().expect("started").time + h;
        self.h1 = h;
        if self.tol.0 != st.error || self.tol.1.len() != n {
            self.tol = (st.error, d.tolerances(st.error));
        }
        // Scratch lent to the iteration (it borrows `self` whole).
        let (tol, mut rhs) = (
            std::mem::take(&mut self.tol.1),
            std::mem::take(&mut self.rhs),
        );
        rhs.resize(n + d.m, 0.0);
        let outcome = self.iterate(d, h, t1, st, &tol, &mut rhs);
        (self.tol.1, self.rhs) = (tol, rhs);
        outcome
    }

    fn accept(&mut self, d: &mut Dynamics) {
        // (Φ_qᵀλ − Q)₁ from the converged residual: s·f₁ = r·f₀ − (s·M₁ − r·M₀)·a₁/UCF.
        let m1 = d.mass_blocks();
        let ma = &mut self.res;
        ma.fill(0.0);
        d.add_blocks_times(&m1, self.s, d.a.as_slice(), ma);
        d.add_blocks_times(&self.m0, -self.r, d.a.as_slice(), ma);
        for (f, x) in self.f0.iter_mut().zip(ma.iter()) {
            *f = (*f * self.r - x) / self.s;
        }
        // Constant mass blocks (2D, isotropic parts) are already m0.
        if let std::borrow::Cow::Owned(m1) = m1 {
            self.m0 = m1;
        }
        self.start = self.base.replace(d.snapshot());
        std::mem::swap(&mut self.start_v, &mut self.v0);
        self.v0 = d.sys.v();
        // The previous values move back a slot; their buffers are reused.
        std::mem::swap(&mut self.a_prev, &mut self.a0);
        std::mem::swap(&mut self.lambda_prev, &mut self.lambda0);
        copy_into(&mut self.a0, d.a.as_slice());
        copy_into(&mut self.lambda0, d.lambda.as_slice());
        copy_into(&mut self.at0, self.at1.as_slice());
        self.h0 = Some(self.h1);
        self.take_committed_states(d);
        d.store_accelerations();
        if d.reads_solution() {
            let mut a = DVec::zeros(d.n);
            self.physical_accelerations(&d.a, &mut a);
            self.a_phys0 = a;
        }
    }

    fn dense(&self) -> bool {
        true
    }

    fn extend(&mut self, d: &mut Dynamics) -> Result<(), DynError> {
        if let (Some(start), Some(end)) = (&self.start, &self.base) {
            let v = (&self.start_v, &self.v0);
            self.hermite.fill(d, start, end, v, self.h1);
        }
        self.states.candidate = false;
        Ok(())
    }

    fn dense_state(&mut self, d: &mut Dynamics, t: f64) {
        self.hermite.place(d, t);
        // The states on the cubic Hermite through the step's ends and slopes.
        let sh = &mut self.states;
        let ((xa, ra), (xb, rb), from) = match sh.candidate {
            false => ((&sh.start.0, &sh.start.1), (&sh.x0, &sh.r0), &self.start),
            true => ((&sh.x0, &sh.r0), (&sh.x1, &sh.r1), &self.base),
        };
        if xa.is_empty() || xb.len() != xa.len() || ra.len() != xa.len() {
            return;
        }
        let h = self.h1;
        let s = match from {
            Some(from) if h > 0.0 => ((t - from.time) / h).clamp(0.0, 1.0),
            _ => 1.0,
        };
        let (h00, h10) = ((1.0 + 2.0 * s) * (1.0 - s).powi(2), s * (1.0 - s).powi(2));
        let (h01, h11) = (s * s * (3.0 - 2.0 * s), s * s * (s - 1.0));
        sh.at.clear();
        for k in 0..xa.len() {
            sh.at
                .push(h00 * xa[k] + h10 * h * ra[k] + h01 * xb[k] + h11 * h * rb[k]);
        }
        d.place_states(&sh.at);
    }

    fn extend_candidate(&mut self, d: &mut Dynamics) -> bool {
        let Some(base) = &self.base else {
            return false;
        };
        let (end, v1) = (d.snapshot(), d.sys.v());
        self.hermite.fill(d, base, &end, (&self.v0, &v1), self.h1);
        self.states.candidate = true;
        true
    }

    fn reject(&mut self, d: &mut Dynamics) {
        let base = self.base.as_ref().expect("started");
        d.forces.states.hold();
        d.restore(base);
        d.a = self.a0.clone();
        d.lambda = self.lambda0.clone();
    }
}
