//! What every integrator implements ([`Integrator`]) and the driver that runs one over a
//! time span ([`simulate`]): step-size selection from the local error estimate (ERROR,
//! HMAX, HINIT, HMIN), rejection and retry, landing exactly on output times, locating the
//! force laws' switches ([`super::events`]), the check that dropped redundant rows stay
//! satisfied, and the output callback. Fixed-step runs divide each output interval into
//! equal steps no longer than the step asked for (and do not locate switches). With
//! [`Settings::interpolate`] (INTERPOLATE = ON) the steps land on the last output time
//! only, and every other output time inside an accepted step takes the method's
//! continuous extension (`dynamics::dense`). A caller's interrupt flag is read before every
//! step attempt, so a run stops within one step of it being set however far apart its
//! output times are.

use super::dense::{self, Kept, Taylor};
use super::events::{Events, Verdict};
use super::{DynError, Dynamics};

/// The smallest fraction of ERROR a step is held to when ERROR is per run.
pub const PER_RUN_FLOOR: f64 = 1e-3;

/// Integrator settings (spec §6.2 names).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// ERROR: local error tolerance per step (model lengths scaled by the model size for
    /// translations, radians for rotations).
    pub error: f64,
    /// HMAX: the longest step.
    pub hmax: f64,
    /// HINIT: the first step asked for.
    pub hinit: f64,
    /// HMIN: the shortest step before the run fails.
    pub hmin: f64,
    /// MAXIT: corrector iterations per attempt.
    pub maxit: usize,
    /// A fixed step instead of error control.
    pub fixed_step: Option<f64>,
    /// ERROR bounds the error of the whole run rather than of each step: a step of h
    /// is held to ERROR·h/T (T the time span the run integrates; at least
    /// ERROR·[`PER_RUN_FLOOR`]), so the steps' local errors add up to about ERROR and
    /// the answer's error falls in proportion to ERROR (tolerance proportionality).
    /// Off, ERROR is per step, as in Adams.
    pub error_per_run: bool,
    /// This step starts in contact (an IMPACT or BISTOP engaged): a method that holds
    /// positions alone to ERROR holds velocities too, since a contact reverses them in
    /// far less time than the positions take to show it.
    pub in_contact: bool,
    /// INTERPOLATE = ON: output times do not cut steps; each one inside an accepted step
    /// takes the method's continuous extension there, and only the last is landed on.
    /// Off (Adams' default), every output time ends a step.
    pub interpolate: bool,
}

impl Settings {
    /// The settings one step of `h` is attempted with over a run of span `span`: the
    /// same, with ERROR scaled down to ERROR·h/span when ERROR is per run, but never
    /// below ERROR·[`PER_RUN_FLOOR`]: the first steps from rest, of a method still at
    /// low order, would otherwise shrink without end, and the few of them shorter than
    /// that fraction of the span add at most about ERROR more.
    pub fn for_step(&self, h: f64, span: f64) -> Settings {
        if self.error_per_run && span > 0.0 {
            Settings {
                error: self.error * (h / span).clamp(PER_RUN_FLOOR, 1.0),
                ..*self
            }
        } else {
            *self
        }
    }

    /// Adams' defaults for an output step `dt`: ERROR 1e-3, HMAX = dt, HINIT = dt/20,
    /// HMIN = 1e-6·HMAX, MAXIT 10.
    pub fn for_output_step(dt: f64) -> Settings {
        Settings {
            error: 1e-3,
            hmax: dt,
            hinit: dt / 20.0,
            hmin: 1e-6 * dt,
            maxit: 10,
            fixed_step: None,
            error_per_run: false,
            in_contact: false,
            interpolate: false,
        }
    }
}

/// The outcome of one attempted step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Attempt {
    /// The corrector converged.
    Converged {
        /// The local error estimate divided by the tolerance (≤ 1 to accept; with fixed
        /// steps only the run's monitors read it, and the BDF reports 0).
        err: f64,
        /// The column where it is largest.
        worst: usize,
    },
    /// The corrector did not converge.
    Diverged,
}

