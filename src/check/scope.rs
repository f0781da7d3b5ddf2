//! Scopes: what the names of an expression refer to outside the builtins table.
//!
//! A [`Scope`] answers for user variables, SPLINE data and measures. Outside a model
//! ([`Variables`]), measures are errors that say a model is needed; the multibody core
//! supplies a scope that resolves marker IDs to measure slots.

use super::units::{Dim, UnitNames};
use crate::diag::{Code, Diagnostic, Span};
use crate::vocab::builtins::{self, Builtin, Needs, Role, Ty};

/// A measure call as written: which builtin and its integer-literal arguments.
pub struct MeasureCall<'a> {
    /// The measure's builtin (`DX`, `VR`, ...).
    pub builtin: &'static Builtin,
    /// The integer-literal arguments (marker or element ids, codes).
    pub ids: &'a [i64],
    /// Span of each ID argument.
    pub arg_spans: &'a [Span],
    /// Span of the whole call.
    pub span: Span,
}

/// Where a resolved measure's value will be in the evaluation context.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeasureValue {
    /// A scalar measure: its slot.
    Scalar(u32),
    /// A vector measure: the slots of its three components.
    Vector([u32; 3]),
}

/// A SPLINE the host supplies: its index in the context's spline table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SplineInfo {
    /// Index in the context's spline table.
    pub index: u32,
    /// True for a surface (several curves at increasing z).
    pub surface: bool,
}

/// Resolves the names an expression uses beyond the builtins.
pub trait Scope {
    /// Slot of the user variable `name` (upper case), if defined.
    fn variable(&self, name: &str) -> Option<u32>;

    /// Every variable name, for "did you mean" hints.
    fn variable_names(&self) -> Vec<String> {
        Vec::new()
    }

    /// The SPLINE with this ID, if the host supplies one.
    fn spline(&self, _id: i64) -> Option<SplineInfo> {
        None
    }

    /// Resolves a measure call. Without a model every measure is an error.
    fn measure(&self, call: &MeasureCall) -> Result<MeasureValue, Diagnostic> {
        Err(needs_model(call))
    }

    /// The names of the units, when expressions are to be checked for units of measure
    /// (see [`super::units`]); `None`, the default, skips that check.
    fn unit_names(&self) -> Option<&UnitNames> {
        None
    }

    /// True when expressions are to be checked for units of measure: when there are unit
    /// names, or (a scope of plain variables) when a variable was given a dimension, in
    /// which case messages name the bases ("a velocity (length/time)").
    fn checks_units(&self) -> bool {
        self.unit_names().is_some()
    }

    /// The dimension of the user variable `name` (upper case); `None`, the default, makes
    /// it free like a number.
    fn variable_dim(&self, _name: &str) -> Option<Dim> {
        None
    }

    /// The dimension of the value of VARIABLE/`id`; `None`, the default, makes it free.
    fn varval_dim(&self, _id: i64) -> Option<Dim> {
        None
    }
}

/// The "needs a model" diagnostic for a measure evaluated where there is none.
pub fn needs_model(call: &MeasureCall) -> Diagnostic {
    let b = call.builtin;
    let what = match b.role {
        Role::Measure(Needs::State) => "reads a model element",
        Role::Measure(Needs::Force) => "measures forces of a model",
        _ => "is a measure of a model",
    };
    let kind = if b.result == Ty::Vector {
        "vector "
    } else {
        ""
    };
    Diagnostic::error(
        Code::NeedsModel,
        call.span.clone(),
        format!("{} {what}; it needs a model", b.name),
    )
    .with_note(format!("{kind}signature: {}", b.signature()))
    .with_help("load a model: mbfx eval --model FILE.adm, or :load FILE.adm in the REPL")
}

/// Why a name cannot be a user variable.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BadVariableName {
    /// Not a letter or `_` followed by letters, digits and `_`.
    NotAName,
    /// A function, measure or constant of the language.
    Builtin,
}

impl BadVariableName {
    /// The message for `name`, e.g. "`PI` is a builtin name".
    pub fn message(self, name: &str) -> String {
        match self {
            BadVariableName::NotAName => format!("`{name}` is not a valid variable name"),
            BadVariableName::Builtin => format!("`{name}` is a builtin name"),
        }
    }

    /// What to do instead.
    pub fn help(self) -> &'static str {
        match self {
            BadVariableName::NotAName => {
                "variable names start with a letter and hold letters, digits and _"
            }
            BadVariableName::Builtin => "choose a name that is no function or constant",
        }
    }
}

