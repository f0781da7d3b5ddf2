//! Solving the state block at the system's current (q, v, t): the residual of every
//! state's equation as a function of the unknowns z (the rates ẋ in a run, the states x
//! in statics), Newton on z with a finite-difference Jacobian of the block, the commit
//! of an accepted state and the trapezoidal rule's local error.

use super::{Committed, Mode, StateExpr, StateSet};
use crate::mbd::error::MbdError;
use crate::mbd::forces::measure_value;
use crate::mbd::system::System;
use crate::vocab::math::{DMat, DVec};

/// Newton iterations before a state solve fails.
const MAX_ITERATIONS: usize = 30;

/// A Newton correction below this (relative to 1 + |z|) has converged.
const CONVERGED: f64 = 1e-11;

/// The relative finite-difference step of the block's Jacobian.
const FD_STEP: f64 = 1e-7;

/// `e`'s value at the state of `sys`, its slots filled into `slots`.
fn value(e: &StateExpr, sys: &System, slots: &mut Vec<f64>) -> Result<f64, String> {
    for (&s, &m) in e.f.slots().iter().zip(&e.map) {
        let s = s as usize;
        if slots.len() <= s {
            slots.resize(s + 1, 0.0);
        }
        slots[s] = measure_value(sys, m);
    }
    e.f.value(sys.time, slots).map_err(|err| err.to_string())
}

impl StateSet {
    /// Per state: its x and ẋ value channels, STATIC_HOLD, and its initial x and ẋ.
    fn layout(&self) -> Vec<(usize, usize, bool, f64, f64)> {
        let mut out = Vec::with_capacity(self.len());
        for (k, d) in self.diffs.iter().enumerate() {
            out.push((2 * k, 2 * k + 1, d.static_hold, d.ic.0, d.ic.1));
        }
        for l in &self.linear {
            for j in 0..l.sys.n {
                let (x, r) = (l.base + j, l.base + l.sys.n + j);
                out.push((x, r, l.sys.static_hold, l.sys.ic[j], 0.0));
            }
        }
        out
    }

    /// The states' rates ẋ as the last solve left them.
    pub fn rates(&self, sys: &System) -> Vec<f64> {
        (self.layout().iter())
            .map(|l| sys.measures.states.get(l.1).copied().unwrap_or(f64::NAN))
            .collect()
    }

    /// The committed states, made from the initial conditions at `sys`'s time the first
    /// time.
    fn committed_or_start(&mut self, sys: &System) -> Committed {
        if let Some(b) = &self.base {
            return b.clone();
        }
        let layout = self.layout();
        let b = Committed {
            t: sys.time,
            x: layout.iter().map(|l| l.3).collect(),
            rate: layout.iter().map(|l| l.4).collect(),
        };
        self.base = Some(b.clone());
        b
    }

