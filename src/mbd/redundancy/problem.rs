//! What the analysis reads ([`Problem`]: the constraint Jacobian and what each row
//! means) and its tolerances ([`Options`]).

use crate::mbd::equations::EquationLabel;
use crate::mbd::sparse::Triplets;
use crate::vocab::elements::ElementRef;

/// What the analysis reads: the constraint Jacobian at the assembled configuration and
/// what each row means.
#[derive(Clone, Copy, Debug)]
pub struct Problem<'a> {
    /// Φ_q with velocity-level columns: per moving part 3 translational and 3 angular (3D)
    /// or 2 translational and 1 angular (2D), ground axes.
    pub jacobian: &'a Triplets,
    /// One label per row.
    pub labels: &'a [EquationLabel],
    /// The elements the labels point into.
    pub elements: &'a [ElementRef],
    /// Moving parts (column blocks).
    pub moving_parts: usize,
    /// 2 or 3.
    pub dim: usize,
    /// Φ at the assembled configuration, one entry per row and scaled like the rows
    /// (translational equations in model lengths); when given, redundant rows are checked
    /// for conflicts.
    pub residuals: Option<&'a [f64]>,
    /// The velocity-level residuals Φ_q v + Φ_t, scaled the same way; when given,
    /// redundant rows are checked for conflicts at velocities too (a GCON of time alone
    /// has no position Jacobian, holds at t = 0, and asks 0 = 1 of the velocities).
    pub velocity_residuals: Option<&'a [f64]>,
}

impl<'a> Problem<'a> {
    /// A problem without residuals (no conflict check).
    pub fn new(
        jacobian: &'a Triplets,
        labels: &'a [EquationLabel],
        elements: &'a [ElementRef],
        moving_parts: usize,
        dim: usize,
    ) -> Self {
        Problem {
            jacobian,
            labels,
            elements,
            moving_parts,
            dim,
            residuals: None,
            velocity_residuals: None,
        }
    }
}

/// Tolerances of the analysis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// A row is redundant when its relative distance to the span of the kept rows (after
    /// column equilibration) is at most this.
    pub tolerance: f64,
    /// A redundant row whose residual magnitude exceeds this is conflicting.
    pub conflict_tolerance: f64,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            tolerance: 1e-8,
            conflict_tolerance: 1e-6,
        }
    }
}
