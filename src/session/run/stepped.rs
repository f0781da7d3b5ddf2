//! What a caller that steps a [`Simulation`] itself needs of it
//! ([`crate::session::stepping`]): the row at the state as it stands, a design value
//! set during the run, and the run's start taken again from a kept state.

use super::Simulation;
use crate::mbd::dynamics::integrator::RowState;
use crate::mbd::dynamics::DynError;
use crate::mbd::rewind::StartState;

impl Simulation {
    /// The output row (time, then the columns) at the integrated state the dynamics
    /// stands on, made as [`Simulation::run`] makes its rows; `last` reconciles it as a
    /// run's final row.
    pub fn stepped_row(&mut self, last: bool) -> Result<&[f64], DynError> {
        self.outputs
            .row(&mut self.dynamics, last, RowState::Stepped)
    }

    /// Whether a MOTION or GCON reads design variable `id` (its value is compiled into
    /// the assembled configuration: setting it needs a new build).
    pub fn constraint_reads(&self, id: i64) -> bool {
        self.constraint_designs.contains(&id)
    }

    /// Gives design variable `id` the value `value` from the current time on (the
    /// expressions read it as an input of their compiled code; a 2D run's 3D shadow
    /// takes it too). The state is left as it is: the caller restarts the integrator.
    pub fn set_design(&mut self, id: i64, value: f64) -> Result<(), DynError> {
        self.dynamics.sys.measures.set_design(id, value);
        if let Some(lifted) = &mut self.outputs.lifted {
            let designs = self.dynamics.sys.measures.designs().to_vec();
            lifted.rewind(&designs)?;
        }
        Ok(())
    }

    /// Makes the dynamics anew at `state` (taken from this simulation's system, with its
    /// time and design values), as [`Simulation::rewind`] does at the start: no factor,
    /// counter or force-element history of the run so far carries over.
    pub fn restart_at(&mut self, state: &StartState) -> Result<(), DynError> {
        self.dynamics.sys.rewind_to(state);
        self.dynamics.restart(&self.dropped)?;
        if let Some(lifted) = &mut self.outputs.lifted {
            let designs = self.dynamics.sys.measures.designs().to_vec();
            lifted.rewind(&designs)?;
        }
        Ok(())
    }
}
