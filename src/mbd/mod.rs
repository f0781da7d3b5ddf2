//! The constrained-multibody core: from a [`crate::model::Model`] (Adams ids and names) to
//! an assembled system with dense indices into the coordinate, velocity and multiplier
//! vectors; marker kinematics and measures, constraint equations with analytic
//! Jacobians, assembly, and redundancy analysis.
//!
//! [`system`] holds parts, markers and the coordinate layout (2D or 3D, [`planar`]
//! decides); [`measures`] computes the expression measures with their derivatives;
//! [`constraints`] builds JOINT, JPRIM, GCON and MOTION from primitive equations;
//! [`assembly`] solves positions and velocities; [`build`] turns a Model into a System.

pub mod assembly;
pub mod build;
pub mod constraints;
mod dual;
pub mod equations;
pub mod error;
pub mod expr;
pub mod math;
pub mod measures;
mod normal;
pub mod planar;
pub mod redundancy;
pub mod sparse;
pub mod system;

pub use assembly::{AssemblyError, AssemblyOptions, AssemblyReport};
pub use error::MbdError;
pub use planar::Dim;
pub use system::{Dimension, ElementHandle, MarkerHandle, PartHandle, System};

#[cfg(test)]
mod tests;
