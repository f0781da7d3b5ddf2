//! The stretches of a run that integrate nothing (SIMULATE/STATICS,
//! SIMULATE/KINEMATICS and LINEAR): each solves the state at its output times and hands
//! it to the run's row writer; a linear analysis moves nothing and writes its own files
//! ([`super::linear`]). A static stretch without an end is one equilibrium where the run
//! stands (`mbd::statics`); with one, a quasi-static sequence, the equilibrium at each
//! output time under the forces and motions of that time, each from the last. A
//! kinematic stretch refuses a model with degrees of freedom left, then solves
//! positions, velocities, accelerations and reactions from the constraints in steps of
//! its own, landing on each output time (`mbd::kinematics`). The stretch's first row, at its start, is written
//! only when the run has written none yet (`first_row`): rows never repeat a time.

use super::linear::{self, LinearReport};
use super::plant::Plant;
use super::run::Segment;
use super::stopped::Stopped;
use crate::mbd::dynamics::integrator::Interrupt;
use crate::mbd::dynamics::integrator::OutputTimes;
use crate::mbd::dynamics::{DynError, Dynamics};
use crate::mbd::kinematics;
use crate::mbd::statics::{self, Report};
use crate::model::commands::Analysis;
use crate::model::kinematics_settings::KinematicsStatement;

/// Writes the row of a solved state.
pub type Emit<'a> = dyn FnMut(&mut Dynamics) -> Result<(), DynError> + 'a;

/// What the analyses found: the equilibria's reports and the linear analyses'.
pub type Found<'a> = (&'a mut Vec<Report>, &'a mut Vec<LinearReport>);

/// Runs segment `seg` (static, kinematic or linear) on `d` (a linear one with the
/// model's `plant` inputs and outputs, a kinematic one under its KINEMATICS
/// statement, solving accelerations and reactions when `motion` says the rows read
/// them); `first_row` says the run has written no row yet, `last` that it is the
/// run's last segment.
pub fn run(
    d: &mut Dynamics,
    (plant, statement, motion): (&Plant, Option<&KinematicsStatement>, bool),
    seg: &Segment,
    (first_row, last): (bool, bool),
    emit: &mut Emit<'_>,
    (reports, linear): Found<'_>,
    interrupt: Option<Interrupt<'_>>,
) -> Result<(), Stopped> {
    match (seg.kind, &seg.linear) {
        (Analysis::Kinematics, _) => {
            let settings = statement.map_or_else(kinematics::Settings::default, settings_of);
            let settings = kinematics::Settings { motion, ..settings };
            kinematics(d, (seg, settings), first_row, emit, interrupt)
        }
        (Analysis::Linear, Some(command)) => {
            // A run that is only a linear analysis writes the state it stands at.
            if first_row {
                d.solve_accelerations()?;
                emit(d)?;
            }
            linear.push(linear::analyse(d, plant, command)?);
            Ok(())
        }
        _ => statics(d, seg, first_row, last, emit, reports, interrupt),
    }
}

/// Runs static segment `seg` on `d`, its equilibria's reports into `reports`; `last`
/// says it is the run's last segment (a lone equilibrium then writes its row even
/// after other rows).
pub fn statics(
    d: &mut Dynamics,
    seg: &Segment,
    first_row: bool,
    last: bool,
    emit: &mut Emit<'_>,
    reports: &mut Vec<Report>,
    interrupt: Option<Interrupt<'_>>,
) -> Result<(), Stopped> {
    let settings = seg
        .equilibrium
        .as_ref()
        .map_or_else(statics::Settings::default, |e| e.settings());
    if seg.output_step == 0.0 {
        reports.push(statics::equilibrium(d, &settings)?);
        return match first_row || last {
            true => Ok(emit(d)?),
            false => Ok(()),
        };
    }
    if first_row {
        reports.push(statics::equilibrium(d, &settings)?);
        emit(d)?;
    }
    for t in OutputTimes::new(d.sys.time, seg.output_step, seg.end).iter() {
        stop_if_asked(d, interrupt)?;
        d.sys.time = t;
        reports.push(statics::equilibrium(d, &settings)?);
        emit(d)?;
    }
    Ok(())
}

/// The kinematic analysis' settings from the KINEMATICS statement: the values written,
/// Adams' defaults for the rest.
pub fn settings_of(statement: &KinematicsStatement) -> kinematics::Settings {
    let d = kinematics::Settings::default();
    kinematics::Settings {
        hmax: statement.hmax.as_ref().map(|g| g.value).or(d.hmax),
        error: statement.error.as_ref().map_or(d.error, |g| g.value),
        motion: d.motion,
    }
}

/// Runs kinematic segment `seg` on `d` under `settings`: refused when `d` has degrees
/// of freedom left.
pub fn kinematics(
    d: &mut Dynamics,
    (seg, settings): (&Segment, kinematics::Settings),
    first_row: bool,
    emit: &mut Emit<'_>,
    interrupt: Option<Interrupt<'_>>,
) -> Result<(), Stopped> {
    kinematics::check_driven(d)?;
    let t0 = d.sys.time;
    kinematics::solve_here(d)?;
    if first_row {
        emit(d)?;
    }
    let mut control = kinematics::Control::new(settings);
    for t in OutputTimes::new(t0, seg.output_step, seg.end).iter() {
        stop_if_asked(d, interrupt)?;
        kinematics::advance_to(d, t, &mut control)?;
        emit(d)?;
    }
    Ok(())
}

fn stop_if_asked(d: &Dynamics, interrupt: Option<Interrupt<'_>>) -> Result<(), DynError> {
    match interrupt.is_some_and(|stop| stop()) {
        true => Err(DynError::Interrupted { time: d.sys.time }),
        false => Ok(()),
    }
}
