//! The FMU's inputs and outputs, chosen in the dataset: the VARIABLEs `--inputs` and
//! `--outputs` name (by `adams_view_name`, `VARIABLE/id` or id), else those of its
//! PINPUT and POUTPUT statements, as Adams Controls takes them. Each gets its FMI name
//! (the view name, else `VARIABLE_id`), an input its start value, and both the dimension
//! the units checker infers: an output's from its FUNCTION; an input's, whose FUNCTION
//! only stands in for the controller, from the force it drives (an SFORCE, VFORCE or
//! VTORQUE component that is `VARVAL(id)` alone), else from its FUNCTION.

use crate::check::units::{infer_text, Dim};
use crate::model::elements::{Id, Model, Variable};
use crate::model::ModelRead;

/// One input or output of the FMU.
#[derive(Clone, Debug, PartialEq)]
pub struct Port {
    /// The FMI variable name.
    pub name: String,
    /// The VARIABLE's id.
    pub variable: Id,
    /// An input's start value: the VARIABLE's IC, else its FUNCTION when that is a
    /// number, else 0. Zero for an output.
    pub start: f64,
    /// The dimension the units checker gives it (None: free).
    pub dim: Option<Dim>,
}

/// The FMU's inputs and outputs, in the order asked.
#[derive(Clone, Debug, PartialEq)]
pub struct Interface {
    /// The inputs.
    pub inputs: Vec<Port>,
    /// The outputs.
    pub outputs: Vec<Port>,
}

/// The interface of the dataset `read` (whose text is `text`): `inputs` and `outputs`
/// as named on the command line, or None for the dataset's PINPUT and POUTPUT.
pub fn resolve(
    read: &ModelRead,
    text: &str,
    inputs: Option<&[String]>,
    outputs: Option<&[String]>,
) -> Result<Interface, String> {
    let model = &read.model;
    let ids = |asked: Option<&[String]>, output: bool| -> Result<Vec<Id>, String> {
        match asked {
            Some(names) => names.iter().map(|n| find(model, n)).collect(),
            None => plant_statement(model, output),
        }
    };
    let (input_ids, output_ids) = (ids(inputs, false)?, ids(outputs, true)?);
    if output_ids.is_empty() {
        return Err("the FMU would have no outputs: name them with --outputs".into());
    }
    for id in &input_ids {
        if output_ids.contains(id) {
            return Err(format!(
                "VARIABLE/{id} is both an input and an output: an input's value is set from \
                 outside, so it cannot also be an output"
            ));
        }
    }
    let port = |id: Id, input: bool| -> Result<Port, String> {
        let v = variable(model, id)?;
        let function = &text[v.function.span.clone()];
        let dim = match input {
            true => driven_force(model, text, id).or_else(|| dim_of(read, function)),
            false => dim_of(read, function),
        };
        Ok(Port {
            name: v
                .el
                .name
                .clone()
                .unwrap_or_else(|| format!("VARIABLE_{id}")),
            variable: id,
            start: match input {
                true => v.ic.or_else(|| number(function)).unwrap_or(0.0),
                false => 0.0,
            },
            dim,
        })
    };
    let interface = Interface {
        inputs: input_ids
            .iter()
            .map(|&id| port(id, true))
            .collect::<Result<_, _>>()?,
        outputs: output_ids
            .iter()
            .map(|&id| port(id, false))
            .collect::<Result<_, _>>()?,
    };
    let mut names: Vec<&str> = interface
        .inputs
        .iter()
        .chain(&interface.outputs)
        .map(|p| p.name.as_str())
        .collect();
    names.sort_unstable();
    if let Some(w) = names.windows(2).find(|w| w[0] == w[1]) {
        return Err(format!(
            "two of the FMU's variables are named `{}`: an FMI name must be unique",
            w[0]
        ));
    }
    Ok(interface)
}

/// The VARIABLE `name` stands for: an `adams_view_name` (any case), `VARIABLE/id` or an
/// id.
fn find(model: &Model, name: &str) -> Result<Id, String> {
    let name = name.trim();
    let by_id = name
        .strip_prefix("VARIABLE/")
        .or_else(|| name.strip_prefix("variable/"))
        .unwrap_or(name)
        .parse::<Id>()
        .ok();
    let found = model.variables.iter().find(|v| {
        Some(v.el.id) == by_id
            || v.el
                .name
                .as_deref()
                .is_some_and(|n| n.eq_ignore_ascii_case(name))
    });
    match found {
        Some(v) => Ok(v.el.id),
        None => {
            let known: Vec<String> = model
                .variables
                .iter()
                .map(|v| match &v.el.name {
                    Some(n) => format!("{n} (VARIABLE/{})", v.el.id),
                    None => format!("VARIABLE/{}", v.el.id),
                })
                .collect();
            Err(match known.is_empty() {
                true => format!("`{name}` is not a VARIABLE: the dataset has none"),
                false => format!(
                    "`{name}` is not a VARIABLE of the dataset; it has {}",
                    known.join(", ")
                ),
            })
        }
    }
}

/// The VARIABLE ids of the dataset's POUTPUT (`output`) or PINPUT statements, in order.
fn plant_statement(model: &Model, output: bool) -> Result<Vec<Id>, String> {
    let mut ids: Vec<Id> = Vec::new();
    for p in model.plants.iter().filter(|p| p.output == output) {
        for &id in &p.variables {
            if !ids.contains(&id) {
                ids.push(id);
            }
        }
    }
    match (ids.is_empty(), output) {
        (true, false) => Err("the dataset has no PINPUT: name the inputs with --inputs".into()),
        (true, true) => Err("the dataset has no POUTPUT: name the outputs with --outputs".into()),
        (false, _) => Ok(ids),
    }
}

/// VARIABLE/`id` (a PINPUT or POUTPUT may name one the dataset lacks).
fn variable(model: &Model, id: Id) -> Result<&Variable, String> {
    model
        .variables
        .iter()
        .find(|v| v.el.id == id)
        .ok_or_else(|| format!("VARIABLE/{id} is not in the dataset"))
}

/// The dimension of an expression in the dataset's scope (None: free, or it does not
/// parse, which the reader has already said).
fn dim_of(read: &ModelRead, function: &str) -> Option<Dim> {
    let scope = read.scope();
    infer_text(function, scope, Some(&scope.unit_names))
        .ok()
        .and_then(|(d, _)| d)
}

/// A force or torque whose whole expression is `VARVAL(id)`: the input is that force.
fn driven_force(model: &Model, text: &str, id: Id) -> Option<Dim> {
    let is_input = |span: &std::ops::Range<usize>| {
        let t: String = text[span.clone()]
            .chars()
            .filter(|c| !c.is_whitespace())
            .collect();
        t.eq_ignore_ascii_case(&format!("VARVAL({id})"))
    };
    for s in &model.sforces {
        if is_input(&s.function.span) {
            return Some(if s.rotation { Dim::TORQUE } else { Dim::FORCE });
        }
    }
    for f in &model.vector_forces {
        if f.force.iter().flatten().any(|e| is_input(&e.span)) {
            return Some(Dim::FORCE);
        }
        if f.torque.iter().flatten().any(|e| is_input(&e.span)) {
            return Some(Dim::TORQUE);
        }
    }
    None
}

/// The value of a FUNCTION that is a plain number (`0`, `-1.5E3`).
fn number(function: &str) -> Option<f64> {
    function.trim().replace(['D', 'd'], "E").parse().ok()
}
