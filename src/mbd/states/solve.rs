//! Solving the state block at the system's current (q, v, t): the residual of every
//! state's equation as a function of the unknowns z (the rates ẋ in a run, x following
//! from them by the integrator's formula x = b + g·ẋ; the states x in statics), Newton
//! on z with a finite-difference Jacobian of the block (or, with g = 0 and every
//! equation explicit, the rates as the equations give them), and the commit of an
//! accepted state.

use super::{Committed, Mode, StateExpr, StateSet};
use crate::mbd::error::MbdError;
use crate::mbd::forces::{measure_value, Source};
use crate::mbd::system::System;
use crate::model::states::Statement;
use crate::vocab::math::{DMat, DVec};

/// Newton iterations before a state solve fails.
const MAX_ITERATIONS: usize = 30;

/// A Newton correction below this (relative to 1 + |z|) has converged.
const CONVERGED: f64 = 1e-11;

/// The relative finite-difference step of the block's Jacobian.
const FD_STEP: f64 = 1e-7;

/// Passes of the explicit rates (g = 0) before Newton takes over: more than one only
/// where an equation reads another's rate (DIF1).
const EXPLICIT_PASSES: usize = 4;

/// How x follows from the unknowns: the integrator's (b, g), or the committed x.
type Formula<'a> = (&'a [f64], f64);

/// `e`'s value at the state of `sys` and the solution values `solved`, its slots
/// filled into `slots`.
fn value(
    e: &StateExpr,
    (sys, solved): (&System, &[f64]),
    slots: &mut Vec<f64>,
) -> Result<f64, String> {
    for (&s, &m) in e.f.slots().iter().zip(&e.map) {
        let s = s as usize;
        if slots.len() <= s {
            slots.resize(s + 1, 0.0);
        }
        slots[s] = match m {
            Source::Measure(m) => measure_value(sys, m),
            Source::Solution(k) => solved.get(k).copied().unwrap_or(0.0),
        };
    }
    e.f.value(sys.time, slots).map_err(|err| err.to_string())
}

