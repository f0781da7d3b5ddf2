//! The consistent solve at a state (spec §6.1 phase 3): accelerations and multipliers
//! from the saddle-point matrix [[M/UCF, Φ_qᵀ], [Φ_q, 0]] (refined when it had to be
//! regularised), swept until forces that read them settle, or solved by Newton with
//! ∂Q/∂λ when the forces differentiate the reactions they read (joint friction); and
//! the reconciliation of the velocities for output ([`Dynamics::reconcile`]).

use super::blocks::Weights;
use super::failure::DynError;
use super::gamma;
use super::setup::Dynamics;
use super::state::{copy_into, zero_into};
use super::workspace::Which;
use crate::mbd::error::MbdError;
use crate::vocab::math::DVec;

/// Sweeps of the consistent accelerations when forces read them (or reactions), and the
/// relative change at which they have settled.
pub(super) const SOLUTION_SWEEPS: usize = 200;

pub(super) const SOLUTION_TOL: f64 = 1e-14;

/// A relative change at which a force–solution loop that no longer contracts is taken as
/// settled: rounding, not a loop that amplifies.
const SOLUTION_NOISE: f64 = 1e-11;

/// The saddle point's weights: the mass and the constraint forces as they are.
const SADDLE: Weights = Weights {
    w_m: 1.0,
    w_k: 0.0,
    w_c: 0.0,
    w_l: 1.0,
};

impl Dynamics {
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

