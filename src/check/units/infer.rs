//! Dimension inference over a checked syntax tree: one walk that gives every node a
//! dimension, or none ("free"), and warns where two dimensions the expression fixes
//! disagree.
//!
//! A number carries no dimension: a literal coefficient takes whichever makes its term
//! consistent, so a product or quotient with a free factor is free (`-1E4*DZ(2,1)` is
//! free, `30.0D*TIME` too), and so is a power of a free base. Every literal occurs once
//! in the tree, so a free node is a fresh unknown that nothing else constrains: keeping
//! "free" as one value is as precise as unification with a variable per literal, and
//! costs no allocation. Only dimensions the expression fixes (measures, TIME, DTOR and
//! RTOD, the results of SIN, ATAN2, IMPACT, ...) can conflict. A conflict is reported once,
//! at the node where the two meet, and that node is free from there up, so one mistake
//! gives one warning.
//!
//! The rules of the library functions are in [`super::rules`].

use super::dim::Dim;
use super::names::{describe, UnitNames};
use crate::check::Scope;
use crate::diag::{Code, Diagnostic, Span};
use crate::syntax::ast::{Ast, BinOp, Kind, NodeId};
use crate::vocab::builtins::{self, Role};

/// A dimension, or `None` for free (a number, or anything with a number as a factor).
pub type D = Option<Dim>;

/// Most unit warnings reported for one expression: the first ones say what is wrong.
const MAX_WARNINGS: usize = 8;

/// Quoted source text longer than this is referred to as "this sum" instead.
const QUOTE: usize = 48;

/// The inference of one expression.
pub(super) struct Infer<'a> {
    pub(super) src: &'a str,
    pub(super) ast: &'a Ast,
    scope: &'a dyn Scope,
    pub(super) names: Option<&'a UnitNames>,
    /// Recursion depth of [`Infer::expr`].
    level: u32,
    pub(super) warnings: Vec<Diagnostic>,
}

/// Infers the dimension of the tree at `root` (the text `src`, checked without errors),
/// returning it and the unit warnings (code W0312).
pub fn infer(
    src: &str,
    ast: &Ast,
    root: NodeId,
    scope: &dyn Scope,
    names: Option<&UnitNames>,
) -> (D, Vec<Diagnostic>) {
    let mut inf = Infer {
        src,
        ast,
        scope,
        names,
        level: 0,
        warnings: Vec::new(),
    };
    let d = inf.expr(root);
    (d, inf.warnings)
}

