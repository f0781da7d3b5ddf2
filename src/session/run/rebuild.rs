//! A run's model changed between two stretches (a command file's ACTIVATE, DEACTIVATE,
//! new expressions, ACCGRAV; [`super::super::changes`]): the system is built again from
//! the changed model, every part keeps its pose, velocity and the time, and the new
//! system is assembled from there (velocities closest to the current ones). When the
//! constraint elements changed, the redundancy analysis runs again on the assembled
//! configuration; otherwise the rows dropped before are dropped again. The forces, the
//! output slots and (in 2D) the reactions' 3D shadow follow the new system; the output
//! columns stay the same, and a slot that reads an element switched off holds 0.
//!
//! Rebuilding rather than patching the system keeps one path for every change (a
//! VARIABLE is inlined into whatever reads it; a joint switched off may turn a 3D scene
//! planar and back). The expressions go through the run's compiler again, whose code
//! cache hands back the machine code of every expression that did not change.

use super::{reads_reconciled, shadow, Segment, Simulation};
use crate::diag::Diagnostic;
use crate::mbd::dynamics::Dynamics;
use crate::mbd::output_slot::OutputSlot;
use crate::mbd::{planar, AssemblyOptions, Dim, Dimension, PartHandle, System};
use crate::model::command_changes::ModelChange;
use crate::session::changes::{self, Applied};
use crate::session::plant::Plant;
use crate::session::stopped::Stopped;

impl Simulation {
    /// Checks every segment's changes against the dataset, in order: the diagnostics
    /// (spans into the command file), errors among them when a change cannot be made.
    pub fn check_changes(&mut self, segments: &[Segment]) -> Vec<Diagnostic> {
        let mut out = Vec::new();
        for c in segments.iter().flat_map(|s| &s.changes) {
            match changes::resolve(&mut self.read, c) {
                Ok((_, warnings)) => out.extend(warnings),
                Err(found) => out.extend(found),
            }
        }
        out
    }

