//! Constraint elements: each is a set of scalar equations between two marker frames.
//! The six primitive equations of multibody spec §4.1 (d·e_J = 0 and u_I·w_J = 0) are
//! differentiated by hand; every JOINT of §4.2, every JPRIM and Exudyn's 2D prismatic
//! joint (§6.4) is a constructor that lists primitives, not a separate code path.
//! RACKPIN, SCREW and MOTION are linear combinations of measures minus a drive g(t);
//! GCON is an expression of measures. Rows carry their [`EquationLabel`].
//!
//! The files: `constructors` (the elements and the equations they list) and `eval` (the
//! rows evaluated).
//!
//! [`EquationLabel`]: crate::mbd::equations::EquationLabel

mod constructors;
mod eval;

pub use constructors::primitive_set;
pub use eval::{PartDerivative, PointAxis, Primitive, RowEval};
