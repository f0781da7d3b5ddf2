//! A MOTION's FUNCTION may depend on time only (Adams: a motion prescribes a joint's or
//! markers' displacement as a function of time). The dynamics evaluates drives with time
//! alone, so a FUNCTION that reads the model's state (a measure such as AZ, or a
//! VARIABLE that reads one) would be evaluated without it: the reader refuses it at the
//! FUNCTION, naming the measure.

use super::elements::{Expr, Model};
use crate::diag::{Code, Diagnostic};
use std::collections::HashSet;

/// An error for each MOTION whose FUNCTION reads a measure, directly or through VARVAL.
pub fn check(model: &Model, diags: &mut Vec<Diagnostic>) {
    for m in &model.motions {
        let mut seen = HashSet::new();
        if let Some(read) = state_read(model, &m.function, &mut seen) {
            let msg = format!(
                "MOTION/{}: its FUNCTION reads {read}; a MOTION's FUNCTION may depend on time only",
                m.el.id
            );
            diags.push(
                Diagnostic::error(Code::BadArgument, m.function.span.clone(), msg).with_help(
                    "a drive that depends on the model's state is a force (SFORCE, \
                         GFORCE) or a constraint (GCON)",
                ),
            );
        }
    }
}

/// The first measure `expr` reads (`AZ(21, 11)`, or `DX(2) through VARVAL(3)`), other
/// than a VARVAL of a VARIABLE that depends on time only; `seen` guards against VARIABLEs
/// that read each other.
fn state_read(model: &Model, expr: &Expr, seen: &mut HashSet<i64>) -> Option<String> {
    for &slot in &expr.function.uses.measures {
        let m = model.measures.get(slot as usize)?;
        let call = format!(
            "{}({})",
            m.name,
            m.ids
                .iter()
                .map(i64::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        );
        if m.name != "VARVAL" {
            return Some(call);
        }
        let Some(&id) = m.ids.first() else {
            return Some(call);
        };
        if !seen.insert(id) {
            continue;
        }
        let variable = model.variables.iter().find(|v| i64::from(v.el.id) == id)?;
        if let Some(inner) = state_read(model, &variable.function, seen) {
            return Some(format!("{inner} through {call}"));
        }
    }
    None
}
