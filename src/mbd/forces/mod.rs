//! Applied forces (multibody spec §7): SFORCE (translational, rotational, ACTIONONLY),
//! VFORCE, VTORQUE, GFORCE, SPRINGDAMPER, BUSHING, BEAM and FIELD, joint FRICTION, and
//! ACCGRAV with the units-consistency
//! factor. Each element is evaluated as duals (the `dual` module) over the local directions
//! of the parts it reads (its markers and the markers of the measures its expressions
//! read, one shared [`PartSlots`] table), so the generalized force Q and its exact
//! Jacobians ∂Q/∂q and ∂Q/∂v come out of one evaluation. Expression magnitudes enter with
//! their compiled gradient ∂f/∂measure chained with the measures' duals: no finite
//! differences.
//!
//! Generalized forces are per moving part at its reference point (the CM): the force F
//! and the moment about the CM, global axes; a force applied at a marker adds the moment
//! of its arm.
//!
//! An expression that calls IMPACT or BISTOP also carries their switching functions
//! ([`ContactProbe`]), which the step control watches ([`ForceSet::switches`]).
//!
//! An expression may also read what only the solution gives (Adams allows it): an
//! acceleration, a reaction, another force's value ([`Source::Solution`]). Those values
//! are filled in by the dynamics before each evaluation and held fixed within it, so the
//! equations of motion solve them by iteration; joint friction also gives its derivative
//! by the reaction it reads ([`Generalized::ds`]), so that loop is solved by Newton. Forces
//! that read each other's values are evaluated in dependency order ([`ForceSet::order`]).
//!
//! The files, one job each: `inputs` (what an expression reads), `element` (an element
//! as data), `expression` (an expression's value or dual), `num` (the numbers an
//! element is evaluated in), `law` (loads by law into Q), `field` (the linear
//! six-component law of FIELD and BEAM) and `field_loads` (its evaluation) with `beam`
//! (BEAM's Timoshenko stiffness), [`friction`] (joint friction, loaded by the joint's
//! reaction) with `friction_loads` (its evaluation) and [`stiction`] (its stiction
//! deformation's law), `generalized` (Q and its
//! Jacobians), `set` (the set: preparing, fusing, evaluating), `order` (the evaluation
//! order), `input_partials` (∂Q/∂u), [`contact`] (the switching functions of IMPACT
//! and BISTOP) and `frame_cache` (the value path's marker frames, each built once an
//! evaluation).
//!
//! [`PartSlots`]: crate::mbd::measures::PartSlots
//! [`ContactProbe`]: contact::ContactProbe

mod beam;
pub mod contact;
mod element;
mod expression;
pub mod field;
mod field_loads;
mod frame_cache;
pub mod friction;
mod friction_loads;
mod generalized;
mod input_partials;
mod inputs;
mod law;
mod num;
mod order;
mod set;
pub mod stiction;

pub use beam::law as beam_law;
pub use element::{angle_of, ForceElement, ForceLaw};
pub use generalized::Generalized;
pub(crate) use inputs::measure_value;
pub use inputs::{Scalar, Source};
pub use law::Loads;
pub use set::ForceSet;

#[cfg(test)]
mod tests;
