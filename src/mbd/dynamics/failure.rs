//! Why the dynamics stops ([`DynError`]): a singular Newton matrix ([`Singularity`]),
//! a value that is not finite ([`NonFinite`]), a dropped row violated, a part free and
//! massless, a model error; each with its time and what it points at ([`Culprit`]), and
//! its message. The analyses above wrap it with their own failures
//! ([`crate::mbd::statics::StaticsError`], [`crate::mbd::kinematics::KinematicsError`]).

use crate::mbd::error::{element_name, MbdError};
use crate::vocab::elements::ElementRef;
use std::fmt;

/// What a failure points at: an element, or a part (by Adams id).
#[derive(Clone, Debug, PartialEq)]
pub enum Culprit {
    /// A constraint or force element.
    Element(ElementRef),
    /// A part, by Adams id.
    Part(u32),
}

impl fmt::Display for Culprit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Culprit::Element(e) => write!(f, "{}", element_name(e)),
            Culprit::Part(id) => write!(f, "PART/{id}"),
        }
    }
}

/// ", at X" when there is a culprit.
fn at(c: &Option<Culprit>) -> String {
    c.as_ref().map_or(String::new(), |c| format!(" (at {c})"))
}

/// Why the dynamics stopped.
#[derive(Clone, Debug, PartialEq)]
pub enum DynError {
    /// An element or expression could not be evaluated.
    Model(MbdError),
    /// The Newton matrix is singular, for the reason `why`.
    Singular {
        /// Simulation time.
        time: f64,
        /// The reason.
        why: Singularity,
        /// What the singular direction points at, when found.
        culprit: Option<Culprit>,
    },
    /// A force or the Newton matrix became NaN or infinite; `element` is the force
    /// element when one is to blame.
    NotFinite {
        /// Simulation time.
        time: f64,
        /// Which quantity became non-finite.
        what: NonFinite,
        /// The force element to blame, when one is.
        element: Option<ElementRef>,
    },
    /// The corrector did not converge even at the smallest step, or (step 0) the
    /// projection of the positions onto the constraints did not.
    Newton {
        /// Simulation time.
        time: f64,
        /// The step size that failed (0: a projection, no step).
        step: f64,
        /// What the largest correction points at, when found.
        culprit: Option<Culprit>,
    },
    /// Error control asked for a step below HMIN.
    StepTooSmall {
        /// Simulation time.
        time: f64,
        /// The step size asked for.
        step: f64,
        /// The smallest step allowed.
        hmin: f64,
        /// What dominates the error estimate, when found.
        culprit: Option<Culprit>,
    },
    /// A constraint the redundancy analysis dropped is violated: the constraints are
    /// conflicting, not redundant.
    DroppedViolated {
        /// Simulation time.
        time: f64,
        /// The element the equation belongs to.
        element: ElementRef,
        /// The equation's Adams label.
        equation: &'static str,
        /// Its scaled residual.
        residual: f64,
    },
    /// A part free to move in `directions` directions that have no mass or inertia.
    Massless {
        /// The part, as messages name it.
        part: String,
        /// How many directions lack mass or inertia.
        directions: usize,
    },
    /// The Newton matrix's pattern is not one faer can factor.
    Structure,
    /// An output row could not be written (the I/O error, worded).
    Output(String),
    /// The caller's interrupt flag was set: the run stopped before its next step
    /// ([`super::time_loop::simulate`] asks before every step attempt).
    Interrupted {
        /// Simulation time of the last accepted step.
        time: f64,
    },
}

/// Why the Newton matrix is singular.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Singularity {
    /// The factorization broke down: dependent constraints, or no mass along a free
    /// direction.
    Dependent,
    /// A kept row's Jacobian vanished: it constrains nothing any more.
    VanishedRow,
    /// The solve gave non-finite values: numerically singular (a lock-up position).
    Numerical,
    /// The run could not go on where the kept constraints are nearly dependent: the
    /// mechanism is at or next to a singular position (a dead centre, a lock-up), where
    /// it cannot move as driven or its branch is not unique.
    LockUp,
}

/// What became NaN or infinite.
#[derive(Clone, Debug, PartialEq)]
pub enum NonFinite {
    /// A force element's load (the element is the error's).
    Force,
    /// A gyroscopic or gravity term (no element to blame).
    Inertial,
    /// An entry of the Newton matrix (a force Jacobian or the mass matrix).
    NewtonMatrix,
}

