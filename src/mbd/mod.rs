//! The constrained-multibody core: from a [`crate::model::Model`] (Adams ids and names) to
//! an assembled system with dense indices into the coordinate, velocity and multiplier
//! vectors; marker kinematics and measures, constraint equations with analytic
//! Jacobians, assembly, and redundancy analysis.

pub mod equations;
pub mod math;
pub mod redundancy;
pub mod sparse;
