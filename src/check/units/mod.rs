//! Units of measure in the checker (issue 24): after an expression has been checked
//! without errors, one more walk over its syntax tree infers its physical dimension and
//! warns (W0312) where the expression adds, compares or passes quantities that cannot go
//! together: `DZ(2,1) + VZ(2,1)`, `SIN(DX(1,2))`, `IMPACT(DZ(2,1), DZ(2,1), …)`. A dataset
//! then compares each expression's dimension with what its statement expects (an SFORCE
//! a force, a rotational MOTION an angle, ...).
//!
//! The walk reads the tree only: it never changes the IR or a value, and it never makes
//! an error. [`dim`] is the algebra of dimensions, [`names`] how they read in messages,
//! [`measures`] the catalogue of what each measure returns, `infer` the walk and `rules`
//! the library functions' rules. The check runs when the [`crate::check::Scope`] gives
//! unit names (a model does; plain expressions do not).

pub mod dim;
mod infer;
pub mod measures;
pub mod names;
pub mod parse;
mod rules;
#[cfg(test)]
mod tests;

pub use dim::{Base, Dim};
pub use infer::{infer, Tree};
pub use names::{describe, UnitNames};

use crate::diag::{Code, Diagnostic, Span};
use crate::vocab::builtins::{Builtin, Role};

/// True when a name or call that resolved to `b` (`None`: a user variable) can give a
/// dimension to an expression whose numbers are all free: TIME, DTOR and RTOD, a measure
/// with a dimension (VARVAL and element forces included), a user variable, and the
/// functions whose value has one whatever their argument (SIN, ..., ATAN2). Every other
/// node's dimension comes from its children's, so a tree without one of these is free
/// throughout and cannot warn: the check skips it (a fifth of the corpus' expressions).
pub fn fixes_a_dimension(b: Option<&'static Builtin>) -> bool {
    use crate::vocab::func::Func as F;
    let Some(b) = b else { return true };
    match b.role {
        Role::Time => true,
        Role::Constant(c) => c == infer::DTOR || c == infer::RTOD,
        Role::Measure(_) => !matches!(measures::kind(b), measures::Kind::Free),
        Role::Function(f) => matches!(
            f,
            F::Sin
                | F::Cos
                | F::Tan
                | F::Sinh
                | F::Cosh
                | F::Tanh
                | F::Exp
                | F::Log
                | F::Log10
                | F::Asin
                | F::Acos
                | F::Atan
                | F::Atan2
        ),
        Role::Mag | Role::Spline(_) | Role::Mode | Role::Unsupported(_) => false,
    }
}

/// The dimension a statement expects of one of its expressions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Expected {
    /// The dimension expected.
    pub dim: Dim,
    /// Dimensions another form of the statement takes, with the help that says how to
    /// write that form ("for a torque, write ROTATION").
    pub alternatives: &'static [(Dim, &'static str)],
}

impl Expected {
    /// Expects `dim`, with no alternative form.
    pub const fn just(dim: Dim) -> Expected {
        Expected {
            dim,
            alternatives: &[],
        }
    }
}

/// The warning for an expression of dimension `got` used where `want` is expected (`None`
/// when it fits or is free): "this SFORCE's FUNCTION is a length (meter) where a force
/// (newton) is expected". `what` names the use, `span` is the expression's.
pub fn check_use(
    got: Option<Dim>,
    want: &Expected,
    what: &str,
    span: Span,
    names: Option<&UnitNames>,
) -> Option<Diagnostic> {
    let got = got.filter(|g| !g.agrees(want.dim))?;
    let msg = format!(
        "{what} is {} where {} is expected",
        describe(got, names),
        describe(want.dim, names)
    );
    let mut d = Diagnostic::warning(Code::UnitMismatch, span, msg);
    // Exactly: "for an angle, write ..." is no help for a plain number.
    if let Some((_, help)) = want.alternatives.iter().find(|(a, _)| *a == got) {
        d = d.with_help(*help);
    }
    Some(d)
}

/// Parses `src` and infers its dimension and unit warnings in `scope`, without checking
/// or lowering it (the caller has checked it, or only wants its dimension); the parser's
/// diagnostics when it does not parse.
pub fn infer_text(
    src: &str,
    scope: &dyn crate::check::Scope,
    names: Option<&UnitNames>,
) -> Result<(Option<Dim>, Vec<Diagnostic>), Vec<Diagnostic>> {
    let parsed = crate::syntax::parser::parse(src);
    match parsed.root {
        Some(root) if !crate::diag::has_errors(&parsed.diagnostics) => {
            let tree = Tree {
                src,
                ast: &parsed.ast,
                root,
                resolved: &Tree::resolve(&parsed.ast),
            };
            Ok(infer(&tree, scope, names, &mut Vec::new()))
        }
        _ => Err(parsed.diagnostics),
    }
}

/// What `:units` prints for an inferred dimension: "a velocity (meter/second)", or that
/// it is free.
pub fn summary(d: Option<Dim>, names: Option<&UnitNames>) -> String {
    match d {
        Some(d) => describe(d, names),
        None => "free: a number in it can give it any dimension".to_string(),
    }
}
