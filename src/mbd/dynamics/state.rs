//! The state of the dynamics: saved and restored as a [`Snapshot`] (poses, velocities,
//! time), moved by an increment in the velocity layout and measured back
//! ([`Dynamics::increment`]), its scale for error control, and the accelerations stored
//! into the parts; with the vector helpers the integrators share ([`copy_into`],
//! [`zero_into`], [`largest_magnitude`]).

use super::setup::Dynamics;
use crate::mbd::system::{Dimension, PartHandle};
use crate::vocab::math::{DVec, Quat, Vec3};

/// A saved configuration: each part's pose, and the velocities.
#[derive(Clone, Debug)]
pub struct Snapshot {
    pub(super) poses: Vec<(Vec3, Quat, f64)>,
    pub(super) v: DVec,
    pub(super) time: f64,
}

/// `x` made a copy of `from`, reallocated only when the length differs (nalgebra's
/// resize always reallocates).
pub(super) fn copy_into(x: &mut DVec, from: &[f64]) {
    if x.len() == from.len() {
        x.copy_from_slice(from);
    } else {
        *x = DVec::from_column_slice(from);
    }
}

/// `x` made `n` zeros, reallocated only when the length differs.
pub(super) fn zero_into(x: &mut DVec, n: usize) {
    if x.len() == n {
        x.fill(0.0);
    } else {
        *x = DVec::zeros(n);
    }
}

/// max |xₖ|, NaN entries skipped (a branch-free select; the corrections it measures are
/// finite, as the solve rejects anything else).
pub(super) fn largest_magnitude(x: &[f64]) -> f64 {
    x.iter().fold(0.0, |m: f64, v| {
        let a = v.abs();
        if a > m {
            a
        } else {
            m
        }
    })
}

impl Dynamics {
    /// The current poses, velocities and time.
    pub fn snapshot(&self) -> Snapshot {
        Snapshot {
            poses: self.sys.snapshot(),
            v: self.sys.v(),
            time: self.sys.time,
        }
    }

    /// Returns to a [`Snapshot`].
    pub fn restore(&mut self, s: &Snapshot) {
        self.sys.restore(&s.poses);
        self.sys.set_v(&s.v);
        self.sys.time = s.time;
    }

    /// Sets the configuration to `base` moved by the increment `dx` (velocity layout:
    /// δr and a rotation vector, global), and the velocities to `v`.
    pub fn set_state(&mut self, base: &Snapshot, dx: &[f64], v: &DVec, time: f64) {
        self.sys.set_moved(&base.poses, dx);
        self.sys.set_v(v);
        self.sys.time = time;
    }

    /// The increment that takes `from` to `to` (velocity layout: δr and the global
    /// rotation vector of R_to·R_fromᵀ in 3D, δx, δy, δθ in 2D) into `out`: the inverse
    /// of [`Dynamics::set_state`]'s move, the chart the multistep methods work in.
    pub fn increment(&self, from: &Snapshot, to: &Snapshot, out: &mut [f64]) {
        let bs = self.sys.dim.cols();
        let (a, b, _) = self.sys.plane_axes();
        for (p, (f, t)) in self.sys.parts.iter().zip(from.poses.iter().zip(&to.poses)) {
            let Some(i) = p.index else { continue };
            let d = &mut out[i * bs..(i + 1) * bs];
            let dr = t.0 - f.0;
            match self.sys.dim {
                Dimension::Three => {
                    let th = (t.1 * f.1.inverse()).scaled_axis();
                    d.copy_from_slice(&[dr[0], dr[1], dr[2], th[0], th[1], th[2]]);
                }
                Dimension::Two => d.copy_from_slice(&[dr[a], dr[b], t.2 - f.2]),
            }
        }
    }

    /// The size of the coordinates: the largest part position component, at least the
    /// model length (their rounding is the floor of every Newton correction).
    pub fn reach(&self) -> f64 {
        self.sys
            .parts
            .iter()
            .map(|p| largest_magnitude(p.r.as_slice()))
            .fold(self.sys.length, f64::max)
    }

    /// Per-column scale of the local error: ERROR × the model length for translations,
    /// ERROR for rotations.
    pub fn tolerances(&self, error: f64) -> Vec<f64> {
        (0..self.n).map(|c| self.tolerance(c, error)).collect()
    }

    /// Column `c`'s scale of the local error ([`Dynamics::tolerances`]).
    pub fn tolerance(&self, c: usize, error: f64) -> f64 {
        match c % self.sys.dim.cols() < self.sys.dim.axes() {
            true => error * self.sys.length,
            false => error,
        }
    }

    /// Copies the accelerations into the parts (for acceleration measures and outputs).
    pub fn store_accelerations(&mut self) {
        for h in 1..self.sys.parts.len() {
            let ph = PartHandle(h as u32);
            let mut acc = [0.0; 6];
            for (c, x) in acc.iter_mut().enumerate() {
                if let Some(col) = self.sys.col(ph, c) {
                    *x = self.a[col];
                }
            }
            let p = self.sys.part_mut(ph);
            p.acc = Vec3::new(acc[0], acc[1], acc[2]);
            p.alpha = Vec3::new(acc[3], acc[4], acc[5]);
        }
    }
}