/// A time-stepping method on [`Dynamics`].
pub trait Integrator {
    /// The name `--integrator` takes.
    fn name(&self) -> &'static str;
    /// The power of h in the local error estimate (3 for a second-order method).
    fn error_order(&self) -> f64;
    /// The order of accuracy of the last step, for the step table of `mbfx run
    /// --verbose` (Adams' "Integration Order" column); `None` when it has none to say.
    fn order(&self) -> Option<u32> {
        None
    }
    /// How it formulated the model's equations when that is worth saying (a form other
    /// than the one its name implies); read after [`Integrator::start`].
    fn formulation(&self) -> Option<String> {
        None
    }
    /// The last attempt's error estimate as the run's monitors should count it, given the
    /// one step control used (`err`); a method may watch more than it controls.
    fn monitored_error(&self, err: f64) -> f64 {
        err
    }
    /// The largest factor a step may grow by after an accepted one (the driver's rule).
    fn max_growth(&self) -> f64 {
        2.0
    }
    /// The factor the integrator wants the next step scaled by after the last accept or
    /// error rejection, when it chooses (a variable-order method compares orders);
    /// `None` leaves it to the driver's rule from [`Integrator::error_order`].
    fn step_factor(&self) -> Option<f64> {
        None
    }
    /// The first step, given HINIT: a method may start shorter where HINIT would be
    /// rejected (an order-one start at a tight ERROR).
    fn first_step(&self, _d: &Dynamics, hinit: f64, _s: &Settings) -> f64 {
        hinit
    }
    /// Whether it has a continuous extension ([`Integrator::extend`]); without one, a run
    /// asked to interpolate lands on every output time.
    fn dense(&self) -> bool {
        false
    }
    /// Readies the continuous extension of the step just accepted, called right after
    /// [`Integrator::accept`] and only for a step with an output time inside it (an
    /// extension that needs more evaluations costs nothing on the others). It may move
    /// `d`: the driver puts the accepted state back.
    fn extend(&mut self, _d: &mut Dynamics) -> Result<(), DynError> {
        Ok(())
    }
    /// Moves `d`'s positions, velocities and time to the continuous extension at `t`,
    /// inside the step [`Integrator::extend`] readied (accelerations and multipliers are
    /// left to the outputs' consistent solve).
    fn dense_state(&mut self, _d: &mut Dynamics, _t: f64) {}
    /// Readies the continuous extension of the candidate just attempted, before it is
    /// rejected for crossing a force law's switch, so that [`Integrator::dense_state`]
    /// places `d` inside it: where the switch lies is estimated on it. False when the
    /// method has none or could not make it (then the switch is located by trial steps
    /// alone). It may move `d` and the method's scratch; the candidate is rejected next.
    fn extend_candidate(&mut self, _d: &mut Dynamics) -> bool {
        false
    }
    /// Whether every state [`Integrator::dense_state`] gives holds the position
    /// constraints by construction (joint coordinates place the parts on them), so an
    /// interpolated row need not measure and project them.
    fn dense_on_constraints(&self) -> bool {
        false
    }
    /// Forgets the past after a located force-law switch (a multistep method restarts
    /// at order one rather than interpolate across it).
    fn restart(&mut self, _d: &mut Dynamics) {}
    /// Starts from the consistent state of `d` (accelerations and multipliers solved).
    fn start(&mut self, d: &mut Dynamics) -> Result<(), DynError>;
    /// Tries a step of `h` from the last accepted state, leaving `d` at the candidate.
    fn attempt(&mut self, d: &mut Dynamics, h: f64, s: &Settings) -> Result<Attempt, DynError>;
    /// Makes the candidate the accepted state.
    fn accept(&mut self, d: &mut Dynamics);
    /// Puts `d` back to the last accepted state.
    fn reject(&mut self, d: &mut Dynamics);
}

/// Whether the caller wants a run to stop, asked before every step attempt: a relaxed
/// load of a flag another thread sets (`|| flag.load(Ordering::Relaxed)`), or a check
/// of its own that looks at the clock every so many steps (Python's Ctrl-C).
pub type Interrupt<'a> = &'a dyn Fn() -> bool;

