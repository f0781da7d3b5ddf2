//! Building a [`Simulation`] from a dataset (read, changed by a command file, analysed,
//! its columns compiled and its dynamics made), running it again from its start with
//! new design values, and why either fails.

use super::{
    reads_reconciled, shadow, standard_component, Column, Engine, Outputs, RunSpec, Simulation,
};
use crate::check::{Expect, Variables};
use crate::diag::{Code, Diagnostic};
use crate::mbd::dynamics::{DynError, Dynamics};
use crate::mbd::error::MbdError;
use crate::mbd::expr::ExprCompiler as _;
use crate::mbd::output_slot::OutputSlot;
use crate::mbd::pipeline::{analyze_model_with, Failure};
use crate::model::command_changes::ModelChange;
use crate::model::elements::Expr;
use crate::model::read_model;
use crate::session::plant::Plant;

/// Where a run stopped before integrating.
pub enum RunFailure {
    /// The dataset (or a probe) has errors; the diagnostics say where. `probe` names the
    /// probe whose text the spans point into.
    Diagnostics {
        /// The probe whose text the spans point into (None: the dataset).
        probe: Option<String>,
        /// The diagnostics, errors and warnings.
        diagnostics: Vec<Diagnostic>,
    },
    /// Reading went well; building, assembly or the redundancy analysis did not.
    Analysis(Failure),
    /// The model cannot be simulated (a force element, a massless part, t = 0 state).
    Dynamics(DynError),
}

impl From<DynError> for RunFailure {
    fn from(e: DynError) -> Self {
        RunFailure::Dynamics(e)
    }
}

impl From<MbdError> for RunFailure {
    fn from(e: MbdError) -> Self {
        RunFailure::Dynamics(DynError::Model(e))
    }
}

/// Why [`Simulation::rewind`] refused.
#[derive(Debug)]
pub enum RewindError {
    /// A constraint reads this design variable.
    ConstraintReads(i64),
    /// The dynamics could not be made again.
    Dynamics(DynError),
    /// A command file changed the model during the last run: its start is another
    /// system's, so a new build is needed.
    ModelChanged,
}

impl Simulation {
    /// Reads, assembles and prepares `text` for `spec`, with `probes` as (name,
    /// expression) columns.
    pub fn new(
        text: &str,
        spec: RunSpec,
        probes: &[(String, String)],
    ) -> Result<Simulation, RunFailure> {
        Self::with_changes(text, spec, probes, &[])
    }