    /// The residual of every state's equation at unknowns `z` from `base` (writing the
    /// state values the expressions read into `sys`), into `r`.
    fn residual(
        &mut self,
        sys: &mut System,
        base: &Committed,
        z: &[f64],
        r: &mut [f64],
    ) -> Result<(), MbdError> {
        let layout = self.layout();
        let h = sys.time - base.t;
        let channels = self.channels;
        let values = &mut sys.measures.states;
        if values.len() != channels {
            values.resize(channels, 0.0);
        }
        // The states and rates the unknowns stand for.
        for (k, &(xc, rc, held, ..)) in layout.iter().enumerate() {
            let (x, rate) = match self.mode {
                Mode::Dynamic => (base.x[k] + 0.5 * h * (base.rate[k] + z[k]), z[k]),
                Mode::Static if held => (base.x[k], 0.0),
                Mode::Static => (z[k], 0.0),
            };
            values[xc] = x;
            values[rc] = rate;
        }
        // The linear systems' inputs, then outputs.
        let mut slots = std::mem::take(&mut self.slots);
        for l in &self.linear {
            let (n, m, p) = (l.sys.n, l.sys.m, l.sys.p);
            for (j, e) in l.inputs.iter().enumerate() {
                let u = value(e, sys, &mut slots).map_err(|why| {
                    MbdError::State(format!(
                        "{}: input {} (VARIABLE/{}): {why}",
                        l.sys.label,
                        j + 1,
                        l.sys.inputs[j]
                    ))
                });
                let u = match u {
                    Ok(u) => u,
                    Err(e) => {
                        self.slots = slots;
                        return Err(e);
                    }
                };
                sys.measures.states[l.base + 2 * n + j] = u;
            }
            let v = &mut sys.measures.states;
            for i in 0..p {
                let mut y = 0.0;
                for j in 0..n {
                    y += l.sys.c[i * n + j] * v[l.base + j];
                }
                for j in 0..m {
                    y += l.sys.d[i * m + j] * v[l.base + 2 * n + j];
                }
                v[l.base + 2 * n + m + i] = y;
            }
        }
        let nd = self.diffs.len();
        for (k, d) in self.diffs.iter().enumerate() {
            let held = self.mode == Mode::Static && d.static_hold;
            if held {
                r[k] = z[k] - base.x[k];
                continue;
            }
            let f = match value(&d.f, sys, &mut slots) {
                Ok(f) => f,
                Err(why) => {
                    self.slots = slots;
                    return Err(MbdError::State(format!("{}: {why}", d.label)));
                }
            };
            let rate = sys.measures.states[2 * k + 1];
            r[k] = if d.implicit { f } else { f - rate };
        }
        self.slots = slots;
        let mut k = nd;
        let v = &sys.measures.states;
        for l in &self.linear {
            let (n, m) = (l.sys.n, l.sys.m);
            for i in 0..n {
                if self.mode == Mode::Static && l.sys.static_hold {
                    r[k] = z[k] - base.x[k];
                    k += 1;
                    continue;
                }
                let mut f = 0.0;
                for j in 0..n {
                    f += l.sys.a[i * n + j] * v[l.base + j];
                }
                for j in 0..m {
                    f += l.sys.b[i * m + j] * v[l.base + 2 * n + j];
                }
                r[k] = f - v[l.base + n + i];
                k += 1;
            }
        }
        Ok(())
    }

    /// Solves the states at `sys`'s current (q, v, t) in the current [`Mode`], and
    /// writes their values (x, ẋ, the linear systems' u and y) where the measures read
    /// them. Nothing to do without states, or [`StateSet::frozen`].
    pub fn solve(&mut self, sys: &mut System) -> Result<(), MbdError> {
        if self.is_empty() || self.frozen {
            return Ok(());
        }
        let base = self.committed_or_start(sys);
        let n = self.len();
        if self.z.len() != n {
            self.z = match self.mode {
                Mode::Dynamic => base.rate.clone(),
                Mode::Static => base.x.clone(),
            };
        }
        let mut z = std::mem::take(&mut self.z);
        let result = self.newton(sys, &base, &mut z);
        self.z = z;
        result
    }

