//! The continuous extensions that place the dynamics inside a step: the Newmark family's
//! cubic [`Hermite`] interpolant, and the quadratic [`Taylor`] extension of an accepted
//! state the driver aims at a force law's switch with. Both move positions in the chart
//! of the step's start ([`Dynamics::increment`], [`super::rotation_chart`]).

use super::rotation_chart::{angular_velocity, rotation_vector_rate};
use super::setup::Dynamics;
use super::state::Snapshot;
use crate::mbd::system::Dimension;
use crate::vocab::math::{DVec, Vec3};

/// The cubic Hermite interpolant of a step (the Newmark family's extension): positions in
/// the chart of the step's start ([`Dynamics::increment`]) through 0 and the end's
/// increment with the chart rates at both ends (v, and for 3D rotations
/// θ̇ = J_l(θ)⁻¹·ω), velocities from its derivative. Third order in positions where the
/// Newmark family is second.
#[derive(Default)]
pub struct Hermite {
    start: Option<Snapshot>,
    h: f64,
    /// The end's increment and the chart rates at the start and at the end.
    x1: Vec<f64>,
    r0: Vec<f64>,
    r1: Vec<f64>,
    /// Scratch: the interpolated increment and velocities.
    x: Vec<f64>,
    v: DVec,
}

impl Hermite {
    /// The interpolant of the step of `h` from `start` (velocities `v0`) to `end`
    /// (velocities `v1`).
    pub fn fill(
        &mut self,
        d: &Dynamics,
        start: &Snapshot,
        end: &Snapshot,
        (v0, v1): (&DVec, &DVec),
        h: f64,
    ) {
        let n = v0.len();
        self.x1.resize(n, 0.0);
        d.increment(start, end, &mut self.x1);
        self.r0.clear();
        self.r0.extend_from_slice(v0.as_slice());
        self.r1.clear();
        self.r1.extend_from_slice(v1.as_slice());
        if d.sys.dim == Dimension::Three {
            for (r, x) in self.r1.chunks_exact_mut(6).zip(self.x1.chunks_exact(6)) {
                let theta = Vec3::new(x[3], x[4], x[5]);
                let w = Vec3::new(r[3], r[4], r[5]);
                r[3..6].copy_from_slice(rotation_vector_rate(theta, w).as_slice());
            }
        }
        self.start = Some(start.clone());
        self.h = h;
    }

    /// Moves `d` to the interpolant's state at `t` (inside the step).
    pub fn place(&mut self, d: &mut Dynamics, t: f64) {
        let Some(start) = self.start.as_ref() else {
            return;
        };
        let h = self.h;
        let s = ((t - start.time) / h).clamp(0.0, 1.0);
        let (s2, s3) = (s * s, s * s * s);
        // Hermite's basis (the start's increment is 0) and its derivative in s.
        let (h10, h01, h11) = (s3 - 2.0 * s2 + s, 3.0 * s2 - 2.0 * s3, s3 - s2);
        let (d10, d01, d11) = (
            3.0 * s2 - 4.0 * s + 1.0,
            6.0 * s - 6.0 * s2,
            3.0 * s2 - 2.0 * s,
        );
        let n = self.x1.len();
        self.x.resize(n, 0.0);
        if self.v.len() != n {
            self.v = DVec::zeros(n);
        }
        for i in 0..n {
            let (x1, r0, r1) = (self.x1[i], self.r0[i], self.r1[i]);
            self.x[i] = h10 * h * r0 + h01 * x1 + h11 * h * r1;
            self.v[i] = d10 * r0 + d01 * x1 / h + d11 * r1;
        }
        if d.sys.dim == Dimension::Three {
            for (v, x) in self
                .v
                .as_mut_slice()
                .chunks_exact_mut(6)
                .zip(self.x.chunks_exact(6))
            {
                let theta = Vec3::new(x[3], x[4], x[5]);
                let rate = Vec3::new(v[3], v[4], v[5]);
                v[3..6].copy_from_slice(angular_velocity(theta, rate).as_slice());
            }
        }
        d.set_state(start, &self.x, &self.v, t);
    }
}

/// The quadratic Taylor extension of an accepted state forward in time: positions
/// x₀ + v₀·τ + ½·a₀·τ² in the chart of the state (whose rate there is (v, ω), and whose
/// second derivative (a, ω̇): the chart's curvature term ½·θ̇ × ω vanishes at θ = 0),
/// velocities v₀ + a₀·τ. It follows the force laws' present branches only, so it says
/// where one of them switches when a step across the switch says little (exact in free
/// flight under constant forces).
pub struct Taylor {
    start: Snapshot,
    a0: DVec,
    /// Scratch: the increment and the velocities.
    x: Vec<f64>,
    v: DVec,
}

impl Taylor {
    /// The extension of `d`'s state with its accelerations `d.a`.
    pub fn of(d: &Dynamics) -> Taylor {
        let start = d.snapshot();
        Taylor {
            x: vec![0.0; start.v.len()],
            v: start.v.clone(),
            a0: d.a.clone(),
            start,
        }
    }

    /// Moves `d` to the extension's state at `t`.
    pub fn place(&mut self, d: &mut Dynamics, t: f64) {
        let tau = t - self.start.time;
        for (i, x) in self.x.iter_mut().enumerate() {
            let (v0, a0) = (self.start.v[i], self.a0[i]);
            *x = tau * (v0 + 0.5 * tau * a0);
            self.v[i] = v0 + tau * a0;
        }
        d.set_state(&self.start, &self.x, &self.v, t);
    }

    /// Puts `d` back at the extended state (accelerations and multipliers were not moved).
    pub fn restore(&self, d: &mut Dynamics) {
        d.restore(&self.start);
    }
}
