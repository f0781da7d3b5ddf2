//! Static equilibrium (Adams' SIMULATE/STATICS and the EQUILIBRIUM statement): the
//! configuration where the applied forces, gravity and the constraint reactions balance
//! with every velocity held at zero,
//!
//! ```text
//! Q(q, 0, t) − Φ_qᵀ·λ = 0,     Φ(q, t) = 0,
//! ```
//!
//! found by Newton on q and λ together ([`solve`]) with the analytic force Jacobian
//! ∂Q/∂q the dynamics uses and the constraint forces' full tangent ([`tangent`]), a
//! fraction STABILITY of the mass and damping matrices added as Adams does, each step
//! held to TLIMIT and ALIMIT and damped by a line search. The equilibrium found is then
//! checked ([`stability`]): the stiffness reduced to the directions the constraints leave
//! free must be positive definite, else a neutral direction (a mechanism no spring
//! holds) or an unstable one is a named failure ([`outcome`]: the report of an
//! equilibrium, or why none came out). The session runs it at one time or at each output
//! time of a quasi-static stretch, with the EQUILIBRIUM statement's values ([`Settings`],
//! the model's own type: the model reads them, the solver takes them as they are).

pub mod outcome;
pub mod solve;
pub mod stability;
pub mod tangent;

pub use crate::model::equilibrium_settings::EquilibriumSettings as Settings;
pub use outcome::{Failure, Reaction, Report, StaticsError};
pub use solve::equilibrium;
