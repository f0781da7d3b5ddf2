//! The model as the scope of its expressions: a measure call resolves to a slot of
//! [`super::elements::Model::measures`] (equal calls share one slot, a vector measure
//! takes three), after its marker ids are checked against the dataset's markers and its
//! element ids (`VARVAL(3)`, `JOINT(1,0,2,0)`, `SFORCE(5,…)`) against the elements.

use super::elements::MeasureSlot;
use crate::check::units::{Dim, UnitNames};
use crate::check::{MeasureCall, MeasureValue, Scope, SplineInfo};
use crate::diag::{Code, Diagnostic};
use crate::vocab::builtins::{Param, Ty};
use std::cell::{Cell, RefCell};
use std::collections::{HashMap, HashSet};

/// Which statement an element function's first argument names, and whether mbfx models
/// that statement (the rest are outside the subset, spec §2.5).
pub fn element_statement(function: &str) -> Option<(&'static str, bool)> {
    Some(match function {
        "SFORCE" => ("SFORCE", true),
        "VFORCE" => ("VFORCE", true),
        "VTORQ" => ("VTORQUE", true),
        "GFORCE" => ("GFORCE", true),
        "BUSH" => ("BUSHING", true),
        "CONTACT" => ("CONTACT", true),
        "SPDP" => ("SPRINGDAMPER", true),
        "JOINT" => ("JOINT", true),
        "JPRIM" => ("JPRIM", true),
        "MOTION" => ("MOTION", true),
        "VARVAL" => ("VARIABLE", true),
        "ARYVAL" => ("ARRAY", true),
        "BEAM" => ("BEAM", true),
        "FIELD" => ("FIELD", true),
        "FRICTION" => ("FRICTION", true),
        "CVCV" => ("CVCV", false),
        "PTCV" => ("PTCV", false),
        "NFORCE" => ("NFORCE", false),
        "DIF" | "DIF1" => ("DIFF", true),
        "PINVAL" => ("PINPUT", false),
        "POUVAL" => ("POUTPUT", false),
        "SENVAL" => ("SENSOR", false),
        _ => return None,
    })
}

/// Ids the dataset defines and the measure slots its expressions have asked for.
pub struct ModelScope {
    /// Ids per canonical statement keyword; MARKER holds only the markers mbfx models.
    pub ids: HashMap<&'static str, HashSet<i64>>,
    /// Elements whose values come from a `USER(…)` subroutine: mbfx leaves them out.
    pub user: HashSet<(&'static str, i64)>,
    /// SPLINE ids in the order of [`super::elements::Model::splines`], and whether each
    /// is a surface.
    pub splines: Vec<(i64, bool)>,
    slots: RefCell<Slots>,
    /// Warnings found while resolving (measures of elements outside the subset).
    warnings: RefCell<Vec<Diagnostic>>,
    /// Check only: measures are resolved to slot 0 and no slot is added (for the
    /// expressions of statements outside the subset, which nothing evaluates).
    pub check_only: Cell<bool>,
    /// The dataset's units, for the units check of its expressions.
    pub unit_names: UnitNames,
    /// The dimensions of the VARIABLEs, for VARVAL in the units check.
    pub variable_dims: super::variable_dims::VariableDims,
}

impl Default for ModelScope {
    fn default() -> Self {
        ModelScope {
            ids: HashMap::new(),
            user: HashSet::new(),
            splines: Vec::new(),
            slots: RefCell::default(),
            warnings: RefCell::default(),
            check_only: Cell::default(),
            unit_names: UnitNames::SI,
            variable_dims: Default::default(),
        }
    }
}

#[derive(Default)]
struct Slots {
    list: Vec<MeasureSlot>,
    index: HashMap<MeasureSlot, u32>,
}

impl ModelScope {
    /// Whether the dataset declares `statement`/`id` (`has("MARKER", 3)`).
    pub fn has(&self, statement: &str, id: i64) -> bool {
        self.ids.get(statement).is_some_and(|s| s.contains(&id))
    }

    fn slot(&self, name: &str, ids: &[i64], component: u8) -> u32 {
        if self.check_only.get() {
            return 0;
        }
        let key = MeasureSlot {
            name: name.to_string(),
            ids: ids.to_vec(),
            component,
        };
        let mut s = self.slots.borrow_mut();
        if let Some(&i) = s.index.get(&key) {
            return i;
        }
        let i = s.list.len() as u32;
        s.list.push(key.clone());
        s.index.insert(key, i);
        i
    }

