//! The driver that runs an [`Integrator`] over a time span ([`simulate`]): step-size
//! selection from the local error estimate (ERROR, HMAX, HINIT, HMIN), rejection and
//! retry, landing exactly on output times, locating the force laws' switches
//! ([`super::events`]), the check that dropped redundant rows stay satisfied, and the
//! output callback. Fixed-step runs divide each output interval into equal steps no
//! longer than the step asked for (and do not locate switches). With
//! [`Settings::interpolate`] (INTERPOLATE = ON) the steps land on the last output time
//! only, and every other output time inside an accepted step takes the method's
//! continuous extension ([`super::inside_step`]). A caller's interrupt flag is read
//! before every step attempt, so a run stops within one step of it being set however far
//! apart its output times are.

use super::events::{Events, Verdict};
use super::failure::DynError;
use super::inside_step::{self, FrameTimes, Kept};
use super::integrator::{Attempt, Integrator, Interrupt, OutputTimes, RowState, Settings};
use super::setup::Dynamics;
use super::step_extension::Taylor;

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
    simulate_framed(d, integrator, s, outputs, output, None, interrupt)
}

/// [`simulate`], also handing `frames`' recorder the state at each of its times (an
/// animation's frames): from the continuous extension inside a step, or the step's end.
/// The steps, and so the outputs, are the same with or without them. A loop over
/// [`TimeLoop::advance_to`], one landing per output time (one in all with INTERPOLATE).
pub fn simulate_framed(
    d: &mut Dynamics,
    integrator: &mut dyn Integrator,
    s: &Settings,
    outputs: &OutputTimes,
    output: &mut dyn FnMut(&mut Dynamics, RowState) -> Result<(), DynError>,
    mut frames: Option<&mut FrameTimes<'_>>,
    interrupt: Option<Interrupt<'_>>,
) -> Result<(), DynError> {
    let span = outputs.last().map_or(0.0, |t| t - d.sys.time);
    let mut stretch = TimeLoop::start(d, integrator, s, span)?;
    let landings = match (stretch.interpolate, outputs.last()) {
        (true, Some(_)) => 1,
        (true, None) => 0,
        (false, _) => outputs.len(),
    };
    for landing in 0..landings {
        let t_out = match stretch.interpolate {
            true => outputs.at(outputs.len() - 1),
            false => outputs.at(landing),
        };
        let inside = Inside { outputs, output };
        stretch.advance_to(
            d,
            integrator,
            t_out,
            inside,
            frames.as_deref_mut(),
            interrupt,
        )?;
        output(d, RowState::Stepped)?;
    }
    Ok(())
}

/// The output rows a stretch run with INTERPOLATE gives from inside its steps: their
/// times and what takes each.
pub struct Inside<'a, 'b> {
    /// The stretch's output times.
    pub outputs: &'a OutputTimes,
    /// What takes a row.
    pub output: &'a mut (dyn FnMut(&mut Dynamics, RowState) -> Result<(), DynError> + 'b),
}

/// What the driver carries from one step to the next, so that a stretch can be
/// integrated a piece at a time ([`TimeLoop::advance_to`]): the switches being watched,
/// the step error control wants, the last rejection, the first output time not yet
/// given from inside a step. Integrating to t₁ and then to t₂ takes the steps a
/// [`simulate`] with output times t₁ and t₂ takes.
pub struct TimeLoop {
    settings: Settings,
    events: Events,
    drift_tol: f64,
    /// The time span ERROR per run is spread over.
    span: f64,
    /// The step error control wants; the step taken may be shorter to land on an output.
    want: f64,
    /// The last error rejection: time, step, estimate.
    last_rejection: Option<(f64, f64, f64)>,
    /// With INTERPOLATE the steps land on the last output time only; `pending` is the
    /// first output time not yet given from inside a step.
    interpolate: bool,
    pending: usize,
}

impl TimeLoop {
    /// Starts `integrator` from the consistent state of `d` under `s`, over a stretch of
    /// `span` (what ERROR per run is spread over).
    pub fn start(
        d: &mut Dynamics,
        integrator: &mut dyn Integrator,
        s: &Settings,
        span: f64,
    ) -> Result<TimeLoop, DynError> {
        integrator.start(d)?;
        // Fixed steps are the user's to choose: no switch moves them.
        let events = match s.fixed_step {
            None => Events::new(d),
            Some(_) => Events::default(),
        };
        let want = match s.fixed_step {
            Some(h) => h.min(s.hmax),
            None => {
                let h0 = s.hinit.min(s.hmax);
                integrator.first_step(d, h0, &s.for_step(h0, span))
            }
        };
        Ok(TimeLoop {
            settings: *s,
            events,
            drift_tol: (s.error * 10.0).max(1e-6),
            span,
            want,
            last_rejection: None,
            interpolate: s.interpolate && integrator.dense(),
            pending: 0,
        })
    }

