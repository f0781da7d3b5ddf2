//! The run's output columns: the probes and each REQUEST's components compiled into
//! one function, the measure slots they read, a 2D run's 3D shadow for its reactions,
//! and the row they make at each output time.

use crate::ir::Function;
use crate::mbd::dynamics::integrator::RowState;
use crate::mbd::dynamics::{DynError, Dynamics};
use crate::mbd::expr::FusedFn;
use crate::mbd::output_slot::OutputSlot;
use crate::model::elements::{Expr, RequestKind};
use crate::session::lifted::Lifted;

/// One output column: its header and its expression.
pub(super) struct Column {
    pub(super) name: String,
    pub(super) function: Function,
    /// The expression as written, its VARIABLEs not inlined (a command file that gives
    /// a VARIABLE a new expression inlines it again).
    pub(super) source: Expr,
    /// Its unit in the dataset's units ([`super::column_units`]).
    pub(super) unit: String,
}

/// The output columns compiled, and the measure slots they read.
pub(super) struct Outputs {
    pub(super) columns: Vec<Column>,
    /// None: the slot reads an element the command file switched off (it holds 0).
    pub(super) slots: Vec<(u32, Option<OutputSlot>)>,
    /// Some column reads velocities, accelerations or forces: each row reconciles.
    pub(super) reconcile: bool,
    /// Every column's value from one call ([`crate::ir::fuse`]), the slots filled once.
    pub(super) code: Option<Box<dyn FusedFn>>,
    pub(super) measures: Vec<f64>,
    /// The compiler all of the model's expressions went through.
    pub(super) exprs: crate::mbd::compiled::CompiledExprs,
    /// A 2D run's 3D shadow for the reactions ([`Lifted`]).
    pub(super) lifted: Option<Lifted>,
    /// The last row (time, then the columns), kept to be filled again.
    pub(super) row: Vec<f64>,
}

/// A 2D run's reactions come from a 3D shadow, which holds the out-of-plane loads: the
/// shadow of `dynamics` (built from `model`) for the reaction slots among `slots`, when
/// the run is 2D and reads any (a note says why when it cannot be built).
pub(super) fn shadow(
    model: &crate::model::Model,
    exprs: &crate::mbd::compiled::CompiledExprs,
    dynamics: &Dynamics,
    slots: &[(u32, Option<OutputSlot>)],
    notes: &mut Vec<String>,
) -> Option<Lifted> {
    let reactions: Vec<u32> = slots
        .iter()
        .filter(|(_, o)| o.is_some_and(|o| o.reads_reaction()))
        .map(|&(s, _)| s)
        .collect();
    if dynamics.sys.dim != crate::mbd::Dimension::Two || reactions.is_empty() {
        return None;
    }
    match Lifted::new(model, exprs, dynamics, &reactions) {
        Ok(l) => Some(l),
        Err(why) => {
            let note = format!(
                "out-of-plane reaction components are left at 0: the 3D system that gives them cannot be built ({why})"
            );
            if !notes.contains(&note) {
                notes.push(note);
            }
            None
        }
    }
}

/// Whether an output slot reads velocities, accelerations or forces: each row then
/// reconciles.
pub(super) fn reads_reconciled(slots: &[(u32, Option<OutputSlot>)], dynamics: &Dynamics) -> bool {
    slots
        .iter()
        .any(|(_, s)| s.is_some_and(|s| s.reads_reconciled(&dynamics.sys)))
}

/// The expression text of component k (1..8) of a standard REQUEST, if it has one.
pub(super) fn standard_component(
    kind: RequestKind,
    i: u32,
    j: u32,
    rm: u32,
    k: usize,
) -> Option<String> {
    let (mag, vec, amag, avec) = match kind {
        RequestKind::Displacement => ("DM", "D", None, None),
        RequestKind::Velocity => ("VM", "V", Some("WM"), Some("W")),
        RequestKind::Acceleration => ("ACCM", "ACC", Some("WDTM"), Some("WDT")),
        RequestKind::Force => ("FM", "F", Some("TM"), Some("T")),
    };
    let xyz = ["X", "Y", "Z"];
    Some(match k {
        1 => format!("{mag}({i},{j})"),
        2..=4 => format!("{vec}{}({i},{j},{rm})", xyz[k - 2]),
        5 => format!("{}({i},{j})", amag?),
        6..=8 => match avec {
            Some(w) => format!("{w}{}({i},{j},{rm})", xyz[k - 6]),
            None => format!("{}({i},{j})", ["PSI", "THETA", "PHI"][k - 6]),
        },
        _ => return None,
    })
}