impl Infer<'_> {
    pub(super) fn span(&self, id: NodeId) -> Span {
        self.ast.node(id).span()
    }

    /// The source text of a node.
    pub(super) fn text(&self, id: NodeId) -> &str {
        self.src.get(self.span(id)).unwrap_or("")
    }

    /// "a length (meter)".
    pub(super) fn describe(&self, d: Dim) -> String {
        describe(d, self.names)
    }

    pub(super) fn warn(&mut self, d: Diagnostic) {
        if self.warnings.len() < MAX_WARNINGS {
            self.warnings.push(d);
        }
    }

    pub(super) fn expr(&mut self, id: NodeId) -> D {
        self.level += 1;
        let d = crate::stack::every_few_levels(self.level, || self.expr_inner(id));
        self.level -= 1;
        d
    }

    fn expr_inner(&mut self, id: NodeId) -> D {
        let node = self.ast.node(id);
        match &node.kind {
            Kind::Num(_) | Kind::Error => None,
            Kind::Name(n) => self.name(self.ast.name(*n)),
            Kind::Unary(_, a) => self.expr(*a),
            Kind::Binary(op, a, b) => self.binary(*op, *a, *b, id),
            Kind::If([test, neg, zero, pos]) => {
                // The test is compared with zero: any dimension will do.
                let _ = self.expr(*test);
                let arms = [
                    (self.expr(*neg), *neg, "the negative branch"),
                    (self.expr(*zero), *zero, "the zero branch"),
                    (self.expr(*pos), *pos, "the positive branch"),
                ];
                self.agree("IF", &arms)
            }
            Kind::Vector([x, y, z]) => {
                let parts = [
                    (self.expr(*x), *x, "the x component"),
                    (self.expr(*y), *y, "the y component"),
                    (self.expr(*z), *z, "the z component"),
                ];
                self.agree("this vector", &parts)
            }
            Kind::Call { name, args, .. } => {
                let name = self.ast.name(*name);
                let args = self.ast.call_args(*args);
                self.call(name, args)
            }
        }
    }

    fn name(&self, name: &str) -> D {
        match builtins::lookup(name).map(|b| b.role) {
            Some(Role::Time) => Some(Dim::TIME),
            // Conversions between two units of angle: an angle stays an angle. PI is a
            // number like any other (`2*PI*TIME`, `PI*TIME`).
            Some(Role::Constant(_)) if matches!(name, "DTOR" | "RTOD") => Some(Dim::NONE),
            Some(_) => None,
            None => self.scope.variable_dim(name),
        }
    }

    fn call(&mut self, name: &str, args: &[NodeId]) -> D {
        let b = builtins::lookup(name)?;
        match b.role {
            Role::Function(f) => self.function(f, b.name, args),
            Role::Mag => args.first().and_then(|&a| self.expr(a)),
            Role::Spline(_) => {
                // The SPLINE's data say nothing about units: argument and value are free.
                for &a in args.iter().take(2) {
                    let _ = self.expr(a);
                }
                None
            }
            Role::Measure(_) => {
                let mut ids = [None; 4];
                for (slot, &a) in ids.iter_mut().zip(args) {
                    if let Kind::Num(v) = self.ast.node(a).kind {
                        *slot = Some(v as i64);
                    }
                }
                if b.name == "VARVAL" {
                    return ids[0].and_then(|id| self.scope.varval_dim(id));
                }
                super::measures::dimension(b.name, &ids)
            }
            Role::Constant(_) | Role::Time | Role::Mode | Role::Unsupported(_) => None,
        }
    }

    fn binary(&mut self, op: BinOp, a: NodeId, b: NodeId, id: NodeId) -> D {
        let x = self.expr(a);
        let y = self.expr(b);
        match op {
            BinOp::Add | BinOp::Sub => self.sum(op, (x, a), (y, b), id),
            BinOp::Mul | BinOp::Cross => x?.times(y?),
            BinOp::Div => x?.per(y?),
            BinOp::Pow => self.power((x, a), (y, b), id),
        }
    }

    /// `a + b`, `a - b`: both sides alike.
    fn sum(&mut self, op: BinOp, (x, a): (D, NodeId), (y, b): (D, NodeId), id: NodeId) -> D {
        let (Some(p), Some(q)) = (x, y) else {
            return x.or(y);
        };
        if p.agrees(q) {
            return Some(p);
        }
        let text = self.text(id);
        let (what, verb) = match op {
            BinOp::Add => ("this sum", "adds"),
            _ => ("this difference", "subtracts"),
        };
        let subject = if text.len() <= QUOTE && !text.contains(['\n', '\r']) {
            format!("`{text}`")
        } else {
            what.to_string()
        };
        let (dp, dq) = (self.describe(p), self.describe(q));
        let message = match op {
            BinOp::Add => format!("{subject} {verb} {dp} to {dq}"),
            _ => format!("{subject} {verb} {dq} from {dp}"),
        };
        let d = Diagnostic::warning(Code::UnitMismatch, self.span(id), message)
            .with_label(self.span(a), dp)
            .with_label(self.span(b), dq);
        self.warn(d);
        None
    }

    /// `a ** b`: a constant exponent scales the base's dimension; any other exponent
    /// needs a dimensionless base and a dimensionless exponent.
    fn power(&mut self, (x, a): (D, NodeId), (y, b): (D, NodeId), id: NodeId) -> D {
        if let Some(p) = self.constant(b, 0) {
            return x?.pow(p);
        }
        if let Some(e) = y.filter(|e| !e.is_dimensionless()) {
            let msg = format!(
                "the exponent of `**` is {}; an exponent must be dimensionless",
                self.describe(e)
            );
            self.warn(Diagnostic::warning(Code::UnitMismatch, self.span(b), msg));
        }
        match x? {
            base if base.is_dimensionless() => Some(Dim::NONE),
            base => {
                let text = self.text(a);
                let subject = if text.len() <= QUOTE {
                    format!("`{text}`")
                } else {
                    "this base".to_string()
                };
                let msg = format!(
                    "{subject} is {} raised to a power that is not a constant: the result has no dimension",
                    self.describe(base)
                );
                let d = Diagnostic::warning(Code::UnitMismatch, self.span(id), msg)
                    .with_label(self.span(b), "exponent")
                    .with_help("write a constant exponent, or make the base a ratio");
                self.warn(d);
                None
            }
        }
    }

    /// The value of a constant subtree (literals, PI, DTOR, RTOD and arithmetic on
    /// them), for exponents; `None` for anything else or a tree too deep to bother.
    pub(super) fn constant(&self, id: NodeId, depth: u32) -> Option<f64> {
        if depth > 32 {
            return None;
        }
        let c = |n: NodeId| self.constant(n, depth + 1);
        match &self.ast.node(id).kind {
            Kind::Num(v) => Some(*v),
            Kind::Name(n) => match builtins::lookup(self.ast.name(*n))?.role {
                Role::Constant(v) => Some(v),
                _ => None,
            },
            Kind::Unary(crate::syntax::ast::UnOp::Neg, a) => c(*a).map(|v| -v),
            Kind::Unary(_, a) => c(*a),
            Kind::Binary(op, a, b) => {
                let (a, b) = (c(*a)?, c(*b)?);
                match op {
                    BinOp::Add => Some(a + b),
                    BinOp::Sub => Some(a - b),
                    BinOp::Mul => Some(a * b),
                    BinOp::Div => Some(a / b),
                    BinOp::Pow => Some(a.powf(b)),
                    BinOp::Cross => None,
                }
            }
            _ => None,
        }
    }

    /// The dimension shared by `items` (dimension, node, role such as "x0"): the first
    /// fixed one; a later fixed one that disagrees is reported ("STEP: x is a time
    /// (second) but x0 is a length (meter)") and makes the group free.
    pub(super) fn agree(&mut self, what: &str, items: &[(D, NodeId, &str)]) -> D {
        let mut first: Option<(Dim, NodeId, &str)> = None;
        for &(d, id, role) in items {
            let Some(d) = d else { continue };
            match first {
                None => first = Some((d, id, role)),
                Some(f) if !f.0.agrees(d) => {
                    self.mismatch(what, f, (d, id, role));
                    return None;
                }
                Some(_) => {}
            }
        }
        first.map(|f| f.0)
    }

    /// Reports two parts of one group that disagree; the caret is on the second.
    pub(super) fn mismatch(&mut self, what: &str, a: (Dim, NodeId, &str), b: (Dim, NodeId, &str)) {
        let (da, db) = (self.describe(a.0), self.describe(b.0));
        let msg = format!("{what}: {} is {da} but {} is {db}", a.2, b.2);
        let d = Diagnostic::warning(Code::UnitMismatch, self.span(b.1), msg)
            .with_label(self.span(a.1), format!("{}: {da}", a.2));
        self.warn(d);
    }

    /// Warns when `d` (the dimension of `what` at node `at`) is not dimensionless or an
    /// angle.
    pub(super) fn needs_number(&mut self, what: &str, d: D, at: NodeId, help: Option<String>) {
        let Some(d) = d.filter(|d| !d.is_dimensionless()) else {
            return;
        };
        let msg = format!(
            "{what} is {}; it must be dimensionless or an angle",
            self.describe(d)
        );
        let mut diag = Diagnostic::warning(Code::UnitMismatch, self.span(at), msg);
        if let Some(h) = help {
            diag = diag.with_help(h);
        }
        self.warn(diag);
    }
}
