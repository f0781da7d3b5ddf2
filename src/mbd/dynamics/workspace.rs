//! The buffers and factors a [`super::Dynamics`] owns for its solves: the Newton matrix's
//! and the saddle-point matrix's factorizations ([`Factors`], told apart by [`Which`]),
//! and the saddle-point solves' scratch ([`Scratch`]), with the entries of ∂Q/∂λ the next
//! factorization takes.

use super::schur;
use crate::mbd::sparse::SparseLu;
use crate::vocab::math::DVec;

/// Which factorization: the integrator's Newton matrix or the outputs' saddle point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Which {
    Newton = 0,
    Saddle = 1,
}

/// One factorization of the Newton matrix: the full LU on the pattern and, when no
/// force element couples two parts, the Schur-complement solver; `via_schur` says which
/// one holds the last factors.
pub(crate) struct Factors {
    pub(super) lu: SparseLu,
    pub(super) values: Vec<f64>,
    pub(super) schur: Option<schur::Schur>,
    pub(super) via_schur: bool,
    /// The factors are of the regularised matrix (a solve must refine).
    pub(super) regularised: bool,
    /// The Schur path declined a matrix that never changes (the saddle point's, with
    /// constant mass blocks): it is not tried again.
    pub(super) schur_declined: bool,
}

/// Reused buffers of the saddle-point solves.
#[derive(Default)]
pub(super) struct Scratch {
    pub(super) rhs: Vec<f64>,
    pub(super) residual: Vec<f64>,
    /// M·a + Φ_qᵀ·λ, and Φ_q·a.
    pub(super) product: DVec,
    pub(super) row_product: Vec<f64>,
    /// γ and the solution (a; λ) of [`super::Dynamics::accelerations_factored`].
    pub(super) gamma: DVec,
    pub(super) solution: Vec<f64>,
    /// −∂Q/∂λ's entries for the next factorization (row, column, ∂Q/∂λ), from
    /// [`super::Dynamics::loop_jacobian`]; empty: none.
    pub(super) loop_jacobian: Vec<(usize, usize, f64)>,
}
