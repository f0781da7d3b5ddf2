//! The square constraint Jacobian of a fully driven model, factored on its own: with as
//! many kept rows as velocity columns, Φ_q (n × n, regular away from a lock-up) alone
//! gives the positions (Newton), the velocities (Φ_q·v = −Φ_t), the accelerations
//! (Φ_q·a = γ) and the multipliers (Φ_qᵀ·λ = Q − M·a), where the saddle-point matrix
//! [[M, Φ_qᵀ], [Φ_q, 0]] is twice its order. The pattern is the dynamics' fixed one,
//! analysed once; each factorization is numeric only ([`SparseLu`], dense at small
//! orders). The transpose, for λ, is factored only when the multipliers are asked for.

use crate::mbd::dynamics::Dynamics;
use crate::mbd::sparse::{Pattern, SparseLu};

/// Φ_q's factors and the maps from the dynamics' Jacobian entries to their slots.
pub struct SquareJacobian {
    lu: SparseLu,
    /// Φ_qᵀ's factors, when the multipliers were solved.
    lu_t: SparseLu,
    /// The slot of each Jacobian entry (in [`crate::mbd::dynamics::jacobian::Jacobian::entries`]'
    /// order) in Φ_q's pattern and in Φ_qᵀ's.
    slot: Vec<usize>,
    slot_t: Vec<usize>,
    values: Vec<f64>,
    /// Φ_q's values (pattern order) at the last two solutions ([`Self::factor_solved`]),
    /// the latest first, for [`Self::factor_extrapolated`].
    solved: [Vec<f64>; 2],
    /// Φ_q's values at the solution of the step being taken.
    candidate: Vec<f64>,
    /// The transpose's factors are of the same evaluation as `lu`'s.
    transposed: bool,
}

impl SquareJacobian {
    /// The factors' structure for `d`, or None when its Jacobian is not square or not
    /// structurally regular (the saddle point then serves).
    pub fn new(d: &Dynamics) -> Option<SquareJacobian> {
        if d.n != d.m || d.n == 0 {
            return None;
        }
        let entries: Vec<(usize, usize)> = d.jac.entries().map(|(r, c, _)| (r, c)).collect();
        let pattern = Pattern::new(d.n, entries.clone());
        let pattern_t = Pattern::new(d.n, entries.iter().map(|&(r, c)| (c, r)).collect());
        let slot = entries
            .iter()
            .map(|&(r, c)| pattern.slot(r, c))
            .collect::<Option<Vec<_>>>()?;
        let slot_t = entries
            .iter()
            .map(|&(r, c)| pattern_t.slot(c, r))
            .collect::<Option<Vec<_>>>()?;
        let values = vec![0.0; pattern.nnz()];
        let solved = [Vec::new(), Vec::new()];
        Some(SquareJacobian {
            lu: SparseLu::new(pattern).ok()?,
            lu_t: SparseLu::new(pattern_t).ok()?,
            slot,
            slot_t,
            values,
            solved,
            candidate: Vec::new(),
            transposed: false,
        })
    }

    /// Factors Φ_q of `d`'s last constraint evaluation (with its Jacobian); false when
    /// it is singular.
    pub fn factor(&mut self, d: &mut Dynamics) -> bool {
        d.stats.factorizations += 1;
        d.stats.jacobian_evaluations += 1;
        self.transposed = false;
        gather(&mut self.values, &self.slot, d);
        self.lu.factor(&self.values).is_ok()
    }

    /// [`Self::factor`] at a solution, whose values [`Self::accept`] keeps for
    /// [`Self::factor_extrapolated`].
    pub fn factor_solved(&mut self, d: &mut Dynamics) -> bool {
        let factored = self.factor(d);
        self.candidate.clone_from(&self.values);
        factored
    }

    /// The solution [`Self::factor_solved`] factored last is accepted: its Φ_q becomes
    /// the latest of the two extrapolated from.
    pub fn accept(&mut self) {
        let [latest, before] = &mut self.solved;
        std::mem::swap(latest, before);
        std::mem::swap(latest, &mut self.candidate);
    }

    /// Factors Φ_q extrapolated from the last two solutions to `ratio` times the last
    /// step beyond the latest (the next solution's Φ_q to O(h²), where the latest alone
    /// is O(h) off): Newton from a prediction then contracts by about h² a correction
    /// instead of h. False (nothing factored) without two solutions, or when singular.
    pub fn factor_extrapolated(&mut self, d: &mut Dynamics, ratio: f64) -> bool {
        let [latest, before] = &self.solved;
        if before.len() != latest.len() || latest.is_empty() {
            return false;
        }
        d.stats.factorizations += 1;
        self.transposed = false;
        for ((v, l), b) in self.values.iter_mut().zip(latest).zip(before) {
            *v = l + ratio * (l - b);
        }
        // Singular there (a lock-up ahead): the latest solution's Φ_q, regular.
        self.lu.factor(&self.values).is_ok() || self.lu.factor(latest).is_ok()
    }

    /// Solves Φ_q·x = b in place; false when the solution is not finite.
    pub fn solve(&mut self, b: &mut [f64]) -> bool {
        self.lu.solve(b).is_ok()
    }

    /// Solves Φ_qᵀ·x = b in place, Φ_q being `d`'s evaluation that [`Self::factor`]
    /// factored (the transpose is factored at the first such solve); false when
    /// singular.
    pub fn solve_transpose(&mut self, d: &Dynamics, b: &mut [f64]) -> bool {
        if !self.transposed {
            gather(&mut self.values, &self.slot_t, d);
            if self.lu_t.factor(&self.values).is_err() {
                return false;
            }
            self.transposed = true;
        }
        self.lu_t.solve(b).is_ok()
    }
}

/// The Jacobian's entries of `d` into `values` at their slots.
fn gather(values: &mut [f64], slot: &[usize], d: &Dynamics) {
    values.fill(0.0);
    for ((_, _, x), &k) in d.jac.entries().zip(slot) {
        values[k] += x;
    }
}
