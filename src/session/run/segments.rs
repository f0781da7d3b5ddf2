//! The run loop: a simulation's segments one after the other (dynamics, equilibria,
//! kinematics, linear analyses), each output row handed out, and the summary made.

use super::cpu_clock::CpuClock;
use super::{monitors, Outputs, Segment, Simulation, Summary, TableRow};
use crate::mbd::dynamics::integrator::{Interrupt, OutputTimes, RowState};
use crate::mbd::dynamics::{simulate_framed, DynError, Dynamics, FrameTimes};
use crate::model::commands::Analysis;
use crate::session::plan::Plan;
use crate::session::stopped::Stopped;

impl Simulation {
    /// Kinetic plus gravitational potential energy (model units, /UCF).
    pub(super) fn energy(&self) -> f64 {
        let sys = &self.dynamics.sys;
        let g = sys.gravity;
        let potential: f64 = sys
            .parts
            .iter()
            .filter(|p| p.index.is_some())
            .map(|p| -p.mass * g.dot(&p.r))
            .sum();
        kinetic(sys) + potential / sys.ucf
    }

    /// Runs to the end time, handing each output row to `out` (the first at t = 0). The
    /// summary comes with the failure that stopped the run, if one did; the rows before
    /// it have been handed out.
    pub fn run(
        &mut self,
        out: &mut dyn FnMut(&[f64]) -> std::io::Result<()>,
    ) -> (Summary, Option<Stopped>) {
        let segment = Segment::dynamic(
            self.spec.end,
            self.spec.output_step,
            self.read.model.integrator.clone(),
        );
        self.run_segments(&[segment], out, None)
    }

    /// Runs the segments one after the other from t = 0, handing each output row to
    /// `out` (the first at t = 0, none twice where two segments meet) and, when `table`
    /// is given, a step-table line at each. The integrator starts afresh at each segment
    /// from the reconciled state where the last one ended, as Adams restarts at each
    /// SIMULATE command. The command line's `spec` overrides each segment's statement.
    pub fn run_segments(
        &mut self,
        segments: &[Segment],
        out: &mut dyn FnMut(&[f64]) -> std::io::Result<()>,
        table: Option<&mut dyn FnMut(&TableRow)>,
    ) -> (Summary, Option<Stopped>) {
        self.run_interruptible(segments, out, table, None)
    }

    /// [`Simulation::run_segments`], stopped with [`DynError::Interrupted`] before the
    /// first step attempt at which `interrupt` answers true. When the spec asks for an
    /// error estimate, a run that finished is made again at a looser ERROR afterwards
    /// ([`super::Estimate`]); the simulation is then left at that run's end.
    pub fn run_interruptible(
        &mut self,
        segments: &[Segment],
        out: &mut dyn FnMut(&[f64]) -> std::io::Result<()>,
        table: Option<&mut dyn FnMut(&TableRow)>,
        interrupt: Option<Interrupt<'_>>,
    ) -> (Summary, Option<Stopped>) {
        let error = self.start_trace(segments);
        let (mut summary, failed) = self.run_once(segments, out, table, interrupt);
        match (error, &failed) {
            (Some(error), None) => self.add_estimate(segments, error, &mut summary, interrupt),
            _ => self.trace = None,
        }
        (summary, failed)
    }

