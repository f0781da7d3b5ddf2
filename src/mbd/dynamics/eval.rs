//! The evaluations at the current state that every step starts from: Φ and Φ_q over the
//! kept rows ([`Dynamics::eval_constraints`], the fused row expressions first) and the
//! generalized forces Q with ∂Q/∂q and ∂Q/∂v ([`Dynamics::eval_forces`]), after the
//! state elements ([`crate::mbd::states`]), which are committed with an accepted state
//! ([`Dynamics::commit_states`]).

use super::setup::Dynamics;
use crate::mbd::error::MbdError;
use crate::mbd::rows::Row;
use crate::mbd::system::Dimension;

impl Dynamics {
    /// Φ over the kept rows (into `self.phi`) and, with `jacobian`, Φ_q (into
    /// `self.jac`; a non-holonomic row holds ∂f/∂v).
    pub fn eval_constraints(&mut self, jacobian: bool) -> Result<(), MbdError> {
        // Every GCON in one call at this state; the rows read it, and only they.
        self.sys.eval_fused_rows(jacobian);
        let rows = self.eval_rows(jacobian);
        self.sys.forget_fused_rows();
        rows
    }

    /// [`Dynamics::eval_constraints`]' rows.
    pub(super) fn eval_rows(&mut self, jacobian: bool) -> Result<(), MbdError> {
        let bs = self.sys.dim.cols();
        let comps = self.sys.column_components();
        for (r, &(e, q)) in self.rows.iter().enumerate() {
            // The primitives (nearly every row of a jointed model) write their blocks
            // directly.
            if let Some((p, slots)) = &self.prims[r] {
                let (mut si, mut sj) = ([0.0; 6], [0.0; 6]);
                if bs == 6 {
                    // 3D: the columns are the six components in order, written in place
                    let (gi, gj) = match jacobian {
                        true => self.jac.six_blocks_mut(slots[0], slots[1]),
                        false => (None, None),
                    };
                    self.phi[r] = self.sys.eval_primitive_into(
                        p,
                        gi.unwrap_or(&mut si),
                        gj.unwrap_or(&mut sj),
                    );
                    continue;
                }
                self.phi[r] = self.sys.eval_primitive_into(p, &mut si, &mut sj);
                if jacobian {
                    // 2D: each part's columns gather their components. The two slots are
                    // distinct parts (a row within one part reads it once).
                    for (g, k) in [&si, &sj].into_iter().zip(slots) {
                        let Some(k) = *k else { continue };
                        for (b, &c) in self.jac.block_at_mut(k).iter_mut().zip(&comps[..bs]) {
                            *b = g[c];
                        }
                    }
                }
                continue;
            }
            if matches!(
                self.sys.elements[e].eqs[q].row,
                Row::Gcon { .. } | Row::Measured { drive: Some(_), .. }
            ) {
                self.stats.expression_evaluations += 1;
            }
            let ev = &mut self.row_scratch;
            self.sys.eval_row_into(e, q, jacobian, ev)?;
            self.phi[r] = ev.value;
            if jacobian {
                let entries = if self.sys.row_reads_velocity(e, q) {
                    &ev.dv
                } else {
                    &ev.dq
                };
                self.jac.clear_row(r);
                for &(c, x) in entries {
                    let read = self.jac.add(r, c, x);
                    debug_assert!(read, "row {r} reads column {c} outside its parts");
                }
            }
        }
        Ok(())
    }