impl DynError {
    /// The simulation time of the failure, when it has one (an expression that
    /// evaluated to NaN or infinity says when).
    pub fn time(&self) -> Option<f64> {
        match self {
            DynError::Model(MbdError::Expression(
                _,
                crate::mbd::expr::ExprError::NotFinite { time, .. },
            )) => Some(*time),
            DynError::Singular { time, .. }
            | DynError::NotFinite { time, .. }
            | DynError::Newton { time, .. }
            | DynError::StepTooSmall { time, .. }
            | DynError::DroppedViolated { time, .. }
            | DynError::Interrupted { time } => Some(*time),
            DynError::Model(_)
            | DynError::Massless { .. }
            | DynError::Structure
            | DynError::Output(_) => None,
        }
    }

    /// The element or part the failure is about, when there is one.
    pub fn culprit(&self) -> Option<Culprit> {
        match self {
            DynError::Singular { culprit, .. }
            | DynError::Newton { culprit, .. }
            | DynError::StepTooSmall { culprit, .. } => culprit.clone(),
            _ => self.element().cloned().map(Culprit::Element),
        }
    }

    /// The element the failure is about, when there is one.
    pub fn element(&self) -> Option<&ElementRef> {
        match self {
            DynError::DroppedViolated { element, .. } => Some(element),
            DynError::NotFinite { element, .. } => element.as_ref(),
            DynError::Singular {
                culprit: Some(Culprit::Element(e)),
                ..
            }
            | DynError::Newton {
                culprit: Some(Culprit::Element(e)),
                ..
            }
            | DynError::StepTooSmall {
                culprit: Some(Culprit::Element(e)),
                ..
            } => Some(e),
            DynError::Model(m) => m.element(),
            _ => None,
        }
    }
}

impl From<MbdError> for DynError {
    fn from(e: MbdError) -> Self {
        DynError::Model(e)
    }
}

impl fmt::Display for DynError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DynError::Model(e) => write!(f, "{e}"),
            DynError::Singular { time, why, culprit } => write!(
                f,
                "at time {time}: the equations of motion are singular{}: {}",
                at(culprit),
                match why {
                    Singularity::Dependent => "the constraints are dependent here, or a part has no mass along a free direction",
                    Singularity::VanishedRow => "this constraint's Jacobian vanishes: it no longer constrains anything",
                    Singularity::Numerical => "the Newton matrix is numerically singular (dependent constraints or a lock-up position)",
                    Singularity::LockUp => "the mechanism is at a singular position (a dead centre or lock-up): its constraints are nearly dependent here, so it cannot move on as driven (named: the drive, else the element whose equation depends on the others)",
                }
            ),
            DynError::NotFinite {
                time,
                what,
                element,
            } => match (what, element) {
                (NonFinite::Force, Some(e)) => {
                    write!(f, "at time {time}: the force of {} is not finite", element_name(e))
                }
                (NonFinite::Force | NonFinite::Inertial, _) => write!(
                    f,
                    "at time {time}: the force of a gyroscopic or gravity term is not finite"
                ),
                (NonFinite::NewtonMatrix, _) => write!(
                    f,
                    "at time {time}: the Newton matrix holds a NaN or infinite value (a force Jacobian or the mass matrix)"
                ),
            },
            DynError::Newton { time, step, culprit } => {
                let largest = culprit
                    .as_ref()
                    .map_or(String::new(), |c| format!("; the largest constraint error is in {c}"));
                match *step > 0.0 {
                    true => write!(
                        f,
                        "at time {time}: the corrector does not converge (Newton diverges even at a time step of {step:e}){largest}"
                    ),
                    // No step: the projection of the positions onto the constraints (an
                    // output row inside a step, an explicit method's drift).
                    false => write!(
                        f,
                        "at time {time}: the positions cannot be projected onto the constraints (Newton does not converge){largest}"
                    ),
                }
            }
            DynError::StepTooSmall {
                time,
                step,
                hmin,
                culprit,
            } => write!(
                f,
                "at time {time}: error control needs a step of {step:e}, below HMIN = {hmin:e}{}",
                culprit.as_ref().map_or(String::new(), |c| format!("; the largest error estimate is {c}'s"))
            ),
            DynError::DroppedViolated {
                time,
                element,
                equation,
                residual,
            } => write!(
                f,
                "at time {time}: conflicting, not redundant: {equation} of {}, dropped as redundant at assembly, is off by {residual:.3e}",
                element_name(element)
            ),
            DynError::Massless { part, directions } => write!(
                f,
                "{part} can move in {directions} direction(s) that have no mass or inertia and that no constraint holds: give it MASS and IP, or constrain it"
            ),
            DynError::Structure => f.write_str("the Newton matrix has no valid structure"),
            DynError::Output(why) => write!(f, "the output could not be written: {why}"),
            DynError::Interrupted { time } => write!(f, "at time {time}: the run was interrupted"),
        }
    }
}

impl std::error::Error for DynError {}
