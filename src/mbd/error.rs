//! Errors of the multibody core, in the user's words: elements are named the Adams way
//! (`JOINT/3 'crank_pin'`), equations by their Adams labels.

use super::expr::ExprError;
use crate::model::states::Statement;
use crate::vocab::elements::ElementRef;
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
    /// A CONTACT that cannot be built (its geometry, or I and J on one part): why.
    Contact(String),
    /// A joint, primitive or motion whose I and J markers are on one part.
    SamePart(ElementRef),
    /// A floating marker used where a fixed one is needed.
    Floating(ElementRef, i64),
    /// A row kind asked of the primitive builder that no primitive equation is (its
    /// label): a fault of the caller, reported rather than panicking.
    NotPrimitive(&'static str),
    /// A GCON whose FUNCTION reads a number of measure slots other than the measures it
    /// was given.
    GconSlots {
        /// The GCON's id.
        id: u32,
        /// Slots the FUNCTION reads.
        slots: usize,
        /// Measures given.
        measures: usize,
    },
    /// A MOTION on a measure that is not an angle, a displacement or a B1/B2/B3 angle.
    MotionMeasure,
    /// A force element reading more moving parts than its Jacobian holds (four).
    TooManyParts(ElementRef),
    /// A measure slot index outside the model's table.
    UnknownMeasureSlot(u32),
    /// ORIENT with a code or component mbfx does not know.
    OrientCode {
        /// The orientation code.
        code: i64,
        /// The component asked for.
        comp: i64,
    },
    /// A force measure (FX…TM) whose marker i is ground.
    GroundForceMarker(String),
    /// A force function `name(id, jflag, comp, rm)` with a component outside 1..8.
    ForceComponent {
        /// The function as written.
        name: String,
        /// The element id.
        id: i64,
        /// The component.
        comp: i64,
    },
    /// A force function naming an element the model does not have.
    UnknownForceElement {
        /// The function as written.
        name: String,
        /// The element id.
        id: i64,
    },
    /// A MOTION on a JOINT the model does not have.
    UnknownMotionJoint {
        /// The MOTION's id.
        motion: u32,
        /// The joint id it names.
        joint: i64,
    },
    /// A FRICTION on a JOINT the model does not have or of a type friction does not act
    /// in.
    FrictionJoint {
        /// The FRICTION's id.
        friction: u32,
        /// The joint id it names.
        joint: i64,
        /// What is wrong with it, in words.
        why: &'static str,
    },
    /// VARVAL of a VARIABLE without a FUNCTION mbfx can evaluate.
    Variable(i64),
    /// The model's SPLINE data cannot be used (why, in the model's words).
    Spline(String),
    /// An expression's value or derivative could not be computed.
    Expression(ElementRef, ExprError),
    /// Consistent accelerations need a second derivative the row's equation does not
    /// have: the element, the equation's label and why.
    NoSecondDerivative(ElementRef, &'static str, String),
    /// Force elements whose expressions read each other's forces in a circle, in
    /// reading order (each reads the next, the last the first).
    ForceCycle(Vec<ElementRef>),
    /// A force that reads accelerations or reactions (`reads`, as written) which depend
    /// on it through the equations of motion, and the loop between them does not settle.
    SolutionLoop {
        /// An element on the loop.
        element: ElementRef,
        /// The chain of values read, in words.
        reads: String,
    },
    /// A plant input or output a linearization cannot use (why, in words).
    Plant(String),
    /// A state element (DIFF, LSE, TFSISO) that cannot be built or solved: the
    /// statement at fault (the element, or the ARRAY, MATRIX or VARIABLE it reads) and
    /// why, in words, naming the element.
    State(Statement, String),
}

/// `JOINT/3 (REVOLUTE) 'name'` (the type for a JOINT or JPRIM, the name only when the
/// dataset gives one).
pub fn element_name(e: &ElementRef) -> String {
    let kind = match e.kind.flag() {
        Some(flag) => format!("{}/{} ({flag})", e.kind.keyword(), e.id),
        None => format!("{}/{}", e.kind.keyword(), e.id),
    };
    match &e.name {
        Some(n) => format!("{kind} '{n}'"),
        None => kind,
    }
}

impl MbdError {
    /// The element the error is about, when it names one: a diagnostic points at its
    /// statement rather than at the dataset's title.
    pub fn element(&self) -> Option<&ElementRef> {
        match self {
            MbdError::SamePart(e)
            | MbdError::Floating(e, _)
            | MbdError::TooManyParts(e)
            | MbdError::Expression(e, _)
            | MbdError::NoSecondDerivative(e, _, _)
            | MbdError::SolutionLoop { element: e, .. } => Some(e),
            MbdError::ForceCycle(circle) => circle.first(),
            _ => None,
        }
    }

    /// The statement a state element's error is at (its DIFF, LSE or TFSISO, or the
    /// ARRAY, MATRIX or VARIABLE at fault): not an [`ElementRef`], which names the
    /// elements of the equations and forces.
    pub fn state_statement(&self) -> Option<Statement> {
        match self {
            MbdError::State(s, _) => Some(*s),
            _ => None,
        }
    }
}

impl fmt::Display for MbdError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MbdError::NeedsDynamics(name, what) => write!(
                f,
                "{name} measures {what}: it is available once dynamics exist, not during assembly"
            ),
            MbdError::NotKinematic(name) => match name.as_str() {
                "ARYVAL" => f.write_str(
                    "it reads ARYVAL of an ARRAY that is not the X, U or Y array of an LSE or TFSISO (the only ARYVAL mbfx gives a value)",
                ),
                "DIF" | "DIF1" => write!(
                    f,
                    "it reads {name} of a DIFF the model does not have"
                ),
                _ => write!(
                    f,
                    "{name} is not a marker measure the multibody core computes"
                ),
            },
            MbdError::UnknownMarker(id) => write!(f, "MARKER/{id} does not exist"),
            MbdError::UnknownPart(id) => write!(f, "PART/{id} does not exist"),
            MbdError::Contact(why) => f.write_str(why),
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
            MbdError::NotPrimitive(label) => write!(f, "{label} is not a primitive equation"),
            MbdError::GconSlots {
                id,
                slots,
                measures,
            } => write!(
                f,
                "GCON/{id}: its FUNCTION reads {slots} measure slots but {measures} measures were given"
            ),
            MbdError::MotionMeasure => {
                f.write_str("a MOTION drives an angle, a displacement or a B1/B2/B3 angle")
            }
            MbdError::TooManyParts(e) => write!(
                f,
                "{}: it reads more than four moving parts, which the force Jacobian does not hold",
                element_name(e)
            ),
            MbdError::UnknownMeasureSlot(slot) => {
                write!(f, "measure slot {slot} is not in the model")
            }
            MbdError::OrientCode { code, comp } => write!(
                f,
                "ORIENT({code}, {comp}, …): only code 27 (Euler parameters e0..e3, components 1..4) is known"
            ),
            MbdError::GroundForceMarker(name) => {
                write!(f, "{name} needs a marker i other than ground")
            }
            MbdError::ForceComponent { name, id, comp } => {
                let top = if name == "CONTACT" { 12 } else { 8 };
                write!(f, "{name}({id}, …): component {comp} is not 1..{top}")
            }
            MbdError::UnknownForceElement { name, id } => {
                write!(f, "{name}({id}, …): no such element in the model")
            }
            MbdError::UnknownMotionJoint { motion, joint } => {
                write!(f, "MOTION/{motion}: JOINT/{joint} does not exist")
            }
            MbdError::FrictionJoint {
                friction,
                joint,
                why,
            } => write!(f, "FRICTION/{friction}: JOINT/{joint} {why}"),
            MbdError::Plant(why) => write!(f, "LINEAR/STATEMAT: {why}"),
            MbdError::State(_, why) => f.write_str(why),
            MbdError::Variable(id) => write!(
                f,
                "it reads VARVAL({id}), and VARIABLE/{id} has no FUNCTION mbfx can evaluate (a USER subroutine, or no such VARIABLE)"
            ),
            MbdError::Spline(why) => f.write_str(why),
            MbdError::Expression(e, s) => write!(f, "{}: {s}", element_name(e)),
            MbdError::NoSecondDerivative(e, equation, why) => write!(
                f,
                "{}: consistent accelerations need the second derivative of its {equation} equation: {why}",
                element_name(e)
            ),
            MbdError::ForceCycle(circle) => {
                let mut names: Vec<String> = circle.iter().map(element_name).collect();
                if let Some(first) = names.first().cloned() {
                    names.push(first);
                }
                write!(
                    f,
                    "forces read each other in a circle ({}): no order evaluates them at one \
                     state; break the circle (read a state measure instead of a force)",
                    names.join(" reads ")
                )
            }
            MbdError::SolutionLoop { element, reads } => write!(
                f,
                "{} reads {reads}, which depends on that force through the equations of \
                 motion, and solving them together does not converge: the loop amplifies \
                 (its gain is 1 or more)",
                element_name(element)
            ),
        }
    }
}

impl std::error::Error for MbdError {}
