//! When an implicit integrator's Newton iteration may keep its factorization of the Newton
//! matrix, across iterations and steps, and when it refactors: the policy HHT,
//! generalized-α and the BDFs share. A factorization is tied to the step weight it was
//! made for (h for the Newmark family, g = h/Σ1/j for a BDF) and to the
//! [`super::Dynamics::factor_generation`] it produced (someone else factoring replaces it).

use super::blocks::Weights;
use super::failure::DynError;
use super::setup::Dynamics;
use super::state::copy_into;
use crate::vocab::math::DVec;

/// The predicted size after two iterations (in tolerances) above which a step refactors
/// before its first iteration rather than risk a third and a refactor mid-step.
const PROACTIVE_REFACTOR: f64 = 0.25;

/// The reuse state of one integrator's factorization.
#[derive(Clone, Debug, Default)]
pub struct Reuse {
    /// The step weight and generation of the factorization this integrator made (None:
    /// none valid).
    weight: Option<f64>,
    generation: u64,
    /// The last converged step's first Newton correction and its contraction with the
    /// factorization it reused.
    last_first: f64,
    last_rate: f64,
    /// The contraction right after the last fresh factorization: what refactoring can
    /// achieve. About 1e-5 (Newton is quadratic) unless forces read accelerations, or
    /// reactions through an expression (`JOINT(…)`), loops Newton does not differentiate
    /// (a FRICTION's reaction it does: ∂Q/∂λ is in the matrix): then refactoring cannot
    /// beat the loop's gain, and is not tried for it.
    fresh_rate: f64,
    /// In the current step: the iteration that factored afresh, and refactors tried.
    fresh_at: Option<usize>,
    fresh_tries: usize,
    /// Steps left that factor afresh at their start because a reused factorization
    /// contracted too slowly recently (its iteration was wasted; at these step sizes an
    /// older matrix is likely no better).
    fresh_steps: usize,
    /// Whether a failed reuse starts [`FRESH_AFTER_FAILED_REUSE`] fresh steps (the BDF's
    /// long steps; the Newmark family keeps reusing, which its dead-centre passages
    /// need).
    refresh: bool,
}

/// Steps that factor afresh after a reused factorization failed, before reuse is tried
/// again.
const FRESH_AFTER_FAILED_REUSE: usize = 4;

impl Reuse {
    /// The policy that factors afresh for a few steps after a reused factorization
    /// contracted too slowly.
    pub fn refreshing() -> Reuse {
        Reuse {
            refresh: true,
            ..Reuse::default()
        }
    }

    /// At a step's start with step weight `w`: drops the factorization when `w` moved
    /// by more than a quarter, someone else factored since (`generation`), or the last
    /// step predicts a third iteration. A first correction of size n contracted by ρ
    /// leaves about n·ρ² after the second, so that must stay below the tolerance (norm 1);
    /// ρ grows as the factorization ages, hence the margin. A refactor costs about one
    /// and a half iterations, and a fresh matrix converges in two.
    pub fn begin_step(&mut self, w: f64, generation: u64) {
        (self.fresh_at, self.fresh_tries) = (None, 0);
        if self.fresh_steps > 0 {
            self.fresh_steps -= 1;
            self.weight = None;
        }
        if let Some(fw) = self.weight {
            let third_likely = self.last_first * self.last_rate.powi(2) > PROACTIVE_REFACTOR
                && self.last_rate > 2.0 * self.fresh_rate;
            if !(0.8..=1.25).contains(&(w / fw)) || generation != self.generation || third_likely {
                self.weight = None;
            }
        }
    }

    /// Whether the next iteration must factor.
    pub fn must_factor(&self) -> bool {
        self.weight.is_none()
    }

    /// Records a fresh factorization at iteration `iter` for weight `w`.
    pub fn factored(&mut self, iter: usize, w: f64, generation: u64) {
        (self.weight, self.generation, self.fresh_at) = (Some(w), generation, Some(iter));
    }

    /// Records a converged step's first correction and last contraction.
    pub fn converged(&mut self, iter: usize, first: f64, rate: f64) {
        (self.last_first, self.last_rate) = (first, if iter > 1 { rate } else { 0.0 });
    }

    /// After iteration `iter` (not converged) contracted by `rate`, `refactored` telling
    /// whether it factored: drops the factorization when it contracts too slowly (at most
    /// twice a step), and says whether to give up on a diverging iteration.
    pub fn after_iteration(&mut self, iter: usize, rate: f64, refactored: bool) -> bool {
        if self.fresh_at == Some(iter - 1) {
            self.fresh_rate = rate;
        }
        if rate > 0.15f64.max(2.0 * self.fresh_rate)
            && iter > 1
            && !refactored
            && self.fresh_tries < 2
        {
            self.weight = None;
            self.fresh_tries += 1;
            if self.refresh {
                self.fresh_steps = FRESH_AFTER_FAILED_REUSE;
            }
            false
        } else {
            rate > 2.0 && iter > 2
        }
    }

    /// Forgets the factorization (a failed step, a restart).
    pub fn invalidate(&mut self) {
        self.weight = None;
    }
}

/// One Newton iteration's evaluations at the state the integrator placed: constraints
/// with their Jacobian; the forces, with Jacobians when `reuse` asks for a factorization
/// (which then follows, with `weights` for the step weight `w`), and when they read
/// accelerations or reactions with this iterate's (`accelerations` fills `d.a`, `lambda`
/// the multipliers: Newton then solves them with the motion, quadratically for a
/// FRICTION's reaction, whose ∂Q/∂λ the matrix holds, else at the loop gain's rate, which
/// the contraction test watches). True when it factored.
pub fn evaluate(
    d: &mut Dynamics,
    reuse: &mut Reuse,
    (iter, w, weights): (usize, f64, Weights),
    lambda: &DVec,
    accelerations: impl FnOnce(&mut DVec),
) -> Result<bool, DynError> {
    let refactor = reuse.must_factor();
    d.eval_constraints(true)?;
    if d.reads_solution() {
        accelerations(&mut d.a);
        copy_into(&mut d.lambda, lambda.as_slice());
        d.store_accelerations();
    }
    d.eval_forces(refactor)?;
    d.check_forces()?;
    d.stats.newton_iterations += 1;
    if refactor {
        d.stats.jacobian_evaluations += 1;
        d.factor(weights, lambda)?;
        reuse.factored(iter, w, d.factor_generation);
    } else {
        // Factoring checks for vanished rows; an old factorization would not see one.
        d.check_rows()?;
    }
    Ok(refactor)
}
