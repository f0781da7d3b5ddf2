//! The state elements' coupling in the Newton matrix of the implicit integrators (BDF,
//! the Newmark family): the matrix of the mechanical unknowns y = (a, λ), K, bordered by
//! the states' rates ż (x = b + g·ż in the integrator's formula),
//!
//! ```text
//! [K   B] [δy]   [f]        B = ∂R/∂ż = −w_Q·∂Q/∂ż     (forces reading the states)
//! [C   D] [δż] = [−Rₛ],     C = ∂Rₛ/∂(a, λ)             (the states reading the plant)
//!                           D = ∂Rₛ/∂ż                  (the block's own Jacobian)
//! ```
//!
//! with Rₛ the states' residuals (ż − f, or f of an IMPLICIT DIFF). K stays factored as
//! it is (Schur path or sparse LU): the small block is the Schur complement against it,
//! S = D − C·K⁻¹·B, with U = K⁻¹·B from one solve per state per factorization. A Newton
//! step then solves S·δż = −Rₛ − C·(K⁻¹f) and corrects δy = K⁻¹f − U·δż
//! ([`StateBorder::correct`]), the step of the whole bordered matrix.
//!
//! The entries come from finite differences, the states' expressions and the force
//! elements reading them having no derivative with respect to the state values in the
//! core: B and D by a forward difference of each rate (the forces evaluated with the
//! states frozen), C·w along a direction w = (w_a, w_λ) by moving the integrator's
//! candidate along w_a (its `place`; the accelerations the states read move with it)
//! and the multipliers along w_λ, each by its own step, and evaluating the residuals
//! again. The multipliers' part is what carries a state reading a reaction
//! (`JOINT(id, 0, 4, rm)`), so a loop force → reaction → state → force is solved by
//! Newton. (Under HHT the states read the physical accelerations, which move as
//! w_a/s; the difference takes them as w_a: an approximation of the matrix only.)

use super::failure::DynError;
use super::setup::Dynamics;
use super::state::largest_magnitude;
use crate::mbd::states::Mode;
use crate::vocab::math::{DMat, DVec};

/// How many states `d` has.
fn states_len(d: &Dynamics) -> usize {
    d.forces.states.len()
}

/// The relative finite-difference step.
const FD_STEP: f64 = 1e-7;

/// Moves the dynamics to the candidate of the given accelerations.
pub(super) type Place<'a> = dyn FnMut(&mut Dynamics, &DVec) + 'a;

/// The bordered block of the current factorization.
#[derive(Default)]
pub(super) struct StateBorder {
    /// The factorization it was built for (None: none yet).
    generation: Option<u64>,
    /// U = K⁻¹·B, one column (n + m) per state; empty when no force reads a state.
    u: Vec<Vec<f64>>,
    /// S = D − C·U, factored.
    s: Option<nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>>,
    /// Scratch: the rates, the residuals at them, and a moved candidate's.
    z: Vec<f64>,
    r0: Vec<f64>,
    r: Vec<f64>,
}

impl StateBorder {
    /// Turns `rhs`, the solve K⁻¹·f of the mechanical Newton matrix at the candidate
    /// of accelerations `a1` (where `d` stands, its evaluations made), into the
    /// mechanical part of the bordered step; `w_q` weighs −Q in the residual, `place`
    /// moves the candidate. Nothing without states.
    pub(super) fn correct(
        &mut self,
        d: &mut Dynamics,
        rhs: &mut [f64],
        (a1, w_q): (&DVec, f64),
        place: &mut Place<'_>,
    ) -> Result<(), DynError> {
        let states = &d.forces.states;
        if states.is_empty() || states.mode() != Mode::Dynamic || states.frozen {
            return Ok(());
        }
        self.z.clear();
        self.z.extend_from_slice(d.forces.states.unknowns());
        let s = self.z.len();
        if s != states_len(d) {
            return Ok(());
        }
        self.r0.resize(s, 0.0);
        self.r.resize(s, 0.0);
        let mut r0 = std::mem::take(&mut self.r0);
        d.state_residual(&self.z, &mut r0)?;
        self.r0 = r0;
        if self.generation != Some(d.factor_generation) {
            self.build(d, w_q, a1, place)?;
        }
        if self.s.is_none() {
            return Ok(());
        }
        // S·δż = −Rₛ − C·(K⁻¹f).
        let c = self.along(d, a1, &rhs[..d.n + d.m], place)?;
        let f = DVec::from_iterator(s, (0..s).map(|i| -self.r0[i] - c[i]));
        // (A singular S leaves K's step: the block's own solve still holds the states.)
        if let Some(dz) = self.s.as_ref().and_then(|lu| lu.solve(&f)) {
            for (k, u) in self.u.iter().enumerate() {
                for (x, &uk) in rhs.iter_mut().zip(u) {
                    *x -= uk * dz[k];
                }
            }
        }
        // The state values back at the candidate's rates.
        let mut r = std::mem::take(&mut self.r);
        d.state_residual(&self.z, &mut r)?;
        self.r = r;
        Ok(())
    }

