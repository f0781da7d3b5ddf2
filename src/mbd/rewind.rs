//! Running a built system again from its start: the state a run starts from, kept once,
//! and the dynamics rebuilt around it, so that a second run of the same system (with other
//! design-variable values) gives the bits a freshly built one would.
//!
//! What a run changes is restored here: poses and velocities (parts), FLOATING markers,
//! the measures' unwrapping references and design values, time, and the histories of
//! integrated MOTION drives. Everything else a run writes is scratch that each evaluation
//! overwrites before it reads it; the dynamics' own state (factors and the flags that pick
//! them, counters) is made anew by [`Dynamics::new`].

use super::dynamics::{DynError, Dynamics};
use super::measure_set::MeasureSet;
use super::rows::Row;
use super::system::{Marker, Part, System};

/// The state of a system at the start of a run.
#[derive(Clone, Debug)]
pub struct StartState {
    parts: Vec<Part>,
    markers: Vec<Marker>,
    measures: MeasureSet,
    time: f64,
}

impl System {
    /// The current state, to start runs from later ([`System::rewind_to`]).
    pub fn start_state(&self) -> StartState {
        StartState {
            parts: self.parts.clone(),
            markers: self.markers.clone(),
            measures: self.measures.clone(),
            time: self.time,
        }
    }

    /// Back to `start` (taken from this system), with its design values; the drives'
    /// histories forgotten.
    pub fn rewind_to(&mut self, start: &StartState) {
        self.parts.clone_from(&start.parts);
        self.markers.clone_from(&start.markers);
        self.measures.clone_from(&start.measures);
        self.time = start.time;
        for eq in self.elements.iter().flat_map(|e| &e.eqs) {
            match &eq.row {
                Row::Measured { drive: Some(g), .. } => g.rewind(),
                Row::Gcon { f, .. } => f.rewind(),
                _ => {}
            }
        }
    }
}

impl Dynamics {
    /// The dynamics made anew around the same system and forces (after
    /// [`System::rewind_to`]): no factors, flags or counters of the last run carry over,
    /// the forces keep their preparation but not their last loads, and the LU solvers their
    /// symbolic analysis.
    /// `dropped` are the rows left out, as [`Dynamics::new`] takes them.
    pub fn restart(&mut self, dropped: &[usize]) -> Result<(), DynError> {
        let sys = std::mem::take(&mut self.sys);
        let mut forces = std::mem::take(&mut self.forces);
        forces.forget_state();
        let factors = self.take_factors();
        *self = Dynamics::with_factors(sys, forces, dropped, factors)?;
        Ok(())
    }
}