    /// The measure slots asked for so far, in slot order.
    pub fn slots(&self) -> Vec<MeasureSlot> {
        self.slots.borrow().list.clone()
    }

    /// Warnings collected since the last call.
    pub fn take_warnings(&self) -> Vec<Diagnostic> {
        std::mem::take(&mut self.warnings.borrow_mut())
    }
}

impl std::fmt::Debug for ModelScope {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ModelScope")
            .field("slots", &self.slots.borrow().list.len())
            .finish_non_exhaustive()
    }
}

/// The model's measures together with user variables: the scope of an expression typed
/// against a loaded model (`mbfx eval --model`, the REPL after `:load`).
pub struct WithVariables<'a> {
    /// The dataset's measures and ids.
    pub model: &'a ModelScope,
    /// The user variables defined so far.
    pub variables: &'a crate::check::Variables,
}

impl Scope for WithVariables<'_> {
    fn variable(&self, name: &str) -> Option<u32> {
        self.variables.variable(name)
    }

    fn spline(&self, id: i64) -> Option<SplineInfo> {
        self.model.spline(id)
    }

    fn measure(&self, call: &MeasureCall) -> Result<MeasureValue, Diagnostic> {
        self.model.measure(call)
    }

    // Expressions typed against a model (`mbfx eval --model`, the REPL, `--probe`) are
    // checked for units in the dataset's units, as its own are.
    fn unit_names(&self) -> Option<&UnitNames> {
        Some(&self.model.unit_names)
    }

    fn variable_dim(&self, name: &str) -> Option<Dim> {
        self.variables.dim(name)
    }

    fn varval_dim(&self, id: i64) -> Option<Dim> {
        self.model.varval_dim(id)
    }
}

impl Scope for ModelScope {
    fn variable(&self, _: &str) -> Option<u32> {
        None
    }

    fn unit_names(&self) -> Option<&UnitNames> {
        Some(&self.unit_names)
    }

    fn varval_dim(&self, id: i64) -> Option<Dim> {
        self.variable_dims.dim(id, self)
    }

    fn spline(&self, id: i64) -> Option<SplineInfo> {
        let index = self.splines.iter().position(|(s, _)| *s == id)?;
        Some(SplineInfo {
            index: index as u32,
            surface: self.splines[index].1,
        })
    }

    fn measure(&self, call: &MeasureCall) -> Result<MeasureValue, Diagnostic> {
        let b = call.builtin;
        let element = element_statement(b.name);
        let span_of = |i: usize| {
            call.arg_spans
                .get(i)
                .cloned()
                .unwrap_or_else(|| call.span.clone())
        };
        for (i, p) in b.params.iter().enumerate() {
            let (Param::Id, Some(&id)) = (p, call.ids.get(i)) else {
                continue;
            };
            let stmt = match (i, element) {
                (0, Some((stmt, _))) if self.user.contains(&(stmt, id)) => {
                    self.warnings.borrow_mut().push(
                        Diagnostic::warning(
                            Code::UnsupportedStatement,
                            span_of(i),
                            format!(
                                "{} reads {stmt}/{id}, which calls a USER subroutine",
                                b.name
                            ),
                        )
                        .with_note("the value cannot be computed"),
                    );
                    stmt
                }
                (0, Some((stmt, supported))) => {
                    if !supported && self.has(stmt, id) {
                        self.warnings.borrow_mut().push(
                            Diagnostic::warning(
                                Code::UnsupportedStatement,
                                span_of(i),
                                format!("{} reads {stmt}/{id}, which mbfx does not model", b.name),
                            )
                            .with_note("the value cannot be computed"),
                        );
                    }
                    stmt
                }
                _ => "MARKER",
            };
            let optional_ground = stmt == "MARKER" && id == 0 && i > 0;
            if !optional_ground && !self.has(stmt, id) {
                return Err(Diagnostic::error(
                    Code::UndefinedElement,
                    span_of(i),
                    format!("{stmt}/{id} is not defined in this dataset"),
                )
                .with_note(format!("{} reads it", b.name)));
            }
        }
        Ok(match b.result {
            Ty::Scalar => MeasureValue::Scalar(self.slot(b.name, call.ids, 0)),
            Ty::Vector => MeasureValue::Vector([0u8, 1, 2].map(|c| self.slot(b.name, call.ids, c))),
        })
    }
}
