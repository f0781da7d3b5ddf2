//! The kinematic analysis' own steps between solved times ([`advance_to`]). Each step
//! predicts the positions by the last solution's Taylor polynomial,
//! q + v·h + a·h²/2, and solves Φ(q, t + h) = 0 by Newton from there down to rounding
//! ([`Dynamics::project_positions`]); velocities, accelerations and reactions follow
//! ([`Dynamics::reconcile`]), and the state elements integrate over the step (the
//! trapezoidal rule). A fully driven model takes the Φ_q path instead
//! ([`super::driven`], its prediction a Hermite cubic whose error grows as h⁴). The
//! step is chosen from the prediction's own error, the
//! difference between the predicted and the solved positions against ERROR (the
//! KINEMATICS statement's, per column: ERROR × the model length for translations,
//! ERROR for rotations): that error grows as h³ (h⁴), so the next step is
//! h·0.9·(ERROR/err)^(1/3) (^(1/4)), at most four times the last and at least a fifth of it,
//! and a step whose prediction misses by more than ERROR is taken again shorter (a
//! far prediction can land Newton on another assembly branch). A step whose Newton
//! does not contract is halved and retried. Steps stop at each solved time, never past
//! HMAX, and never turn a part by more than 30° (Adams' ALIMIT default), so that angle
//! measures unwrap unambiguously. Below the smallest step the analysis stops: at a
//! lock-up or singular position, named ([`super::lock_up`]), or else with the
//! positions unsolved.

use super::driven::{Driven, Failed, SOLVED};
use super::error::KinematicsError;
use super::lock_up;
use crate::mbd::dynamics::{DynError, Dynamics, Singularity};
use crate::vocab::math::DVec;

/// The largest rotation of a part over one step (rad): Adams' ALIMIT default, 30°.
const ALIMIT: f64 = std::f64::consts::PI / 6.0;

/// The smallest step, relative to the larger of 1 and the time reached.
const HMIN_RELATIVE: f64 = 1e-10;

/// What the KINEMATICS statement sets for the steps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// The largest step (HMAX); None: only the solved times and the prediction bound
    /// it.
    pub hmax: Option<f64>,
    /// How far the prediction may miss the solution (ERROR), scaled per column.
    pub error: f64,
    /// Solve accelerations and multipliers at every step (false: the outputs read
    /// neither, and a fully driven model solves positions and velocities only).
    pub motion: bool,
}

impl Default for Settings {
    /// Adams' KINEMATICS defaults: ERROR = 1e-4; HMAX, the output step there, left to
    /// the prediction here.
    fn default() -> Self {
        Settings {
            hmax: None,
            error: 1e-4,
            motion: true,
        }
    }
}

/// The step control of one kinematic stretch: its settings and the step the last
/// prediction asks for next.
pub struct Control {
    /// The statement's settings.
    pub settings: Settings,
    /// The next step to try (infinite before the first: the solved time bounds it).
    next: f64,
    /// The Φ_q path of a fully driven model ([`Driven`]), once the first step has
    /// looked whether the model qualifies.
    driven: Option<Option<Driven>>,
}

impl Control {
    /// A stretch's control under `settings`.
    pub fn new(settings: Settings) -> Control {
        Control {
            settings,
            next: f64::INFINITY,
            driven: None,
        }
    }
}

/// Advances `d` from its solved time to time `t` in steps of its own (`control`),
/// solving positions, velocities, accelerations, reactions and state elements at
/// each; `d` ends solved at `t`. Counts steps and rejected attempts in `d.stats`.
pub fn advance_to(d: &mut Dynamics, t: f64, control: &mut Control) -> Result<(), KinematicsError> {
    let hmax = control.settings.hmax.unwrap_or(f64::INFINITY);
    let driven = control
        .driven
        .get_or_insert_with(|| Driven::new(d, control.settings.motion));
    while d.sys.time < t {
        let remaining = t - d.sys.time;
        let mut h = control.next.min(hmax);
        // A sliver left before the solved time would be a step of its own: stretch to it.
        if remaining <= 1.1 * h && remaining <= hmax {
            h = remaining;
        }
        let hmin = HMIN_RELATIVE * d.sys.time.abs().max(1.0);
        let base = (d.snapshot(), d.a.clone(), d.lambda.clone());
        let (v0, t0) = (d.sys.v(), d.sys.time);
        let (result, order) = match driven.as_mut() {
            Some(dr) => {
                let order = dr.prepare(d, &base.0);
                h = within_alimit(d, h, |c, h| dr.increment(c, h));
                (dr.attempt(d, h, control.settings.error), order)
            }
            None => {
                let (v, a) = (&v0, &d.a);
                let taylor =
                    |c: usize, h: f64| v[c] * h + 0.5 * a.get(c).copied().unwrap_or(0.0) * h * h;
                h = within_alimit(d, h, taylor);
                (attempt(d, h, control.settings.error), 3)
            }
        };
        let miss = match result {
            Ok(err) => {
                d.stats.steps += 1;
                d.stats.last_step = h;
                // Never below the smallest step: steps shrinking towards a singular
                // position reach it, and fail there, in finitely many.
                control.next = (h * growth(err, order)).max(hmin);
                if let Some(dr) = driven.as_mut() {
                    dr.solved_from(base.0, v0, t0);
                }
                continue;
            }
            Err(miss) => miss,
        };
        d.restore(&base.0);
        (d.a, d.lambda) = (base.1, base.2);
        d.forces.states.hold();
        d.stats.rejected += 1;
        control.next = match &miss {
            Failed::Far(err) => h * growth(*err, order),
            Failed::Newton(_) | Failed::Other(_) => 0.5 * h,
        };
        if control.next < hmin {
            return Err(stop(d, miss, h));
        }
    }
    Ok(())
}

