//! What the dynamics checks: a part free and massless at setup, a kept row whose
//! Jacobian vanished, generalized forces that are not finite, dropped rows that drift;
//! and what a failure points at ([`Culprit`]): the row with the largest residual or the
//! part of a column, to name in the error.

use super::blocks::Mat3Block;
use super::failure::{Culprit, DynError, NonFinite, Singularity};
use super::setup::Dynamics;

impl Dynamics {
    /// A part must not have a direction of motion that is massless and free: one along
    /// which its mass matrix vanishes and no constraint row it is in changes. (A point
    /// mass on a pendulum rod is fine: its rotation has no inertia but moves the pin.)
    pub(super) fn check_massless(&mut self) -> Result<(), DynError> {
        self.eval_constraints(true)?;
        let bs = self.sys.dim.cols();
        let blocks = self.mass_blocks();
        let part_slots = self.jac.part_slots(self.sys.moving_parts());
        for (h, p) in self.sys.parts.iter().enumerate() {
            let Some(i) = p.index else { continue };
            // Mass in every direction (relative to the largest): nothing to check.
            let (lo, hi) = match blocks[i] {
                Mat3Block::Three(m, j) => {
                    let eig = j.symmetric_eigenvalues();
                    (m.min(eig.min()), m.max(eig.max()))
                }
                Mat3Block::Two(m, j) => (m.min(j), m.max(j)),
            };
            if lo > 1e-9 * hi {
                continue;
            }
            // Otherwise the mass block stacked on the rows that read the part must have
            // full rank: each massless direction held by a constraint.
            let slots = &part_slots[i];
            let mut stack = crate::vocab::math::DMat::zeros(bs + slots.len(), bs);
            match blocks[i] {
                Mat3Block::Three(m, j) => {
                    for c in 0..3 {
                        stack[(c, c)] = m;
                        for r in 0..3 {
                            stack[(3 + r, 3 + c)] = j[(r, c)];
                        }
                    }
                }
                Mat3Block::Two(m, j) => {
                    (stack[(0, 0)], stack[(1, 1)], stack[(2, 2)]) = (m, m, j);
                }
            }
            let top = stack.amax();
            if top > 0.0 {
                stack /= top;
            }
            for (row, &k) in slots.iter().enumerate() {
                for (c, &x) in self.jac.block(k).iter().enumerate() {
                    stack[(bs + row, c)] = x;
                }
                let top = stack.row(bs + row).amax();
                if top > 0.0 {
                    stack.row_mut(bs + row).scale_mut(1.0 / top);
                }
            }
            let sv = stack.singular_values();
            let rank = sv.iter().filter(|&&s| s > 1e-9).count();
            if rank < bs {
                let name = p.id.map_or(format!("part {h}"), |id| format!("PART/{id}"));
                return Err(DynError::Massless {
                    part: name,
                    directions: bs - rank,
                });
            }
        }
        Ok(())
    }

    /// A kept row whose Jacobian vanished at the last evaluation constrains nothing any
    /// more: the Newton matrix is singular there, even while an older factorization
    /// still converges.
    pub fn check_rows(&self) -> Result<(), DynError> {
        match self.vanished_row() {
            Some(r) => Err(DynError::Singular {
                time: self.sys.time,
                why: Singularity::VanishedRow,
                culprit: Some(self.row_culprit(r)),
            }),
            None => Ok(()),
        }
    }

    /// The element of the kept row with the largest residual at the last constraint
    /// evaluation (translational rows over the model length).
    pub fn worst_row(&self) -> Option<Culprit> {
        (0..self.m)
            .max_by(|&a, &b| self.scaled_residual(a).total_cmp(&self.scaled_residual(b)))
            .map(|r| self.row_culprit(r))
    }

    /// |Φ| of kept row `r` at the last evaluation, translational rows over the model
    /// length.
    pub fn scaled_residual(&self, r: usize) -> f64 {
        let (e, q) = self.rows[r];
        self.phi[r].abs() * self.sys.row_scale(e, q)
    }

    pub(super) fn row_culprit(&self, r: usize) -> Culprit {
        Culprit::Element(self.sys.elements[self.rows[r].0].elref.clone())
    }

    /// A kept row whose Jacobian (the last evaluation's) has vanished: it constrains
    /// nothing any more.
    pub(super) fn vanished_row(&self) -> Option<usize> {
        let floor = 1e-12 * self.jac_top;
        self.may_vanish
            .iter()
            .copied()
            .find(|&r| !self.jac.row_exceeds(r, floor))
    }

    /// Names what makes the Newton matrix singular: a kept row whose Jacobian vanishes
    /// (the constraint no longer constrains anything), else the row with the largest
    /// residual.
    pub fn singular_culprit(&self) -> Option<Culprit> {
        self.vanished_row()
            .map(|r| self.row_culprit(r))
            .or_else(|| self.worst_row())
    }

    /// The part whose velocity-layout column is `col`.
    pub fn part_of_column(&self, col: usize) -> Option<Culprit> {
        let i = col / self.sys.dim.cols();
        self.sys
            .parts
            .iter()
            .find(|p| p.index == Some(i))
            .and_then(|p| p.id)
            .map(Culprit::Part)
    }

    /// NaN or infinity in the generalized forces: names the element.
    pub fn check_forces(&self) -> Result<(), DynError> {
        if self.gen.q.iter().all(|x| x.is_finite()) {
            return Ok(());
        }
        let element = self
            .forces
            .loads
            .iter()
            .zip(&self.forces.elements)
            .find(|(l, _)| {
                ![l.on_i.0, l.on_i.1, l.on_j.0, l.on_j.1]
                    .iter()
                    .all(|v| v.iter().all(|x| x.is_finite()))
            })
            .map(|(_, e)| e.elref.clone());
        Err(DynError::NotFinite {
            time: self.sys.time,
            what: match element {
                Some(_) => NonFinite::Force,
                None => NonFinite::Inertial,
            },
            element,
        })
    }

    /// The largest residual of the kept rows (model units) and of the dropped rows, the
    /// latter checked against `tol`: a violated dropped row is a conflict.
    pub fn check_dropped(&self, tol: f64) -> Result<f64, DynError> {
        let mut worst: f64 = 0.0;
        for &(e, q) in &self.dropped {
            let scaled = self.sys.row_value(e, q)? * self.sys.row_scale(e, q);
            if scaled.abs() > tol || scaled.is_nan() {
                return Err(DynError::DroppedViolated {
                    time: self.sys.time,
                    element: self.sys.elements[e].elref.clone(),
                    equation: self.sys.elements[e].eqs[q].label.label(),
                    residual: scaled.abs(),
                });
            }
            worst = worst.max(scaled.abs());
        }
        Ok(worst)
    }
}
