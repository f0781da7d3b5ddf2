//! Kinematic analysis (Adams' SIMULATE/KINEMATICS): a model whose kept constraints
//! (joints, GCONs, MOTIONs) leave no degree of freedom is solved from them alone,
//! nothing integrated. From one solved time to the next the analysis takes its own
//! steps ([`steps`]), as Adams' does: each predicts the positions from the last
//! solution's velocity and acceleration (q + v·h + a·h²/2), solves Φ(q, t) = 0 by
//! Newton down to rounding, and is halved when Newton does not contract; the step
//! grows back, bounded by HMAX, while the prediction lands within ERROR of the
//! solution, so the output step never decides whether the analysis converges.
//! Velocities come from Φ_q·v = −Φ_t; accelerations and reactions from the
//! saddle-point system [[M, Φ_qᵀ], [Φ_q, 0]]·[a; λ] = [Q; γ], whose constraint block,
//! square and regular, fixes a alone (the forces then give λ). The last two are the
//! dynamics' own reconciliation ([`Dynamics::reconcile`]), exact for a model without
//! freedom. A fully driven model whose rows are all positional and whose forces read
//! no solution skips the saddle point ([`driven`]): Φ_q alone ([`square`]), factored
//! once a step at the solution, gives the positions by modified Newton (Φ_q
//! extrapolated from the last two solutions), the velocities, and, only where the
//! outputs read them, the accelerations (Φ_q·a = γ) and multipliers (Φ_qᵀ·λ = Q − M·a);
//! its prediction is the Hermite cubic through the last two solutions.
//!
//! A model with degrees of freedom left is refused before anything runs
//! ([`KinematicsError::FreeDegrees`]), each free direction named with the element that
//! leaves it free ([`super::freedom`]). A run that cannot go on stops at a lock-up or
//! singular position, named ([`lock_up`]), or, the constraints of full rank there, as
//! positions Newton cannot reach even over the smallest step
//! ([`KinematicsError::Unsolved`]).

pub mod driven;
pub mod error;
pub mod lock_up;
pub mod square;
pub mod steps;

pub use error::{FreeDegrees, KinematicsError, LockUp};
pub use steps::{advance_to, Control, Settings};

use super::dynamics::{DynError, Dynamics};
use super::freedom::{describe_all, null_space};

/// Refuses a model with degrees of freedom left: their count and each named.
pub fn check_driven(d: &mut Dynamics) -> Result<(), KinematicsError> {
    if d.n <= d.m {
        return Ok(());
    }
    d.eval_constraints(true)?;
    let basis = null_space(d);
    Err(KinematicsError::FreeDegrees(FreeDegrees {
        count: d.n - d.m,
        free: describe_all(d, &basis),
    }))
}

/// Solves velocities, accelerations and multipliers of `d` where it stands, the
/// positions taken as they are (assembled, or solved before): the analysis' first
/// row.
pub fn solve_here(d: &mut Dynamics) -> Result<(), DynError> {
    d.forces.states.trapezoidal_to(d.sys.time);
    d.reconcile()?;
    Ok(d.commit_states()?)
}
