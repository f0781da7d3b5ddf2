//! Why a simulation's run stopped ([`Stopped`]): an analysis failed ([`RunError`]: the
//! dynamics, an equilibrium, a kinematic analysis), or a command file's change to the
//! model could not be made at its time, at the changes' commands (a command-file span,
//! the session's to point at).

use crate::diag::Span;
use crate::mbd::dynamics::{Culprit, DynError};
use crate::mbd::error::MbdError;
use crate::mbd::run_error::RunError;
use std::fmt;

/// Why a run stopped.
#[derive(Clone, Debug, PartialEq)]
pub enum Stopped {
    /// An analysis failed (the dynamics, an equilibrium, a kinematic analysis).
    Run(RunError),
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
            Stopped::Run(e) => e.time(),
            Stopped::Change { time, .. } => Some(*time),
        }
    }

    /// The element or part the failure is about, when there is one.
    pub fn culprit(&self) -> Option<Culprit> {
        match self {
            Stopped::Run(e) => e.culprit(),
            Stopped::Change { .. } => None,
        }
    }

    /// The dynamics' own failure, when it is one (match [`DynError::Interrupted`]).
    pub fn dynamics(&self) -> Option<&DynError> {
        match self {
            Stopped::Run(RunError::Dynamics(e)) => Some(e),
            _ => None,
        }
    }
}

impl From<RunError> for Stopped {
    fn from(e: RunError) -> Self {
        Stopped::Run(e)
    }
}

impl From<DynError> for Stopped {
    fn from(e: DynError) -> Self {
        Stopped::Run(RunError::Dynamics(e))
    }
}

impl From<MbdError> for Stopped {
    fn from(e: MbdError) -> Self {
        Stopped::Run(RunError::from(e))
    }
}

impl fmt::Display for Stopped {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Stopped::Run(e) => write!(f, "{e}"),
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
