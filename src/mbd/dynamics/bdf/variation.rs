//! The global error estimate a BDF step carries (issue 41 §1): the first variation of the
//! step, e₁ = ∂y₁/∂(history)·e + le₁, the error of each past point carried through the
//! step's own linearization, plus the step's own local error (Skeel, *Global error
//! estimation and the backward differentiation formulas*, 1986; the same idea as the
//! "solve the variational equation alongside" estimators Shampine surveys).
//!
//! The step is y₁ = b + g·ẏ₁ with b the predictor's part (linear in the past points),
//! solved by Newton for the accelerations. Moving the past points by their errors moves
//! b by the same combination of the errors, δb; the step's answer then moves by the
//! solution of one Newton iteration from the converged candidate with b + δb:
//!
//! ```text
//! δx⁰ = δb_x + g·δb_v,  δv⁰ = δb_v,
//! N·[δa; δλ] = −[R(x₁ + δx⁰, v₁ + δv⁰, a₁, λ); Φ(x₁ + δx⁰)/g²],
//! δx₁ = δx⁰ + g²·δa,  δv₁ = δv⁰ + g·δa,
//! ```
//!
//! with N the matrix the step factored. That is one residual evaluation and one
//! back-substitution per accepted step, and it is exact to first order in the error (the
//! residual at the converged candidate is below the corrector's tolerance). The local
//! error added is the one error control uses, h/(t₁ − tₙ₋ₖ)·(y₁ − p(t₁)), as a signed
//! vector: errors of opposite signs cancel as they do in the answer.
//!
//! The state elements' own error is not carried (their contribution to the mechanical
//! error is), nor is the border of their coupling in N; SI2's position projection is
//! left out of the variation (its velocity rows keep the error on the velocity
//! constraints).

use super::Bdf;
use crate::mbd::dynamics::failure::DynError;
use crate::mbd::dynamics::setup::Dynamics;
use crate::vocab::math::DVec;

/// The largest perturbation the residual is evaluated at, in tolerances (the step's
/// per-column ones).
const PERTURBATION: f64 = 0.1;

/// The most corrector iterations the variation repeats.
const ITERATIONS: usize = 4;

impl Bdf {
    /// The candidate's global error from the history's and the step's local error, into
    /// `self.variation` (positions, then velocities). `d` stands at the converged
    /// candidate and is put back there; its last evaluations are not (the next attempt
    /// and the outputs evaluate again).
    pub(super) fn vary(&mut self, d: &mut Dynamics) -> Result<(), DynError> {
        let n = d.n;
        let hist = self.hist.as_ref().expect("started");
        let k = self.k_step.min(hist.len()).max(1);
        let t1 = d.sys.time;
        let (g, c_err) = (self.pred.g, self.pred.c_err);
        let (l, dl) = super::predictor_weights(hist, k, t1 - hist.newest().t);
        // δb = Σⱼ (lⱼ − g·l̇ⱼ)·eⱼ, positions and velocities alike.
        let e = &mut self.variation;
        e.clear();
        e.resize(2 * n, 0.0);
        let mut carried = false;
        for j in 0..=k {
            let ej = &hist.point(j).e;
            if ej.len() != 2 * n {
                continue;
            }
            carried = true;
            let w = l[j] - g * dl[j];
            for (x, &y) in e.iter_mut().zip(ej) {
                *x += w * y;
            }
        }
        if carried {
            // δx⁰ = δb_x + g·δb_v.
            for c in 0..n {
                e[c] += g * e[n + c];
            }
            let tol = std::mem::take(&mut self.tol.1);
            let stepped = self.linear_step(d, t1, &tol);
            self.tol.1 = tol;
            stepped?;
        }
        // The step's own local error.
        let e = &mut self.variation;
        for c in 0..n {
            e[c] += c_err * (self.x[c] - self.pred.xp[c]);
            e[n + c] += c_err * (self.v1[c] - self.pred.vp[c]);
        }
        self.onto_constraints(d)
    }

    /// Removes from the error what the constraints forbid: the corrector meets them, so
    /// its error lies along them (Φ_q·eₓ = 0, and Φ_q·eᵥ = 0 to first order), while the
    /// predictor in the local error does not. Each part is moved by the smallest step in
    /// the Newton matrix's metric, one back-substitution each (as SI2's projection).
    fn onto_constraints(&mut self, d: &mut Dynamics) -> Result<(), DynError> {
        let (n, m) = (d.n, d.m);
        if m == 0 {
            return Ok(());
        }
        let mut rhs = std::mem::take(&mut self.proj);
        for half in 0..2 {
            rhs.clear();
            rhs.resize(n + m, 0.0);
            let e = &self.variation[half * n..(half + 1) * n];
            d.jac.add_times(e, &mut rhs[n..]);
            for (r, &(el, q)) in d.rows.iter().enumerate() {
                // A row on velocities constrains the velocities' error only.
                let on_velocities = d.sys.row_reads_velocity(el, q);
                rhs[n + r] = match (half, on_velocities) {
                    (0, true) => 0.0,
                    _ => -rhs[n + r],
                };
            }
            rhs[..n].fill(0.0);
            let solved = d.solve(&mut rhs);
            if solved.is_err() {
                self.proj = rhs;
                return solved;
            }
            for (x, &dy) in self.variation[half * n..(half + 1) * n]
                .iter_mut()
                .zip(&rhs[..n])
            {
                *x += dy;
            }
        }
        self.proj = rhs;
        Ok(())
    }

