//! Output times inside a step (INTERPOLATE = ON, `mbfx run --interpolate`): the driver
//! ([`super::integrator::simulate`]) steps over them by error control, and each one inside
//! an accepted step gets its state from the method's continuous extension
//! ([`super::integrator::Integrator::dense_state`]: DOP853's order-7 extension, the BDF's
//! interpolating polynomial, the Newmark family's [`Hermite`] cubic). [`emit`] makes that
//! state what an output needs: positions back on the constraints when the extension left
//! them further off than the run's drift tolerance (measured at every interpolated row,
//! [`super::Stats::interpolation_residual`]); the outputs' own consistent solve (velocities
//! projected, accelerations and multipliers) then follows as at a step's end. The
//! accepted state is put back before the next step.

use super::dopri853::rotation_vector_rate;
use super::integrator::{Integrator, OutputTimes, RowState};
use super::{DynError, Dynamics, Snapshot};
use crate::mbd::system::Dimension;
use crate::vocab::math::{DVec, Mat3, Vec3};

/// The projection's target on the largest scaled position residual, in ulps of the
/// coordinates (over the model length), as dopri853 projects its steps.
const PROJECTION_ULPS: f64 = 64.0;

/// The accepted state, kept while outputs inside the step move `d`.
pub(super) struct Kept {
    snap: Snapshot,
    a: DVec,
    lambda: DVec,
}

impl Kept {
    /// The state of `d`.
    pub(super) fn of(d: &Dynamics) -> Kept {
        Kept {
            snap: d.snapshot(),
            a: d.a.clone(),
            lambda: d.lambda.clone(),
        }
    }

    /// Puts `d` back at the kept state.
    pub(super) fn restore(&self, d: &mut Dynamics) {
        d.restore(&self.snap);
        super::copy_into(&mut d.a, self.a.as_slice());
        super::copy_into(&mut d.lambda, self.lambda.as_slice());
        d.store_accelerations();
    }
}

/// Outputs the times of `outputs` from `*next` that the step just accepted (ending at
/// `end`) reaches, all but the last (the driver lands on it): those inside the step from
/// the integrator's continuous extension, made consistent ([`consistent`]), with the
/// accepted state put back after them; one at `end` itself as the stepped outputs are.
pub(super) fn emit(
    d: &mut Dynamics,
    integrator: &mut dyn Integrator,
    outputs: &OutputTimes,
    next: &mut usize,
    drift_tol: f64,
    output: &mut dyn FnMut(&mut Dynamics, RowState) -> Result<(), DynError>,
) -> Result<(), DynError> {
    let last = outputs.len().saturating_sub(1);
    let end = d.sys.time;
    if *next < last && outputs.at(*next) < end {
        let kept = Kept::of(d);
        while *next < last && outputs.at(*next) < end {
            integrator.dense_state(d, outputs.at(*next));
            match integrator.dense_on_constraints() {
                true => d.stats.interpolated += 1,
                false => consistent(d, drift_tol)?,
            }
            output(d, RowState::Interpolated)?;
            *next += 1;
        }
        kept.restore(d);
    }
    while *next < last && outputs.at(*next) <= end {
        output(d, RowState::Stepped)?;
        *next += 1;
    }
    Ok(())
}

/// Measures the position constraints' residual at an interpolated state (into the run's
/// counters) and projects the positions back when it exceeds `drift_tol`: what a step's
/// end would hold them to. Velocities, accelerations and multipliers are the outputs'.
pub(super) fn consistent(d: &mut Dynamics, drift_tol: f64) -> Result<(), DynError> {
    d.eval_constraints(false)?;
    let worst = (0..d.m)
        .filter(|&r| {
            let (e, q) = d.rows[r];
            !d.sys.row_reads_velocity(e, q)
        })
        .map(|r| d.scaled_residual(r))
        .fold(0.0, f64::max);
    let st = &mut d.stats;
    st.interpolated += 1;
    st.interpolation_residual = st.interpolation_residual.max(worst);
    if worst > drift_tol || worst.is_nan() {
        d.stats.projected += 1;
        let target = PROJECTION_ULPS * f64::EPSILON * d.reach() / d.sys.length;
        d.project_positions(target)?;
    }
    Ok(())
}

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

/// The global angular velocity ω whose chart rate at θ is `rate`: the inverse of
/// [`rotation_vector_rate`], which is linear in ω (J_l(θ)⁻¹·ω), solved as a 3×3 system.
fn angular_velocity(theta: Vec3, rate: Vec3) -> Vec3 {
    let columns = [Vec3::x(), Vec3::y(), Vec3::z()].map(|e| rotation_vector_rate(theta, e));
    let m = Mat3::from_columns(&columns);
    // (Regular wherever the chart is: |θ| < 2π.)
    m.try_inverse().map_or(rate, |inv| inv * rate)
}

/// Lagrange weights at `tau` of the interpolant through the nodes `ts` (value only; `tau`
/// may be a node).
pub fn lagrange_weights(ts: &[f64], tau: f64, l: &mut [f64]) {
    for j in 0..ts.len() {
        l[j] = ts
            .iter()
            .enumerate()
            .filter(|&(m, _)| m != j)
            .map(|(_, &tm)| (tau - tm) / (ts[j] - tm))
            .product();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angular_velocity_inverts_the_chart_rate() {
        let w = Vec3::new(0.4, -1.1, 2.0);
        for theta in [
            Vec3::zeros(),
            Vec3::new(0.3, 0.2, -0.5),
            Vec3::new(-1.5, 1.0, 0.8),
        ] {
            let back = angular_velocity(theta, rotation_vector_rate(theta, w));
            assert!((back - w).norm() < 1e-13, "{theta:?}: {back:?}");
        }
    }

    #[test]
    fn lagrange_weights_reproduce_a_cubic_through_four_nodes() {
        let p = |t: f64| 2.0 - t + 0.5 * t * t - 0.25 * t * t * t;
        let ts = [0.0, -0.1, -0.25, -0.3];
        let mut l = [0.0; 4];
        for tau in [-0.05, -0.2, 0.0, -0.3] {
            lagrange_weights(&ts, tau, &mut l);
            let value: f64 = ts.iter().zip(&l).map(|(&t, w)| w * p(t)).sum();
            assert!((value - p(tau)).abs() < 1e-14, "{tau}: {value}");
        }
    }
}
