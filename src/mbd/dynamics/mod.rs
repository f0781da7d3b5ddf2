//! Equations of motion of the constrained system, the index-3 DAE (multibody spec §6.1)
//!
//! ```text
//! (1/UCF)·M(q)·a + Φ_qᵀ·λ = Q(q, v, t),     Φ(q, t) = 0,
//! ```
//!
//! over the core's velocity-level columns: per moving part the CM velocity and the
//! angular velocity, global axes (6 columns in 3D, 3 in 2D), so M is block diagonal,
//! diag(m·I, R·J·Rᵀ), and Q holds gravity, the force elements and the gyroscopic moment
//! −ω × (J·ω). [`Dynamics`] owns the system and its forces, the kept constraint rows
//! (rows the redundancy analysis dropped stay out, as in Adams, and are watched for
//! drift), the Newton matrix on one sparse pattern with a sparse LU, and the state's
//! accelerations and multipliers. Integrators ([`integrator`]) drive it.
//!
//! One job a file: `setup` (the struct and its construction), `eval` (Φ, Φ_q, Q and its
//! Jacobians at a state), `mass` (the mass blocks), `newton` (the Newton matrix's factors
//! and solves), `saddle` (consistent accelerations, reconciliation), `project` (positions
//! back onto the constraints), `state` (snapshots and increments), `checks` (checks and
//! failure culprits), `error` and `stats`; then the integrators and what they share.

pub mod bdf;
mod checks;
mod crossing;
mod dense;
pub mod dopri853;
mod error;
mod eval;
pub mod events;
mod fill;
mod gamma;
pub mod integrator;
pub mod jacobian;
mod mass;
pub mod newmark;
mod newton;
pub mod outputs;
mod project;
mod reuse;
mod saddle;
pub mod schur;
mod setup;
mod state;
mod stats;
mod stiffness;
pub mod tree;

pub use checks::Culprit;
pub use error::{DynError, NonFinite, Singularity};
pub use mass::Mat3Block;
pub(crate) use newton::Factors;
pub use newton::Weights;
pub use setup::{row_parts, Dynamics};
use state::copy_into;
pub use state::Snapshot;
pub use stats::Stats;