/// Where an output row's state comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RowState {
    /// A state the integrator stands on: a step's end.
    Stepped,
    /// A continuous extension's state inside a step, whose position residual has been
    /// measured already or holds by construction (the dense output of `dense.rs`).
    Interpolated,
}

/// The output times of a stretch from `t0`: `t0 + k·dt` for k = 1, 2, ... while below
/// `end`, then `end` itself. Made one at a time, so a stretch of 10⁹ rows holds none.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OutputTimes {
    t0: f64,
    dt: f64,
    end: f64,
    count: usize,
}

impl OutputTimes {
    /// The times after `t0` every `dt` up to `end` (`end` included: a last short interval
    /// rather than a time past it; a hair short of `end` counts as reaching it).
    pub fn new(t0: f64, dt: f64, end: f64) -> OutputTimes {
        // (A float-to-int cast saturates: a count past usize::MAX cannot run anyway.)
        let count = ((end - t0) / dt - 1e-9).ceil().max(0.0) as usize;
        OutputTimes { t0, dt, end, count }
    }

    /// How many times there are.
    pub fn len(&self) -> usize {
        self.count
    }

    /// Whether there are none (`end` at or before `t0`).
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// The last time, if any.
    pub fn last(&self) -> Option<f64> {
        self.count.checked_sub(1).map(|k| self.at(k))
    }

    /// The `k`-th time (from 0).
    pub fn at(&self, k: usize) -> f64 {
        (self.t0 + (k + 1) as f64 * self.dt).min(self.end)
    }

    /// The times in order.
    pub fn iter(&self) -> impl Iterator<Item = f64> + '_ {
        (0..self.count).map(|k| self.at(k))
    }
}