    /// Moves `self.variation` from the perturbation with the accelerations held
    /// (δx⁰, δv⁰) to the one the step's Newton matrix gives, with `d` at the candidate
    /// at `t1` before and after:
    /// N·[δa; δλ] = −[R(x₁ + ε·δx, v₁ + ε·δv, a₁ + ε·δa, λ + ε·δλ); Φ(x₁ + ε·δx)/g²]/ε
    /// (I3; SI2's rows at the velocities), δx = δx⁰ + g²·δa, δv = δv⁰ + g·δa, from
    /// δa = 0. The residual is evaluated, not linearized from the matrix's Jacobians:
    /// those may be steps old, and a stale constraint stiffness of the wrong sign makes
    /// an error grow that does not. The matrix may be as old; where the step's corrector
    /// contracted slowly with it (a stiff contact), the variation iterates as the
    /// corrector did, up to [`ITERATIONS`] times. ε keeps the perturbation within
    /// [`PERTURBATION`] tolerances, where a contact's force is still near its
    /// linearization; the residual left at the converged candidate (a thousandth of a
    /// tolerance) is then a thousandth of the perturbation's.
    fn linear_step(&mut self, d: &mut Dynamics, t1: f64, tol: &[f64]) -> Result<(), DynError> {
        let (n, m, g) = (d.n, d.m, self.pred.g);
        let size = (self.variation[..n].iter().zip(tol))
            .map(|(x, t)| x.abs() / t)
            .fold(0.0, f64::max);
        if size == 0.0 || !size.is_finite() {
            return Ok(());
        }
        let eps = (PERTURBATION / size).min(1.0);
        // Iterations as the corrector needed to come within a twentieth.
        let rate = self.newton_rate.clamp(0.0, 0.9);
        let iterations = match rate > 0.05 {
            true => ((0.05f64).ln() / rate.ln()).ceil() as usize,
            false => 1,
        }
        .clamp(1, ITERATIONS);
        let hist = self.hist.take().expect("started");
        let base = &hist.newest().snap;
        let mut w = std::mem::take(&mut self.scratch);
        w.a.clone_from(&d.a);
        w.lambda.clone_from(&d.lambda);
        w.e0.clone_from(&self.variation);
        w.da.clear();
        w.da.resize(n, 0.0);
        w.dl.clear();
        w.dl.resize(m, 0.0);
        let mut rhs = std::mem::take(&mut self.rhs);
        let mut outcome = Ok(());
        for _ in 0..iterations {
            let e = &mut self.variation;
            for c in 0..n {
                e[c] = w.e0[c] + g * g * w.da[c];
                e[n + c] = w.e0[n + c] + g * w.da[c];
            }
            w.x.clear();
            w.x.extend((self.x.iter().zip(&e[..n])).map(|(x, dx)| x + eps * dx));
            w.v.clone_from(&self.v1);
            for (v, dv) in w.v.iter_mut().zip(&e[n..]) {
                *v += eps * dv;
            }
            for (a, (a1, da)) in d.a.iter_mut().zip(w.a.iter().zip(&w.da)) {
                *a = a1 + eps * da;
            }
            for (l, (l1, dl)) in d.lambda.iter_mut().zip(w.lambda.iter().zip(&w.dl)) {
                *l = l1 + eps * dl;
            }
            d.set_state(base, &w.x, &w.v, t1);
            let evaluated = d
                .eval_constraints(false)
                .and_then(|()| d.eval_forces(false));
            rhs.clear();
            rhs.resize(n + m, 0.0);
            let solved = evaluated.map_err(DynError::from).and_then(|()| {
                let r = &mut w.r;
                if r.len() != n {
                    *r = DVec::zeros(n);
                }
                d.motion_residual(d.a.as_slice(), &d.lambda, r);
                for (x, &r) in rhs[..n].iter_mut().zip(r.as_slice()) {
                    *x = -r;
                }
                // The constraint rows at the perturbed velocities (SI2 reads them).
                std::mem::swap(&mut self.v1, &mut w.v);
                let rows = self.constraint_rhs(d, &mut rhs);
                std::mem::swap(&mut self.v1, &mut w.v);
                rows?;
                d.solve(&mut rhs)
            });
            if let Err(e) = solved {
                outcome = Err(e);
                break;
            }
            for (x, &r) in w.da.iter_mut().zip(&rhs[..n]) {
                *x += r / eps;
            }
            for (x, &r) in w.dl.iter_mut().zip(&rhs[n..]) {
                *x += r / eps;
            }
        }
        d.set_state(base, &self.x, &self.v1, t1);
        std::mem::swap(&mut d.a, &mut w.a);
        std::mem::swap(&mut d.lambda, &mut w.lambda);
        let e = &mut self.variation;
        for c in 0..n {
            e[c] = w.e0[c] + g * g * w.da[c];
            e[n + c] = w.e0[n + c] + g * w.da[c];
        }
        (self.rhs, self.scratch, self.hist) = (rhs, w, Some(hist));
        outcome
    }
}

/// The variation's scratch: the perturbed state, the candidate's accelerations and
/// multipliers, the error before the step's correction, the correction, a residual.
#[derive(Default)]
pub(super) struct Scratch {
    x: Vec<f64>,
    v: DVec,
    a: DVec,
    lambda: DVec,
    e0: Vec<f64>,
    da: Vec<f64>,
    dl: Vec<f64>,
    r: DVec,
}
