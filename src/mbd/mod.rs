//! The constrained-multibody core: from a [`crate::model::Model`] (Adams ids and names) to
//! an assembled system with dense indices into the coordinate, velocity and multiplier
//! vectors; marker kinematics and measures, constraint equations with analytic
//! Jacobians, assembly, and redundancy analysis.
//!
//! [`system`] holds parts, markers and the coordinate layout (2D or 3D, [`planar`]
//! decides); [`measures`] computes the expression measures with their derivatives;
//! [`constraints`] builds JOINT, JPRIM, GCON and MOTION from primitive equations;
//! [`assembly`] solves positions and velocities; [`build`] turns a Model into a System.
//! The redundancy analysis reads [`System::jacobian`] (scaled) with [`System::labels`]
//! and [`System::element_refs`], and hands the rows it drops back through
//! [`AssemblyOptions::dropped`].
//!
//! ```
//! use mbfx::vocab::elements::{ElementKind, ElementRef, JointType};
//! use mbfx::vocab::math::{Mat3, Vec3};
//! use mbfx::mbd::{AssemblyOptions, Dim, Dimension, System};
//!
//! // A unit pendulum hinged at the origin, placed slightly off.
//! let mut sys = System::new();
//! let link = sys.add_part(Some(2), Vec3::new(1.05, 0.1, 0.0), Mat3::identity());
//! let i = sys.add_marker(Some(20), link, Vec3::new(-1.0, 0.0, 0.0), Mat3::identity());
//! let j = sys.add_marker(Some(10), System::GROUND, Vec3::zeros(), Mat3::identity());
//! let hinge = ElementRef { kind: ElementKind::Joint(JointType::Revolute), id: 1, name: None };
//! sys.joint(hinge, JointType::Revolute, i, j, 0.0).unwrap();
//! sys.prepare(Dim::Auto);
//! assert_eq!(sys.dim, Dimension::Two); // X Delta and Y Delta remain
//! let report = sys.assemble(&AssemblyOptions::default()).unwrap();
//! assert!((sys.part(link).r.norm() - 1.0).abs() < 1e-12);
//! assert!(report.residual < 1e-10);
//! ```

pub mod assembly;
pub mod build;
pub mod compiled;
pub mod constraints;
mod dense;
mod dual;
pub mod dynamics;
pub mod equations;
pub mod error;
pub mod expr;
mod force_order;
pub mod forces;
pub mod freedom;
pub mod fused_rows;
pub mod inertia;
pub mod kinematics;
pub mod linear;
pub mod measures;
mod normal;
pub mod output_slot;
pub mod planar;
pub mod redundancy;
pub mod rewind;
pub mod sparse;
pub mod statics;
pub mod system;

pub use assembly::{AssemblyError, AssemblyOptions, AssemblyReport};
pub use error::MbdError;
pub use planar::Dim;
pub use system::{Dimension, ElementHandle, MarkerHandle, PartHandle, System};

#[cfg(test)]
mod tests;