    /// Starts the integrator again from the state of `d` as it stands, which a change
    /// of the forces made inconsistent (an input set): consistent accelerations there,
    /// the integrator's history forgotten, the switches watched from here, and the next
    /// step no longer than the method takes from a start (as after a located switch,
    /// the past says nothing of the new law's pace). The BDFs restart their history at
    /// order one from the new accelerations and keep their Newton matrix, as at a
    /// located switch (the matrix only steers Newton; a start would evaluate it again,
    /// which tripled the cost of a model stepped by 1 ms with an input changed at each
    /// step); the one-step methods start afresh, since their first stage, and HHT's
    /// forces of the last step, read what the change made stale.
    pub fn restart(
        &mut self,
        d: &mut Dynamics,
        integrator: &mut dyn Integrator,
    ) -> Result<(), DynError> {
        let s = self.settings;
        d.solve_accelerations()?;
        // (The integrator trait has no word for "multistep"; the BDFs are these two.)
        if matches!(integrator.name(), "gstiff" | "wstiff") {
            // The state elements' rates under the new forces, for the history's start.
            d.commit_states()?;
            integrator.restart(d);
        } else {
            integrator.start(d)?;
        }
        if s.fixed_step.is_none() {
            self.events = Events::new(d);
            let h0 = self.want.min(s.hmax);
            self.want = integrator.first_step(d, h0, &s.for_step(h0, self.span));
        }
        self.last_rejection = None;
        Ok(())
    }

