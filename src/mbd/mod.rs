//! The constrained-multibody core: from a [`crate::model::Model`] (Adams ids and names) to
//! an assembled system with dense indices into the coordinate, velocity and multiplier
//! vectors; marker kinematics and measures, constraint equations with analytic
//! Jacobians, assembly, redundancy analysis, and the dynamics with its analyses.
//!
//! **Layers.** The files stand in layers, lowest first. A file may refer (`use`, or a
//! path in code) to modules of its own layer and of lower ones, never to a higher one;
//! what a lower layer owns but a higher one computes is data below (the [`System`] holds
//! [`rows::Row`]s and a [`measure_set::MeasureSet`]) and `impl` blocks above. No two
//! files refer to each other through a circle, except a parent module and its own child;
//! inside `dynamics` the files stand in sublayers of their own (its module doc). The
//! test `layering::mbd_layers` reads this list and fails on an edge upward or a circle,
//! quoting the line.
//!
//! 1. Vocabulary, what the rest is written in: `dual` numbers, `dense` and `sparse`
//!    matrices, the minimum-norm solve `normal`, `expr` (expressions and their
//!    compiler) with `compiled` (the JIT's), `error`, `equations` (the Adams labels),
//!    `handles` (what parts, markers and elements are addressed by), and
//!    `redundancy` (the analysis of a Jacobian's rows).
//! 2. System: `system` (parts, markers, coordinates) and the data it holds: `rows`
//!    (constraint elements and their rows) and `measure_set`.
//! 3. Measures: `measures` (values and derivatives from the state) and `output_slot`
//!    (what an output expression reads).
//! 4. Constraints and forces: `constraints` (JOINT, JPRIM, GCON and MOTION from primitive
//!    equations, evaluated), `fused_rows`, `states` (DIFF, LSE and TFSISO states, solved
//!    at each evaluation), `forces` (applied forces, evaluated in the order of what they
//!    read) and `contacts` (CONTACT forces between geometries).
//! 5. Build: `build` (a Model into a System), `planar` (2D or 3D), `assembly` (positions
//!    and velocities solved), and `pipeline` (the three, then the redundancy analysis:
//!    what every session starts with).
//! 6. Dynamics: `dynamics` (equations of motion, the Newton matrix, integrators and the
//!    time loop).
//! 7. Analyses on the dynamics, which wrap its failures in their own: `freedom` (the
//!    directions the constraints leave free), `statics`, `kinematics`, `linear` and
//!    `rewind` (the start state kept for a rerun).
//!
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
pub mod contacts;
mod dense;
mod dual;
pub mod dynamics;
pub mod equations;
pub mod error;
pub mod expr;
pub mod forces;
pub mod freedom;
pub mod fused_rows;
pub mod handles;
pub mod kinematics;
pub mod linear;
pub mod measure_set;
pub mod measures;
mod normal;
pub mod output_slot;
pub mod pipeline;
pub mod planar;
pub mod redundancy;
pub mod rewind;
pub mod rows;
pub mod sparse;
pub mod states;
pub mod statics;
pub mod system;

pub use assembly::{AssemblyError, AssemblyOptions, AssemblyReport};
pub use error::MbdError;
pub use handles::{ElementHandle, MarkerHandle, PartHandle};
pub use planar::Dim;
pub use system::{Dimension, System};

#[cfg(test)]
mod tests;