    /// B, D, U = K⁻¹·B and S at the current factorization.
    fn build(
        &mut self,
        d: &mut Dynamics,
        w_q: f64,
        a1: &DVec,
        place: &mut Place<'_>,
    ) -> Result<(), DynError> {
        let (n, m, s) = (d.n, d.m, self.z.len());
        self.generation = Some(d.factor_generation);
        self.s = None;
        self.u.clear();
        // Q at the candidate, as this iteration's evaluation left it (the states solved
        // at the rates `z`).
        let q0 = d.gen.q.clone();
        let mut dmat = DMat::zeros(s, s);
        let mut coupled = false;
        for k in 0..s {
            let keep = self.z[k];
            let e = FD_STEP * keep.abs().max(1.0);
            self.z[k] = keep + e;
            let mut r = std::mem::take(&mut self.r);
            let moved = d.state_residual(&self.z, &mut r);
            self.r = r;
            self.z[k] = keep;
            moved?;
            for i in 0..s {
                dmat[(i, k)] = (self.r[i] - self.r0[i]) / e;
            }
            let q = self.frozen_forces(d)?;
            let mut col = vec![0.0; n + m];
            for (c, (a, b)) in col.iter_mut().zip(q.iter().zip(q0.iter())) {
                *c = -w_q * (a - b) / e;
            }
            coupled |= largest_magnitude(&col) > 0.0;
            d.solve(&mut col)?;
            self.u.push(col);
        }
        // The state values and forces back at the candidate.
        let mut r = std::mem::take(&mut self.r);
        d.state_residual(&self.z, &mut r)?;
        self.r = r;
        d.gen.q.copy_from(&q0);
        if !coupled {
            // No force reads a state: the block decouples, K's step is the whole step.
            self.u.clear();
            return Ok(());
        }
        let mut smat = dmat;
        for k in 0..s {
            let u = std::mem::take(&mut self.u[k]);
            let cu = self.along(d, a1, &u, place);
            self.u[k] = u;
            let cu = cu?;
            for i in 0..s {
                smat[(i, k)] -= cu[i];
            }
        }
        self.s = Some(smat.lu());
        Ok(())
    }

    /// Q with the state values as they stand (the states frozen).
    fn frozen_forces(&self, d: &mut Dynamics) -> Result<DVec, DynError> {
        d.forces.states.frozen = true;
        let q = d.eval_forces(false);
        d.forces.states.frozen = false;
        q?;
        Ok(d.gen.q.clone())
    }

    /// C·w: the change of the states' residuals at fixed rates as the accelerations
    /// move along `w`'s first n entries from `a1` and the multipliers along the rest
    /// (the candidate put back after).
    fn along(
        &mut self,
        d: &mut Dynamics,
        a1: &DVec,
        w: &[f64],
        place: &mut Place<'_>,
    ) -> Result<Vec<f64>, DynError> {
        let n = d.n;
        let (wa, wl) = w.split_at(n.min(w.len()));
        let mut out = self.along_accelerations(d, a1, wa, place)?;
        if d.forces.states.reads_solution() {
            for (o, c) in out.iter_mut().zip(self.along_multipliers(d, wl)?) {
                *o += c;
            }
        }
        Ok(out)
    }

    /// C_a·w: the accelerations moved along `w` from `a1` (the candidate, and the
    /// accelerations the states read, put back after).
    fn along_accelerations(
        &mut self,
        d: &mut Dynamics,
        a1: &DVec,
        w: &[f64],
        place: &mut Place<'_>,
    ) -> Result<Vec<f64>, DynError> {
        let s = self.z.len();
        let size = largest_magnitude(w);
        if size == 0.0 {
            return Ok(vec![0.0; s]);
        }
        let e = FD_STEP * largest_magnitude(a1.as_slice()).max(1.0) / size;
        if !e.is_finite() {
            // A direction of subnormal size (a converged step's): its C·w is zero to
            // the precision there is, and the step along it would overflow.
            return Ok(vec![0.0; s]);
        }
        let mut moved = a1.clone();
        for (a, &x) in moved.iter_mut().zip(w) {
            *a += e * x;
        }
        place(d, &moved);
        let reads = d.forces.states.reads_solution() && d.a.len() == w.len();
        if reads {
            for (a, &x) in d.a.iter_mut().zip(w) {
                *a += e * x;
            }
            d.store_accelerations();
        }
        let mut r = std::mem::take(&mut self.r);
        let at = d.state_residual(&self.z, &mut r);
        place(d, a1);
        if reads {
            for (a, &x) in d.a.iter_mut().zip(w) {
                *a -= e * x;
            }
            d.store_accelerations();
        }
        let out = at.map(|()| (0..s).map(|i| (r[i] - self.r0[i]) / e).collect());
        self.r = r;
        Ok(out?)
    }

    /// C_λ·w: the multipliers moved along `w` (and put back after).
    fn along_multipliers(&mut self, d: &mut Dynamics, w: &[f64]) -> Result<Vec<f64>, DynError> {
        let s = self.z.len();
        let size = largest_magnitude(w);
        if size == 0.0 || d.lambda.len() != w.len() {
            return Ok(vec![0.0; s]);
        }
        let e = FD_STEP * largest_magnitude(d.lambda.as_slice()).max(1.0) / size;
        let keep = d.lambda.clone();
        for (l, &x) in d.lambda.iter_mut().zip(w) {
            *l += e * x;
        }
        let mut r = std::mem::take(&mut self.r);
        let at = d.state_residual(&self.z, &mut r);
        d.lambda = keep;
        let out = at.map(|()| (0..s).map(|i| (r[i] - self.r0[i]) / e).collect());
        self.r = r;
        d.fill_state_inputs();
        Ok(out?)
    }
}