    /// Makes `changes` to the model and rebuilds the dynamics around the current state
    /// when any changed something. The state is assembled but its accelerations are not
    /// solved: the caller reconciles before the next stretch.
    pub(super) fn change_model(&mut self, changes: &[ModelChange]) -> Result<(), Stopped> {
        let time = self.dynamics.sys.time;
        let at = match (changes.first(), changes.last()) {
            (Some(a), Some(b)) => a.span.start..b.span.end,
            _ => 0..0,
        };
        let fail = |why: String| Stopped::Change {
            time,
            why,
            at: at.clone(),
        };
        let mut applied = Applied::default();
        for c in changes {
            let (r, _) = changes::resolve(&mut self.read, c)
                .map_err(|d| fail(d.first().map_or_else(String::new, |d| d.message.clone())))?;
            applied = applied.and(r.apply(&mut self.read.model, &mut self.inactive));
        }
        if !applied.rebuild {
            return Ok(());
        }
        let model = changes::effective(&self.read.model, &self.inactive);
        let exprs = self.outputs.exprs.clone();
        let old = &self.dynamics.sys;
        // A 3D run stays 3D (its state has no 2D form); a 2D one may become 3D.
        let dim = match old.dim {
            Dimension::Three => Dim::Three,
            Dimension::Two => Dim::Auto,
        };
        let mut sys = planar::build(&model, dim, &exprs).map_err(|e| fail(e.to_string()))?;
        if sys.parts.len() != old.parts.len() {
            return Err(fail("the changed model has other parts".into()));
        }
        carry_state(old, &mut sys);
        let constraints = applied.constraints || sys.dim != old.dim;
        let dropped = match constraints {
            true => Vec::new(),
            false => self.dropped.clone(),
        };
        let options = AssemblyOptions {
            dropped: dropped.clone(),
            ..AssemblyOptions::default()
        };
        sys.assemble(&options).map_err(|e| fail(e.to_string()))?;
        let dropped = match constraints {
            false => dropped,
            true => {
                let report =
                    crate::mbd::pipeline::redundancy_of(&sys).map_err(|e| fail(e.to_string()))?;
                self.redundant = report.redundant.len();
                match self.spec.keep_redundant {
                    true => Vec::new(),
                    false => report.redundant.iter().map(|r| r.row).collect(),
                }
            }
        };
        let (meshes, _) = super::contact_meshes::contact_meshes(&model, &self.spec.geometry);
        let forces = sys
            .forces_with_meshes(&model, &exprs, &meshes)
            .map_err(|e| fail(e.to_string()))?;
        // An element switched off has no slot to read: its columns hold 0.
        let slots: Vec<(u32, Option<OutputSlot>)> = (self.outputs.slots.iter())
            .map(|&(s, _)| (s, OutputSlot::resolve(&mut sys, &model, s).ok()))
            .collect();
        adopt_unwrapping(old, &mut sys);
        // The plant's outputs read measures of the new system.
        let designs: Vec<i64> = (model.constraint_designs().into_iter())
            .map(i64::from)
            .collect();
        self.plant = Plant::new(&model, &exprs, &mut sys, &designs);
        let stats = self.dynamics.stats;
        let mut dynamics = Dynamics::new(sys, forces, &dropped)?;
        dynamics.stats = stats;
        self.outputs.lifted = shadow(&model, &exprs, &dynamics, &slots, &mut self.notes);
        self.outputs.reconcile = reads_reconciled(&slots, &dynamics);
        self.outputs.slots = slots;
        self.outputs
            .measures
            .resize(self.read.model.measures.len(), 0.0);
        if applied.variables {
            self.recompile_columns().map_err(fail)?;
        }
        let redundancy = match constraints {
            true => format!(
                "; a new redundancy analysis found {} redundant equations",
                self.redundant
            ),
            false => String::new(),
        };
        self.notes.push(format!(
            "at t = {time} the command file changed the model (elements switched off: {}){redundancy}",
            self.inactive.len()
        ));
        (self.dynamics, self.dropped, self.changed) = (dynamics, dropped, true);
        Ok(())
    }

    /// The output columns with the VARIABLEs they read inlined again (some have new
    /// expressions), fused again.
    fn recompile_columns(&mut self) -> Result<(), String> {
        use crate::mbd::expr::ExprCompiler as _;
        let outputs = &mut self.outputs;
        for c in &mut outputs.columns {
            c.function = (self.read.model.inline_variables(&c.source))
                .map_err(|why| format!("{}: {why}", c.name))?
                .function;
        }
        let functions: Vec<&crate::ir::Function> =
            outputs.columns.iter().map(|c| &c.function).collect();
        if !functions.is_empty() {
            outputs.code = outputs.exprs.fuse(&functions);
        }
        Ok(())
    }
}

/// Poses, velocities (as the velocities assembly stays closest to), input poses and time
/// of `from` onto the same parts of `to`.
fn carry_state(from: &System, to: &mut System) {
    to.restore(&from.snapshot());
    for (h, p) in from.parts.iter().enumerate() {
        let h = PartHandle(h as u32);
        to.set_part_velocity(h, p.v, p.w);
        // The input pose stays the run's: a 2D part's θ is its rotation from it.
        let q = to.part_mut(h);
        (q.input_r, q.input_rot) = (p.input_r, p.input_rot);
    }
    to.time = from.time;
}

/// The unwrapping references (angles past ±π) of `from`'s measures for the same
/// measures of `to`, so that an angle output does not jump back at the change.
fn adopt_unwrapping(from: &System, to: &mut System) {
    let same: Vec<Option<usize>> = (to.measures.list.iter())
        .map(|m| from.measures.list.iter().position(|x| x == m))
        .collect();
    let mut measures = std::mem::take(&mut to.measures);
    measures.adopt_unwrapping(&from.measures, &same);
    to.measures = measures;
}
