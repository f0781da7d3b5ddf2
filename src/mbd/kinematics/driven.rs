//! One kinematic step of a fully driven model on Φ_q alone ([`Driven`]): the issue 42 §2
//! path, taken when the kept rows are as many as the velocity columns, all positional,
//! and nothing reads the solution back (no state elements, no force reading an
//! acceleration or a reaction); otherwise [`super::steps`] solves on the saddle point.
//!
//! - **The prediction** is the cubic through the last two solutions' positions and
//!   velocities (Hermite, extrapolated over the step; its miss grows as h⁴), or, at a
//!   stretch's first step, q + v·h + a·h²/2 from the start's accelerations.
//! - **Positions:** modified Newton on Φ(q, t + h) = 0 with the factors of Φ_q at the
//!   last solution, the residuals evaluated without derivatives (a MOTION's measure on
//!   plain numbers, not dual frames), down to the coordinates' rounding floor. Where the
//!   old factors no longer contract, Φ_q is evaluated and factored where Newton stands.
//! - **At the solution** Φ_q is evaluated and factored once: velocities from
//!   Φ_q·v = −Φ_t; when the outputs read accelerations or reactions
//!   ([`super::Settings::motion`]), accelerations from Φ_q·a = γ and multipliers from
//!   Φ_qᵀ·λ = Q − M·a (the transpose factored only then). The same factors start the
//!   next step's Newton.
//!
//! The step's error is the prediction's miss, the sum of the Newton corrections, in
//! ERRORs per column as before.

use super::square::SquareJacobian;
use crate::mbd::dynamics::{DynError, Dynamics, Singularity, Snapshot};
use crate::vocab::math::DVec;

/// The largest position residual (scaled as [`Dynamics::scaled_residual`]) a solved
/// step may keep (on either path): Newton stops at rounding, far below; a projection
/// that stalls above this has not converged.
pub const SOLVED: f64 = 1e-10;

/// Newton corrections before the attempt counts as failed.
const ITERATIONS: usize = 24;

/// The residual, in rounding floors, that confirms a solution Newton's contraction
/// said was reached (rounding noise lies within it).
const SETTLED: f64 = 8.0;

/// A failed attempt: Newton (a shorter step may converge), a prediction too far, or an
/// evaluation's failure.
pub enum Failed {
    /// Newton did not converge or a matrix was singular.
    Newton(DynError),
    /// The prediction missed by this many ERRORs (more than one).
    Far(f64),
    /// Anything else.
    Other(DynError),
}

/// The state of the Φ_q path over a kinematic stretch: the factors, the last solution
/// before the current one, and scratch.
pub struct Driven {
    square: SquareJacobian,
    /// The solution before the current one (for the Hermite prediction): its state,
    /// velocities and time.
    prev: Option<(Snapshot, DVec, f64)>,
    /// Solve accelerations and multipliers at every step.
    motion: bool,
    /// 1/h₁, the last step's inverse, when two solutions give Φ_q's extrapolation.
    ratio: Option<f64>,
    /// The prediction's polynomial per column: v₀, c₂, c₃ of v₀·τ + c₂·τ² + c₃·τ³.
    poly: Vec<[f64; 3]>,
    /// The prediction, the Newton corrections' sum, a solve's right-hand side, the
    /// increment back to the last solution.
    dx: Vec<f64>,
    moved: Vec<f64>,
    rhs: Vec<f64>,
    back: Vec<f64>,
    gamma: DVec,
    /// Per column, ERROR's scale (the model length for translations, 1 for rotations).
    scale: Vec<f64>,
    /// Per row, its residual's scale ([`Dynamics::scaled_residual`]'s: 1/the model
    /// length for a translation), taken once: the residual is measured four or five
    /// times a step, and looking each row's kind up again was 4 % of a step.
    row_scale: Vec<f64>,
}

impl Driven {
    /// The Φ_q path for `d` at its solved state, Φ_q factored there; None when the
    /// model does not qualify (module doc) or Φ_q is singular where it stands.
    pub fn new(d: &mut Dynamics, motion: bool) -> Option<Driven> {
        let positional = d.rows.iter().all(|&(e, q)| !d.sys.row_reads_velocity(e, q));
        if !positional || !d.forces.states.is_empty() || d.reads_solution() {
            return None;
        }
        let mut square = SquareJacobian::new(d)?;
        d.eval_constraints(true).ok()?;
        if !square.factor_solved(d) {
            return None;
        }
        square.accept();
        let n = d.n;
        Some(Driven {
            square,
            prev: None,
            motion,
            ratio: None,
            poly: vec![[0.0; 3]; n],
            dx: vec![0.0; n],
            moved: vec![0.0; n],
            rhs: vec![0.0; n],
            back: vec![0.0; n],
            gamma: DVec::zeros(n),
            scale: d.tolerances(1.0),
            row_scale: d.rows.iter().map(|&(e, q)| d.sys.row_scale(e, q)).collect(),
        })
    }

