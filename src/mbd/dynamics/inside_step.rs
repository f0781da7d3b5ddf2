//! Output times inside a step (INTERPOLATE = ON, `mbfx run --interpolate`): the driver
//! ([`super::time_loop::simulate`]) steps over them by error control, and each one inside
//! an accepted step gets its state from the method's continuous extension
//! ([`super::integrator::Integrator::dense_state`]: DOP853's order-7 extension, the BDF's
//! interpolating polynomial, the Newmark family's [`super::step_extension::Hermite`] cubic).
//! [`emit`] makes that state what an output needs: positions back on the constraints
//! when the extension left them further off than the run's drift tolerance (measured at
//! every interpolated row, [`super::Stats::interpolation_residual`]); the outputs' own
//! consistent solve (velocities projected, accelerations and multipliers) then follows
//! as at a step's end. The accepted state is put back before the next step.

use super::failure::DynError;
use super::integrator::{Integrator, OutputTimes, RowState};
use super::setup::Dynamics;
use super::state::{copy_into, Snapshot};
use crate::vocab::math::DVec;

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
        copy_into(&mut d.a, self.a.as_slice());
        copy_into(&mut d.lambda, self.lambda.as_slice());
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

/// Times a caller records the state at, apart from the output times (an animation's
/// frames): `record` gets `d` at each, moved to the continuous extension inside a step
/// (positions, velocities and time; nothing projected or solved) or at the step's end.
pub struct FrameTimes<'a> {
    /// The times.
    pub times: OutputTimes,
    /// The first not recorded yet.
    pub next: usize,
    /// What records one.
    pub record: &'a mut dyn FnMut(&mut Dynamics) -> Result<(), DynError>,
}

impl FrameTimes<'_> {
    /// Whether a time not recorded yet lies before `end` (the step needs its extension).
    pub(super) fn inside(&self, end: f64) -> bool {
        self.next < self.times.len() && self.times.at(self.next) < end
    }
}

/// Records the frame times the step just accepted reaches: those inside it from the
/// continuous extension, the accepted state put back after them; one at its end from it.
pub(super) fn frames(
    d: &mut Dynamics,
    integrator: &mut dyn Integrator,
    f: &mut FrameTimes<'_>,
) -> Result<(), DynError> {
    let end = d.sys.time;
    if f.inside(end) {
        let kept = Kept::of(d);
        while f.inside(end) {
            integrator.dense_state(d, f.times.at(f.next));
            (f.record)(d)?;
            f.next += 1;
        }
        kept.restore(d);
    }
    while f.next < f.times.len() && f.times.at(f.next) <= end {
        (f.record)(d)?;
        f.next += 1;
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