    /// Integrates from the time of `d` to `t_out`, landing on it (nothing when `d` is
    /// there already). With INTERPOLATE, each of `inside`'s output times inside a step
    /// takes its row there; `frames` records its times as [`simulate_framed`] says.
    /// `interrupt` is asked before every step attempt.
    pub fn advance_to(
        &mut self,
        d: &mut Dynamics,
        integrator: &mut dyn Integrator,
        t_out: f64,
        inside: Inside<'_, '_>,
        mut frames: Option<&mut FrameTimes<'_>>,
        interrupt: Option<Interrupt<'_>>,
    ) -> Result<(), DynError> {
        let s = self.settings;
        let Inside { outputs, output } = inside;
        while d.sys.time < t_out {
            let t = d.sys.time;
            if interrupt.is_some_and(|stop| stop()) {
                return Err(DynError::Interrupted { time: t });
            }
            let left = t_out - t;
            let mut h = self.want;
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
            if let Some(aim) = self.events.aim(t).filter(|&a| a < h) {
                (h, end) = (aim, t + aim);
            }
            // Nor may a contact pair pass through another unseen inside it (onset is
            // seen only at a step's ends): the contacts' conservative bound.
            if s.fixed_step.is_none() && !d.forces.contacts.is_empty() {
                let reach = d.forces.contacts.step_bound(&d.sys, h);
                if reach < h {
                    (h, end) = (reach, t + reach);
                }
            }
            let clipped = h < self.want;
            let step_settings = Settings {
                in_contact: self.events.engaged(),
                ..s.for_step(end - t, self.span)
            };
            // A force that is not finite at a trial state (a Newton iterate thrown far by
            // too long a step) is the step's failure, as a divergence is; only when the
            // steps can shrink no more does it end the run, with the element named.
            let attempt = match integrator.attempt(d, end - t, &step_settings) {
                Err(DynError::NotFinite { .. }) if s.fixed_step.is_none() && h * 0.25 >= s.hmin => {
                    Attempt::Diverged
                }
                other => other?,
            };
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
                    self.want = h * 0.25;
                }
                Attempt::Converged { err, worst } if err > 1.0 && s.fixed_step.is_none() => {
                    // A candidate over a force law's switch integrated two laws: its
                    // error says nothing of either, and shrinking by it only creeps up
                    // on the switch. Locate the switch instead (`events` aims at it).
                    d.sys.time = end;
                    if self.events.crosses(d)
                        && self.events.judge(end, h, s.hmin) == Verdict::Locate
                    {
                        reject_locating(d, integrator, &mut self.events, (t, end), false);
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
                    let order = match self.last_rejection {
                        Some((t1, h1, e1)) if t1 == t && h1 > h && e1 > err => {
                            ((e1 / err).ln() / (h1 / h).ln()).clamp(1.0, integrator.error_order())
                        }
                        _ => integrator.error_order(),
                    };
                    self.last_rejection = Some((t, h, err));
                    let shrink = integrator
                        .step_factor()
                        .unwrap_or_else(|| (0.9 * err.powf(-1.0 / order)).clamp(0.1, 0.9));
                    self.want = h * shrink;
                    if self.want < s.hmin {
                        return Err(DynError::StepTooSmall {
                            time: t,
                            step: self.want,
                            hmin: s.hmin,
                            culprit: d.part_of_column(worst),
                        });
                    }
                }
                Attempt::Converged { err, .. } => {
                    d.sys.time = end;
                    let verdict = self.events.check(d, h, s.hmin);
                    if verdict == Verdict::Locate {
                        reject_locating(d, integrator, &mut self.events, (t, end), true);
                        d.stats.rejected += 1;
                        continue;
                    }
                    self.events.accept();
                    let event = verdict == Verdict::Accept { event: true };
                    d.stats.events += event as usize;
                    // The state elements first: the integrator's history reads them.
                    d.commit_states()?;
                    integrator.accept(d);
                    // The extension of a step with an output time inside it is readied
                    // before a restart forgets the step (the outputs come at its end).
                    let inside = self.interpolate
                        && self.pending + 1 < outputs.len()
                        && outputs.at(self.pending) < end;
                    let framed = frames.as_ref().is_some_and(|f| f.inside(end));
                    if inside || framed {
                        let kept = Kept::of(d);
                        integrator.extend(d)?;
                        kept.restore(d);
                    }
                    if event {
                        integrator.restart(d);
                    }
                    estimate_ahead(d, &mut self.events);
                    d.stats.steps += 1;
                    (d.stats.last_step, d.stats.order) = (h, integrator.order());
                    if let Some(k) = d.stats.order {
                        d.stats.steps_at_order[(k as usize).clamp(1, 6) - 1] += 1;
                    }
                    carry_estimate(d, integrator, s.error, end);
                    let watched = integrator.monitored_error(err);
                    d.stats.error_sum += watched * step_settings.error / s.error;
                    if watched > d.stats.worst_error {
                        (d.stats.worst_error, d.stats.worst_error_time) = (watched, end);
                    }
                    d.check_dropped(self.drift_tol)?;
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
                        let grow = match self.last_rejection {
                            Some((t1, ..)) if t1 == t => grow.min(1.0),
                            _ => grow,
                        };
                        let next = (h * grow).min(s.hmax);
                        // A step cut short to land on an output says little about a longer
                        // one unless its error was large. One across a switch starts a new
                        // law, whose pace the steps before it do not know: its own
                        // estimate sets the next.
                        self.want = if clipped && err < 0.5 && !event {
                            self.want.max(next)
                        } else {
                            next
                        };
                    }
                    if self.interpolate {
                        inside_step::emit(
                            d,
                            integrator,
                            outputs,
                            &mut self.pending,
                            self.drift_tol,
                            output,
                        )?;
                    }
                    if let Some(f) = frames.as_deref_mut() {
                        inside_step::frames(d, integrator, f)?;
                    }
                    // The extensions placed the states inside the step: back to its end.
                    if (self.interpolate || frames.is_some()) && !d.forces.states.is_empty() {
                        d.forces.states.hold();
                        d.solve_states()?;
                    }
                }
            }
        }
        Ok(())
    }
}

/// Keeps the largest global error estimate the integrator carries, in ERRORs over the
/// positions, after a step accepted at `end`; none once it carries none.
fn carry_estimate(d: &mut Dynamics, integrator: &dyn Integrator, error: f64, end: f64) {
    let Some(e) = integrator.global_error() else {
        d.stats.global_error = None;
        return;
    };
    let scaled = (e[..d.n].iter().enumerate())
        .map(|(c, x)| x.abs() / d.tolerance(c, error))
        .fold(0.0, f64::max);
    // From the run's first step on, or never: a gap would leave the estimate short.
    let worst = match (d.stats.steps, d.stats.global_error) {
        (1, _) => f64::NEG_INFINITY,
        (_, Some(w)) => w,
        (_, None) => return,
    };
    // (A NaN estimate is kept: it says the estimate broke down.)
    if scaled.partial_cmp(&worst) != Some(std::cmp::Ordering::Less) {
        (d.stats.global_error, d.stats.global_error_time) = (Some(scaled), end);
    }
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