    /// [`Simulation::new`] for a command file whose changes `initial`, written before
    /// its first SIMULATE, make the model the run starts from (Adams View writes the
    /// elements switched off in a model as DEACTIVATE commands there). A change that does
    /// not resolve is left out here; [`Simulation::check_changes`] reports it.
    pub fn with_changes(
        text: &str,
        spec: RunSpec,
        probes: &[(String, String)],
        initial: &[ModelChange],
    ) -> Result<Simulation, RunFailure> {
        let mut read = read_model(text);
        if read.has_errors() {
            return Err(RunFailure::Diagnostics {
                probe: None,
                diagnostics: read.diagnostics,
            });
        }
        let mut inactive = crate::session::changes::Inactive::new();
        for c in initial {
            if let Ok((r, _)) = crate::session::changes::resolve(&mut read, c) {
                r.apply(&mut read.model, &mut inactive);
            }
        }
        // The model built: the dataset without the elements switched off (the dataset
        // itself, not a copy, when none is).
        let switched_off = (!inactive.is_empty())
            .then(|| crate::session::changes::effective(&read.model, &inactive));
        let interpret = spec.engine == Engine::Interp;
        let analysis = analyze_model_with(
            switched_off.as_ref().unwrap_or(&read.model),
            spec.dim,
            interpret,
        )
        .map_err(RunFailure::Analysis)?;
        let mut columns = Vec::new();
        let mut probe_warnings = Vec::new();
        for (name, text) in probes {
            let fail = |diagnostics| RunFailure::Diagnostics {
                probe: Some(name.clone()),
                diagnostics,
            };
            let checked = read
                .compile(text, &Variables::new(), Expect::Scalar)
                .map_err(fail)?;
            if !checked.warnings.is_empty() {
                probe_warnings.push((name.clone(), text.clone(), checked.warnings));
            }
            let e = Expr {
                span: 0..text.len(),
                function: checked.function,
            };
            let function = read.model.inline_variables(&e).map_err(|why| {
                fail(vec![Diagnostic::error(
                    Code::Unsupported,
                    0..text.len(),
                    why,
                )])
            })?;
            columns.push(Column {
                name: name.clone(),
                function: function.function,
                source: e,
                unit: super::column_units::unit_of(&read, text),
            });
        }
        let mut notes = Vec::new();
        for r in read.model.requests.clone() {
            for k in 1..=8 {
                let name = format!("REQ{}.F{k}", r.el.id);
                let (expr, unit) = if let Some((kind, i, j, rm)) = r.standard {
                    let Some(text) =
                        standard_component(kind, i, j.unwrap_or(0), rm.unwrap_or(0), k)
                    else {
                        continue;
                    };
                    match read.compile(&text, &Variables::new(), Expect::Scalar) {
                        Ok(c) => (
                            Expr {
                                span: r.el.span.clone(),
                                function: c.function,
                            },
                            super::column_units::unit_of(&read, &text),
                        ),
                        Err(_) => {
                            notes.push(format!("{name} ({text}) left out: it does not check"));
                            continue;
                        }
                    }
                } else {
                    match r.functions.iter().find(|(n, _)| *n + 1 == k) {
                        Some((_, e)) => {
                            let written = text.get(e.span.clone()).unwrap_or("");
                            (e.clone(), super::column_units::unit_of(&read, written))
                        }
                        None => continue,
                    }
                };
                match read.model.inline_variables(&expr) {
                    Ok(e) => columns.push(Column {
                        name,
                        function: e.function,
                        source: expr,
                        unit,
                    }),
                    Err(why) => notes.push(format!("{name} left out: {why}")),
                }
            }
        }
        // Each CONTACT's normal force, friction force, penetration and slip speed
        // (`CONTACT(id, 0, 9..12, 0)`), then each FRICTION's, after the REQUESTs.
        let contacts = read.model.contacts.iter().flat_map(|c| {
            let id = c.el.id;
            [("FN", 9), ("FF", 10), ("PEN", 11), ("SLIP", 12)].map(|(suffix, comp)| {
                (
                    format!("CONTACT{id}.{suffix}"),
                    format!("CONTACT({id}, 0, {comp}, 0)"),
                )
            })
        });
        let element_columns: Vec<(String, String)> = contacts
            .chain(super::friction_columns::columns(&read.model))
            .collect();
        for (name, text) in element_columns {
            match read.compile(&text, &Variables::new(), Expect::Scalar) {
                Ok(c) => columns.push(Column {
                    name,
                    function: c.function.clone(),
                    source: Expr {
                        span: 0..text.len(),
                        function: c.function,
                    },
                    unit: super::column_units::unit_of(&read, &text),
                }),
                Err(_) => notes.push(format!("{name} ({text}) left out: it does not check")),
            }
        }
        let exprs = analysis.exprs;
        let mut system = analysis.system;
        // (The columns added their measures to the dataset's slots.)
        let switched_off = switched_off.map(|mut m| {
            m.measures.clone_from(&read.model.measures);
            m
        });
        let model = switched_off.as_ref().unwrap_or(&read.model);
        let (meshes, contact_warnings) =
            super::contact_meshes::contact_meshes(model, &spec.geometry);
        if contact_warnings
            .iter()
            .any(|d| d.severity == crate::diag::Severity::Error)
        {
            return Err(RunFailure::Diagnostics {
                probe: None,
                diagnostics: contact_warnings,
            });
        }
        let forces = system.forces_with_meshes(model, &exprs, &meshes)?;
        let mut contact_warnings = contact_warnings;
        contact_warnings.extend(super::contact_meshes::left_out(model, &forces.contacts));
        contact_warnings.extend(super::contact_meshes::held_out(model, &forces.contacts));
        // Energy is conserved only without force elements and without rows that move
        // with time (MOTIONs, time-dependent GCONs) or do work through velocities
        // (non-holonomic GCONs).
        let conservative = forces.elements.is_empty()
            && forces.contacts.is_empty()
            && system
                .rows()
                .all(|(e, q)| !system.row_reads_time(e, q) && !system.row_reads_velocity(e, q));
        // Every slot the columns read, resolved for the dynamics. A probe that reads what
        // the dynamics cannot give is an error; a REQUEST column, a note.
        let mut slots: Vec<(u32, Option<OutputSlot>)> = Vec::new();
        let mut kept = Vec::with_capacity(columns.len());
        for (k, c) in columns.into_iter().enumerate() {
            let mut ok = Ok(());
            for &s in &c.function.uses.measures {
                if slots.iter().any(|(x, _)| *x == s) {
                    continue;
                }
                match OutputSlot::resolve(&mut system, model, s) {
                    Ok(o) => slots.push((s, Some(o))),
                    // An element switched off: the column holds 0 while it is.
                    Err(_)
                        if crate::session::changes::reads_inactive(&read.model, s, &inactive) =>
                    {
                        slots.push((s, None));
                    }
                    Err(e) => {
                        ok = Err(e);
                        break;
                    }
                }
            }
            match ok {
                Ok(()) => kept.push(c),
                Err(e) if k < probes.len() => {
                    let text = &probes[k].1;
                    return Err(RunFailure::Diagnostics {
                        probe: Some(c.name),
                        diagnostics: vec![Diagnostic::error(
                            Code::Unsupported,
                            0..text.len(),
                            e.to_string(),
                        )],
                    });
                }
                Err(e) => notes.push(format!("{} left out: {e}", c.name)),
            }
        }
        let columns = kept;
        let redundant = analysis.redundancy.redundant.len();
        let dropped: Vec<usize> = match spec.keep_redundant {
            true => Vec::new(),
            false => analysis
                .redundancy
                .redundant
                .iter()
                .map(|r| r.row)
                .collect(),
        };
        let constraint_designs: Vec<i64> = read
            .model
            .constraint_designs()
            .into_iter()
            .map(i64::from)
            .collect();
        let plant = Plant::new(model, &exprs, &mut system, &constraint_designs);
        let start = system.start_state();
        let dynamics = Dynamics::new(system, forces, &dropped)?;
        let lifted = shadow(model, &exprs, &dynamics, &slots, &mut notes);
        // Every expression of the model is recorded now: constraints, forces, outputs.
        let functions: Vec<&crate::ir::Function> = columns.iter().map(|c| &c.function).collect();
        let code = match functions.is_empty() {
            true => None,
            false => exprs.fuse(&functions),
        };
        exprs.unify();
        if let Some(e) = exprs.jit_error() {
            notes.push(format!(
                "the JIT could not compile the model ({e}); the interpreter runs it"
            ));
        }
        let measures = vec![0.0; read.model.measures.len()];
        let reconcile = reads_reconciled(&slots, &dynamics);
        Ok(Simulation {
            read,
            dynamics,
            outputs: Outputs {
                columns,
                slots,
                reconcile,
                code,
                measures,
                exprs,
                lifted,
                row: Vec::new(),
            },
            spec,
            notes,
            conservative,
            redundant,
            dropped: dropped.clone(),
            start,
            constraint_designs,
            probe_warnings,
            contact_warnings,
            plant,
            inactive,
            changed: false,
            trace: None,
            recorder: None,
        })
    }