    /// One run of `segments` ([`Simulation::run_interruptible`] without the estimate).
    pub(super) fn run_once(
        &mut self,
        segments: &[Segment],
        out: &mut dyn FnMut(&[f64]) -> std::io::Result<()>,
        mut table: Option<&mut dyn FnMut(&TableRow)>,
        interrupt: Option<Interrupt<'_>>,
    ) -> (Summary, Option<Stopped>) {
        let clock = CpuClock::start();
        // Energy is watched over runs of dynamics alone (an equilibrium changes it).
        // (A command file that changes the model changes its energy too.)
        let integrates_only = segments
            .iter()
            .all(|s| s.kind == Analysis::Dynamic && s.changes.is_empty());
        let e0 = (self.conservative && integrates_only).then(|| self.energy());
        let mut max_residual: f64 = 0.0;
        let mut name = match segments.iter().find(|s| s.kind != Analysis::Dynamic) {
            Some(s) if s.kind == Analysis::Kinematics => "kinematics",
            Some(s) if s.kind == Analysis::Linear => "linear",
            Some(_) => "statics",
            None => "hht",
        };
        let mut error: f64 = 0.0;
        let mut notes = self.notes.clone();
        let mut equilibria = Vec::new();
        let mut linear = Vec::new();
        let conservative = self.conservative;
        let mut kinetic_max: f64 = 0.0;
        let mut trace = self.trace.take();
        // The animation's frames: at each row, or (at a frame rate) at the first row,
        // each solved one, and the frame times inside the steps.
        let recorder = std::cell::RefCell::new(self.recorder.take());
        let step = recorder.borrow().as_ref().and_then(|r| r.step);
        // The output columns' errors, from the error the integrator carries: the largest
        // over the rows (absolute, in the columns' units) and its time.
        let mut columns_error = ColumnsError::default();
        // A row of the integrated state (`Some((last, state))`: reconciled when the
        // columns need it or it is a segment's last) or of a state solved already (None;
        // `evaluated` when the analysis left its constraints and forces evaluated there).
        let mut emit = |outputs: &mut Outputs,
                        d: &mut Dynamics,
                        row: Option<(bool, RowState)>,
                        evaluated: bool|
         -> Result<(), DynError> {
            if conservative {
                kinetic_max = kinetic_max.max(kinetic(&d.sys));
            }
            let solved = row.is_none();
            let stepped = matches!(row, Some((_, RowState::Stepped)));
            let row = match row {
                Some((last, state)) => outputs.row(d, last, state)?,
                None if evaluated => outputs.fill_row(d)?,
                None => outputs.solved_row(d)?,
            };
            if let Some(t) = trace.as_mut() {
                t.push(row.to_vec());
            }
            if let Some(r) = recorder.borrow_mut().as_mut() {
                if step.is_none() || r.frames.times.is_empty() || solved {
                    r.record(d);
                }
            }
            max_residual = max_residual.max(residual(d));
            if let Some(table) = table.as_mut() {
                table(&TableRow {
                    time: d.sys.time,
                    step: d.stats.last_step,
                    steps: d.stats.steps,
                    newton_iterations: d.stats.newton_iterations,
                    order: d.stats.order,
                    cpu_seconds: clock.seconds(),
                });
            }
            let written = out(row).map_err(|e| DynError::Output(e.to_string()));
            if stepped && !d.carried.is_empty() {
                columns_error.add(outputs, d);
            }
            written
        };
        // The row at the start belongs to the first segment: the dynamics' consistent
        // state, or the first equilibrium or kinematic solution. The command file's
        // changes before its first SIMULATE come before it.
        let mut first_row = true;
        let mut result = match segments.first() {
            Some(s) => self.change_model(&s.changes),
            None => Ok(()),
        };
        if result.is_ok() && segments.first().is_none_or(|s| s.kind == Analysis::Dynamic) {
            let (dynamics, outputs) = (&mut self.dynamics, &mut self.outputs);
            result = dynamics
                .solve_accelerations()
                .and_then(|()| {
                    emit(
                        outputs,
                        dynamics,
                        Some((segments.is_empty(), RowState::Stepped)),
                        false,
                    )
                })
                .map_err(Stopped::from);
            first_row = false;
        }
        let mut after_solved = false;
        for (k, seg) in segments.iter().enumerate() {
            if result.is_err() {
                break;
            }
            if k > 0 && !seg.changes.is_empty() {
                // The stretch starts from the changed model, assembled where the last
                // one stopped: its velocities and accelerations are reconciled below.
                result = self.change_model(&seg.changes);
                if result.is_err() {
                    break;
                }
                after_solved = true;
            }
            let last = k + 1 == segments.len();
            let (dynamics, outputs, plant) = (&mut self.dynamics, &mut self.outputs, &self.plant);
            if seg.kind != Analysis::Dynamic {
                // A kinematic solution leaves Φ, Φ_q and the forces evaluated where it
                // stands: its row reads them as they are.
                let evaluated = seg.kind == Analysis::Kinematics;
                let motion = outputs.reads_motion() || recorder.borrow().is_some();
                let mut solved_emit = |d: &mut Dynamics| emit(outputs, d, None, evaluated);
                result = crate::session::analyses::run(
                    dynamics,
                    (plant, self.read.model.kinematics.as_ref(), motion),
                    seg,
                    (first_row, last),
                    &mut solved_emit,
                    (&mut equilibria, &mut linear),
                    interrupt,
                );
                (first_row, after_solved) = (false, true);
                continue;
            }
            // From an equilibrium (velocities zero), a kinematic state or a changed
            // model: velocities consistent with the constraints, then the accelerations.
            if after_solved {
                result = dynamics.reconcile().map_err(Stopped::from);
                if result.is_err() {
                    break;
                }
            }
            after_solved = false;
            let plan = Plan::new(seg.integrator.as_ref(), &self.spec, seg.output_step);
            let (mut integrator, note) = plan.integrator();
            integrator.carry_global_error(self.spec.carry_error);
            name = integrator.name();
            error = error.max(plan.settings.error);
            if let Some(n) = note.filter(|n| !notes.contains(n)) {
                notes.push(n);
            }
            let (t0, dt, end) = (dynamics.sys.time, seg.output_step, seg.end);
            let times = OutputTimes::new(t0, dt, end);
            // Each segment's last row reconciles: the next segment starts from it.
            let mut segment_emit =
                |d: &mut Dynamics, state| emit(outputs, d, Some((d.sys.time >= end, state)), false);
            let mut record = |d: &mut Dynamics| {
                if let Some(r) = recorder.borrow_mut().as_mut() {
                    r.record(d);
                }
                Ok(())
            };
            let mut frames = step.map(|dt| FrameTimes {
                times: OutputTimes::new(t0, dt, end),
                next: 0,
                record: &mut record,
            });
            result = simulate_framed(
                dynamics,
                integrator.as_mut(),
                &plan.settings,
                &times,
                &mut segment_emit,
                frames.as_mut(),
                interrupt,
            )
            .map_err(Stopped::from);
            if let Some(n) = integrator.formulation().filter(|n| !notes.contains(n)) {
                notes.push(n);
            }
        }
        self.trace = trace;
        self.recorder = recorder.into_inner();
        columns_error.judge(&mut self.dynamics.stats, error);
        // Notes the changes to the model added.
        for n in &self.notes {
            if !notes.contains(n) {
                notes.push(n.clone());
            }
        }
        let result = result.map_err(|e| self.diagnose_lock_up(e));
        let summary = Summary {
            integrator: name,
            equilibria,
            linear,
            stats: self.dynamics.stats,
            cpu_seconds: clock.seconds(),
            max_residual,
            energy: e0.map(|e| (e, self.energy())),
            notes,
            dim: self.dynamics.sys.dim_reason.clone(),
            warnings: Vec::new(),
            estimate: None,
            error,
            reused: false,
        };
        let summary = Summary {
            warnings: monitors(
                &summary,
                (
                    self.spec.fixed_step.is_some(),
                    self.dynamics.m >= self.dynamics.n,
                    self.trace.is_some() || self.dynamics.stats.global_error.is_some(),
                ),
                error,
                kinetic_max,
            ),
            ..summary
        };
        (summary, result.err())
    }
}