/// The next step over this one for a prediction whose miss, `err` ERRORs, grows as
/// h^`order`.
fn growth(err: f64, order: i32) -> f64 {
    (0.9 * err.max(1e-12).powf(-1.0 / order as f64)).clamp(0.2, 4.0)
}

/// `h` shortened until the prediction (`increment(column, h)`) turns no part by more
/// than [`ALIMIT`].
fn within_alimit(d: &Dynamics, mut h: f64, increment: impl Fn(usize, f64) -> f64) -> f64 {
    let (cols, axes) = (d.sys.dim.cols(), d.sys.dim.axes());
    let rotation = |h: f64| {
        (0..d.n)
            .filter(|&c| c % cols >= axes)
            .map(|c| increment(c, h).abs())
            .fold(0.0, f64::max)
    };
    for _ in 0..8 {
        let turn = rotation(h);
        if turn <= ALIMIT {
            break;
        }
        h *= 0.95 * ALIMIT / turn;
    }
    h
}

/// One step of `h` from where `d` stands: Ok with the prediction's miss in ERRORs
/// (at most one), `d` solved at the step's end; else why not, `d` left anywhere.
fn attempt(d: &mut Dynamics, h: f64, error: f64) -> Result<f64, Failed> {
    let v = d.sys.v();
    let dx: Vec<f64> = (0..d.n)
        .map(|c| v[c] * h + 0.5 * d.a.get(c).copied().unwrap_or(0.0) * h * h)
        .collect();
    d.sys.apply_increment(&dx);
    d.sys.time += h;
    let predicted = d.snapshot();
    // The state elements integrate over the step: the trapezoidal rule from the last
    // solved time, the formula of every evaluation that follows.
    d.forces.states.trapezoidal_to(d.sys.time);
    // To rounding: the projection stops at the coordinates' rounding floor, or where a
    // fresh factorization no longer contracts.
    let floor = 2.0 * f64::EPSILON * d.reach() / d.sys.length;
    d.project_positions(floor).map_err(classify)?;
    let residual = (0..d.m)
        .filter(|&r| {
            let (e, q) = d.rows[r];
            !d.sys.row_reads_velocity(e, q)
        })
        .map(|r| d.scaled_residual(r))
        .fold(0.0, f64::max);
    if residual.is_nan() || residual > SOLVED {
        return Err(Failed::Newton(DynError::Newton {
            time: d.sys.time,
            step: h,
            culprit: d.worst_row(),
        }));
    }
    let err = miss(d, &predicted, error);
    if err > 1.0 {
        return Err(Failed::Far(err));
    }
    d.reconcile().map_err(classify)?;
    d.commit_measures();
    d.commit_states().map_err(|e| Failed::Other(e.into()))?;
    Ok(err)
}

/// How far the solved positions are from `predicted`, in ERRORs (the largest column).
fn miss(d: &Dynamics, predicted: &crate::mbd::dynamics::Snapshot, error: f64) -> f64 {
    let mut diff = DVec::zeros(d.n);
    d.increment(predicted, &d.snapshot(), diff.as_mut_slice());
    let tolerances = d.tolerances(error);
    (0..d.n)
        .map(|c| diff[c].abs() / tolerances[c])
        .fold(0.0, f64::max)
}

/// A failure a shorter step may cure (Newton, a singular matrix) apart from the rest.
fn classify(e: DynError) -> Failed {
    match e {
        DynError::Newton { .. } | DynError::Singular { .. } | DynError::NotFinite { .. } => {
            Failed::Newton(e)
        }
        _ => Failed::Other(e),
    }
}

/// Why the analysis stops where `d` stands (its last solved time), the step `h` failing
/// for `miss`: a lock-up when the constraints lose rank here, else the failure itself.
fn stop(d: &mut Dynamics, miss: Failed, h: f64) -> KinematicsError {
    if let Some(l) = lock_up::diagnose(d) {
        return KinematicsError::LockUp(Box::new(l));
    }
    match miss {
        Failed::Other(e) => KinematicsError::Dynamics(e),
        Failed::Newton(DynError::Singular {
            why: Singularity::Numerical | Singularity::Dependent,
            culprit,
            ..
        })
        | Failed::Newton(DynError::Newton { culprit, .. }) => KinematicsError::Unsolved {
            time: d.sys.time,
            step: h,
            culprit,
        },
        Failed::Newton(e) => KinematicsError::Dynamics(e),
        Failed::Far(_) => KinematicsError::Unsolved {
            time: d.sys.time,
            step: h,
            culprit: None,
        },
    }
}
