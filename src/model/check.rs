//! Checking a whole dataset's expressions: every expression argument of an `.adm` file is
//! compiled against a scope built from the dataset itself, so measures and element
//! functions must name markers and elements the file defines (`DX(11,21)` needs
//! `MARKER/11` and `MARKER/21`, `VARVAL(3)` needs `VARIABLE/3`). Diagnostics point into
//! the file and name the statement (by its `adams_view_name` when it has one).

use super::{expression_arguments, read_statements, Statement};
use crate::check::builtins::{Param, Ty};
use crate::check::{self, Expect, MeasureCall, MeasureValue, Scope, SplineInfo};
use crate::diag::{Code, Diagnostic};
use std::collections::{HashMap, HashSet};

/// The outcome of checking a dataset.
pub struct DatasetReport {
    pub diagnostics: Vec<Diagnostic>,
    pub statements: usize,
    pub expressions: usize,
}

impl DatasetReport {
    /// One line for the CLI: how much was checked.
    pub fn summary(&self) -> String {
        format!(
            "{} statements, {} expressions",
            self.statements, self.expressions
        )
    }
}

/// IDs the dataset defines, per canonical statement keyword.
struct DatasetScope {
    ids: HashMap<&'static str, HashSet<i64>>,
}

/// Which statement an element function's first argument names.
fn element_statement(function: &str) -> Option<&'static str> {
    Some(match function {
        "SFORCE" => "SFORCE",
        "VFORCE" => "VFORCE",
        "VTORQ" => "VTORQUE",
        "GFORCE" => "GFORCE",
        "BUSH" => "BUSHING",
        "BEAM" => "BEAM",
        "FIELD" => "FIELD",
        "FRICTION" => "FRICTION",
        "SPDP" => "SPRINGDAMPER",
        "JOINT" => "JOINT",
        "JPRIM" => "JPRIM",
        "MOTION" => "MOTION",
        "CVCV" => "CVCV",
        "PTCV" => "PTCV",
        "NFORCE" => "NFORCE",
        "VARVAL" => "VARIABLE",
        "ARYVAL" => "ARRAY",
        "DIF" | "DIF1" => "DIFF",
        "PINVAL" => "PINPUT",
        "POUVAL" => "POUTPUT",
        "SENVAL" => "SENSOR",
        _ => return None,
    })
}

impl DatasetScope {
    fn new(stmts: &[Statement]) -> Self {
        let mut ids: HashMap<&'static str, HashSet<i64>> = HashMap::new();
        for s in stmts {
            if let (Some(k), Some(id)) = (s.canonical, s.id) {
                ids.entry(k).or_default().insert(id);
            }
        }
        DatasetScope { ids }
    }

    fn has(&self, statement: &str, id: i64) -> bool {
        self.ids.get(statement).is_some_and(|s| s.contains(&id))
    }
}

impl Scope for DatasetScope {
    fn variable(&self, _: &str) -> Option<u32> {
        None
    }

    fn spline(&self, id: i64) -> Option<SplineInfo> {
        self.has("SPLINE", id).then_some(SplineInfo {
            index: 0,
            surface: false,
        })
    }

    fn measure(&self, call: &MeasureCall) -> Result<MeasureValue, Diagnostic> {
        let b = call.builtin;
        // (argument index, statement it names): an element function's first ID names its
        // element, every other ID argument a marker (0 standing for ground).
        let element = element_statement(b.name);
        let refs = b
            .params
            .iter()
            .enumerate()
            .filter_map(|(i, p)| match (p, i, element) {
                (Param::Id, 0, Some(stmt)) => Some((i, stmt)),
                (Param::Id, _, _) => Some((i, "MARKER")),
                _ => None,
            });
        for (i, stmt) in refs {
            let Some(&id) = call.ids.get(i) else { continue };
            let optional_ground = stmt == "MARKER" && id == 0 && i > 0;
            if !optional_ground && !self.has(stmt, id) {
                let span = call
                    .arg_spans
                    .get(i)
                    .cloned()
                    .unwrap_or_else(|| call.span.clone());
                return Err(Diagnostic::error(
                    Code::UndefinedElement,
                    span,
                    format!("{stmt}/{id} is not defined in this dataset"),
                )
                .with_note(format!("{} reads it", b.name)));
            }
        }
        Ok(match b.result {
            Ty::Scalar => MeasureValue::Scalar(0),
            Ty::Vector => MeasureValue::Vector([0, 1, 2]),
        })
    }
}

/// Vector-valued expression arguments (spec §2.6, §7).
fn expects(argument: &str) -> Expect {
    match argument {
        "FXYZ" | "TXYZ" => Expect::Vector,
        _ => Expect::Scalar,
    }
}

/// Reads the statements of `text` and checks every expression argument.
pub fn check_dataset(text: &str) -> DatasetReport {
    let (stmts, mut diagnostics) = read_statements(text);
    let scope = DatasetScope::new(&stmts);
    let exprs = expression_arguments(&stmts);
    for e in &exprs {
        let place = match (&e.view_name, e.id) {
            (Some(v), _) => format!(
                "in {} ({}/{}), argument {}",
                v,
                e.statement,
                e.id.unwrap_or(0),
                e.argument
            ),
            (None, Some(id)) => format!("in {}/{id}, argument {}", e.statement, e.argument),
            (None, None) => format!("in {}, argument {}", e.statement, e.argument),
        };
        if e.is_user_call {
            diagnostics.push(
                Diagnostic::warning(
                    Code::UnsupportedStatement,
                    e.span.clone(),
                    "USER(...) calls a user subroutine, which mbfx cannot run",
                )
                .with_note(place),
            );
            continue;
        }
        let found = match check::compile(&text[e.span.clone()], &scope, expects(&e.argument)) {
            Ok(c) => c.warnings,
            Err(d) => d,
        };
        diagnostics.extend(
            found
                .into_iter()
                .map(|d| d.shifted(e.span.start).with_note(place.clone())),
        );
    }
    diagnostics.sort_by_key(|d| d.span.start);
    DatasetReport {
        diagnostics,
        statements: stmts.len(),
        expressions: exprs.len(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MODEL: &str = "title\nPART/1, GROUND\nMARKER/11, PART=1\nMARKER/21, PART=1\nVARIABLE/3, FUNCTION=DX(11,21)\nSFORCE/1, I=11, J=21, TRANSLATION, FUNCTION=VARVAL(3)+DM(11,21)\nEND\n";

    #[test]
    fn a_consistent_dataset_checks_clean() {
        let r = check_dataset(MODEL);
        assert!(r.diagnostics.is_empty(), "{:?}", r.diagnostics);
        assert_eq!(r.expressions, 2);
    }

    #[test]
    fn undefined_markers_and_variables_are_errors_pointing_into_the_file() {
        let text = MODEL
            .replace("DX(11,21)", "DX(11,99)")
            .replace("VARVAL(3)", "VARVAL(4)");
        let r = check_dataset(&text);
        let codes: Vec<_> = r
            .diagnostics
            .iter()
            .map(|d| (d.code, &text[d.span.clone()]))
            .collect();
        assert_eq!(
            codes,
            vec![
                (Code::UndefinedElement, "99"),
                (Code::UndefinedElement, "4")
            ]
        );
    }
}
