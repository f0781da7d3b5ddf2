//! Typed access to one statement's arguments for the model reader: each lookup marks the
//! argument as used and reports values of the wrong kind (`E0605`) or missing required
//! arguments (`E0604`); [`Args::finish`] reports every argument nothing asked for
//! (`W0602`), so no argument is dropped silently.

use super::elements::Id;
use super::keywords::abbreviates;
use super::statement::{ArgValue, Argument, ItemKind, Statement};
use crate::diag::{Code, Diagnostic, Span};
use crate::vocab::math::Vec3;
use std::ops::RangeInclusive;

/// Arguments that configure joint friction, which mbfx does not model (spec §2.5).
const FRICTION_ARGUMENTS: &[&str] = &[
    "MU_DYN_ROT",
    "MU_STAT_ROT",
    "MAX_FRIC_ROT",
    "MU_DYN_TRANS",
    "MU_STAT_TRANS",
    "MAX_FRIC_TRANS",
    "PRELOAD_RADIAL",
    "PRELOAD_AXIAL",
    "INNER_RADIUS",
    "OUTER_RADIUS",
    "DELTA_V",
    "MAXIMUM_DEFORMATION",
    "FRICTION",
    "FRICTION_ARM",
    "BENDING_REACTION_ARM",
    "PIN_RADIUS",
    "STICTION_TRANSITION_VELOCITY",
    "TRANSITION_VELOCITY_COEFFICIENT",
    "MAX_STICTION_DEFORMATION",
    "EFFECT",
    "INPUTS",
    "TORSIONAL_MOMENT",
    "BENDING_MOMENT",
    "RADIAL_FORCE",
    "AXIAL_FORCE",
    "PRELOAD_ONLY",
];

/// `KIND/id (view name)`, the way messages name a statement.
pub fn statement_label(stmt: &Statement) -> String {
    let kind = stmt.canonical.unwrap_or(&stmt.keyword);
    let head = match stmt.id {
        Some(id) => format!("{kind}/{id}"),
        None => kind.to_string(),
    };
    match &stmt.view_name {
        Some(name) => format!("{head} ({name})"),
        None => head,
    }
}

/// The arguments of one statement, with what has been asked for so far.
pub struct Args<'s> {
    pub stmt: &'s Statement,
    /// [`statement_label`] of the statement.
    pub label: String,
    used: Vec<bool>,
    pub diags: Vec<Diagnostic>,
}

impl<'s> Args<'s> {
    pub fn new(stmt: &'s Statement) -> Self {
        Args {
            stmt,
            label: statement_label(stmt),
            used: vec![false; stmt.args.len()],
            diags: Vec::new(),
        }
    }

