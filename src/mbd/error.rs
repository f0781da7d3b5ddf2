//! Errors of the multibody core, in the user's words: elements are named the Adams way
//! (`JOINT/3 'crank_pin'`), equations by their Adams labels.

use super::equations::{ElementKind, ElementRef, JointType, JprimType};
use std::fmt;

/// Something the core cannot build, evaluate or solve.
#[derive(Clone, Debug, PartialEq)]
pub enum MbdError {
    /// An acceleration or force measure read before dynamics exist.
    NeedsDynamics(String, &'static str),
    /// A system-element value (VARVAL, ARYVAL, DIF, ...) or a measure whose meaning is
    /// not established (ORIENT): not a marker measure of this core.
    NotKinematic(String),
    /// A marker id that names no marker.
    UnknownMarker(i64),
    /// A part id that names no part.
    UnknownPart(u32),
    /// A joint, primitive or motion whose I and J markers are on one part.
    SamePart(ElementRef),
    /// A floating marker used where a fixed one is needed.
    Floating(ElementRef, i64),
    /// A construct the core does not support yet.
    Unsupported(String),
    /// An expression's value or derivative could not be computed.
    Expression(ElementRef, String),
}

/// `JOINT/3 'name'` (the name only when the dataset gives one).
pub fn element_name(e: &ElementRef) -> String {
    let kind = match e.kind {
        ElementKind::Joint(t) => format!("JOINT/{} ({})", e.id, joint_word(t)),
        ElementKind::Jprim(t) => format!("JPRIM/{} ({})", e.id, jprim_word(t)),
        ElementKind::Gcon => format!("GCON/{}", e.id),
        ElementKind::Motion => format!("MOTION/{}", e.id),
        ElementKind::Prismatic2d => format!("PRISMATIC_2D/{}", e.id),
        ElementKind::Force(k) => format!("{}/{}", k.keyword(), e.id),
    };
    match &e.name {
        Some(n) => format!("{kind} '{n}'"),
        None => kind,
    }
}

fn joint_word(t: JointType) -> &'static str {
    use JointType::*;
    match t {
        Fixed => "FIXED",
        Revolute => "REVOLUTE",
        Spherical => "SPHERICAL",
        Translational => "TRANSLATIONAL",
        Cylindrical => "CYLINDRICAL",
        Planar => "PLANAR",
        Hooke => "HOOKE",
        Universal => "UNIVERSAL",
        Convel => "CONVEL",
        Rackpin => "RACKPIN",
        Screw => "SCREW",
    }
}

fn jprim_word(t: JprimType) -> &'static str {
    use JprimType::*;
    match t {
        Atpoint => "ATPOINT",
        Inline => "INLINE",
        Inplane => "INPLANE",
        Orientation => "ORIENTATION",
        ParallelAxes => "PARALLEL_AXES",
        Perpendicular => "PERPENDICULAR",
    }
}

impl fmt::Display for MbdError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MbdError::NeedsDynamics(name, what) => write!(
                f,
                "{name} measures {what}: it is available once dynamics exist, not during assembly"
            ),
            MbdError::NotKinematic(name) => {
                write!(
                    f,
                    "{name} is not a marker measure the multibody core computes"
                )
            }
            MbdError::UnknownMarker(id) => write!(f, "MARKER/{id} does not exist"),
            MbdError::UnknownPart(id) => write!(f, "PART/{id} does not exist"),
            MbdError::SamePart(e) => write!(
                f,
                "{}: its I and J markers are on the same part; put them on different parts",
                element_name(e)
            ),
            MbdError::Floating(e, id) => write!(
                f,
                "{}: MARKER/{id} is FLOATING; constraints need fixed markers",
                element_name(e)
            ),
            MbdError::Unsupported(s) => write!(f, "{s}"),
            MbdError::Expression(e, s) => write!(f, "{}: {s}", element_name(e)),
        }
    }
}

impl std::error::Error for MbdError {}