/// Kinetic energy (model units, /UCF).
pub(super) fn kinetic(sys: &crate::mbd::system::System) -> f64 {
    sys.parts
        .iter()
        .filter(|p| p.index.is_some())
        .map(|p| {
            let w = p.w;
            0.5 * p.mass * p.v.norm_squared() + 0.5 * w.dot(&(p.inertia_global() * w))
        })
        .sum::<f64>()
        / sys.ucf
}

/// The largest scaled residual of the kept rows of `d` (translational rows over the
/// model length), from its last constraint evaluation.
pub(super) fn residual(d: &Dynamics) -> f64 {
    (0..d.m).map(|r| d.scaled_residual(r)).fold(0.0, f64::max)
}

/// The largest error of the output columns that read the state only, estimated at each
/// row from the error the integrator carries ([`Outputs::column_errors`]): what the
/// run's verdict judges, rather than the state, since the columns are what a user reads.
#[derive(Default)]
struct ColumnsError {
    /// Which columns read the state only (made at the first row).
    positional: Option<Vec<bool>>,
    /// The largest, absolute, and the time of its row (None: no column of the state had
    /// an estimate).
    worst: Option<(f64, f64)>,
    errors: Vec<f64>,
}

impl ColumnsError {
    /// Adds the row just made at the state of `d`.
    fn add(&mut self, outputs: &mut Outputs, d: &mut Dynamics) {
        let positional = self.positional.get_or_insert_with(|| outputs.positional());
        if !positional.contains(&true) {
            return;
        }
        let e = std::mem::take(&mut d.carried);
        outputs.column_errors(d, &e, positional, &mut self.errors);
        d.carried = e;
        // A NaN says the estimate broke down: it stays.
        let worst = (self.errors.iter().zip(positional.iter()))
            .filter(|&(_, &p)| p)
            .fold(0.0, |m: f64, (&x, _)| match m.is_nan() || x.is_nan() {
                true => f64::NAN,
                false => m.max(x),
            });
        match self.worst {
            Some((w, _)) if w.is_nan() || worst <= w => {}
            _ => self.worst = Some((worst, d.sys.time)),
        }
    }

    /// Puts the verdict in `stats` (in units of `error`, the run's ERROR) when some
    /// column of the state had an estimate; else the state's own stays.
    fn judge(self, stats: &mut crate::mbd::dynamics::Stats, error: f64) {
        if let (Some((w, t)), Some(_)) = (self.worst, stats.global_error) {
            (stats.global_error, stats.global_error_time) = (Some(w / error), t);
        }
    }
}