    /// The first argument written as `full` or an abbreviation of it at least `min` long;
    /// marks every such argument used, warning about repeats.
    pub fn find(&mut self, full: &str, min: usize) -> Option<&'s Argument> {
        let stmt = self.stmt;
        let mut first = None;
        for (i, a) in stmt.args.iter().enumerate() {
            if !abbreviates(&a.name, full, min) || self.used[i] {
                continue;
            }
            self.used[i] = true;
            if first.is_none() {
                first = Some(a);
            } else {
                self.diags.push(
                    Diagnostic::warning(
                        Code::UnsupportedStatement,
                        a.name_span.clone(),
                        format!("{full} is given twice in {}", self.label),
                    )
                    .with_note("the first value is used"),
                );
            }
        }
        first
    }

    /// True when the flag (or any form of the argument) is present.
    pub fn flag(&mut self, full: &str, min: usize) -> bool {
        match self.find(full, min) {
            Some(a) if a.value != ArgValue::Flag => {
                self.error(
                    Code::BadArgument,
                    a.span.clone(),
                    format!("{full} is a flag and takes no value"),
                );
                true
            }
            found => found.is_some(),
        }
    }

    /// Which one of several flags is present (`REVOLUTE`, `SPHERICAL`, ...); an error
    /// when more than one is.
    pub fn choice(&mut self, options: &[(&str, usize)]) -> Option<usize> {
        let mut hit: Option<(usize, &Argument)> = None;
        for (k, (full, min)) in options.iter().enumerate() {
            let Some(a) = self.find(full, *min) else {
                continue;
            };
            if let Some((_, first)) = hit {
                let msg = format!(
                    "{} and {} exclude each other in {}",
                    first.name, a.name, self.label
                );
                self.error(Code::BadArgument, a.name_span.clone(), msg);
            } else {
                hit = Some((k, a));
            }
        }
        hit.map(|(k, _)| k)
    }

    /// The numbers of a list argument, `count` of them; reports other values.
    pub fn numbers(
        &mut self,
        full: &str,
        min: usize,
        count: RangeInclusive<usize>,
    ) -> Option<Vec<f64>> {
        let a = self.find(full, min)?;
        let values = self.numbers_of(a)?;
        if !count.contains(&values.len()) {
            let want = if count.start() == count.end() {
                count.start().to_string()
            } else if *count.end() == usize::MAX {
                format!("at least {}", count.start())
            } else {
                format!("{} to {}", count.start(), count.end())
            };
            let msg = format!("{full} takes {want} numbers, found {}", values.len());
            self.error(Code::BadArgument, a.span.clone(), msg);
            return None;
        }
        Some(values)
    }

    /// Every item of a list argument as a number (radians where a `D` says degrees).
    pub fn numbers_of(&mut self, a: &Argument) -> Option<Vec<f64>> {
        let mut out = Vec::with_capacity(a.items().len());
        for item in a.items() {
            match item.as_f64() {
                Some(v) if v.is_finite() => out.push(v),
                // Reported where the statement was read (E0607): no value, no second message.
                Some(_) => return None,
                None => {
                    let msg = format!("{}: expected a number, found `{}`", a.name, item.text);
                    self.error(Code::BadArgument, item.span.clone(), msg);
                    return None;
                }
            }
        }
        if out.is_empty() {
            let msg = format!("{} needs a value", a.name);
            self.error(Code::BadArgument, a.span.clone(), msg);
            return None;
        }
        Some(out)
    }

    pub fn number(&mut self, full: &str, min: usize) -> Option<f64> {
        self.numbers(full, min, 1..=1).map(|v| v[0])
    }

    pub fn vec3(&mut self, full: &str, min: usize) -> Option<Vec3> {
        self.numbers(full, min, 3..=3)
            .map(|v| Vec3::new(v[0], v[1], v[2]))
    }

    /// An element reference (`I = 0102`): one non-negative integer.
    pub fn id(&mut self, full: &str, min: usize) -> Option<(Id, Span)> {
        let a = self.find(full, min)?;
        let item = match a.items() {
            [one] => one,
            _ => {
                let msg = format!("{full} takes one id");
                self.error(Code::BadArgument, a.span.clone(), msg);
                return None;
            }
        };
        match item.as_integer().and_then(|v| Id::try_from(v).ok()) {
            Some(id) => Some((id, item.span.clone())),
            None => {
                let msg = format!("{full}: expected an id, found `{}`", item.text);
                self.error(Code::BadArgument, item.span.clone(), msg);
                None
            }
        }
    }

    /// A reference the statement cannot do without.
    pub fn required_id(&mut self, full: &str, min: usize) -> Option<(Id, Span)> {
        let found = self.find_untouched(full, min);
        let id = self.id(full, min);
        if !found {
            self.missing(&format!("{full} = id"));
        }
        id
    }

    /// A number the statement cannot do without (`E0604` at the keyword when absent).
    pub fn required_number(&mut self, full: &str, min: usize) -> Option<f64> {
        let found = self.find_untouched(full, min);
        let v = self.number(full, min);
        if !found {
            self.missing(&format!("{full} = value"));
        }
        v
    }

    fn find_untouched(&self, full: &str, min: usize) -> bool {
        self.stmt
            .args
            .iter()
            .enumerate()
            .any(|(i, a)| !self.used[i] && abbreviates(&a.name, full, min))
    }

    /// A word value (`SYSTEM = MKS`): its text and span.
    pub fn word(&mut self, full: &str, min: usize) -> Option<(&'s str, Span)> {
        let a = self.find(full, min)?;
        match a.items() {
            [one] if matches!(one.kind, ItemKind::Word | ItemKind::Quoted) => {
                Some((one.text.as_str(), one.span.clone()))
            }
            _ => {
                let msg = format!("{full} takes one name");
                self.error(Code::BadArgument, a.span.clone(), msg);
                None
            }
        }
    }

    /// Reports a required argument that is absent, at the statement keyword.
    pub fn missing(&mut self, what: &str) {
        let msg = format!("{} needs {what}", self.label);
        self.error(Code::MissingArgument, self.stmt.keyword_span.clone(), msg);
    }

    pub fn error(&mut self, code: Code, span: Span, message: String) {
        self.diags.push(Diagnostic::error(code, span, message));
    }

    /// Warns about every argument nothing asked for and returns the diagnostics.
    pub fn finish(mut self) -> Vec<Diagnostic> {
        for (i, a) in self.stmt.args.iter().enumerate() {
            if self.used[i] {
                continue;
            }
            let friction = FRICTION_ARGUMENTS
                .iter()
                .any(|f| abbreviates(&a.name, f, f.len().min(6)));
            let d = Diagnostic::warning(
                Code::UnsupportedStatement,
                a.name_span.clone(),
                format!(
                    "{} of {} (line {}) is not supported; it is ignored",
                    a.name, self.label, a.line
                ),
            );
            self.diags.push(if friction {
                d.with_note("joint friction is outside the mbfx subset")
            } else {
                d
            });
        }
        self.diags
    }
}
