//! What a finished run warns about: a failed step control diagnosed as a lock-up
//! of the mechanism, and the accuracy monitors (energy, fixed steps, local errors,
//! constraint drift).

use super::{Simulation, Summary};
use crate::mbd::dynamics::DynError;
use crate::session::stopped::Stopped;

/// Relative distance of a kept row to the span of the others below which a failed run's
/// configuration counts as singular (a lock-up): the redundancy analysis' own
/// tolerance is 1e-8, for exact dependence; a run fails a little before that.
pub(super) const LOCK_UP_DISTANCE: f64 = 1e-3;

impl Simulation {
    /// A failure of the step control (the corrector diverging, the step below HMIN) at
    /// a configuration where the kept constraints are nearly dependent becomes a
    /// lock-up naming the element whose equation depends on the others; any other
    /// failure is returned as it is.
    pub(super) fn diagnose_lock_up(&self, e: Stopped) -> Stopped {
        use crate::mbd::redundancy::{analyze, Options, Problem};
        use crate::vocab::elements::ElementKind;
        let time = match e.dynamics() {
            Some(DynError::Newton { time, .. } | DynError::StepTooSmall { time, .. }) => *time,
            _ => return e,
        };
        let sys = &self.dynamics.sys;
        let Ok(jacobian) = sys.jacobian(true) else {
            return e;
        };
        let (labels, elements) = (sys.labels(), sys.element_refs());
        let dim = sys.dim.axes();
        let options = Options {
            tolerance: LOCK_UP_DISTANCE,
            conflict_tolerance: f64::INFINITY,
        };
        // The first kept row nearly dependent on the others, with the rows `skip` says
        // to leave out (indices of the full Jacobian), if any.
        let dependent = |skip: &dyn Fn(usize) -> bool| -> Option<usize> {
            let rows: Vec<usize> = (0..labels.len()).filter(|&r| !skip(r)).collect();
            let mut new_index = vec![u32::MAX; labels.len()];
            for (k, &r) in rows.iter().enumerate() {
                new_index[r] = k as u32;
            }
            let mut jac = crate::mbd::sparse::Triplets::new(rows.len(), jacobian.ncols);
            for &(r, c, v) in &jacobian.entries {
                let k = new_index[r as usize];
                if k != u32::MAX {
                    jac.push(k as usize, c as usize, v);
                }
            }
            let sub: Vec<_> = rows.iter().map(|&r| labels[r]).collect();
            let problem = Problem::new(&jac, &sub, &elements, sys.moving_parts(), dim);
            let report = analyze(&problem, &options).ok()?;
            report
                .redundant
                .iter()
                .map(|d| rows[d.row])
                .find(|r| !self.dropped.contains(r))
        };
        let Some(row) = dependent(&|_| false) else {
            return e;
        };
        // A drive whose rows, left out, leave the rest independent is what cannot move
        // the mechanism any further: name it rather than a joint of its loop.
        let drives = (0..elements.len()).filter(|&el| elements[el].kind == ElementKind::Motion);
        let culprit = drives
            .into_iter()
            .find(|&el| dependent(&|r| labels[r].element == el).is_none())
            .unwrap_or(labels[row].element);
        Stopped::from(DynError::Singular {
            time,
            why: crate::mbd::dynamics::Singularity::LockUp,
            culprit: Some(crate::mbd::dynamics::Culprit::Element(
                elements[culprit].clone(),
            )),
        })
    }
}

/// Past this many ERRORs, a fixed-step run's local error estimate makes it a warning.
pub(super) const FIXED_STEP_WARNING: f64 = 10.0;

/// Past this many ERRORs (relative to the largest kinetic energy), the energy change of
/// a conservative model makes it a warning.
pub(super) const ENERGY_WARNING: f64 = 10.0;

/// Past this many ERRORs, the global error estimate the steps carried makes a warning:
/// the bench's line between an accurate run and a wrong one (error at most 10·ERROR).
pub const GLOBAL_WARNING: f64 = 10.0;

