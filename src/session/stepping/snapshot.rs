//! What a [`super::Stepping`] can be taken back to: the system's state (poses,
//! velocities, FLOATING markers, the measures' unwrapping and the design values, which
//! hold the inputs; the time) and the state elements' committed values (DIFF, LSE, GSE,
//! TFSISO, a FRICTION's stiction).

use crate::mbd::dynamics::DynError;
use crate::mbd::rewind::StartState;
use crate::session::run::Simulation;

/// A stepping's state at one time ([`super::Stepping::state`]). Left out: the
/// integrator's history (a restore starts it afresh), the histories of MOTIONs
/// integrated from a velocity or acceleration, and which mesh contacts were held (both
/// start again from the run's start).
#[derive(Clone, Debug)]
pub struct Snapshot {
    system: StartState,
    /// The state elements' committed values and rates, when the model has any.
    states: Option<(Vec<f64>, Vec<f64>)>,
    time: f64,
}

impl Snapshot {
    /// The state of `sim` now.
    pub(super) fn of(sim: &Simulation) -> Snapshot {
        let d = &sim.dynamics;
        Snapshot {
            system: d.sys.start_state(),
            states: (d.forces.states.committed()).map(|(x, rate)| (x.to_vec(), rate.to_vec())),
            time: d.sys.time,
        }
    }

    /// Its time.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Puts `sim` back to this state, its dynamics made anew there (accelerations not
    /// solved yet).
    pub(super) fn restore(&self, sim: &mut Simulation) -> Result<(), DynError> {
        sim.restart_at(&self.system)?;
        if let Some((x, rate)) = &self.states {
            sim.dynamics.forces.states.hold_at(x.clone(), rate.clone());
        }
        Ok(())
    }
}
