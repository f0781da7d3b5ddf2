//! The linear six-component law of FIELD and BEAM (issue 40 §4): in J's axes, the
//! deflection X of I relative to J (translations, then the AX, AY, AZ angles) and its
//! rate V (the relative velocity seen in J's frame, then the relative angular velocity
//! in J's axes) give
//!
//! ```text
//! (F, T) = −K·(X − L) − C·V + (F₀, T₀)
//! ```
//!
//! on I, and the reaction on J: −F at I's origin and −T (the beam's equilibrium: the
//! force and the moment of its arm about J). A BEAM is this law with Timoshenko's K
//! (the `beam` module) and L = (LENGTH, 0, …). This file holds the law's constants; the
//! evaluation is in `field_loads`.

pub use crate::model::beams::Mat6;

/// The constants of a linear six-component law.
#[derive(Clone, Debug, PartialEq)]
pub struct Linear6 {
    /// Stiffness.
    pub k: Mat6,
    /// Damping.
    pub c: Mat6,
    /// The deflection at which the element gives `preload`.
    pub length: [f64; 6],
    /// The force and torque at `length`, J axes.
    pub preload: [f64; 6],
}
