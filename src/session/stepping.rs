//! Stepping a model from outside: a [`Stepping`] owns a built [`Simulation`] and a
//! resumable time loop ([`TimeLoop`]), and its caller says when to advance, reads the
//! outputs between and sets the inputs: a controller, a co-simulation master (an FMU's,
//! [`crate::session`]'s shells) or a learning agent in the loop, as Adams Controls
//! couples a plant to Simulink and as MuJoCo and Exudyn users step a model themselves.
//!
//! It is made from what [`super::request::run`] takes ([`Stepping::new`], a
//! [`RunRequest`]): the dataset with its `set` values, the integrator and its settings,
//! the probes. The request's output step sets HMAX and HINIT as it does for `run` (END/100
//! when only END is given; with neither, the first advance's interval); END is needed
//! only for ERROR per run (the span it is spread over) and for the last row, which
//! reconciles as a run's does.
//!
//! **The rule:** advancing to each of `run`'s output times with the inputs held gives
//! `run`'s rows bit for bit: the steps are the same (the time loop lands on each time
//! it is advanced to, as it lands on each output time) and so are the rows. Output
//! rows from inside steps (INTERPOLATE = ON) are not made: a stepped model lands on
//! every time it is advanced to.
//!
//! **Inputs** are design variables (constant VARIABLEs the expressions read as inputs
//! of their compiled code): the dataset's PINPUT VARIABLEs by name, or any other design
//! variable. A changed value is a discontinuity of the forces: at the next advance the
//! integrator starts again from the current state (consistent accelerations under the
//! new value, its history forgotten, as after a located switch), as Adams restarts its
//! integrator when Adams Controls changes a plant input.
//!
//! `snapshot` holds the [`Snapshot`] a stepping can be taken back to, and `names` the
//! outputs' and inputs' names.

use super::plan::Plan;
use super::request::built;
use super::request::{RunFailed, RunRequest};
use super::run::Simulation;
use super::stopped::Stopped;
use crate::diag::SourceFile;
use crate::mbd::dynamics::integrator::{Integrator, Interrupt, OutputTimes, RowState};
use crate::mbd::dynamics::{DynError, Dynamics, Inside, TimeLoop};

mod names;
mod snapshot;

pub use snapshot::Snapshot;

/// A model being stepped: the simulation, its integrator and time loop, the outputs at
/// the current time and the inputs' names.
pub struct Stepping {
    sim: Simulation,
    /// The dataset as built (its `set` values applied): what failures point into.
    source: SourceFile,
    integrator: Box<dyn Integrator>,
    /// The output step HMAX and HINIT follow (None: the first advance's interval).
    output_step: Option<f64>,
    /// The time loop, started at the first advance after the start, a restore or a
    /// reset (None until then).
    stretch: Option<TimeLoop>,
    /// END: the row there reconciles as a run's last; ERROR per run spreads over it.
    end: Option<f64>,
    output_names: Vec<String>,
    /// The outputs at the current time.
    outputs: Vec<f64>,
    /// The inputs: (name, design variable id).
    inputs: names::Inputs,
    input_names: Vec<String>,
    /// An input changed since the last advance: the next one restarts the integrator.
    changed: bool,
    /// The start, for [`Stepping::reset`].
    start: Snapshot,
    /// The failure that stopped the stepping: every advance gives it until a restore.
    failed: Option<Stopped>,
    /// The note on the integrator asked for, when mbfx runs another (`INTEGRATOR/
    /// HASTIFF` runs GSTIFF).
    note: Option<String>,
}