/// Whether an output slot's value is the state's alone: a measure of positions or
/// velocities, not an acceleration, a reaction or a force law's value.
fn reads_state(slot: &OutputSlot) -> bool {
    matches!(
        slot,
        OutputSlot::Kinematic(_) | OutputSlot::EulerParameter { .. }
    )
}

impl Outputs {
    /// The output row of a state solved already (an equilibrium, a kinematic solution):
    /// its velocities, accelerations and multipliers are the solution's, not reconciled.
    pub(super) fn solved_row(&mut self, d: &mut Dynamics) -> Result<&[f64], DynError> {
        d.refresh_outputs()?;
        self.fill_row(d)
    }

    /// The output row at the state of `d`; `last` says it is the run's final row, which
    /// the summary's energy and residual read.
    pub(super) fn row(
        &mut self,
        d: &mut Dynamics,
        last: bool,
        state: RowState,
    ) -> Result<&[f64], DynError> {
        // The integrator's accelerations and multipliers are its own (HHT's are shifted
        // by α and only first-order accurate), and index 3 lets velocities drift: outputs
        // get velocities projected onto the velocity constraints and the consistent a
        // and λ of that state, M·a/UCF + Φ_qᵀλ = Q with Φ_q·a = γ (spec §6.1 phase 3), as
        // Adams reconciles at output steps. The integrator keeps its own state. Columns
        // that read positions only skip it (compute only what the outputs read).
        if self.reconcile || last {
            d.reconcile()?;
            d.refresh_outputs()?;
        } else if state == RowState::Stepped {
            // Φ at this state, for the summary's largest constraint residual (an
            // interpolated row's was measured where it was made).
            d.eval_constraints(false)?;
        }
        self.fill_row(d)
    }

    /// Whether a column reads more than the positions and velocities (accelerations,
    /// reactions, forces): a kinematic analysis then solves accelerations and
    /// multipliers at every step.
    pub(super) fn reads_motion(&self) -> bool {
        self.lifted.is_some()
            || self.slots.iter().any(|(_, s)| {
                !matches!(
                    s,
                    None | Some(OutputSlot::Kinematic(_) | OutputSlot::EulerParameter { .. })
                )
            })
    }

    /// The columns at the state of `d` as it stands (evaluated for outputs).
    pub(super) fn fill_row(&mut self, d: &mut Dynamics) -> Result<&[f64], DynError> {
        for &(s, slot) in &self.slots {
            self.measures[s as usize] = slot.map_or(0.0, |o| o.value(d));
        }
        if let Some(lifted) = &mut self.lifted {
            lifted.fill(d, &mut self.measures)?;
        }
        let t = d.sys.time;
        let row = &mut self.row;
        row.clear();
        row.push(t);
        row.resize(self.columns.len() + 1, 0.0);
        if let Some(code) = &self.code {
            code.eval_into(t, &self.measures, &mut row[1..]);
        }
        Ok(row)
    }

    /// Whether each column reads the state alone (displacements, angles, velocities,
    /// time): the columns whose error the carried error of the state gives.
    pub(super) fn positional(&self) -> Vec<bool> {
        let slot = |m: u32| {
            self.slots
                .iter()
                .find(|&&(s, _)| s == m)
                .and_then(|&(_, o)| o)
        };
        (self.columns.iter())
            .map(|c| {
                (c.function.uses.measures.iter()).all(|&m| slot(m).is_none_or(|o| reads_state(&o)))
            })
            .collect()
    }

    /// The error of each column of the row just made, estimated from the error `e` the
    /// integrator carries (positions in the velocity layout, then velocities): each
    /// column at the state moved by `e`, less its value; NaN for a column that is not
    /// `positional` (a carried error of the state says nothing of accelerations and
    /// forces). `d` is left at its state (its velocities may be the row's reconciled
    /// ones: the integrator's error moves them alike).
    pub(super) fn column_errors(
        &mut self,
        d: &mut Dynamics,
        e: &[f64],
        positional: &[bool],
        out: &mut Vec<f64>,
    ) {
        out.clear();
        let Some(code) = &self.code else { return };
        let n = d.n;
        let (at, t) = (d.snapshot(), d.sys.time);
        let mut v = d.sys.v();
        for (x, de) in v.iter_mut().zip(e.iter().skip(n)) {
            *x += de;
        }
        d.set_state(&at, &e[..n.min(e.len())], &v, t);
        for &(s, slot) in &self.slots {
            if let Some(o) = slot.filter(reads_state) {
                self.measures[s as usize] = o.value(d);
            }
        }
        d.restore(&at);
        out.resize(self.columns.len(), 0.0);
        code.eval_into(t, &self.measures, out);
        for ((x, &y), &p) in out.iter_mut().zip(&self.row[1..]).zip(positional) {
            *x = if p { (*x - y).abs() } else { f64::NAN };
        }
    }
}
