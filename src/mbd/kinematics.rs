//! Kinematic analysis (Adams' SIMULATE/KINEMATICS): a model whose kept constraints
//! (joints, GCONs, MOTIONs) leave no degree of freedom is solved from them alone at
//! each output time, nothing integrated. Positions: Newton on Φ(q, t) = 0 from the
//! last time's state carried forward by its velocity and acceleration (q + v·Δt +
//! a·Δt²/2), down to rounding; velocities from Φ_q·v = −Φ_t; accelerations and
//! reactions from the saddle-point system [[M, Φ_qᵀ], [Φ_q, 0]]·[a; λ] = [Q; γ], whose
//! constraint block, square and regular, fixes a alone (the forces then give λ). The last
//! two are the dynamics' own reconciliation ([`Dynamics::reconcile`]), which is exact
//! for a model without freedom.
//!
//! A model with degrees of freedom left is refused before anything runs
//! ([`KinematicsError::FreeDegrees`]), each free direction named with the element that
//! leaves it free ([`super::freedom`]).

use super::dynamics::{Culprit, DynError, Dynamics};
use super::error::MbdError;
use super::freedom::{describe_all, null_space, Freedom};
use std::fmt;

/// The degrees of freedom a model has left, refused by a kinematic analysis: how many,
/// and each named.
#[derive(Clone, Debug, PartialEq)]
pub struct FreeDegrees {
    /// The degrees of freedom.
    pub count: usize,
    /// Each one, named.
    pub free: Vec<Freedom>,
}

impl FreeDegrees {
    /// The element or part the first named direction points at, when one does.
    pub fn culprit(&self) -> Option<Culprit> {
        self.free.iter().find_map(|f| f.culprit.clone())
    }
}

impl fmt::Display for FreeDegrees {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (count, free) = (self.count, &self.free);
        write!(
            f,
            "a kinematic analysis needs a model without degrees of freedom, and this one has {count}: "
        )?;
        let named: Vec<String> = free.iter().map(|x| x.to_string()).collect();
        write!(
            f,
            "{} (drive each with a MOTION, or run SIMULATE/DYNAMIC)",
            named.join("; ")
        )
    }
}

/// Why a kinematic analysis stopped: the dynamics failed under it, or the model has
/// degrees of freedom left.
#[derive(Clone, Debug, PartialEq)]
pub enum KinematicsError {
    /// The dynamics failed (an evaluation, a solve).
    Dynamics(DynError),
    /// The model has degrees of freedom left.
    FreeDegrees(FreeDegrees),
}

impl From<DynError> for KinematicsError {
    fn from(e: DynError) -> Self {
        KinematicsError::Dynamics(e)
    }
}

impl From<MbdError> for KinematicsError {
    fn from(e: MbdError) -> Self {
        KinematicsError::Dynamics(DynError::Model(e))
    }
}

impl fmt::Display for KinematicsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            KinematicsError::Dynamics(e) => write!(f, "{e}"),
            KinematicsError::FreeDegrees(free) => write!(f, "{free}"),
        }
    }
}

impl std::error::Error for KinematicsError {}

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

/// Solves positions, velocities, accelerations and multipliers of `d` at time `t` from
/// the constraints alone (`d` fully driven: [`check_driven`]). At its own time the
/// positions are taken as they stand (assembled, or solved before).
pub fn solve_at(d: &mut Dynamics, t: f64) -> Result<(), DynError> {
    let dt = t - d.sys.time;
    if dt != 0.0 {
        let v = d.sys.v();
        let dx: Vec<f64> = (0..d.n)
            .map(|c| v[c] * dt + 0.5 * d.a.get(c).copied().unwrap_or(0.0) * dt * dt)
            .collect();
        d.sys.apply_increment(&dx);
        d.sys.time = t;
        // To rounding: the projection stops at the coordinates' rounding floor, or where
        // a fresh factorization no longer contracts.
        let floor = 2.0 * f64::EPSILON * d.reach() / d.sys.length;
        d.project_positions(floor)?;
        d.commit_measures();
    }
    // The state elements integrate along the prescribed motion (the trapezoidal rule
    // from the last time), committed at each time.
    d.forces.states.trapezoidal_to(t);
    d.reconcile()?;
    Ok(d.commit_states()?)
}