impl Stepping {
    /// The model `request` asks `run` for, built and at its consistent start (t = 0),
    /// ready to advance: its dataset (not a command file) with the `set` values, the
    /// integrator and its settings, the probes. The outputs are the dataset's POUTPUT
    /// VARIABLEs (named by their `adams_view_name`, else `VARIABLE/id`), then the probes.
    /// Refuses what `run` refuses, worded as `run` words it. HMAX and HINIT follow the
    /// output step as in `run` (END/100 when only END is given); with neither, the
    /// first advance's interval is the output step, as Adams Controls takes its
    /// communication interval.
    pub fn new(request: &RunRequest) -> Result<Stepping, Box<RunFailed>> {
        let built::BuiltSimulation {
            simulation: mut sim,
            source,
            columns: plant_outputs,
        } = names::build(request)?;
        let output_names: Vec<String> = (plant_outputs.iter())
            .map(|(name, _)| name.clone())
            .chain(request.probes.iter().map(|(name, _)| name.clone()))
            .collect();
        let inputs = names::Inputs::of(&sim);
        let input_names = inputs.plant_names();
        let output_step = request.output_step.or(request.end.map(|end| end / 100.0));
        // (The method does not depend on the output step; its settings do.)
        let plan = Plan::new(sim.read.model.integrator.as_ref(), &sim.spec, 1.0);
        let (mut integrator, note) = plan.integrator();
        integrator.carry_global_error(sim.spec.carry_error);
        let start = Snapshot::of(&sim);
        let outputs = match first_row(&mut sim, output_names.len()) {
            Ok(o) => o,
            Err(e) => return Err(built::failure(Stopped::from(e), &source, &sim)),
        };
        Ok(Stepping {
            sim,
            source,
            integrator,
            output_step,
            stretch: None,
            end: request.end,
            output_names,
            outputs,
            inputs,
            input_names,
            changed: false,
            start,
            failed: None,
            note,
        })
    }

    /// The simulation time.
    pub fn time(&self) -> f64 {
        self.sim.dynamics.sys.time
    }

    /// Integrates to `t`, landing on it (steps of its own between, switches located),
    /// the inputs held at their values; the outputs are then those at `t`. A time not
    /// ahead of [`Stepping::time`] leaves the model where it is. A failure stops the
    /// stepping where the last accepted step ended: every later advance gives it, until
    /// [`Stepping::restore`] or [`Stepping::reset`].
    pub fn advance(&mut self, t: f64) -> Result<(), Stopped> {
        self.advance_interruptible(t, None)
    }

    /// [`Stepping::advance`], asking `interrupt` before every step attempt: once it
    /// answers true, the advance stops with [`DynError::Interrupted`] at the last
    /// accepted step (the outputs are those there), and a later advance goes on from it.
    pub fn advance_interruptible(
        &mut self,
        t: f64,
        interrupt: Option<Interrupt<'_>>,
    ) -> Result<(), Stopped> {
        if let Some(e) = &self.failed {
            return Err(e.clone());
        }
        if t.is_nan() || t <= self.time() {
            return Ok(());
        }
        let result = self.integrate_to(t, interrupt);
        match result {
            Ok(()) => Ok(()),
            Err(e @ DynError::Interrupted { .. }) => {
                // (The state is an accepted step's: its row, as an advance there gives.)
                match self.row() {
                    Ok(()) => Err(Stopped::from(e)),
                    Err(e) => Err(self.stop(e)),
                }
            }
            Err(e) => Err(self.stop(e)),
        }
    }

    /// The outputs' names: the POUTPUT VARIABLEs, then the probes.
    pub fn output_names(&self) -> &[String] {
        &self.output_names
    }

    /// The outputs at [`Stepping::time`], in the order of [`Stepping::output_names`]
    /// (made where the last advance, restore or reset ended: an input set since shows
    /// after the next advance).
    pub fn outputs(&self) -> &[f64] {
        &self.outputs
    }

    /// The inputs' names: the PINPUT VARIABLEs (by `adams_view_name`, else
    /// `VARIABLE/id`). Any other design variable may be set too
    /// ([`Stepping::set_input`]).
    pub fn input_names(&self) -> &[String] {
        &self.input_names
    }

    /// The value input `name` holds (a PINPUT VARIABLE's name or any design variable's,
    /// as [`Stepping::set_input`] takes them).
    pub fn input(&self, name: &str) -> Result<f64, String> {
        let id = self.inputs.find(&self.sim, name)?;
        Ok(self.sim.dynamics.sys.measures.design(id))
    }

    /// Gives input `name` the value `value` from [`Stepping::time`] on: a PINPUT
    /// VARIABLE by its name (any case), or any design variable by its `adams_view_name`
    /// or as `VARIABLE/id`. Refuses a name that is none, a value that is not finite,
    /// and a design variable a MOTION or GCON reads (its value is built into the
    /// assembled configuration) or no expression reads. A changed value restarts the
    /// integrator at the next advance.
    pub fn set_input(&mut self, name: &str, value: f64) -> Result<(), String> {
        let id = self.inputs.find_kept(&self.sim, name)?;
        if !value.is_finite() {
            return Err(format!(
                "{name} = {value}: an input must be a finite number"
            ));
        }
        if self.sim.dynamics.sys.measures.design(id) == value {
            return Ok(());
        }
        if let Err(e) = self.sim.set_design(id, value) {
            self.stop(e);
        }
        self.changed = true;
        Ok(())
    }

