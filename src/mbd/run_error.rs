//! Why an analysis of the dynamics stopped ([`RunError`]): the dynamics' own failure
//! ([`DynError`]), no static equilibrium ([`crate::mbd::statics`]), or a kinematic
//! analysis asked of a model with degrees of freedom left ([`crate::mbd::kinematics`]).
//! It sits above the dynamics and the analyses, so the dynamics' error names neither.

use super::dynamics::{Culprit, DynError};
use super::error::MbdError;
use super::freedom::Freedom;
use super::statics::Failure;
use crate::vocab::elements::ElementRef;
use std::fmt;

/// Why an analysis stopped.
#[derive(Clone, Debug, PartialEq)]
pub enum RunError {
    /// The dynamics failed (the integration, a consistent solve, a model error).
    Dynamics(DynError),
    /// No static equilibrium came out ([`crate::mbd::statics`]).
    Statics(Box<Failure>),
    /// A kinematic analysis asked of a model with degrees of freedom left
    /// ([`crate::mbd::kinematics`]): how many, and each named.
    FreeDegrees {
        /// The degrees of freedom.
        count: usize,
        /// Each one, named.
        free: Vec<Freedom>,
    },
}

impl RunError {
    /// The simulation time of the failure, when it has one.
    pub fn time(&self) -> Option<f64> {
        match self {
            RunError::Dynamics(e) => e.time(),
            RunError::Statics(f) => Some(f.time()),
            RunError::FreeDegrees { .. } => None,
        }
    }

    /// The element or part the failure is about, when there is one.
    pub fn culprit(&self) -> Option<Culprit> {
        match self {
            RunError::Dynamics(e) => e.culprit(),
            RunError::Statics(f) => f.culprit(),
            RunError::FreeDegrees { free, .. } => free.iter().find_map(|f| f.culprit.clone()),
        }
    }

    /// The element the failure is about, when there is one.
    pub fn element(&self) -> Option<&ElementRef> {
        match self {
            RunError::Dynamics(e) => e.element(),
            RunError::Statics(f) => match f.as_ref() {
                Failure::Unstable { freedom, .. } => match &freedom.culprit {
                    Some(Culprit::Element(e)) => Some(e),
                    _ => None,
                },
                _ => None,
            },
            RunError::FreeDegrees { free, .. } => free.iter().find_map(|f| match &f.culprit {
                Some(Culprit::Element(e)) => Some(e),
                _ => None,
            }),
        }
    }
}

impl From<DynError> for RunError {
    fn from(e: DynError) -> Self {
        RunError::Dynamics(e)
    }
}

impl From<MbdError> for RunError {
    fn from(e: MbdError) -> Self {
        RunError::Dynamics(DynError::Model(e))
    }
}

impl fmt::Display for RunError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RunError::Dynamics(e) => write!(f, "{e}"),
            RunError::Statics(failure) => write!(f, "{failure}"),
            RunError::FreeDegrees { count, free } => {
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
    }
}

impl std::error::Error for RunError {}
