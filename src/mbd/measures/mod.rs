//! Marker measures of expr-language §6 from the system state: value and exact
//! derivatives with respect to the position-level increments (δr, δθ per part) and the
//! velocities (v, ω per part), through the `dual` module. GCON and MOTION rows read them;
//! their Jacobians follow by the chain rule ∂f/∂slot · ∂slot/∂(q, v).
//!
//! Conventions (spec §6): `i` measured marker, `j` reference (ground origin when absent
//! or 0), `k` resolving frame (ground), `l` frame of time differentiation (ground).
//! AX/AY/AZ, INCANG, the B1/B3 angles of MOTION and the RACKPIN pinion angle are
//! unwrapped: each value is taken within π of a reference that [`MeasureSet::commit`]
//! moves to the current value after every accepted state, so angles accumulate turns.
//! Acceleration and force measures need dynamics and are refused with a clear error.
//!
//! The files: `frames` (marker frames as duals or values) and `eval` (the measures
//! from them).
//!
//! [`MeasureSet::commit`]: crate::mbd::measure_set::MeasureSet::commit

mod eval;
mod frames;

pub use frames::PartSlots;
pub(crate) use frames::{dual_frame, value_frame, Frame};