    /// The state now, to come back to ([`Stepping::restore`]).
    pub fn state(&self) -> Snapshot {
        Snapshot::of(&self.sim)
    }

    /// Back to `s` (a snapshot of this stepping): its time, state and inputs, and the
    /// outputs there.
    /// The integrator starts afresh there, as at the start (its history is not in a
    /// snapshot), so advancing from a restored snapshot gives the same bits each time,
    /// though not the bits of the stepping that went on when it was taken. A failure to
    /// start again there is given by the next advance.
    pub fn restore(&mut self, s: &Snapshot) {
        self.failed = None;
        self.changed = false;
        self.stretch = None;
        // As the start: consistent accelerations and the row; the integrator starts at
        // the next advance.
        let restarted = s.restore(&mut self.sim).and_then(|()| {
            self.sim.dynamics.solve_accelerations()?;
            self.row()
        });
        if let Err(e) = restarted {
            self.stop(e);
        }
    }

    /// Back to the start (t = 0, the inputs at the dataset's values): the bits a new
    /// stepping of the same request gives.
    pub fn reset(&mut self) {
        let start = self.start.clone();
        self.restore(&start);
    }

    /// The simulation stepped (its model, its dynamics' statistics).
    pub fn simulation(&self) -> &Simulation {
        &self.sim
    }

    /// The note on the integrator asked for, when mbfx runs another.
    pub fn note(&self) -> Option<&str> {
        self.note.as_deref()
    }

    /// `e` worded as `run` words a failure: at its element, the spans into the dataset.
    pub fn failure(&self, e: Stopped) -> Box<RunFailed> {
        built::failure(e, &self.source, &self.sim)
    }

    fn integrate_to(&mut self, t: f64, interrupt: Option<Interrupt<'_>>) -> Result<(), DynError> {
        let d = &mut self.sim.dynamics;
        let changed = std::mem::take(&mut self.changed);
        let stretch = match &mut self.stretch {
            Some(stretch) => {
                if changed {
                    stretch.restart(d, self.integrator.as_mut())?;
                }
                stretch
            }
            None => {
                if changed {
                    d.solve_accelerations()?;
                }
                let dt = self.output_step.unwrap_or(t - d.sys.time);
                let mut plan =
                    Plan::new(self.sim.read.model.integrator.as_ref(), &self.sim.spec, dt);
                plan.settings.interpolate = false;
                let span = self.end.unwrap_or(0.0);
                let started = TimeLoop::start(d, self.integrator.as_mut(), &plan.settings, span)?;
                self.stretch.insert(started)
            }
        };
        // No rows from inside the steps: the advance lands on `t`.
        let none = OutputTimes::new(t, 1.0, t);
        let mut ignore = |_: &mut Dynamics, _: RowState| Ok(());
        let inside = Inside {
            outputs: &none,
            output: &mut ignore,
        };
        stretch.advance_to(d, self.integrator.as_mut(), t, inside, None, interrupt)?;
        self.row()
    }

    /// The outputs at the state the dynamics stands on, made as `run` makes its row.
    fn row(&mut self) -> Result<(), DynError> {
        let last = self.end.is_some_and(|end| self.time() >= end);
        let row = self.sim.stepped_row(last)?;
        let n = self.outputs.len();
        self.outputs.copy_from_slice(&row[1..=n]);
        Ok(())
    }

    /// Keeps `e` as the failure that stopped the stepping.
    fn stop(&mut self, e: DynError) -> Stopped {
        let e = Stopped::from(e);
        self.failed = Some(e.clone());
        e
    }
}

/// The outputs at the start: consistent accelerations there, then the row `run` makes
/// first (its first `n` columns).
fn first_row(sim: &mut Simulation, n: usize) -> Result<Vec<f64>, DynError> {
    sim.dynamics.solve_accelerations()?;
    let row = sim.stepped_row(false)?;
    Ok(row[1..=n].to_vec())
}

#[cfg(test)]
mod tests;