    /// Newton on the unknowns `z` (left at the solution, its values written).
    fn newton(
        &mut self,
        sys: &mut System,
        base: &Committed,
        z: &mut [f64],
    ) -> Result<(), MbdError> {
        let n = z.len();
        let (mut r, mut rp) = (vec![0.0; n], vec![0.0; n]);
        let mut jac = DMat::zeros(n, n);
        for _ in 0..MAX_ITERATIONS {
            self.residual(sys, base, z, &mut r)?;
            for c in 0..n {
                let step = FD_STEP * z[c].abs().max(1.0);
                let keep = z[c];
                z[c] = keep + step;
                self.residual(sys, base, z, &mut rp)?;
                z[c] = keep;
                for i in 0..n {
                    jac[(i, c)] = (rp[i] - r[i]) / step;
                }
            }
            let rhs = DVec::from_iterator(n, r.iter().map(|v| -v));
            let Some(dz) = jac.clone().lu().solve(&rhs) else {
                let worst = (0..n)
                    .max_by(|&a, &b| r[a].abs().total_cmp(&r[b].abs()))
                    .unwrap_or(0);
                let what = match self.mode {
                    Mode::Dynamic => "its equation cannot be solved for its rate (singular Jacobian)",
                    Mode::Static => {
                        "statics cannot fix its state from ẋ = 0 (its equation does not depend on it): give it STATIC_HOLD"
                    }
                };
                // Restore the values of the unknowns as they stand.
                self.residual(sys, base, z, &mut r)?;
                return Err(self.failure(worst, what));
            };
            let mut converged = true;
            for (zi, d) in z.iter_mut().zip(dz.iter()) {
                if !d.is_finite() {
                    converged = false;
                    break;
                }
                converged &= d.abs() <= CONVERGED * (1.0 + zi.abs());
                *zi += d;
            }
            if converged {
                return self.residual(sys, base, z, &mut r);
            }
        }
        self.residual(sys, base, z, &mut r)?;
        let worst = (0..n)
            .max_by(|&a, &b| r[a].abs().total_cmp(&r[b].abs()))
            .unwrap_or(0);
        Err(self.failure(
            worst,
            &format!("its equation did not converge in {MAX_ITERATIONS} Newton iterations"),
        ))
    }

    /// Makes the states at `sys`'s current (accepted) state the committed ones: their
    /// values from a solve in the current mode, their rates from the run's equations
    /// there (a statics' equilibrium commits its states with the rates a run starts
    /// from).
    pub fn commit(&mut self, sys: &mut System) -> Result<(), MbdError> {
        if self.is_empty() {
            return Ok(());
        }
        self.solve(sys)?;
        let layout = self.layout();
        let old = self.committed_or_start(sys);
        let x: Vec<f64> = layout.iter().map(|l| sys.measures.states[l.0]).collect();
        let rate: Vec<f64> = layout.iter().map(|l| sys.measures.states[l.1]).collect();
        let h = sys.time - old.t;
        if h > 0.0 {
            self.previous = Some((old.rate.clone(), h));
        }
        let mode = std::mem::take(&mut self.mode);
        self.base = Some(Committed {
            t: sys.time,
            x,
            rate: rate.clone(),
        });
        // The rates at the new base, from the run's equations (h = 0: x stays).
        self.z = rate;
        let solved = self.solve(sys);
        self.mode = mode;
        solved?;
        if let Some(b) = &mut self.base {
            b.rate.clone_from(&self.z);
        }
        if self.mode == Mode::Static {
            self.z.clear();
        }
        Ok(())
    }

    /// The trapezoidal rule's local error of the step from the committed states to
    /// `sys`'s current (candidate) state over the tolerance ERROR·max(1, |x|), its
    /// largest ratio (0 without states): h³/12·|x⃛| with x⃛ from the divided
    /// differences of ẋ over this step and the one before; on a first step, with none
    /// before, h/2·|ẋₙ₊₁ − ẋₙ| (the difference from Euler's, an over-estimate).
    pub fn local_error(&mut self, sys: &mut System, error: f64) -> Result<f64, MbdError> {
        if self.is_empty() || self.mode == Mode::Static {
            return Ok(0.0);
        }
        self.solve(sys)?;
        let base = self.committed_or_start(sys);
        let h = sys.time - base.t;
        if h <= 0.0 {
            return Ok(0.0);
        }
        let layout = self.layout();
        let mut worst: f64 = 0.0;
        for (k, l) in layout.iter().enumerate() {
            let (x, r1, r0) = (
                sys.measures.states[l.0],
                sys.measures.states[l.1],
                base.rate[k],
            );
            let est = match &self.previous {
                Some((rates, hp)) => {
                    let third = 2.0 * ((r1 - r0) / h - (r0 - rates[k]) / hp) / (h + hp);
                    h * h * h / 12.0 * third.abs()
                }
                None => 0.5 * h * (r1 - r0).abs(),
            };
            let tol = error * x.abs().max(base.x[k].abs()).max(1.0);
            worst = worst.max(est / tol);
        }
        Ok(worst)
    }
}