    /// Solves [[M/UCF, Φ_qᵀ], [Φ_q, 0]]·x = b in place with the factorization of
    /// [`Dynamics::factor_saddle`]: its regularisation is taken back out by iterative
    /// refinement against the exact matrix (a direct solve, unlike a Newton step, would
    /// keep the regularisation's bias).
    pub(super) fn solve_saddle(&mut self, b: &mut [f64]) -> Result<(), DynError> {
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
    pub(super) fn factor_saddle(&mut self) -> Result<(), DynError> {
        self.stats.jacobian_evaluations += 1;
        self.scratch.loop_jacobian.clear();
        self.factor_into(Which::Saddle, SADDLE)
    }

    /// The accelerations and multipliers with the saddle-point matrix factored. Forces
    /// that read accelerations or reactions make this a fixed point: where a force law
    /// differentiates the reactions it reads (joint friction), solved by Newton on
    /// (a, λ) ([`Dynamics::newton_solution`]), else by repeating the solve with the
    /// forces at the last accelerations and multipliers until they settle (at the loop's
    /// gain per sweep).
    pub(super) fn accelerations_factored(&mut self) -> Result<(), DynError> {
        // (Buffers taken out of the scratch are put back on success; a failure ends the
        // attempt, and a lost buffer is only allocated again.)
        let mut gamma = std::mem::take(&mut self.scratch.gamma);
        gamma::gamma(self, &mut gamma)?;
        let mut rhs = std::mem::take(&mut self.scratch.solution);
        let looped = self.reads_solution();
        let solved = match looped && self.forces.differentiates_reactions() {
            // (A first sweep that changes nothing has found the loop settled already.)
            true => match self.sweep(&gamma, &mut rhs) {
                Ok(change) if change > SOLUTION_TOL => {
                    self.newton_solution(&gamma, &mut rhs, change)
                }
                other => other.map(|_| ()),
            },
            false => self.swept_solution(&gamma, &mut rhs, looped),
        };
        (self.scratch.gamma, self.scratch.solution) = (gamma, rhs);
        solved
    }

    /// One solve with the factored saddle-point matrix and the forces at the current
    /// accelerations and multipliers, which it replaces (`rhs` is scratch): the largest
    /// change relative to the solution's size (infinite when there was none before).
    fn sweep(&mut self, gamma: &DVec, rhs: &mut Vec<f64>) -> Result<f64, DynError> {
        self.eval_forces(false)?;
        self.check_forces()?;
        rhs.clear();
        rhs.extend_from_slice(self.gen.q.as_slice());
        rhs.extend_from_slice(gamma.as_slice());
        self.solve_saddle(rhs)?;
        let (a, lambda) = rhs.split_at(self.n);
        let change = if self.a.len() == self.n && self.lambda.len() == self.m {
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
        Ok(change)
    }

    /// The sweeps of [`Dynamics::accelerations_factored`] (one when not `looped`).
    fn swept_solution(
        &mut self,
        gamma: &DVec,
        rhs: &mut Vec<f64>,
        looped: bool,
    ) -> Result<(), DynError> {
        let mut best_change = f64::INFINITY;
        let mut stalled = 0;
        for _ in 0..SOLUTION_SWEEPS {
            let change = self.sweep(gamma, rhs)?;
            // A loop that has stopped contracting at the rounding of its values (a
            // friction reading its joint's reaction settles to within a few ulps, then
            // wanders there) has converged as far as the numbers allow.
            let settled = stalled >= 4 && change <= SOLUTION_NOISE;
            if !looped || change <= SOLUTION_TOL || settled {
                return Ok(());
            }
            // Progress is judged against the smallest change so far: at the rounding
            // floor the changes wander in a cycle, and each dip must not reset the count.
            stalled = if change < 0.9 * best_change {
                0
            } else {
                stalled + 1
            };
            if stalled >= 5 && change > SOLUTION_NOISE {
                break;
            }
            best_change = best_change.min(change);
        }
        Err(self.solution_loop())
    }

    /// Newton on (a, λ) for forces that read reactions with their derivative by them,
    /// from the accelerations and multipliers of a first sweep, which changed them by
    /// `swept` (relative): the residual
    /// [M·a/UCF + Φ_qᵀ·λ − Q(λ); Φ_q·a − γ] against the matrix [[M/UCF, Φ_qᵀ − ∂Q/∂λ],
    /// [Φ_q, 0]], refactored while it contracts slowly (∂Q/∂λ follows the reaction's
    /// direction; forces reading accelerations, which it leaves out, converge at their
    /// loop's gain). `x` is scratch.
    fn newton_solution(
        &mut self,
        gamma: &DVec,
        x: &mut Vec<f64>,
        swept: f64,
    ) -> Result<(), DynError> {
        let (n, m) = (self.n, self.m);
        let mut top = std::mem::take(&mut self.scratch.product);
        let (mut refactor, mut last) = (true, swept);
        for _ in 0..SOLUTION_SWEEPS {
            self.eval_forces(false)?;
            self.check_forces()?;
            // −R: −(M·a/UCF + Φ_qᵀ·λ − Q), −(Φ_q·a − γ).
            zero_into(&mut top, n);
            self.add_blocks_times(&self.mass_blocks(), 1.0, self.a.as_slice(), &mut top);
            self.add_constraint_forces(&self.lambda, &mut top);
            x.clear();
            x.extend(top.iter().zip(self.gen.q.iter()).map(|(r, q)| q - r));
            x.resize(n + m, 0.0);
            self.jac.add_times(self.a.as_slice(), &mut x[n..]);
            for (r, g) in x[n..].iter_mut().zip(gamma.iter()) {
                *r = g - *r;
            }
            if refactor {
                self.loop_jacobian();
                let factors = self.factor_into(Which::Saddle, SADDLE);
                self.scratch.loop_jacobian.clear();
                factors?;
            }
            self.solve_with(Which::Saddle, x)?;
            let size =
                (self.a.iter().chain(self.lambda.iter())).fold(0.0f64, |s, v| s.max(v.abs()));
            let change = x.iter().fold(0.0f64, |s, v| s.max(v.abs())) / (size + f64::MIN_POSITIVE);
            self.a += DVec::from_column_slice(&x[..n]);
            self.lambda += DVec::from_column_slice(&x[n..]);
            self.store_accelerations();
            // Converged: this change, or what is left after it at this contraction
            // (ρ·change/(1 − ρ)), below the tolerance; or at the rounding floor, where
            // it no longer contracts.
            let rate = change / last;
            let left = match rate < 1.0 && last.is_finite() {
                true => rate * change / (1.0 - rate),
                false => change,
            };
            if left <= SOLUTION_TOL || (change <= SOLUTION_NOISE && change > 0.5 * last) {
                self.scratch.product = top;
                return Ok(());
            }
            if !change.is_finite() {
                break;
            }
            // A slow contraction asks for the matrix at the new multipliers.
            refactor = change >= 0.1 * last;
            last = change;
        }
        Err(self.solution_loop())
    }

    /// The failure of a force–solution loop that does not settle: names the first force
    /// reading an acceleration or a reaction, and what it reads.
    pub(super) fn solution_loop(&self) -> DynError {
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
}
