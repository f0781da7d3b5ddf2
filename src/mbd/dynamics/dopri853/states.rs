//! The state elements ([`crate::mbd::states`]) as extra components of DOP853's ODE: at
//! every stage their x is the stage's sum x₀ + h·Σⱼ aᵢⱼ·kⱼ, set as the formula of the
//! evaluations that follow (g = 0: x given), and their rates there are the stage's
//! slope. Their components join the error estimate (over ERROR·max(1, |x|)) and the
//! continuous extension like the positions'.

use super::dense_output::{Extension, END, EXTENDED};
use crate::mbd::dynamics::setup::Dynamics;
use crate::mbd::states::StateSet;

/// The state elements' side of the integrator.
#[derive(Default)]
pub(super) struct StateStages {
    /// x and ẋ committed at the last accepted state.
    pub(super) x0: Vec<f64>,
    r0: Vec<f64>,
    /// x at the start of the last accepted step.
    start: Vec<f64>,
    /// The stages' slopes.
    pub(super) k: Vec<Vec<f64>>,
    /// The last stage sum (the candidate's x after the final combination), and scratch.
    pub(super) y: Vec<f64>,
    rates: Vec<f64>,
    /// The continuous extension and the x it starts from.
    dense: Extension,
    from: Vec<f64>,
}

impl StateStages {
    /// How many states.
    pub(super) fn len(&self) -> usize {
        self.x0.len()
    }

    /// Takes the committed states of `d` as the next step's start (the old start kept
    /// for the accepted step's extension).
    pub(super) fn take_committed(&mut self, d: &Dynamics) {
        self.start = std::mem::take(&mut self.x0);
        self.r0.clear();
        if let Some((x, r)) = d.forces.states.committed() {
            self.x0.extend_from_slice(x);
            self.r0.extend_from_slice(r);
        }
        if self.k.len() != EXTENDED || self.k[0].len() != self.x0.len() {
            self.k = vec![vec![0.0; self.x0.len()]; EXTENDED];
        }
    }

    /// The first stage's slope: the committed rates.
    pub(super) fn first(&mut self) {
        self.k[0].clone_from(&self.r0);
    }

    /// Sets the stage x = `from` + h·Σⱼ wⱼ·kⱼ as the formula of the evaluations that
    /// follow (x₀ when `from` is None).
    pub(super) fn combine(&mut self, d: &mut Dynamics, w: &[(usize, f64)], h: f64, start: bool) {
        if self.x0.is_empty() {
            return;
        }
        let from = if start { &self.start } else { &self.x0 };
        self.y.clear();
        for (i, &x) in from.iter().enumerate() {
            let sum: f64 = w.iter().map(|&(j, a)| a * self.k[j][i]).sum();
            self.y.push(x + h * sum);
        }
        d.forces.states.set_formula(&self.y, 0.0);
    }

    /// Stage `s`'s slope: the rates the last evaluation solved.
    pub(super) fn slope(&mut self, d: &Dynamics, s: usize) {
        if self.x0.is_empty() {
            return;
        }
        let mut x = std::mem::take(&mut self.rates);
        d.forces.states.current(&d.sys, &mut x, &mut self.k[s]);
        self.rates = x;
    }

    /// The tolerance of component `i` at ERROR `error`.
    pub(super) fn tolerance(&self, i: usize, error: f64) -> f64 {
        StateSet::tolerance(self.x0[i], error)
    }

    /// The extension of the step just accepted (its end the committed states, its
    /// slopes through [`END`] and the extra stages already in `k`), `full` when the
    /// extra stages were evaluated.
    pub(super) fn extend(&mut self, h: f64, full: bool) {
        if self.x0.is_empty() || self.start.len() != self.x0.len() {
            return;
        }
        self.k[END].clone_from(&self.r0);
        let (x0, x1, k) = (&self.start, &self.x0, &self.k);
        self.dense
            .fill(x0.len(), h, full, |i| x1[i] - x0[i], |j, i| k[j][i]);
        self.from.clone_from(&self.start);
    }

    /// The extension of the candidate (its end `self.y`, its end's rates in `k[END]`).
    pub(super) fn extend_candidate(&mut self, h: f64, end: &[f64]) {
        if self.x0.is_empty() {
            return;
        }
        let (x0, k) = (&self.x0, &self.k);
        self.dense
            .fill(x0.len(), h, true, |i| end[i] - x0[i], |j, i| k[j][i]);
        self.from.clone_from(&self.x0);
    }

    /// Sets the states at fraction `s` of the extended step as the evaluations' x.
    pub(super) fn dense_state(&mut self, d: &mut Dynamics, s: f64) {
        if self.from.is_empty() || self.from.len() != self.x0.len() {
            return;
        }
        self.y.clear();
        for (i, &x) in self.from.iter().enumerate() {
            self.y.push(x + self.dense.at(i, s));
        }
        d.place_states(&self.y);
    }
}