    /// Makes the prediction from `now` (where `d` stands): the polynomial's
    /// coefficients per column; the order of its miss (3 for the Taylor start, 4 for
    /// the Hermite cubic).
    pub fn prepare(&mut self, d: &Dynamics, now: &Snapshot) -> i32 {
        let v = d.sys.v();
        let Some((prev, v1, t1)) = &self.prev else {
            self.ratio = None;
            for c in 0..d.n {
                let a = d.a.get(c).copied().unwrap_or(0.0);
                self.poly[c] = [v[c], 0.5 * a, 0.0];
            }
            return 3;
        };
        // p(τ) = v₀·τ + c₂·τ² + c₃·τ³ through p(−h₁) = D (the increment back to the last
        // solution) with p'(−h₁) = v₁ (its velocity).
        let h1 = d.sys.time - t1;
        self.ratio = Some(1.0 / h1);
        d.increment(now, prev, &mut self.back);
        for c in 0..d.n {
            let (v0, v1, back) = (v[c], v1[c], self.back[c]);
            let a = (back + v0 * h1) / (h1 * h1);
            let b = (v0 - v1) / (2.0 * h1);
            let c3 = 2.0 * (a - b) / h1;
            self.poly[c] = [v0, a + c3 * h1, c3];
        }
        4
    }

    /// Keeps `now` (where `d` stood before the step just solved) for the next
    /// prediction; `v` its velocities.
    pub fn solved_from(&mut self, now: Snapshot, v: DVec, time: f64) {
        self.square.accept();
        self.prev = Some((now, v, time));
    }

    /// The predicted increment of column `c` over `h` ([`Driven::prepare`] first).
    pub fn increment(&self, c: usize, h: f64) -> f64 {
        let [v0, c2, c3] = self.poly[c];
        h * (v0 + h * (c2 + h * c3))
    }

    /// One step of `h` from where `d` stands, predicted by [`Driven::prepare`]: Ok with the
    /// prediction's miss in ERRORs (`error`), `d` solved at the step's end; else why
    /// not, `d` left anywhere.
    pub fn attempt(&mut self, d: &mut Dynamics, h: f64, error: f64) -> Result<f64, Failed> {
        for c in 0..d.n {
            self.dx[c] = self.increment(c, h);
        }
        d.sys.apply_increment(&self.dx);
        d.sys.time += h;
        self.newton(d, h)?;
        let miss = (0..d.n)
            .map(|c| self.moved[c].abs() / (error * self.scale[c]))
            .fold(0.0, f64::max);
        if miss > 1.0 {
            return Err(Failed::Far(miss));
        }
        self.rates(d)?;
        d.commit_measures();
        Ok(miss)
    }

    /// Newton on the positions from the prediction to the rounding floor, the
    /// corrections summed into `self.moved`; Φ and Φ_q then evaluated, and Φ_q
    /// factored, at the solution. The corrections use Φ_q extrapolated from the last
    /// two solutions (else the last one's) while they contract; a correction whose
    /// contraction says the next is below the floor is the last before the solution's
    /// own evaluation, which confirms it (else Newton goes on with its factors).
    fn newton(&mut self, d: &mut Dynamics, h: f64) -> Result<(), Failed> {
        let floor = 2.0 * f64::EPSILON * d.reach() / d.sys.length;
        let unsolved = |d: &Dynamics| {
            Failed::Newton(DynError::Newton {
                time: d.sys.time,
                step: h,
                culprit: d.worst_row(),
            })
        };
        self.moved.fill(0.0);
        if let Some(ratio) = self.ratio {
            self.square.factor_extrapolated(d, h * ratio);
        }
        evaluate(d, false)?;
        let first = self.worst(d);
        let mut residual = first;
        // Whether the factors are of the current iterate, and whether Φ_q is evaluated
        // there (Φ with it).
        let (mut fresh, mut evaluated) = (false, false);
        let mut last_size = f64::INFINITY;
        for _ in 0..ITERATIONS {
            if residual <= floor {
                if !evaluated {
                    evaluate(d, true)?;
                }
                return self.solved(d, &unsolved);
            }
            for (x, p) in self.rhs.iter_mut().zip(d.phi.iter()) {
                *x = -p;
            }
            if !self.square.solve(&mut self.rhs) {
                return Err(singular(d));
            }
            d.stats.newton_iterations += 1;
            d.sys.apply_increment(&self.rhs);
            let mut size: f64 = 0.0;
            for ((m, x), s) in self.moved.iter_mut().zip(&self.rhs).zip(&self.scale) {
                *m += x;
                size = size.max(x.abs() / s);
            }
            // What is left after this correction at the contraction of the last two.
            let rate = size / last_size;
            last_size = size;
            let converging = rate < 0.5 && rate * size / (1.0 - rate) <= floor;
            evaluate(d, converging)?;
            evaluated = converging;
            let next = self.worst(d);
            if !next.is_finite() {
                return Err(unsolved(d));
            }
            if converging && next <= SETTLED * floor {
                return self.solved(d, &unsolved);
            }
            if next > 0.5 * residual {
                if fresh && next < first {
                    // Newton with the exact Jacobian stalls only at rounding.
                    if !evaluated {
                        evaluate(d, true)?;
                    }
                    return self.solved(d, &unsolved);
                }
                if fresh {
                    return Err(unsolved(d));
                }
                // The factors no longer contract: factors here.
                if !evaluated {
                    evaluate(d, true)?;
                }
                if !self.square.factor(d) {
                    return Err(singular(d));
                }
                (residual, fresh, last_size) = (next, true, f64::INFINITY);
                continue;
            }
            (residual, fresh) = (next, false);
        }
        Err(unsolved(d))
    }

