//! Shared services of the model reader for the per-statement readers: marker references
//! (they exist, they are fixed or floating as needed, I and J on different parts) and
//! expression arguments (checked and lowered with the model as scope, `USER(…)` warned).

use super::elements::{Expr, Id, Marker, Named};
use super::reader::Reader;
use super::stmt_args::Args;
use crate::check::units::{check_use, Expected};
use crate::check::{self, Expect};
use crate::diag::{Code, Diagnostic, Span};

/// What a marker reference must be.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum MarkerUse {
    Fixed,
    Floating,
    Any,
}

/// An expression argument as found.
pub(super) enum ExprArg {
    Absent,
    /// Present but unusable (errors reported, or a USER call warned about).
    Unusable,
    Ok(Expr),
}

impl Reader<'_> {
    /// The id of the statement being read (the first pass made sure it has one).
    pub fn named(&self, a: &Args) -> Named {
        Named {
            id: a.stmt.id.and_then(|id| Id::try_from(id).ok()).unwrap_or(0),
            name: a.stmt.view_name.clone(),
            span: a.stmt.span.clone(),
        }
    }

    pub fn add_marker(&mut self, m: Marker) {
        self.markers.insert(m.el.id, self.model.markers.len());
        self.model.markers.push(m);
    }

    pub fn marker(&self, id: Id) -> Option<&Marker> {
        self.markers.get(&id).map(|&i| &self.model.markers[i])
    }

    /// Reads a marker reference argument and checks that the marker exists and is fixed
    /// or floating as `need` says. `None` when absent or wrong (reported).
    pub fn marker_ref(
        &mut self,
        a: &mut Args,
        full: &str,
        min: usize,
        need: MarkerUse,
        required: bool,
    ) -> Option<(Id, Span)> {
        let (id, span) = if required {
            a.required_id(full, min)?
        } else {
            a.id(full, min)?
        };
        let Some(m) = self.marker(id) else {
            a.diags.push(
                Diagnostic::error(
                    Code::UndefinedElement,
                    span,
                    format!("MARKER/{id} is not defined in this dataset"),
                )
                .with_note(format!("{full} of {} names it", a.label)),
            );
            return None;
        };
        let wrong = match need {
            MarkerUse::Fixed if m.floating => Some("a fixed marker; this one is FLOATING"),
            MarkerUse::Floating if !m.floating => Some("a FLOATING marker"),
            _ => None,
        };
        if let Some(what) = wrong {
            a.diags.push(
                Diagnostic::error(
                    Code::Topology,
                    span,
                    format!("{full} of {} must be {what}", a.label),
                )
                .with_label(m.el.span.clone(), format!("MARKER/{id}")),
            );
            return None;
        }
        Some((id, span))
    }

    /// Checks that the I and J markers of a connector lie on different parts.
    pub fn distinct_parts(&self, a: &mut Args, i: &(Id, Span), j: &(Id, Span)) -> bool {
        let (Some(mi), Some(mj)) = (self.marker(i.0), self.marker(j.0)) else {
            return false;
        };
        if mi.part != mj.part {
            return true;
        }
        a.diags.push(
            Diagnostic::error(
                Code::Topology,
                j.1.clone(),
                format!("I and J of {} are both on PART/{}", a.label, mi.part),
            )
            .with_label(i.1.clone(), "I marker")
            .with_help("a connector joins two different parts"),
        );
        false
    }

    /// Reads, checks and lowers an expression argument with the model as its scope.
    pub fn expr(&mut self, a: &mut Args, full: &str, min: usize, expect: Expect) -> ExprArg {
        self.expr_as(a, full, min, expect, None)
    }

    /// [`Reader::expr`] for an argument whose value the statement expects in a dimension
    /// (an SFORCE's FUNCTION is a force): a warning (W0312) when it is another.
    pub fn expr_as(
        &mut self,
        a: &mut Args,
        full: &str,
        min: usize,
        expect: Expect,
        want: Option<Expected>,
    ) -> ExprArg {
        let Some(arg) = a.find(full, min) else {
            return ExprArg::Absent;
        };
        let Some(span) = arg.expr_span() else {
            let msg = format!("{full} of {} must be an expression", a.label);
            a.error(Code::BadArgument, arg.span.clone(), msg);
            return ExprArg::Unusable;
        };
        let place = format!("in {}, argument {}", a.label, arg.name);
        if arg.is_user_call {
            a.diags.push(
                Diagnostic::warning(
                    Code::UnsupportedStatement,
                    span,
                    "USER(...) calls a user subroutine, which mbfx cannot run",
                )
                .with_note(place),
            );
            return ExprArg::Unusable;
        }
        let compiled = check::compile(&self.text[span.clone()], &self.scope, expect);
        let shift = |d: Diagnostic| d.shifted(span.start).with_note(place.clone());
        a.diags
            .extend(self.scope.take_warnings().into_iter().map(shift));
        match compiled {
            Ok(c) => {
                a.diags.extend(c.warnings.into_iter().map(shift));
                let statement = a.stmt.canonical.unwrap_or("statement");
                let what = || format!("this {statement}'s {full}");
                let names = Some(&self.scope.unit_names);
                if let Some(d) =
                    want.and_then(|w| check_use(c.dim, &w, &what(), span.clone(), names))
                {
                    a.diags.push(d.with_note(place));
                }
                ExprArg::Ok(Expr {
                    span,
                    function: c.function,
                })
            }
            Err(found) => {
                a.diags.extend(found.into_iter().map(shift));
                ExprArg::Unusable
            }
        }
    }

    /// An expression the statement needs: `E0604` when absent.
    pub fn required_expr(&mut self, a: &mut Args, full: &str, min: usize) -> Option<Expr> {
        self.required_expr_as(a, full, min, None)
    }

    /// [`Reader::required_expr`] with the dimension the statement expects.
    pub fn required_expr_as(
        &mut self,
        a: &mut Args,
        full: &str,
        min: usize,
        want: Option<Expected>,
    ) -> Option<Expr> {
        match self.expr_as(a, full, min, Expect::Scalar, want) {
            ExprArg::Ok(e) => Some(e),
            ExprArg::Absent => {
                a.missing(&format!("{full} = expression"));
                None
            }
            ExprArg::Unusable => None,
        }
    }
}