    /// Q (gravity, force elements, gyroscopic moments) into `self.gen`, with ∂Q/∂q and
    /// ∂Q/∂v when `jacobians`.
    pub fn eval_forces(&mut self, jacobians: bool) -> Result<(), MbdError> {
        // The state elements first: the forces may read them (none: nothing to do).
        if !self.forces.states.is_empty() {
            self.fill_state_inputs();
            self.forces.states.solve(&mut self.sys)?;
        }
        self.gen.clear();
        let bs = self.sys.dim.cols();
        let g = self.sys.gravity / self.sys.ucf;
        for p in &self.sys.parts {
            let Some(i) = p.index else { continue };
            let b = i * bs;
            match self.sys.dim {
                Dimension::Three => {
                    for c in 0..3 {
                        self.gen.q[b + c] += p.mass * g[c];
                    }
                    // −ω × (J ω), with ∂/∂ω = −([ω]× J − [J ω]×) and, through J = R J Rᵀ
                    // turning with δR = [δθ]× R, ∂/∂θ = [ω]× ([J ω]× − J [ω]×). All
                    // three vanish when J is isotropic.
                    if p.isotropic() {
                        continue;
                    }
                    let j = self.inertia_over_ucf(p);
                    let jw = j * p.w;
                    let gyro = -p.w.cross(&jw);
                    for c in 0..3 {
                        self.gen.q[b + 3 + c] += gyro[c];
                    }
                    if jacobians && p.w.norm() > 0.0 {
                        let wx = p.w.cross_matrix();
                        let dw = -(wx * j - jw.cross_matrix());
                        let dth = wx * (jw.cross_matrix() - j * wx);
                        for r in 0..3 {
                            for c in 0..3 {
                                self.gen.dv.push((b + 3 + r, b + 3 + c, dw[(r, c)]));
                                self.gen.dq.push((b + 3 + r, b + 3 + c, dth[(r, c)]));
                            }
                        }
                    }
                }
                Dimension::Two => {
                    let (x, y, _) = self.sys.plane_axes();
                    self.gen.q[b] += p.mass * g[x];
                    self.gen.q[b + 1] += p.mass * g[y];
                }
            }
        }
        let gen = &mut self.gen;
        (self.forces.contacts).eval(&self.sys, &mut gen.q, &mut gen.dq, &mut gen.dv, jacobians);
        self.stats.expression_evaluations += self.forces.expression_count();
        if !self.forces.reads_solution() {
            return self.forces.eval(&self.sys, &mut self.gen, jacobians);
        }
        // Each element after the forces it reads, its solution values read just before
        // it: accelerations and multipliers as they stand (`a`, `lambda`, the parts'),
        // forces as this pass left them.
        for o in 0..self.forces.order.len() {
            let k = self.forces.order[o];
            for r in 0..self.forces.reads[k].len() {
                let s = self.forces.reads[k][r];
                self.forces.solved[s] = self.forces.solution[s].value(self);
            }
            self.forces
                .eval_element(k, &self.sys, &mut self.gen, jacobians)?;
        }
        Ok(())
    }

    /// Commits the state elements at the current (accepted) state: a step, an
    /// equilibrium, a kinematic solution.
    pub fn commit_states(&mut self) -> Result<(), MbdError> {
        self.fill_state_inputs();
        self.forces.states.commit(&mut self.sys)
    }

    /// Solves the state elements at the current state under the integrator's formula
    /// (the values a converged step ends with, before its error estimate reads them).
    pub fn solve_states(&mut self) -> Result<(), MbdError> {
        self.fill_state_inputs();
        self.forces.states.solve(&mut self.sys)
    }

    /// Whether an expression, of a force or of a state element, reads the solution
    /// (accelerations, reactions, forces): the iterations then keep `a` and `lambda` at
    /// their iterate, and the consistent solve sweeps until they settle.
    pub fn reads_solution(&self) -> bool {
        self.forces.reads_solution() || self.forces.states.reads_solution()
    }

    /// The solution values the state elements read (reactions, forces, accelerations)
    /// at the current multipliers and accelerations, for the solves that follow
    /// (nothing when they read none).
    pub fn fill_state_inputs(&mut self) {
        if !self.forces.states.reads_solution() {
            return;
        }
        let mut solved = std::mem::take(&mut self.forces.states.solved);
        solved.clear();
        solved.extend(self.forces.states.solution.iter().map(|s| s.value(self)));
        self.forces.states.solved = solved;
    }

    /// The residuals of the state elements' equations at rates `z` (their solution
    /// values filled in at the current iterate), into `r`: what the bordered Newton
    /// matrix differentiates.
    pub(super) fn state_residual(&mut self, z: &[f64], r: &mut [f64]) -> Result<(), MbdError> {
        self.fill_state_inputs();
        self.forces.states.residual_of_rates(&mut self.sys, z, r)
    }

    /// Places the state elements at `x` (a continuous extension's values inside a step)
    /// and solves their rates there, for the outputs that read them. A failure leaves
    /// them as they stand: the extension's rows are outputs only, and the same
    /// equations are solved, and their failure reported, at the next step.
    pub fn place_states(&mut self, x: &[f64]) {
        if x.is_empty() {
            return;
        }
        self.forces.states.set_formula(x, 0.0);
        self.fill_state_inputs();
        let _ = self.forces.states.solve(&mut self.sys);
    }
}
