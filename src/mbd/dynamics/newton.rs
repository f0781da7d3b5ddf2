//! The Newton matrix [[w_m·M/UCF − w_k·∂Q/∂q − w_c·∂Q/∂v, w_l·(Φ_qᵀ − ∂Q/∂λ)], [Φ_q, 0]]
//! ([`Weights`]; ∂Q/∂λ from forces that read a joint's reaction, `reaction_partials`):
//! filled on its sparse pattern and factored, by the Schur complement when no force
//! element couples two parts and none reads a reaction (the complement assumes the
//! symmetric Φ_qᵀ there), else by the sparse LU, regularised near a dead centre (into
//! [`super::workspace::Factors`]); and its solves.

use super::blocks::{Mat3Block, Weights};
use super::failure::{DynError, NonFinite, Singularity};
use super::setup::Dynamics;
use super::workspace::Which;
use crate::mbd::sparse::FactorError;
use crate::vocab::math::DVec;

/// The dense saddle-point matrix is factored without regularisation while its smallest
/// pivot is at least this fraction of its largest; nearer singular (a dead centre), it
/// is regularised and its solves refined ([`Dynamics::solve_saddle`]).
pub(super) const EXACT_PIVOT_RATIO: f64 = 1e-8;

impl Dynamics {
    /// Fills and factors the Newton matrix with weights `w` from the last evaluations of
    /// constraints (with Jacobian) and forces (with Jacobians, and ∂Q/∂λ where forces
    /// read reactions).
    /// Factors the Newton matrix with weights `w` at the current state and multipliers
    /// `lambda` (their geometric stiffness enters with w_k).
    pub fn factor(&mut self, w: Weights, lambda: &DVec) -> Result<(), DynError> {
        self.loop_jacobian();
        if w.w_k != 0.0 {
            self.geometric_stiffness(lambda);
        } else {
            self.geo.clear();
        }
        self.factor_into(Which::Newton, w)
    }

    pub(super) fn factor_into(&mut self, which: Which, w: Weights) -> Result<(), DynError> {
        // Where the constraints lose rank for an instant (a four-bar passing its dead
        // centre), the saddle-point matrix is singular although the motion goes on. A
        // regularisation −ε·I on the multipliers' block, ε = 1e-10 of the Schur complement's
        // scale |Φ_q|²/m, keeps it factorable; it changes the Newton matrix only, so a
        // converged step still solves the equations exactly. A row whose Jacobian has
        // vanished altogether constrains nothing any more: that is reported.
        let top = self.jac.amax();
        self.jac_top = top;
        self.check_rows()?;
        // (Constant blocks are lent out for the factorization rather than copied.)
        let blocks = match self.constant_mass.take() {
            Some(b) => b,
            None => self.mass_blocks().into_owned(),
        };
        let factored = self.factor_blocks(which, w, &blocks, top);
        if self.mass_is_constant() {
            self.constant_mass = Some(blocks);
        }
        factored
    }

    /// [`Dynamics::factor_into`] with the mass blocks `blocks` and the Jacobian's
    /// largest entry `top`.
    pub(super) fn factor_blocks(
        &mut self,
        which: Which,
        w: Weights,
        blocks: &[Mat3Block],
        top: f64,
    ) -> Result<(), DynError> {
        let time = self.sys.time;
        let heaviest = blocks
            .iter()
            .map(|b| match b {
                Mat3Block::Three(m, j) => m.max(j.amax()),
                Mat3Block::Two(m, j) => m.max(*j),
            })
            .fold(0.0f64, f64::max);
        let eps = 1e-10 * w.w_l * top * top / heaviest.max(f64::MIN_POSITIVE);
        self.stats.factorizations += 1;
        if which == Which::Newton {
            self.factor_generation += 1;
        }
        let constant = self.mass_is_constant();
        let f = &mut self.factors[which as usize];
        f.via_schur = false;
        f.regularised = true;
        // A NaN or infinity in the matrix makes the Schur path decline (its block
        // inverses and factorizations check); the full LU then reports it.
        // ∂Q/∂λ makes the matrix unsymmetric in the multipliers' columns: the LU takes it.
        let looped = !self.scratch.loop_jacobian.is_empty();
        if let (Some(schur), false, false) = (&mut f.schur, f.schur_declined, looped) {
            match schur.factor(&self.jac, blocks, &self.gen, &self.geo, w, eps) {
                Ok(true) => {
                    f.via_schur = true;
                    return Ok(());
                }
                // The saddle point's blocks are the mass's: when that never changes, a
                // block the Schur path cannot invert never will be.
                Ok(false) if which == Which::Saddle && constant => {
                    f.schur_declined = true;
                }
                _ => {}
            }
        }
        let forces = (&self.gen, self.scratch.loop_jacobian.as_slice());
        // The saddle point's dense matrix is factored as it is unless it is nearly
        // singular: its solves then need no refinement.
        if which == Which::Saddle && f.lu.pivot_ratio().is_some() {
            let f = &mut self.factors[which as usize];
            if self
                .fill
                .factor(f, blocks, &self.jac, forces, &self.geo, w, 0.0)
                .is_ok()
                && f.lu.pivot_ratio().is_some_and(|r| r >= EXACT_PIVOT_RATIO)
            {
                f.regularised = false;
                return Ok(());
            }
        }
        let f = &mut self.factors[which as usize];
        let factored = self
            .fill
            .factor(f, blocks, &self.jac, forces, &self.geo, w, eps);
        let culprit = if factored.is_err() {
            self.singular_culprit()
        } else {
            None
        };
        factored.map_err(|e| match e {
            FactorError::NotFinite => DynError::NotFinite {
                time,
                what: NonFinite::NewtonMatrix,
                element: None,
            },
            FactorError::Singular => DynError::Singular {
                time,
                why: Singularity::Dependent,
                culprit,
            },
        })
    }

    /// Solves the factored Newton matrix in place.
    pub fn solve(&mut self, rhs: &mut [f64]) -> Result<(), DynError> {
        self.solve_with(Which::Newton, rhs)
    }

    pub(super) fn solve_with(&mut self, which: Which, rhs: &mut [f64]) -> Result<(), DynError> {
        let time = self.sys.time;
        let f = &mut self.factors[which as usize];
        let solved = match (&mut f.schur, f.via_schur) {
            (Some(schur), true) => schur.solve(rhs),
            _ => f.lu.solve(rhs),
        };
        let solved = solved.and_then(|()| match rhs.iter().all(|x| x.is_finite()) {
            true => Ok(()),
            false => Err(FactorError::Singular),
        });
        let culprit = if solved.is_err() {
            self.singular_culprit()
        } else {
            None
        };
        solved.map_err(|_| DynError::Singular {
            time,
            why: Singularity::Numerical,
            culprit,
        })
    }
}