    /// The design variables the model's expressions read (constant VARIABLEs, read by
    /// VARVAL), with their values (the build's, or the last rewind's).
    pub fn designs(&self) -> &[(i64, f64)] {
        self.dynamics.sys.measures.designs()
    }

    /// Makes the simulation ready to run again from t = 0 with the design values
    /// `values` (VARIABLE id, value; the others keep the values it was built with): the
    /// next run gives the bits a simulation built from the dataset with those values
    /// would. Refuses (with the VARIABLE's id) a value of a design variable a constraint
    /// reads, which moves the assembled configuration: that needs a new build.
    pub fn rewind(&mut self, values: &[(i64, f64)]) -> Result<(), RewindError> {
        if let Some(&(id, _)) = values
            .iter()
            .find(|(id, _)| self.constraint_designs.contains(id))
        {
            return Err(RewindError::ConstraintReads(id));
        }
        if self.changed {
            return Err(RewindError::ModelChanged);
        }
        let sys = &mut self.dynamics.sys;
        sys.rewind_to(&self.start);
        for &(id, v) in values {
            sys.measures.set_design(id, v);
        }
        self.dynamics
            .restart(&self.dropped)
            .map_err(RewindError::Dynamics)?;
        if let Some(lifted) = &mut self.outputs.lifted {
            lifted.rewind(values).map_err(RewindError::Dynamics)?;
        }
        Ok(())
    }

    /// How many JIT modules hold the model's compiled expressions: 1 with the JIT (every
    /// GCON, MOTION, force component and output column in one), 0 interpreted.
    pub fn jit_modules(&self) -> usize {
        self.outputs.exprs.modules()
    }

    /// The column headers: `time`, then the probes, then the request components.
    pub fn header(&self) -> Vec<String> {
        std::iter::once("time".to_string())
            .chain(self.outputs.columns.iter().map(|c| c.name.clone()))
            .collect()
    }

    /// The unit of each column of [`Simulation::header`], in the dataset's units
    /// ("second", "meter", "newton"; "1" dimensionless, "" when the units checker cannot
    /// tell): what a chart with one panel per unit groups by.
    pub fn units(&self) -> Vec<String> {
        std::iter::once(super::column_units::time_unit(&self.read))
            .chain(self.outputs.columns.iter().map(|c| c.unit.clone()))
            .collect()
    }
}