    /// The largest scaled residual of the rows (all positional here), each as
    /// [`Dynamics::scaled_residual`] gives it, with the rows' scales taken once.
    fn worst(&self, d: &Dynamics) -> f64 {
        if self.row_scale.len() != d.m {
            return (0..d.m).map(|r| d.scaled_residual(r)).fold(0.0, f64::max);
        }
        let phi = d.phi.iter().take(d.m);
        (phi.zip(&self.row_scale))
            .map(|(p, s)| p.abs() * s)
            .fold(0.0, f64::max)
    }

    /// The positions solved where `d` stands (Φ and Φ_q evaluated there): Φ_q
    /// factored for the rates and the next step, or why not.
    fn solved(
        &mut self,
        d: &mut Dynamics,
        unsolved: &dyn Fn(&Dynamics) -> Failed,
    ) -> Result<(), Failed> {
        let residual = self.worst(d);
        if residual.is_nan() || residual > SOLVED {
            return Err(unsolved(d));
        }
        match self.square.factor_solved(d) {
            true => Ok(()),
            false => Err(singular(d)),
        }
    }

    /// Velocities, and with [`Driven::motion`] accelerations and multipliers, at the
    /// solved positions from Φ_q's factors.
    fn rates(&mut self, d: &mut Dynamics) -> Result<(), Failed> {
        for (r, &(e, q)) in d.rows.iter().enumerate() {
            self.rhs[r] = -d.sys.row_dt(e, q).map_err(other)?;
        }
        if !self.square.solve(&mut self.rhs) {
            return Err(singular(d));
        }
        d.sys.set_v(&DVec::from_column_slice(&self.rhs));
        if !self.motion {
            return Ok(());
        }
        crate::mbd::dynamics::gamma::gamma(d, &mut self.gamma).map_err(other)?;
        if !self.square.solve(self.gamma.as_mut_slice()) {
            return Err(singular(d));
        }
        if d.a.len() != d.n {
            d.a = DVec::zeros(d.n);
        }
        d.a.copy_from(&self.gamma);
        d.store_accelerations();
        d.eval_forces(false).map_err(other)?;
        d.check_forces().map_err(Failed::Other)?;
        // Φ_qᵀ·λ = Q − M·a/UCF.
        let mut inertia = DVec::zeros(d.n);
        d.add_mass_times(d.a.as_slice(), &mut inertia);
        for ((x, q), m) in self.rhs.iter_mut().zip(d.gen.q.iter()).zip(inertia.iter()) {
            *x = q - m;
        }
        if !self.square.solve_transpose(d, &mut self.rhs) {
            return Err(singular(d));
        }
        if d.lambda.len() != d.m {
            d.lambda = DVec::zeros(d.m);
        }
        d.lambda.copy_from_slice(&self.rhs);
        Ok(())
    }
}

/// Φ (and Φ_q with `jacobian`) at `d`'s state.
fn evaluate(d: &mut Dynamics, jacobian: bool) -> Result<(), Failed> {
    d.eval_constraints(jacobian)
        .map_err(|e| classify(DynError::Model(e)))
}

/// A singular Φ_q where `d` stands.
fn singular(d: &Dynamics) -> Failed {
    Failed::Newton(DynError::Singular {
        time: d.sys.time,
        why: Singularity::Numerical,
        culprit: d.worst_row(),
    })
}

fn other(e: crate::mbd::error::MbdError) -> Failed {
    Failed::Other(DynError::Model(e))
}

/// A non-finite evaluation is Newton's failure (a shorter step may cure it); the rest
/// is reported as it is.
fn classify(e: DynError) -> Failed {
    match e {
        DynError::NotFinite { .. } => Failed::Newton(e),
        _ => Failed::Other(e),
    }
}
