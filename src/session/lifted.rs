//! Reactions of a 2D run in full. A planar scene runs in 2D: its out-of-plane equations
//! hold identically and are left out, which is exact for the motion, but the loads they
//! carry (an out-of-plane force, or the moment a product of inertia such as IXZ needs to
//! keep a part turning in the plane) are then nobody's reaction. When an output reads a
//! reaction (`JOINT(…)`, `JPRIM`, `MOTION`, FX…TM), the run keeps a shadow 3D system of
//! the same model: at each output it takes the 2D state (poses, velocities, time), solves
//! the 3D consistent accelerations and multipliers there (spec §6.1 phase 3, the dropped
//! redundant rows as Adams drops them in 3D), and reads the reactions from it. Everything
//! else the outputs read stays 2D.

use crate::mbd::dynamics::{DynError, Dynamics};
use crate::mbd::expr::ExprCompiler;
use crate::mbd::output_slot::OutputSlot;
use crate::mbd::planar::{self, Dim};
use crate::mbd::rewind::StartState;
use crate::mbd::system::{PartHandle, System};
use crate::model::elements::Model;

/// The shadow 3D dynamics and the output slots it answers.
pub struct Lifted {
    three: Dynamics,
    /// (model slot, its resolution in the 3D system).
    slots: Vec<(u32, OutputSlot)>,
    /// For each 3D measure, the 2D measure it equals (whose unwrapping it adopts).
    same_measure: Vec<Option<usize>>,
    /// The 3D system's state before the first run, and its redundant rows.
    start: StartState,
    dropped: Vec<usize>,
}

impl Lifted {
    /// The shadow of `two` (a 2D run of `model`) for the model slots in `reactions`,
    /// or why it cannot be built.
    pub fn new(
        model: &Model,
        exprs: &dyn ExprCompiler,
        two: &Dynamics,
        reactions: &[u32],
    ) -> Result<Lifted, String> {
        let mut sys = planar::build(model, Dim::Three, exprs).map_err(|e| e.to_string())?;
        if sys.parts.len() != two.sys.parts.len() {
            return Err("the 3D build has other parts".into());
        }
        // The contacts' EXTERNAL geometries as the run has them (their warnings are the
        // run's).
        let (meshes, _) = crate::session::run::contact_meshes(model, &[]);
        let forces = sys
            .forces_with_meshes(model, exprs, &meshes)
            .map_err(|e| e.to_string())?;
        let slots = reactions
            .iter()
            .map(|&s| OutputSlot::resolve(&mut sys, model, s).map(|o| (s, o)))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| e.to_string())?;
        // The redundancy analysis at the 2D run's (assembled) state.
        copy_state(&two.sys, &mut sys);
        let report = crate::mbd::pipeline::redundancy_of(&sys).map_err(|e| e.to_string())?;
        let dropped: Vec<usize> = report.redundant.iter().map(|r| r.row).collect();
        let start = sys.start_state();
        let three = Dynamics::new(sys, forces, &dropped).map_err(|e| e.to_string())?;
        let (list2, list3) = (&two.sys.measures.list, &three.sys.measures.list);
        let same_measure = list3
            .iter()
            .map(|m| list2.iter().position(|x| x == m))
            .collect();
        Ok(Lifted {
            three,
            slots,
            same_measure,
            start,
            dropped,
        })
    }

    /// Ready for a run from t = 0 with the design values `values` (see
    /// [`super::run::Simulation::rewind`]).
    pub fn rewind(&mut self, values: &[(i64, f64)]) -> Result<(), DynError> {
        let sys = &mut self.three.sys;
        sys.rewind_to(&self.start);
        for &(id, v) in values {
            sys.measures.set_design(id, v);
        }
        self.three.restart(&self.dropped)
    }

    /// Solves the 3D system at the state of `two` and writes the reaction slots into
    /// `measures` (model slot values).
    pub fn fill(&mut self, two: &Dynamics, measures: &mut [f64]) -> Result<(), DynError> {
        let d = &mut self.three;
        copy_state(&two.sys, &mut d.sys);
        let mut m3 = std::mem::take(&mut d.sys.measures);
        m3.adopt_unwrapping(&two.sys.measures, &self.same_measure);
        d.sys.measures = m3;
        // The state elements where the 2D run has them (the forces may read them).
        if !two.forces.states.is_empty() {
            let (mut x, mut rate) = (Vec::new(), Vec::new());
            two.forces.states.current(&two.sys, &mut x, &mut rate);
            d.forces.states.hold_at(x, rate);
        }
        d.solve_accelerations()?;
        d.refresh_outputs()?;
        for &(s, slot) in &self.slots {
            measures[s as usize] = slot.value(d);
        }
        Ok(())
    }
}

/// Poses, velocities and time of `from` onto the same parts of `to`.
fn copy_state(from: &System, to: &mut System) {
    to.restore(&from.snapshot());
    for (h, p) in from.parts.iter().enumerate() {
        let q = to.part_mut(PartHandle(h as u32));
        (q.v, q.w) = (p.v, p.w);
    }
    to.time = from.time;
}
