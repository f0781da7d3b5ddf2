//! Why a simulation's run stopped ([`Stopped`]): the dynamics failed, no static
//! equilibrium came out, a kinematic analysis found degrees of freedom left or could not
//! go on (a lock-up), or a command file's change to the model could not be made at its
//! time (at the changes' commands: a command-file span, the session's to point at).
//! The analyses' own errors ([`StaticsError`], [`KinematicsError`]) convert into it.

use crate::diag::Span;
use crate::mbd::dynamics::{Culprit, DynError};
use crate::mbd::error::MbdError;
use crate::mbd::kinematics::{FreeDegrees, KinematicsError};
use crate::mbd::statics::{Failure, StaticsError};
use std::fmt;

/// Why a run stopped.
#[derive(Clone, Debug, PartialEq)]
pub enum Stopped {
    /// The dynamics failed (the integration, a consistent solve, a model error).
    Dynamics(DynError),
    /// No static equilibrium came out ([`crate::mbd::statics`]).
    Statics(Box<Failure>),
    /// A kinematic analysis asked of a model with degrees of freedom left
    /// ([`crate::mbd::kinematics`]).
    FreeDegrees(FreeDegrees),
    /// A kinematic analysis could not go on: a lock-up or singular position, or
    /// positions Newton cannot reach ([`crate::mbd::kinematics`]).
    Kinematics(Box<KinematicsError>),
    /// A command file's change to the model could not be made at `time` (the changed
    /// model does not build or assemble), for the reason `why`.
    Change {
        /// Simulation time of the change.
        time: f64,
        /// What went wrong, in words.
        why: String,
        /// The changes' commands in the command file.
        at: Span,
    },
}

impl Stopped {
    /// The simulation time of the failure, when it has one.
    pub fn time(&self) -> Option<f64> {
        match self {
            Stopped::Dynamics(e) => e.time(),
            Stopped::Statics(f) => Some(f.time()),
            Stopped::FreeDegrees(_) => None,
            Stopped::Kinematics(e) => e.time(),
            Stopped::Change { time, .. } => Some(*time),
        }
    }

    /// The element or part the failure is about, when there is one.
    pub fn culprit(&self) -> Option<Culprit> {
        match self {
            Stopped::Dynamics(e) => e.culprit(),
            Stopped::Statics(f) => f.culprit(),
            Stopped::FreeDegrees(free) => free.culprit(),
            Stopped::Kinematics(e) => e.culprit(),
            Stopped::Change { .. } => None,
        }
    }

    /// The dynamics' own failure, when it is one (match [`DynError::Interrupted`]).
    pub fn dynamics(&self) -> Option<&DynError> {
        match self {
            Stopped::Dynamics(e) => Some(e),
            _ => None,
        }
    }
}

impl From<DynError> for Stopped {
    fn from(e: DynError) -> Self {
        Stopped::Dynamics(e)
    }
}

impl From<MbdError> for Stopped {
    fn from(e: MbdError) -> Self {
        Stopped::Dynamics(DynError::Model(e))
    }
}

impl From<StaticsError> for Stopped {
    fn from(e: StaticsError) -> Self {
        match e {
            StaticsError::Dynamics(e) => Stopped::Dynamics(e),
            StaticsError::Failed(f) => Stopped::Statics(f),
        }
    }
}

impl From<KinematicsError> for Stopped {
    fn from(e: KinematicsError) -> Self {
        match e {
            KinematicsError::Dynamics(e) => Stopped::Dynamics(e),
            KinematicsError::FreeDegrees(free) => Stopped::FreeDegrees(free),
            e => Stopped::Kinematics(Box::new(e)),
        }
    }
}

impl fmt::Display for Stopped {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Stopped::Dynamics(e) => write!(f, "{e}"),
            Stopped::Statics(failure) => write!(f, "{failure}"),
            Stopped::FreeDegrees(free) => write!(f, "{free}"),
            Stopped::Kinematics(e) => write!(f, "{e}"),
            Stopped::Change { time, why, .. } => {
                write!(
                    f,
                    "the command file's change to the model at t = {time}: {why}"
                )
            }
        }
    }
}

impl std::error::Error for Stopped {}