/// Past this many ERRORs, the sum of a run's local errors makes it a warning, unless the
/// run's error is estimated.
pub const ACCUMULATED_WARNING: f64 = 10.0;

/// The warnings of a finished run (see [`Summary::warnings`]): fixed steps whose local
/// error estimate exceeded ERROR more than tenfold, local errors that add up to more than
/// ten ERRORs, a conservative model whose energy changed by more than ten ERRORs of its
/// largest kinetic energy, and a constraint residual larger than the drift the run
/// allows dropped rows (10·ERROR, at least 1e-6). When the run's error is estimated
/// (`estimated`, [`Estimate`]) the estimate judges it instead of the local errors' sum,
/// which over the work-precision bench warned 71 % of the accurate runs.
pub(super) fn monitors(
    s: &Summary,
    (fixed, driven, estimated): (bool, bool, bool),
    error: f64,
    kinetic_max: f64,
) -> Vec<String> {
    // Fully driven: the constraints fix every coordinate at every time, so no local
    // error of the integrator is the answer's (nothing is left to integrate).
    let mut w = match driven {
        true => Vec::new(),
        false => integration_warnings(s, fixed, estimated, error, kinetic_max),
    };
    let drift = (10.0 * error).max(1e-6);
    if s.max_residual > drift {
        w.push(format!(
            "the constraints drifted: residual {:.1e} exceeds {drift:.0e}",
            s.max_residual
        ));
    }
    w
}

/// The warnings about the integration's accuracy: energy, fixed steps, local errors.
pub(super) fn integration_warnings(
    s: &Summary,
    fixed: bool,
    estimated: bool,
    error: f64,
    kinetic_max: f64,
) -> Vec<String> {
    let mut w = Vec::new();
    if let Some((e0, e1)) = s.energy {
        // Against the largest kinetic energy seen at the output times: what the motion
        // trades back and forth, whatever the potential's datum.
        let scale = kinetic_max.max(e0.abs());
        if scale > 0.0 && (e1 - e0).abs() > ENERGY_WARNING * error * scale {
            w.push(format!(
                "the energy changed by {:.1e} in a conservative model, {:.1e} of the largest kinetic energy ({scale:.3e}): more than {ENERGY_WARNING}·ERROR ({error:e}), so the answer is not accurate to ERROR",
                e1 - e0,
                (e1 - e0).abs() / scale
            ));
        }
    }
    if fixed && s.stats.worst_error > FIXED_STEP_WARNING {
        w.push(format!(
            "fixed steps: the local error estimate reached {:.1e} × ERROR ({error:e}) at time {}; the results are not accurate to ERROR (use error control or a smaller step)",
            s.stats.worst_error, s.stats.worst_error_time
        ));
    }
    let over = |k: f64| k.partial_cmp(&GLOBAL_WARNING) != Some(std::cmp::Ordering::Less);
    if let Some(k) = s
        .stats
        .global_error
        .filter(|&k| over(k) && k != GLOBAL_WARNING)
    {
        w.push(format!(
            "the estimated global error reached {:.1e} ({k:.0}×ERROR, ERROR = {error:e}) at t = {}: more than {GLOBAL_WARNING}×ERROR, so the answer is not accurate to ERROR (tighten ERROR; --estimate-error=rerun checks it by a second run)",
            k * error,
            s.stats.global_error_time
        ));
    }
    if fixed || !estimated {
        w.extend(sum_warning(s, fixed, error));
    }
    w
}

/// The warning of a run whose steps' local errors add up to more than
/// [`ACCUMULATED_WARNING`] ERRORs, if they do.
pub(super) fn sum_warning(s: &Summary, fixed: bool, error: f64) -> Option<String> {
    let remedy = if fixed {
        "use error control or a smaller step"
    } else {
        "ERROR bounds each step, as in Adams; --estimate-error estimates the answer's error"
    };
    (s.stats.error_sum > ACCUMULATED_WARNING).then(|| {
        format!(
            "the steps' local error estimates add up to {:.0}×ERROR ({error:e}): the answer may be off by that much ({remedy})",
            s.stats.error_sum
        )
    })
}
