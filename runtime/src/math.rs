//! FORTRAN-77 style math functions of spec §4 and the `**` operator.
//!
//! [`elementary`] holds the smooth functions (trigonometric, hyperbolic, exponential,
//! logarithms, square root, power), thin wrappers over `std` that only add the NaN rule
//! and the derivative companions. [`piecewise`] holds the non-smooth ones (ABS, AINT,
//! ANINT, MOD, SIGN, DIM, MAX, MIN), written as explicit comparisons so that NaN never
//! falls into a constant branch. Angles are radians; domain errors follow IEEE (`LOG(0)`
//! is −∞, `SQRT(-1)` and `ACOS(2)` are NaN), spec §10 decision 7.

pub mod elementary;
pub mod piecewise;
pub mod trig;

pub use elementary::*;
pub use piecewise::*;