/// The Newton correction of the rates with x held (g = 0) where the block's Jacobian
/// is singular: an IMPLICIT DIFF whose FUNCTION does not read its own rate (an
/// algebraic equation, `DIF(1) − DIF(2)` = 0) fixes its x, not its ẋ, and with x held
/// nothing fixes that rate. The least-squares correction of least norm leaves such a
/// rate where it stands (the integrator's last solve of it, where x = b + g·ẋ with g > 0
/// did fix it) and corrects the others.
fn held_rates(jac: &DMat, rhs: &DVec) -> Option<DVec> {
    let svd = jac.clone().svd(true, true);
    let largest = svd.singular_values.iter().fold(0.0f64, |m, &v| m.max(v));
    svd.solve(rhs, 1e-12 * largest).ok()
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
        self.stiction_layout(&mut out);
        out
    }

    /// The states' rates ẋ as the last solve left them.
    pub fn rates(&self, sys: &System) -> Vec<f64> {
        (self.layout().iter())
            .map(|l| sys.measures.states.get(l.1).copied().unwrap_or(f64::NAN))
            .collect()
    }

    /// The committed states, made from the initial conditions the first time.
    fn committed_or_start(&mut self) -> Committed {
        if let Some(b) = &self.base {
            return b.clone();
        }
        let layout = self.layout();
        let b = Committed {
            x: layout.iter().map(|l| l.3).collect(),
            rate: layout.iter().map(|l| l.4).collect(),
        };
        self.base = Some(b.clone());
        b
    }

    /// The residual of every state's equation at unknowns `z` under `formula` (statics:
    /// `base` holds the STATIC_HOLD states), writing the state values the expressions
    /// read into `sys`, into `r`.
    fn residual(
        &mut self,
        sys: &mut System,
        (base, formula): (&Committed, Formula<'_>),
        z: &[f64],
        r: &mut [f64],
    ) -> Result<(), MbdError> {
        let layout = self.layout();
        let (b, g) = formula;
        let channels = self.channels;
        let values = &mut sys.measures.states;
        if values.len() != channels {
            values.resize(channels, 0.0);
        }
        // The states and rates the unknowns stand for.
        for (k, &(xc, rc, held, ..)) in layout.iter().enumerate() {
            let (x, rate) = match self.mode {
                Mode::Dynamic => (b[k] + g * z[k], z[k]),
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
                let u = value(e, (sys, &self.solved), &mut slots).map_err(|why| {
                    let variable = l.sys.inputs[j];
                    MbdError::State(
                        Statement::new("VARIABLE", variable),
                        format!(
                            "{}: input {} (VARIABLE/{variable}): {why}",
                            l.sys.label,
                            j + 1
                        ),
                    )
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
            let f = match value(&d.f, (sys, &self.solved), &mut slots) {
                Ok(f) => f,
                Err(why) => {
                    self.slots = slots;
                    return Err(MbdError::State(d.statement, format!("{}: {why}", d.label)));
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
        self.stiction_residual(sys, base, (k, z), r);
        Ok(())
    }

    /// Solves the states at `sys`'s current (q, v, t) in the current [`Mode`] and
    /// formula, and writes their values (x, ẋ, the linear systems' u and y) where the
    /// measures read them. Nothing to do without states, or [`StateSet::frozen`].
    pub fn solve(&mut self, sys: &mut System) -> Result<(), MbdError> {
        if self.is_empty() || self.frozen {
            return Ok(());
        }
        let base = self.committed_or_start();
        let n = self.len();
        if self.z.len() != n {
            self.z = match self.mode {
                Mode::Dynamic => base.rate.clone(),
                Mode::Static => base.x.clone(),
            };
        }
        let formula = self.formula.take();
        let (b, g) = match (&formula, self.mode) {
            (Some((b, g)), Mode::Dynamic) => (b.as_slice(), *g),
            _ => (base.x.as_slice(), 0.0),
        };
        let mut z = std::mem::take(&mut self.z);
        let explicit = self.mode == Mode::Dynamic && g == 0.0;
        let direct = match explicit && self.diffs.iter().all(|d| !d.implicit) {
            true => self.rates_directly(sys, (&base, (b, g)), &mut z),
            false => Ok(false),
        };
        let result = match direct {
            Ok(true) => Ok(()),
            Ok(false) => self.newton(sys, (&base, (b, g)), &mut z),
            Err(e) => Err(e),
        };
        self.z = z;
        self.formula = formula;
        result
    }

    /// The rates as the explicit equations give them at x fixed (g = 0), passed again
    /// while one reads another's rate; true when they settled (`z` left at them).
    fn rates_directly(
        &mut self,
        sys: &mut System,
        at: (&Committed, Formula<'_>),
        z: &mut [f64],
    ) -> Result<bool, MbdError> {
        let mut r = vec![0.0; z.len()];
        for _ in 0..EXPLICIT_PASSES {
            self.residual(sys, at, z, &mut r)?;
            let mut settled = true;
            for (zi, d) in z.iter_mut().zip(&r) {
                settled &= d.abs() <= CONVERGED * (1.0 + zi.abs());
                *zi += d;
            }
            if settled {
                self.residual(sys, at, z, &mut r)?;
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// Newton on the unknowns `z` (left at the solution, its values written).
    fn newton(
        &mut self,
        sys: &mut System,
        at: (&Committed, Formula<'_>),
        z: &mut [f64],
    ) -> Result<(), MbdError> {
        let n = z.len();
        let (mut r, mut rp) = (vec![0.0; n], vec![0.0; n]);
        let mut jac = DMat::zeros(n, n);
        for _ in 0..MAX_ITERATIONS {
            self.residual(sys, at, z, &mut r)?;
            for c in 0..n {
                let step = FD_STEP * z[c].abs().max(1.0);
                let keep = z[c];
                z[c] = keep + step;
                self.residual(sys, at, z, &mut rp)?;
                z[c] = keep;
                for i in 0..n {
                    jac[(i, c)] = (rp[i] - r[i]) / step;
                }
            }
            let rhs = DVec::from_iterator(n, r.iter().map(|v| -v));
            let held = self.mode == Mode::Dynamic && at.1 .1 == 0.0;
            let Some(dz) = jac.clone().lu().solve(&rhs).or_else(|| match held {
                true => held_rates(&jac, &rhs),
                false => None,
            }) else {
                // The state no equation depends on, if one is (the singularity's cause),
                // else the one furthest from its equation.
                let free = (0..n).find(|&c| (0..n).all(|i| jac[(i, c)] == 0.0));
                let worst = free.unwrap_or_else(|| {
                    (0..n)
                        .max_by(|&a, &b| r[a].abs().total_cmp(&r[b].abs()))
                        .unwrap_or(0)
                });
                let what = match self.mode {
                    Mode::Dynamic => "its equation cannot be solved for its rate (singular Jacobian)",
                    Mode::Static => {
                        "statics cannot fix its state from ẋ = 0 (its equation does not depend on it): give it STATIC_HOLD"
                    }
                };
                // Restore the values of the unknowns as they stand.
                self.residual(sys, at, z, &mut r)?;
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
                return self.residual(sys, at, z, &mut r);
            }
        }
        self.residual(sys, at, z, &mut r)?;
        let worst = (0..n)
            .max_by(|&a, &b| r[a].abs().total_cmp(&r[b].abs()))
            .unwrap_or(0);
        Err(self.failure(
            worst,
            &format!("its equation did not converge in {MAX_ITERATIONS} Newton iterations"),
        ))
    }

    /// Makes the states at `sys`'s current (accepted) state the committed ones: their
    /// values from a solve in the current mode and formula, their rates from the run's
    /// equations there with x held (a statics' equilibrium commits its states with the
    /// rates a run starts from). The evaluations that follow hold them.
    pub fn commit(&mut self, sys: &mut System) -> Result<(), MbdError> {
        if self.is_empty() {
            return Ok(());
        }
        self.solve(sys)?;
        let layout = self.layout();
        let x: Vec<f64> = layout.iter().map(|l| sys.measures.states[l.0]).collect();
        let rate: Vec<f64> = layout.iter().map(|l| sys.measures.states[l.1]).collect();
        let mode = std::mem::take(&mut self.mode);
        self.base = Some(Committed {
            x,
            rate: rate.clone(),
        });
        self.formula = None;
        self.committed_time = Some(sys.time);
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

    /// The unknowns of the last solve: the rates ẋ in a run.
    pub fn unknowns(&self) -> &[f64] {
        &self.z
    }

    /// The residuals of the states' equations at rates `z` under the current formula
    /// at `sys`'s current (q, v, t), into `r`, without solving (the state values the
    /// expressions read are left at `z`'s): what the integrators' Newton matrix
    /// differentiates.
    pub fn residual_of_rates(
        &mut self,
        sys: &mut System,
        z: &[f64],
        r: &mut [f64],
    ) -> Result<(), MbdError> {
        let base = self.committed_or_start();
        let formula = self.formula.take();
        let (b, g) = match &formula {
            Some((b, g)) => (b.as_slice(), *g),
            None => (base.x.as_slice(), 0.0),
        };
        let out = self.residual(sys, (&base, (b, g)), z, r);
        self.formula = formula;
        out
    }

    /// The states x and rates ẋ as the last solve left them, into `x` and `rate`
    /// (resized to the states).
    pub fn current(&self, sys: &System, x: &mut Vec<f64>, rate: &mut Vec<f64>) {
        x.clear();
        rate.clear();
        for l in self.layout() {
            x.push(sys.measures.states.get(l.0).copied().unwrap_or(f64::NAN));
            rate.push(sys.measures.states.get(l.1).copied().unwrap_or(f64::NAN));
        }
    }
}
