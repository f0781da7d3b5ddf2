//! Why a kinematic analysis stops ([`KinematicsError`]): the model has degrees of
//! freedom left ([`FreeDegrees`]), the constraints lose rank at a lock-up or singular
//! position ([`LockUp`]), the positions cannot be solved even over the smallest step,
//! or the dynamics under it failed (an evaluation, a solve).

use crate::mbd::dynamics::{Culprit, DynError};
use crate::mbd::error::{element_name, MbdError};
use crate::mbd::freedom::Freedom;
use crate::vocab::elements::ElementRef;
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

/// A lock-up or singular position: where the kept constraints lose rank, the
/// mechanism cannot move on as driven.
#[derive(Clone, Debug, PartialEq)]
pub struct LockUp {
    /// The last time the positions were solved, next to the singular position.
    pub time: f64,
    /// The elements whose equations become dependent there, the most involved first.
    pub elements: Vec<ElementRef>,
    /// The direction the constraints no longer fix, named (part, coordinate, and the
    /// element that lets it move).
    pub free: Freedom,
    /// The smallest singular value of the scaled constraint Jacobian over its largest.
    pub distance: f64,
    /// The drive (a MOTION among `elements`) that cannot move the mechanism on.
    pub drive: Option<ElementRef>,
}

impl LockUp {
    /// The element that lets the freed direction move, else the most involved one.
    pub fn culprit(&self) -> Option<Culprit> {
        match &self.free.culprit {
            Some(c @ Culprit::Element(_)) => Some(c.clone()),
            _ => self.elements.first().cloned().map(Culprit::Element),
        }
    }
}

impl fmt::Display for LockUp {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "at t = {} the constraints lose rank (a lock-up or singular position): ",
            self.time
        )?;
        match &self.free.culprit {
            Some(c @ Culprit::Element(_)) => write!(f, "{c} leaves {} free", self.free.coordinate)?,
            _ => write!(f, "{} is no longer fixed", self.free.coordinate)?,
        }
        let names: Vec<String> = self.elements.iter().map(element_name).collect();
        write!(
            f,
            "; the equations of {} become dependent (smallest singular value {:.1e} of the largest)",
            names.join(", "),
            self.distance
        )?;
        match &self.drive {
            Some(m) => write!(
                f,
                ": {} cannot drive the mechanism past here",
                element_name(m)
            ),
            None => f.write_str(": the mechanism cannot move on as driven"),
        }
    }
}

/// Why a kinematic analysis stopped.
#[derive(Clone, Debug, PartialEq)]
pub enum KinematicsError {
    /// The dynamics failed (an evaluation, a solve).
    Dynamics(DynError),
    /// The model has degrees of freedom left.
    FreeDegrees(FreeDegrees),
    /// The constraints lose rank: a lock-up or singular position.
    LockUp(Box<LockUp>),
    /// Newton on Φ(q, t) = 0 does not converge even over the smallest step from the last
    /// solution, the constraints of full rank there.
    Unsolved {
        /// The last time the positions were solved.
        time: f64,
        /// The smallest step tried.
        step: f64,
        /// The element with the largest constraint error at the last attempt.
        culprit: Option<Culprit>,
    },
}

impl KinematicsError {
    /// The time of the failure, when it has one.
    pub fn time(&self) -> Option<f64> {
        match self {
            KinematicsError::Dynamics(e) => e.time(),
            KinematicsError::FreeDegrees(_) => None,
            KinematicsError::LockUp(l) => Some(l.time),
            KinematicsError::Unsolved { time, .. } => Some(*time),
        }
    }

    /// The element or part the failure is about, when there is one.
    pub fn culprit(&self) -> Option<Culprit> {
        match self {
            KinematicsError::Dynamics(e) => e.culprit(),
            KinematicsError::FreeDegrees(free) => free.culprit(),
            KinematicsError::LockUp(l) => l.culprit(),
            KinematicsError::Unsolved { culprit, .. } => culprit.clone(),
        }
    }
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
            KinematicsError::LockUp(l) => write!(f, "{l}"),
            KinematicsError::Unsolved {
                time,
                step,
                culprit,
            } => write!(
                f,
                "at t = {time} the positions cannot be solved from the constraints: Newton does not converge even over a time step of {step:.1e} from the last solution{}",
                culprit
                    .as_ref()
                    .map_or(String::new(), |c| format!("; the largest constraint error is in {c}"))
            ),
        }
    }
}

impl std::error::Error for KinematicsError {}
