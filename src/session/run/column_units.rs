//! The unit of each output column, for a chart that draws one panel per unit (Python's
//! `Run.plot`): the units checker's dimension of the column's expression, named in the
//! dataset's units ("meter", "newton", "meter/second", "radian").

use crate::check::units::{self, Dim};
use crate::model::ModelRead;

/// The unit of an expression `text` read in `read`'s scope: its dimension in the
/// dataset's unit names, "1" for a dimensionless one, and "" when the checker cannot
/// tell (a number alone is free, so is an expression of free parts only).
pub(super) fn unit_of(read: &ModelRead, text: &str) -> String {
    let scope = read.scope();
    match units::infer_text(text, scope, Some(&scope.unit_names)) {
        Ok((Some(d), _)) => named(d, read),
        _ => String::new(),
    }
}

/// The unit of TIME in `read`'s units.
pub(super) fn time_unit(read: &ModelRead) -> String {
    named(Dim::TIME, read)
}

fn named(d: Dim, read: &ModelRead) -> String {
    match units::names::unit(d, Some(&read.scope().unit_names)) {
        u if u.is_empty() => "1".to_string(),
        u => u,
    }
}
