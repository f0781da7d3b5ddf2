//! Projection of the positions back onto the constraints
//! ([`Dynamics::project_positions`]): the closest configuration in the mass metric, for
//! output rows interpolated inside a step and for drift.

use super::failure::DynError;
use super::setup::Dynamics;

impl Dynamics {
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
}
