//! DOP853 on the joint coordinates of a planar tree ([`super::tree::JointTree`]): the ODE
//! y = (θ, θ̇), ẏ = (θ̇, θ̈), integrated with the same tableau, estimate and continuous
//! extension as the Cartesian form, where every state places the parts on the position
//! constraints by construction. [`super::Dopri853`] switches to it when the model is such
//! a tree.

use super::dense_output::{Extension, A_EXTRA, C_EXTRA, END, EXTENDED};
use super::error_estimate::estimate;
use super::tableau::{A, B, C, STAGES};
use super::tree::JointTree;
use crate::mbd::dynamics::failure::DynError;
use crate::mbd::dynamics::integrator::{Attempt, Settings};
use crate::mbd::dynamics::setup::Dynamics;

/// DOP853 on the joint coordinates of a planar tree: the ODE y = (θ, θ̇), ẏ = (θ̇, θ̈).
pub(super) struct Joints {
    pub(super) tree: JointTree,
    /// The accepted y and θ̈ there; the candidate's. (The Cartesian accelerations and
    /// multipliers of `Dynamics` are solved before outputs only.)
    pub(super) y0: Vec<f64>,
    pub(super) a0: Vec<f64>,
    pub(super) y1: Vec<f64>,
    pub(super) a1: Vec<f64>,
    /// The stages' slopes, a stage's y, and per-coordinate error scales.
    k: Vec<Vec<f64>>,
    y: Vec<f64>,
    /// Per-coordinate error scales and the ERROR they are for.
    tol: Vec<f64>,
    tol_error: f64,
    /// The continuous extension of the last step with an output inside it (or of the
    /// last candidate across a switch), and the y it starts from.
    dense: Extension,
    dense_from: Vec<f64>,
}

impl Joints {
    /// The joint form of `tree` from `d`'s consistent state (at the tree's origin).
    pub(super) fn start(mut tree: JointTree, d: &mut Dynamics) -> Result<Joints, DynError> {
        let f = tree.coordinates();
        let mut y0 = vec![0.0; 2 * f];
        let mut a0 = vec![0.0; f];
        let (theta, rate) = y0.split_at_mut(f);
        tree.rates_at_start(d, rate)?;
        tree.accelerations(d, (theta, rate, d.sys.time), &mut a0, false)?;
        // The Cartesian accelerations and multipliers at the start, for the outputs.
        d.solve_accelerations()?;
        Ok(Joints {
            tree,
            y1: y0.clone(),
            a1: a0.clone(),
            y0,
            a0,
            k: vec![vec![0.0; 2 * f]; EXTENDED],
            y: vec![0.0; 2 * f],
            tol: Vec::new(),
            tol_error: f64::NAN,
            dense: Extension::default(),
            dense_from: Vec::new(),
        })
    }

    /// The continuous extension of the step of `h` from `t0` just accepted (its start in
    /// `y1` now, its end in `y0`): the end's slope, the three extra stages, the rows.
    pub(super) fn extend(&mut self, d: &mut Dynamics, h: f64, t0: f64) -> Result<(), DynError> {
        let f = self.tree.coordinates();
        let (dy, dv) = self.k[END].split_at_mut(f);
        dy.copy_from_slice(&self.y0[f..]);
        dv.copy_from_slice(&self.a0);
        // The stages start from the step's start: y0 and y1 trade places meanwhile.
        std::mem::swap(&mut self.y0, &mut self.y1);
        let mut full = true;
        let mut outcome = Ok(());
        for (e, s) in (END + 1..EXTENDED).enumerate() {
            if !self.combine(A_EXTRA[e], h) {
                full = false;
                break;
            }
            outcome = self.slope(d, s, t0 + C_EXTRA[e] * h);
            if outcome.is_err() {
                break;
            }
        }
        std::mem::swap(&mut self.y0, &mut self.y1);
        outcome?;
        let (y0, y1, k) = (&self.y0, &self.y1, &self.k);
        self.dense
            .fill(2 * f, h, full, |i| y0[i] - y1[i], |j, i| k[j][i]);
        self.dense_from.clone_from(&self.y1);
        Ok(())
    }

