//! The Newton matrix's building blocks, below everything that assembles it: one moving
//! part's mass block ([`Mat3Block`]) and the weights the integrators put on its terms
//! ([`Weights`]).

use crate::vocab::math::Mat3;

/// One part's mass block divided by UCF: 3D (m, R·J·Rᵀ) or 2D (m, J about the normal).
#[derive(Clone, Copy, Debug)]
pub enum Mat3Block {
    /// 3D: mass and the inertia tensor in global axes.
    Three(f64, Mat3),
    /// 2D: mass and the inertia about the plane's normal.
    Two(f64, f64),
}

/// Weights of the Newton matrix [[w_m·M/UCF − w_k·∂Q/∂q − w_c·∂Q/∂v, w_l·Φ_qᵀ], [Φ_q, 0]].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Weights {
    /// Weight of the mass matrix.
    pub w_m: f64,
    /// Weight of the stiffness ∂Q/∂q.
    pub w_k: f64,
    /// Weight of the damping ∂Q/∂v.
    pub w_c: f64,
    /// Weight of the constraint forces Φ_qᵀ.
    pub w_l: f64,
}
