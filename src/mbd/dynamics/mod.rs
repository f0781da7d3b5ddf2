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
//! **Sublayers.** The files stand in sublayers, lowest first. A file refers only to
//! files of its own sublayer and of lower ones: what [`Dynamics`] is built from sits
//! below it and never names it, helpers several integrators share sit below the
//! integrators, and nothing here names the analyses above (statics, kinematics, …).
//!
//! 1. kernel: `blocks` (mass blocks, Newton weights), `jacobian`, `schur`, `workspace`
//!    (factors and scratch), `fill`, `resolved` (the rows' primitives), `stats`,
//!    `failure` (the error and its culprit) and `rotation_chart` (the rotation-vector
//!    chart's rates): what the object is built from.
//! 2. object: `setup` (the struct and its construction), `eval` (Φ, Φ_q, Q and its
//!    Jacobians), `mass`, `stiffness`, `gamma`, `newton` (the Newton matrix's factors and
//!    solves), `saddle` (consistent accelerations, reconciliation), `project`, `state`
//!    (snapshots, increments, the vector helpers), `checks`, `outputs`,
//!    `reaction_partials` (∂Q/∂λ of forces reading a joint's reaction) and
//!    `step_extension` (continuous extensions inside a step): the struct and its impl
//!    blocks.
//! 3. drive: `integrator` (the contract and its settings), `reuse`, `crossing`, `events`,
//!    `inside_step` (output times inside a step), `states_border` (the state elements'
//!    border of the Newton matrix) and `time_loop` (the driver): what runs an
//!    integrator.
//! 4. methods: `newmark`, `bdf` and `dopri853`, the integrators.

pub mod bdf;
mod blocks;
mod checks;
mod crossing;
pub mod dopri853;
mod eval;
pub mod events;
mod failure;
mod fill;
pub(crate) mod gamma;
mod inside_step;
pub mod integrator;
pub mod jacobian;
mod mass;
pub mod newmark;
mod newton;
pub mod outputs;
mod project;
mod reaction_partials;
mod resolved;
mod reuse;
mod rotation_chart;
mod saddle;
pub mod schur;
mod setup;
mod state;
mod states_border;
mod stats;
mod step_extension;
mod stiffness;
mod time_loop;
mod workspace;

pub use blocks::{Mat3Block, Weights};
pub use dopri853::tree;
pub use failure::{Culprit, DynError, NonFinite, Singularity};
pub use inside_step::FrameTimes;
pub use setup::{row_parts, Dynamics};
pub use state::Snapshot;
pub use stats::Stats;
pub use step_extension::{Hermite, Taylor};
pub use time_loop::{simulate, simulate_framed, Inside, TimeLoop};
