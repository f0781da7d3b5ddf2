//! What every integrator implements ([`Integrator`]) and what the driver
//! ([`super::time_loop::simulate`]) runs it with: its settings ([`Settings`], spec §6.2
//! names), the outcome of one attempted step ([`Attempt`]), the output times of a stretch
//! ([`OutputTimes`]), where an output row's state comes from ([`RowState`]), and the
//! caller's interrupt flag ([`Interrupt`]).

use super::failure::DynError;
use super::setup::Dynamics;

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
    /// Whether to carry an estimate of the global error through the steps
    /// ([`Integrator::global_error`]); a method that has none ignores it.
    fn carry_global_error(&mut self, _on: bool) {}
    /// The estimate of the last accepted state's global error, carried through the
    /// steps by the method's own linearization: positions (velocity layout), then
    /// velocities. None when the method carries none (or was told not to, or the
    /// estimate failed).
    fn global_error(&self) -> Option<&[f64]> {
        None
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
    /// measured already or holds by construction (`inside_step.rs`).
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