/// Checks that `name` can name a user variable (the rule `--var` and `:let` share).
pub fn check_variable_name(name: &str) -> Result<(), BadVariableName> {
    let valid = name.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_')
        && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
    if !valid {
        Err(BadVariableName::NotAName)
    } else if builtins::lookup(&name.to_ascii_uppercase()).is_some() {
        Err(BadVariableName::Builtin)
    } else {
        Ok(())
    }
}

/// A scope of named user variables and host-supplied splines, with no model.
#[derive(Clone, Debug, Default)]
pub struct Variables {
    names: Vec<String>,
    /// The dimension a user gave each variable (`--unit`), in slot order; a variable
    /// without one is free like a number.
    dims: Vec<Option<Dim>>,
    /// (SPLINE id, is a surface), indexed like the context's spline table.
    splines: Vec<(i64, bool)>,
}

impl Variables {
    /// A scope with no variables and no splines.
    pub fn new() -> Self {
        Self::default()
    }

    /// Defines a variable (case-insensitive) and returns its slot; redefining a name
    /// returns its existing slot.
    pub fn define(&mut self, name: &str) -> u32 {
        let upper = name.to_ascii_uppercase();
        if let Some(i) = self.names.iter().position(|n| *n == upper) {
            return i as u32;
        }
        self.names.push(upper);
        (self.names.len() - 1) as u32
    }

    /// Gives the variable `name` (defined before) the dimension `dim`, which turns the
    /// units check on for this scope; false when there is no such variable.
    pub fn set_dim(&mut self, name: &str, dim: Dim) -> bool {
        let upper = name.to_ascii_uppercase();
        let Some(slot) = self.names.iter().position(|n| *n == upper) else {
            return false;
        };
        if self.dims.len() < self.names.len() {
            self.dims.resize(self.names.len(), None);
        }
        self.dims[slot] = Some(dim);
        true
    }

    /// The dimension given to variable `name` (upper case), if any.
    pub fn dim(&self, name: &str) -> Option<Dim> {
        let slot = self.names.iter().position(|n| n == name)?;
        self.dims.get(slot).copied().flatten()
    }

    /// True when some variable has a dimension.
    pub fn has_dims(&self) -> bool {
        self.dims.iter().any(Option::is_some)
    }

    /// Registers SPLINE `id` at the next index of the context's spline table.
    pub fn define_spline(&mut self, id: i64, surface: bool) -> u32 {
        self.splines.push((id, surface));
        (self.splines.len() - 1) as u32
    }

    /// Variable names in slot order.
    pub fn names(&self) -> &[String] {
        &self.names
    }
}

impl Scope for Variables {
    fn variable(&self, name: &str) -> Option<u32> {
        self.names.iter().position(|n| n == name).map(|i| i as u32)
    }

    fn checks_units(&self) -> bool {
        self.has_dims()
    }

    fn variable_dim(&self, name: &str) -> Option<Dim> {
        self.dim(name)
    }

    fn variable_names(&self) -> Vec<String> {
        self.names.clone()
    }

    fn spline(&self, id: i64) -> Option<SplineInfo> {
        self.splines
            .iter()
            .position(|(i, _)| *i == id)
            .map(|index| SplineInfo {
                index: index as u32,
                surface: self.splines[index].1,
            })
    }
}

/// A scope standing in for a model that defines every marker, element and SPLINE an
/// expression names: for checking expressions apart from their model (the corpus tests,
/// benchmarks and fuzzing use it). Measures resolve to slot 0 (vectors to 0, 1, 2), so the
/// IR it yields is for checking, not for evaluating against real data. Units are checked,
/// in SI, as a dataset without UNITS would be.
#[derive(Clone, Copy, Debug, Default)]
pub struct EveryIdExists;

impl Scope for EveryIdExists {
    fn variable(&self, _: &str) -> Option<u32> {
        None
    }

    fn spline(&self, _: i64) -> Option<SplineInfo> {
        Some(SplineInfo {
            index: 0,
            surface: false,
        })
    }

    fn unit_names(&self) -> Option<&UnitNames> {
        static SI: UnitNames = UnitNames::SI;
        Some(&SI)
    }

    fn measure(&self, call: &MeasureCall) -> Result<MeasureValue, Diagnostic> {
        Ok(match call.builtin.result {
            Ty::Scalar => MeasureValue::Scalar(0),
            Ty::Vector => MeasureValue::Vector([0, 1, 2]),
        })
    }
}
