//! The names a [`super::Stepping`]'s caller reads and sets: the outputs (the dataset's
//! POUTPUT VARIABLEs, then the probes) and the inputs (its PINPUT VARIABLEs, or any
//! design variable), each VARIABLE by its `adams_view_name`, else as `VARIABLE/id`.

use crate::model::elements::{Id, Model};
use crate::session::request::built;
use crate::session::request::{RunFailed, RunRequest};
use crate::session::run::Simulation;

/// The name of VARIABLE/`id` in `model`: its `adams_view_name`, else `VARIABLE/id`.
fn variable_name(model: &Model, id: Id) -> String {
    (model.variable(id).and_then(|v| v.el.name.clone())).unwrap_or_else(|| format!("VARIABLE/{id}"))
}

/// The VARIABLEs of `model`'s PINPUTs (`output` false) or POUTPUTs, in order, once each.
fn plant_variables(model: &Model, output: bool) -> Vec<Id> {
    let mut ids = Vec::new();
    for p in model.plants.iter().filter(|p| p.output == output) {
        for &id in &p.variables {
            if !ids.contains(&id) {
                ids.push(id);
            }
        }
    }
    ids
}

/// The simulation `request` asks for, with the POUTPUT VARIABLEs as its first columns
/// (`VARVAL(id)`, named as [`variable_name`] says), its source, and those columns.
pub(super) fn build(request: &RunRequest) -> Result<built::BuiltSimulation, Box<RunFailed>> {
    let outputs = |model: &Model| {
        (plant_variables(model, true).into_iter())
            .map(|id| (variable_name(model, id), format!("VARVAL({id})")))
            .collect()
    };
    built::simulation(request, &outputs)
}

/// A stepping's inputs: the PINPUT VARIABLEs' names and ids, and the names found
/// settable so far (a controller sets the same few at every step).
pub(super) struct Inputs {
    plant: Vec<(String, i64)>,
    found: Vec<(String, i64)>,
}

impl Inputs {
    /// The PINPUT VARIABLEs of `sim`'s model.
    pub(super) fn of(sim: &Simulation) -> Inputs {
        let model = &sim.read.model;
        Inputs {
            plant: (plant_variables(model, false).into_iter())
                .map(|id| (variable_name(model, id), i64::from(id)))
                .collect(),
            found: Vec::new(),
        }
    }

    /// The PINPUT VARIABLEs' names.
    pub(super) fn plant_names(&self) -> Vec<String> {
        self.plant.iter().map(|(n, _)| n.clone()).collect()
    }

    /// [`Inputs::find`], remembered: the checks read the model, and a name found once
    /// stays settable.
    pub(super) fn find_kept(&mut self, sim: &Simulation, name: &str) -> Result<i64, String> {
        if let Some(&(_, id)) = self.found.iter().find(|(n, _)| n == name) {
            return Ok(id);
        }
        let id = self.find(sim, name)?;
        self.found.push((name.to_string(), id));
        Ok(id)
    }

    /// The design variable `name` names (a PINPUT VARIABLE's name, `VARIABLE/id`, or a
    /// VARIABLE's `adams_view_name`, any case), or why it cannot be set.
    pub(super) fn find(&self, sim: &Simulation, name: &str) -> Result<i64, String> {
        let model = &sim.read.model;
        let wanted = name.trim();
        let by_id = (wanted.get(..9))
            .filter(|k| k.eq_ignore_ascii_case("VARIABLE/"))
            .and_then(|_| wanted[9..].trim().parse::<Id>().ok());
        let id = (self.plant.iter())
            .find(|(n, _)| n.eq_ignore_ascii_case(wanted))
            .map(|&(_, id)| id)
            .or(by_id.map(i64::from))
            .or_else(|| {
                (model.variables.iter())
                    .find(|v| {
                        v.el.name
                            .as_deref()
                            .is_some_and(|n| n.eq_ignore_ascii_case(wanted))
                    })
                    .map(|v| i64::from(v.el.id))
            });
        let Some(id) = id else {
            let inputs = match self.plant.is_empty() {
                true => "the dataset has no PINPUT".to_string(),
                false => format!("the PINPUT inputs are {}", self.plant_names().join(", ")),
            };
            return Err(format!(
                "no input {name}: {inputs}; any design variable may be set too, as VARIABLE/id or by its name"
            ));
        };
        let Ok(var) = Id::try_from(id) else {
            return Err(format!("no VARIABLE/{id} in the dataset"));
        };
        if model.variable(var).is_none() {
            return Err(format!("no VARIABLE/{id} in the dataset"));
        }
        if model.design_value(var).is_none() {
            return Err(format!("VARIABLE/{id} is not an input: its FUNCTION reads time, the state or another VARIABLE; an input's FUNCTION is a constant (FUNCTION = 0, as Adams Controls writes it)"));
        }
        if sim.constraint_reads(id) {
            return Err(format!("VARIABLE/{id} is read by a MOTION or GCON, whose values are built into the assembled model: it cannot be an input"));
        }
        if !sim.designs().iter().any(|&(d, _)| d == id) {
            return Err(format!(
                "VARIABLE/{id} is read by no force or output: setting it would change nothing"
            ));
        }
        Ok(id)
    }
}