    /// The continuous extension of the candidate just attempted, a step of `h` from `t0`
    /// that error control accepted (its end in `y1`, θ̈ there in `a1`); false when a
    /// stage could not be evaluated.
    pub(super) fn extend_candidate(&mut self, d: &mut Dynamics, h: f64, t0: f64) -> bool {
        let f = self.tree.coordinates();
        let (dy, dv) = self.k[END].split_at_mut(f);
        dy.copy_from_slice(&self.y1[f..]);
        dv.copy_from_slice(&self.a1);
        for (e, s) in (END + 1..EXTENDED).enumerate() {
            if !self.combine(A_EXTRA[e], h) || self.slope(d, s, t0 + C_EXTRA[e] * h).is_err() {
                return false;
            }
        }
        let (y0, y1, k) = (&self.y0, &self.y1, &self.k);
        self.dense
            .fill(2 * f, h, true, |i| y1[i] - y0[i], |j, i| k[j][i]);
        self.dense_from.clone_from(&self.y0);
        true
    }

    /// Places `d` at the continuous extension's state at `s` (of the step), time `t`.
    pub(super) fn dense_state(&mut self, d: &mut Dynamics, s: f64, t: f64) {
        let f = self.tree.coordinates();
        for i in 0..2 * f {
            self.y[i] = self.dense_from[i] + self.dense.at(i, s);
        }
        let (theta, rate) = self.y.split_at(f);
        self.tree.place(d, theta, rate, t);
    }

    /// Sets stage `s`'s slope from the state in `self.y` at time `t`.
    fn slope(&mut self, d: &mut Dynamics, s: usize, t: f64) -> Result<(), DynError> {
        let f = self.tree.coordinates();
        let (theta, rate) = self.y.split_at(f);
        let (dy, dv) = self.k[s].split_at_mut(f);
        dy.copy_from_slice(rate);
        self.tree.accelerations(d, (theta, rate, t), dv, true)
    }

    /// `self.y` = y₀ + h·Σⱼ wⱼ·kⱼ; false when it is not finite.
    fn combine(&mut self, w: &[(usize, f64)], h: f64) -> bool {
        for i in 0..self.y.len() {
            let sum: f64 = w.iter().map(|&(j, a)| a * self.k[j][i]).sum();
            self.y[i] = self.y0[i] + h * sum;
        }
        self.y.iter().all(|x| x.is_finite())
    }

    /// One step of `h` from the accepted state: the stages, the estimate, and θ̈ at a
    /// candidate error control accepts (the next step's first stage). The Cartesian
    /// accelerations and multipliers are not solved: an output row that reads them
    /// reconciles, which solves them afresh (`session::run`'s `Outputs::row`).
    pub(super) fn attempt(
        &mut self,
        d: &mut Dynamics,
        h: f64,
        st: &Settings,
    ) -> Result<Attempt, DynError> {
        let f = self.tree.coordinates();
        if self.tol_error != st.error || self.tol.len() != 2 * f {
            self.tol_error = st.error;
            self.tol = (0..2 * f)
                .map(|i| match self.tree.rotational(i % f) {
                    true => st.error,
                    false => st.error * d.sys.length,
                })
                .collect();
        }
        let t0 = d.sys.time;
        let (dy, dv) = self.k[0].split_at_mut(f);
        dy.copy_from_slice(&self.y0[f..]);
        dv.copy_from_slice(&self.a0);
        for s in 1..STAGES {
            if !self.combine(A[s], h) {
                return Ok(Attempt::Diverged);
            }
            self.slope(d, s, t0 + C[s] * h)?;
        }
        if !self.combine(&B, h) {
            return Ok(Attempt::Diverged);
        }
        let (err, worst) = estimate(self.tol.len(), |i| self.tol[i], |j, i| self.k[j][i], h);
        // The column of the part the worst coordinate moves, for a step-size failure.
        let worst = 3 * self.tree.child(worst % f) + 2;
        self.y1.copy_from_slice(&self.y);
        let (theta, rate) = self.y1.split_at(f);
        if err <= 1.0 || st.fixed_step.is_some() {
            // θ̈ at the candidate: the next step's first stage.
            self.tree
                .accelerations(d, (theta, rate, t0 + h), &mut self.a1, false)?;
        } else {
            // The state alone, for the switches the driver reads.
            self.tree.place(d, theta, rate, t0 + h);
        }
        Ok(Attempt::Converged { err, worst })
    }
}
