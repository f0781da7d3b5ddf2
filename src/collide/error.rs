//! Why a GRAPHICS statement gives no contact geometry, in a form the diagnostics of a
//! run or a check can show at the statement.

use crate::diag::{Code, Diagnostic, Span};
use crate::model::elements::Id;
use std::fmt;

/// A GRAPHICS statement that cannot be a contact geometry, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct CollideError {
    /// The GRAPHICS id.
    pub graphic: Id,
    /// The span of the GRAPHICS statement (empty when the id names no statement).
    pub span: Span,
    /// Why, one phrase (`an OUTLINE has no volume to collide`).
    pub why: String,
}

impl CollideError {
    /// The error for GRAPHICS/`graphic` at `span`.
    pub fn new(graphic: Id, span: Span, why: impl Into<String>) -> Self {
        CollideError {
            graphic,
            span,
            why: why.into(),
        }
    }

    /// As a diagnostic at the GRAPHICS statement (`E0605`: a bad argument of the
    /// statement that names it as a contact geometry).
    pub fn diagnostic(&self) -> Diagnostic {
        Diagnostic::error(Code::BadArgument, self.span.clone(), self.to_string())
    }
}

impl fmt::Display for CollideError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "GRAPHICS/{} cannot be a contact geometry: {}",
            self.graphic, self.why
        )
    }
}

impl std::error::Error for CollideError {}
