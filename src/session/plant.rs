//! A dataset's plant inputs and outputs (PINPUT, POUTPUT) made ready when the model is
//! built, for a LINEAR/STATEMAT that names them: each output VARIABLE compiled with its
//! measures resolved (the system is still open to new measures then), each input
//! checked to be a design variable the constraints do not read. What cannot be used is
//! kept as the reason, reported only if a command asks for it.

use crate::mbd::expr::ExprCompiler;
use crate::mbd::linear::plant::Output;
use crate::mbd::system::System;
use crate::model::elements::{Id, Model, PlantVariables};
use crate::model::linear_command::Linear;

/// The plant statements of a model, ready.
#[derive(Default)]
pub struct Plant {
    statements: Vec<PlantVariables>,
    /// Each output VARIABLE's expression, or why it cannot be one.
    outputs: Vec<(Id, Result<Output, String>)>,
    /// Each input VARIABLE, or why it cannot be one.
    inputs: Vec<(Id, Result<(), String>)>,
}

impl Plant {
    /// The plant statements of `model`, their outputs compiled by `exprs` into `sys`;
    /// `constraint_designs` are the design variables a constraint reads.
    pub fn new(
        model: &Model,
        exprs: &dyn ExprCompiler,
        sys: &mut System,
        constraint_designs: &[i64],
    ) -> Plant {
        let mut plant = Plant {
            statements: model.plants.clone(),
            ..Plant::default()
        };
        for p in &model.plants {
            for &id in &p.variables {
                match p.output {
                    true if !plant.outputs.iter().any(|(x, _)| *x == id) => {
                        plant.outputs.push((id, output(model, exprs, sys, id)));
                    }
                    false if !plant.inputs.iter().any(|(x, _)| *x == id) => {
                        plant
                            .inputs
                            .push((id, input(model, id, constraint_designs)));
                    }
                    _ => {}
                }
            }
        }
        plant
    }

    /// The inputs (design variable ids) and outputs `command` names, or why they cannot
    /// be used.
    pub fn resolve(&self, command: &Linear) -> Result<(Vec<i64>, Vec<&Output>), String> {
        let mut inputs = Vec::new();
        if let Some(p) = &command.pinput {
            for id in self.statement(p.value, false)? {
                match self.inputs.iter().find(|(x, _)| *x == id) {
                    Some((_, Err(why))) => return Err(why.clone()),
                    _ => inputs.push(i64::from(id)),
                }
            }
        }
        let mut outputs = Vec::new();
        if let Some(p) = &command.poutput {
            for id in self.statement(p.value, true)? {
                match self.outputs.iter().find(|(x, _)| *x == id) {
                    Some((_, Ok(o))) => outputs.push(o),
                    Some((_, Err(why))) => return Err(why.clone()),
                    None => return Err(format!("VARIABLE/{id} was not prepared")),
                }
            }
        }
        Ok((inputs, outputs))
    }

    fn statement(&self, id: Id, output: bool) -> Result<Vec<Id>, String> {
        let kind = if output { "POUTPUT" } else { "PINPUT" };
        self.statements
            .iter()
            .find(|p| p.el.id == id && p.output == output)
            .map(|p| p.variables.clone())
            .ok_or_else(|| format!("{kind}/{id} is not in the dataset"))
    }
}

/// Output VARIABLE/`id` compiled, its measures resolved into `sys`.
fn output(
    model: &Model,
    exprs: &dyn ExprCompiler,
    sys: &mut System,
    id: Id,
) -> Result<Output, String> {
    let v = model.variable(id).ok_or_else(|| {
        format!(
            "VARIABLE/{id} (an output) is not in the dataset, or has no FUNCTION mbfx evaluates"
        )
    })?;
    let e = model.inline_variables(&v.function)?;
    let f = exprs.compile(&e);
    let map = sys
        .resolve_slots(model, f.slots())
        .map_err(|e| format!("VARIABLE/{id} (an output): {e}"))?;
    Ok(Output {
        name: format!("VARIABLE/{id}"),
        f,
        map,
    })
}

/// Whether VARIABLE/`id` can be an input: a design variable (constant FUNCTION) no
/// constraint reads.
fn input(model: &Model, id: Id, constraint_designs: &[i64]) -> Result<(), String> {
    if model.variable(id).is_none() {
        return Err(format!(
            "VARIABLE/{id} (an input) is not in the dataset, or has no FUNCTION mbfx evaluates"
        ));
    }
    if model.design_value(id).is_none() {
        return Err(format!("VARIABLE/{id} (an input) has a FUNCTION of time or the state; an input's FUNCTION must be a constant, its value the input's (FUNCTION = 0, as Adams Controls writes it)"));
    }
    if constraint_designs.contains(&i64::from(id)) {
        return Err(format!("VARIABLE/{id} (an input) is read by a MOTION or GCON; mbfx takes inputs through forces only"));
    }
    Ok(())
}