/// Runs `integrator` on `d` from its current time through every time of `outputs`
/// (increasing, the first at or after the current time), calling `output` at each with
/// `d` at exactly that time. Stops at the first failure, after the outputs before it.
/// When `interrupt` is given, it is asked before every step attempt: once it answers
/// true, the run stops with [`DynError::Interrupted`] at the last accepted state.
pub fn simulate(
    d: &mut Dynamics,
    integrator: &mut dyn Integrator,
    s: &Settings,
    outputs: &OutputTimes,
    output: &mut dyn FnMut(&mut Dynamics, RowState) -> Result<(), DynError>,
    interrupt: Option<Interrupt<'_>>,
) -> Result<(), DynError> {
    integrator.start(d)?;
    // Fixed steps are the user's to choose: no switch moves them.
    let mut events = match s.fixed_step {
        None => Events::new(d),
        Some(_) => Events::default(),
    };
    let drift_tol = (s.error * 10.0).max(1e-6);
    let span = outputs.last().map_or(0.0, |t| t - d.sys.time);
    // The step error control wants; the step taken may be shorter to land on an output.
    let mut want = match s.fixed_step {
        Some(h) => h.min(s.hmax),
        None => {
            let h0 = s.hinit.min(s.hmax);
            integrator.first_step(d, h0, &s.for_step(h0, span))
        }
    };
    // The last error rejection: time, step, estimate.
    let mut last_rejection: Option<(f64, f64, f64)> = None;
    // With INTERPOLATE the steps land on the last output time only; `pending` is the first
    // output time not yet given from inside a step.
    let interpolate = s.interpolate && integrator.dense();
    let landings = match (interpolate, outputs.last()) {
        (true, Some(_)) => 1,
        (true, None) => 0,
        (false, _) => outputs.len(),
    };
    let mut pending = 0;
    for landing in 0..landings {
        let t_out = match interpolate {
            true => outputs.at(outputs.len() - 1),
            false => outputs.at(landing),
        };
        while d.sys.time < t_out {
            let t = d.sys.time;
            if interrupt.is_some_and(|stop| stop()) {
                return Err(DynError::Interrupted { time: t });
            }
            let left = t_out - t;
            let mut h = want;
            if let Some(fixed) = s.fixed_step {
                let n = (left / fixed - 1e-9).ceil().max(1.0);
                h = left / n;
            } else if h >= left * (1.0 - 1e-9) {
                // (Within rounding of the time left, the step lands rather than split.)
                h = left;
            } else if 2.0 * h > left {
                // Two even steps rather than a long one and a sliver.
                h = left / 2.0;
            }
            let mut end = if h == left { t_out } else { t + h };
            // Aiming at a switch being located only ever shortens the step.
            if let Some(aim) = events.aim(t).filter(|&a| a < h) {
                (h, end) = (aim, t + aim);
            }
            let clipped = h < want;
            let step_settings = Settings {
                in_contact: events.engaged(),
                ..s.for_step(end - t, span)
            };
            let attempt = integrator.attempt(d, end - t, &step_settings)?;
            match attempt {
                Attempt::Diverged => {
                    d.stats.rejected += 1;
                    if !(s.fixed_step.is_some() || h * 0.25 < s.hmin) {
                        integrator.reject(d);
                    }
                    if s.fixed_step.is_some() || h * 0.25 < s.hmin {
                        let culprit = d.worst_row();
                        integrator.reject(d);
                        return Err(DynError::Newton {
                            time: t,
                            step: h,
                            culprit,
                        });
                    }
                    want = h * 0.25;
                }
                Attempt::Converged { err, worst } if err > 1.0 && s.fixed_step.is_none() => {
                    // A candidate over a force law's switch integrated two laws: its
                    // error says nothing of either, and shrinking by it only creeps up
                    // on the switch. Locate the switch instead (`events` aims at it).
                    d.sys.time = end;
                    if events.crosses(d) && events.judge(end, h, s.hmin) == Verdict::Locate {
                        reject_locating(d, integrator, &mut events, (t, end), false);
                        d.stats.rejected += 1;
                        continue;
                    }
                    integrator.reject(d);
                    d.stats.rejected += 1;
                    // Where the solution is less smooth than the method's order assumes
                    // (a contact's first instants: k·δ^1.5 has no second derivative at
                    // δ = 0), the estimate falls slower with h than h^order, and shrinking
                    // by that order creeps down in many rejections. A second rejection at
                    // the same time measures the order the estimate shows and shrinks by
                    // it (no more than the method's, no less than one).
                    let order = match last_rejection {
                        Some((t1, h1, e1)) if t1 == t && h1 > h && e1 > err => {
                            ((e1 / err).ln() / (h1 / h).ln()).clamp(1.0, integrator.error_order())
                        }
                        _ => integrator.error_order(),
                    };
                    last_rejection = Some((t, h, err));
                    let shrink = integrator
                        .step_factor()
                        .unwrap_or_else(|| (0.9 * err.powf(-1.0 / order)).clamp(0.1, 0.9));
                    want = h * shrink;
                    if want < s.hmin {
                        return Err(DynError::StepTooSmall {
                            time: t,
                            step: want,
                            hmin: s.hmin,
                            culprit: d.part_of_column(worst),
                        });
                    }
                }
                Attempt::Converged { err, .. } => {
                    d.sys.time = end;
                    let verdict = events.check(d, h, s.hmin);
                    if verdict == Verdict::Locate {
                        reject_locating(d, integrator, &mut events, (t, end), true);
                        d.stats.rejected += 1;
                        continue;
                    }
                    events.accept();
                    let event = verdict == Verdict::Accept { event: true };
                    d.stats.events += event as usize;
                    integrator.accept(d);
                    // The extension of a step with an output time inside it is readied
                    // before a restart forgets the step (the outputs come at its end).
                    let inside =
                        interpolate && pending + 1 < outputs.len() && outputs.at(pending) < end;
                    if inside {
                        let kept = Kept::of(d);
                        integrator.extend(d)?;
                        kept.restore(d);
                    }
                    if event {
                        integrator.restart(d);
                    }
                    estimate_ahead(d, &mut events);
                    d.stats.steps += 1;
                    (d.stats.last_step, d.stats.order) = (h, integrator.order());
                    if let Some(k) = d.stats.order {
                        d.stats.steps_at_order[(k as usize).clamp(1, 6) - 1] += 1;
                    }
                    let watched = integrator.monitored_error(err);
                    d.stats.error_sum += watched * step_settings.error / s.error;
                    if watched > d.stats.worst_error {
                        (d.stats.worst_error, d.stats.worst_error_time) = (watched, end);
                    }
                    d.check_dropped(drift_tol)?;
                    d.commit_measures();
                    if s.fixed_step.is_none() {
                        let most = integrator.max_growth();
                        let grow = if let Some(f) = integrator.step_factor() {
                            f
                        } else if err > 0.0 {
                            (0.9 * err.powf(-1.0 / integrator.error_order())).clamp(0.2, most)
                        } else {
                            most
                        };
                        // Not longer right after a rejection (Hairer & Wanner's rule): the
                        // estimate that accepted this step just refused a longer one.
                        let grow = match last_rejection {
                            Some((t1, ..)) if t1 == t => grow.min(1.0),
                            _ => grow,
                        };
                        let next = (h * grow).min(s.hmax);
                        // A step cut short to land on an output says little about a longer
                        // one unless its error was large. One across a switch starts a new
                        // law, whose pace the steps before it do not know: its own
                        // estimate sets the next.
                        want = if clipped && err < 0.5 && !event {
                            want.max(next)
                        } else {
                            next
                        };
                    }
                    if interpolate {
                        dense::emit(d, integrator, outputs, &mut pending, drift_tol, output)?;
                    }
                }
            }
        }
        output(d, RowState::Stepped)?;
    }
    Ok(())
}

