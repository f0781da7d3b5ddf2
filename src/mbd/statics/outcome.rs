//! What one static equilibrium found ([`Report`], with every constraint element's
//! [`Reaction`]) or why none came out ([`Failure`], and with the dynamics' own failures
//! [`StaticsError`]), each with its message.

use crate::mbd::dynamics::{Culprit, DynError};
use crate::mbd::error::MbdError;
use crate::mbd::freedom::Freedom;
use crate::vocab::math::Vec3;
use std::fmt;

/// One constraint element's reaction at equilibrium: the load it applies to its I
/// marker's part, at the I marker, global axes.
#[derive(Clone, Debug, PartialEq)]
pub struct Reaction {
    /// The element, as messages name it (`JOINT/1 (REVOLUTE)`).
    pub element: String,
    /// Force.
    pub force: Vec3,
    /// Torque about the I marker.
    pub torque: Vec3,
}

/// What one equilibrium took and found.
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    /// Simulation time of the equilibrium.
    pub time: f64,
    /// Newton iterations.
    pub iterations: usize,
    /// Iterations whose step TLIMIT or ALIMIT cut short.
    pub limited: usize,
    /// The largest force or torque imbalance left, model units.
    pub imbalance: f64,
    /// The coordinate it is in (`PART/2 y translation`).
    pub imbalance_at: String,
    /// The largest constraint residual (translations over the model length).
    pub residual: f64,
    /// The lowest eigenvalue of the reduced stiffness over the largest, in scaled
    /// coordinates: how firmly the softest free direction is held (None: no free
    /// direction, fully constrained).
    pub softest: Option<f64>,
    /// Every constraint element's reaction.
    pub reactions: Vec<Reaction>,
}

impl Report {
    /// The lines `mbfx run` prints about the equilibrium.
    pub fn text(&self) -> String {
        let mut out = format!(
            "static equilibrium at time {}: {} Newton iterations ({} held to TLIMIT/ALIMIT), largest imbalance {:.3e} ({}), constraint residual {:.3e}",
            self.time, self.iterations, self.limited, self.imbalance, self.imbalance_at, self.residual
        );
        if let Some(s) = self.softest {
            out += &format!(", softest free direction {s:.3e} of the stiffest");
        }
        out.push('\n');
        for r in &self.reactions {
            let (f, t) = (r.force, r.torque);
            out += &format!(
                "  reaction {}: force ({:.6e}, {:.6e}, {:.6e}), torque ({:.6e}, {:.6e}, {:.6e})\n",
                r.element, f.x, f.y, f.z, t.x, t.y, t.z
            );
        }
        out
    }
}

/// Why no equilibrium came out.
#[derive(Clone, Debug, PartialEq)]
pub enum Failure {
    /// MAXIT iterations did not bring the imbalance below IMBALANCE.
    NoEquilibrium {
        /// Simulation time.
        time: f64,
        /// Iterations done.
        iterations: usize,
        /// The largest imbalance left.
        imbalance: f64,
        /// The coordinate it is in.
        at: String,
        /// Its part.
        part: Option<u32>,
    },
    /// Every one of the last iterations was cut to TLIMIT or ALIMIT: the equilibrium, if
    /// there is one, lies farther than MAXIT such steps.
    Limited {
        /// Simulation time.
        time: f64,
        /// Iterations done.
        iterations: usize,
        /// Which limit held the steps: `TLIMIT` or `ALIMIT`.
        limit: &'static str,
        /// Its value.
        value: f64,
        /// The coordinate that moved most.
        at: String,
        /// Its part.
        part: Option<u32>,
    },
    /// The reduced stiffness is singular (neutral) or has a negative eigenvalue
    /// (unstable) along a free direction.
    Unstable {
        /// Simulation time.
        time: f64,
        /// Neutral (no stiffness) rather than unstable (negative stiffness).
        neutral: bool,
        /// Whether the iteration had converged (an unstable equilibrium) or not.
        converged: bool,
        /// The direction, named.
        freedom: Freedom,
    },
}

impl Failure {
    /// The simulation time of the failure.
    pub fn time(&self) -> f64 {
        match self {
            Failure::NoEquilibrium { time, .. }
            | Failure::Limited { time, .. }
            | Failure::Unstable { time, .. } => *time,
        }
    }

    /// The element or part it is about.
    pub fn culprit(&self) -> Option<Culprit> {
        match self {
            Failure::NoEquilibrium { part, .. } | Failure::Limited { part, .. } => {
                part.map(Culprit::Part)
            }
            Failure::Unstable { freedom, .. } => freedom.culprit.clone(),
        }
    }
}

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Failure::NoEquilibrium {
                time,
                iterations,
                imbalance,
                at,
                ..
            } => write!(
                f,
                "at time {time}: no static equilibrium within MAXIT = {iterations} iterations: the largest force imbalance left is {imbalance:.3e}, in {at} (raise MAXIT, or start closer to equilibrium)"
            ),
            Failure::Limited {
                time,
                iterations,
                limit,
                value,
                at,
                ..
            } => write!(
                f,
                "at time {time}: {limit} = {value} exceeded: every one of the last iterations was cut to it, in {at}, and {iterations} iterations did not reach equilibrium (raise {limit} or MAXIT)"
            ),
            Failure::Unstable {
                time,
                neutral,
                converged,
                freedom,
            } => {
                let what = match (neutral, converged) {
                    (true, _) => "nothing holds",
                    (false, true) => "the equilibrium found is unstable along",
                    (false, false) => "no stable equilibrium: the stiffness is negative along",
                };
                write!(f, "at time {time}: {what} {freedom}")?;
                if *neutral {
                    f.write_str(": a mechanism with no spring or force holding this degree of freedom has no static equilibrium (add a spring, a MOTION, or a constraint)")?;
                }
                Ok(())
            }
        }
    }
}

/// Why an equilibrium run stopped: the dynamics failed under it (an evaluation, a
/// singular Newton matrix), or no equilibrium came out.
#[derive(Clone, Debug, PartialEq)]
pub enum StaticsError {
    /// The dynamics failed.
    Dynamics(DynError),
    /// No static equilibrium came out.
    Failed(Box<Failure>),
}

impl From<DynError> for StaticsError {
    fn from(e: DynError) -> Self {
        StaticsError::Dynamics(e)
    }
}

impl From<MbdError> for StaticsError {
    fn from(e: MbdError) -> Self {
        StaticsError::Dynamics(DynError::Model(e))
    }
}

impl fmt::Display for StaticsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StaticsError::Dynamics(e) => write!(f, "{e}"),
            StaticsError::Failed(failure) => write!(f, "{failure}"),
        }
    }
}

impl std::error::Error for StaticsError {}