/// Rejects the candidate in `d` (a step over `span`, judged to cross a switch) after
/// estimating where the switch lies: on the candidate's continuous extension when error
/// control accepted the candidate (`trusted`) and the method has one; else, or when that
/// shows no switch, on the accepted state's Taylor extension. A candidate the error
/// estimate refuses has integrated a stiff contact with far too long a step, and its
/// extension is no better than its end, while the Taylor extension follows the branch
/// the switch ends (exactly, in free flight).
fn reject_locating(
    d: &mut Dynamics,
    integrator: &mut dyn Integrator,
    events: &mut Events,
    span: (f64, f64),
    trusted: bool,
) {
    if trusted && integrator.extend_candidate(d) {
        events.estimate(span, |t, out| {
            integrator.dense_state(d, t);
            d.forces.switches(&d.sys, out);
        });
    }
    integrator.reject(d);
    estimate_ahead(d, events);
}

/// Estimates where the switch being located lies on the Taylor extension of the
/// accepted state in `d` when there is no estimate ahead of it (none was made, or a
/// step went past it without crossing: from closer by, the extension is closer to the
/// truth).
fn estimate_ahead(d: &mut Dynamics, events: &mut Events) {
    let Some(span) = events.unestimated(d.sys.time) else {
        return;
    };
    let mut taylor = Taylor::of(d);
    events.estimate(span, |t, out| {
        taylor.place(d, t);
        d.forces.switches(&d.sys, out);
    });
    taylor.restore(d);
}

#[cfg(test)]
mod tests {
    use super::OutputTimes;

    #[test]
    fn output_times_step_from_the_start_and_end_exactly_at_the_end() {
        let t = OutputTimes::new(0.0, 0.3, 1.0);
        let times: Vec<f64> = t.iter().collect();
        // 0.3·k in doubles, then the end itself rather than 1.2.
        assert_eq!(times, [0.3, 0.6, 0.8999999999999999, 1.0]);
        assert_eq!((t.len(), t.last()), (4, Some(1.0)));
        // A hair short of the end (rounding of k·dt) does not add a sliver of a row.
        assert_eq!(OutputTimes::new(0.0, 0.1, 1.0).len(), 10);
        assert!(OutputTimes::new(2.0, 0.5, 2.0).is_empty());
    }

    #[test]
    fn a_billion_billion_output_times_hold_no_memory() {
        let t = OutputTimes::new(0.0, 1e-9, 1e9);
        assert_eq!(t.len(), 1_000_000_000_000_000_000);
        assert_eq!((t.at(0), t.last()), (1e-9, Some(1e9)));
    }
}
