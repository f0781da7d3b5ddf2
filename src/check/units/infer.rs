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
//! The walk is one linear pass over the tree's arena: the parsers build every node after
//! its children, so visiting nodes in index order sees children first, and each node
//! reads its children's dimensions from a table. No recursion, no stack to guard, and
//! about half the cost of a recursive walk, which matters: the check runs on every
//! expression a dataset holds (`benches/frontend.rs` measures it).
//!
//! The rules of the library functions are in [`super::rules`].

use super::dim::Dim;
use super::measures::Kind as MeasureKind;
use super::names::{describe, UnitNames};
use crate::check::Scope;
use crate::diag::{Code, Diagnostic, Span};
use crate::syntax::ast::{Ast, BinOp, Kind, NodeId};
use crate::vocab::builtins::{self, Builtin, Role};

/// DTOR and RTOD, as the builtins table gives them.
pub(super) const DTOR: f64 = std::f64::consts::PI / 180.0;
pub(super) const RTOD: f64 = 180.0 / std::f64::consts::PI;

/// A dimension, or `None` for free (a number, or anything with a number as a factor).
pub type D = Option<Dim>;

/// Most unit warnings reported for one expression: the first ones say what is wrong.
const MAX_WARNINGS: usize = 8;

/// Quoted source text longer than this is referred to as "this sum" instead.
const QUOTE: usize = 48;

/// A checked expression as the units check reads it.
pub struct Tree<'a> {
    /// The text.
    pub src: &'a str,
    /// Its syntax tree, in post order (every node after its children).
    pub ast: &'a Ast,
    /// The root node.
    pub root: NodeId,
    /// The builtin each name and call node stands for, by node id, as the checker
    /// resolved them (`None` for a user variable).
    pub resolved: &'a [Option<&'static Builtin>],
}

impl Tree<'_> {
    /// The builtin of each node of `ast` whose name is one, looked up here (for a tree
    /// the checker has not seen).
    pub fn resolve(ast: &Ast) -> Vec<Option<&'static Builtin>> {
        (ast.nodes.iter())
            .map(|n| match n.kind {
                Kind::Name(i) | Kind::Call { name: i, .. } => builtins::lookup(ast.name(i)),
                _ => None,
            })
            .collect()
    }
}

/// The inference of one expression.
pub(super) struct Infer<'a> {
    pub(super) src: &'a str,
    pub(super) ast: &'a Ast,
    resolved: &'a [Option<&'static Builtin>],
    scope: &'a dyn Scope,
    pub(super) names: Option<&'a UnitNames>,
    /// The dimension of every node visited so far, by node id.
    dims: &'a mut Vec<D>,
    pub(super) warnings: Vec<Diagnostic>,
}

/// Infers the dimension of a tree (checked without errors), returning it and the unit
/// warnings (code W0312). `dims` is scratch space, kept by the caller so that checking
/// many expressions allocates once.
pub fn infer(
    tree: &Tree,
    scope: &dyn Scope,
    names: Option<&UnitNames>,
    dims: &mut Vec<D>,
) -> (D, Vec<Diagnostic>) {
    let Tree {
        src,
        ast,
        root,
        resolved,
    } = *tree;
    let n = (root as usize + 1).min(ast.nodes.len());
    dims.clear();
    dims.resize(n, None);
    let mut inf = Infer {
        src,
        ast,
        resolved,
        scope,
        names,
        dims,
        warnings: Vec::new(),
    };
    // Children before parents (see the module doc); the root is the last node.
    for id in 0..n as NodeId {
        let d = inf.node(id);
        inf.dims[id as usize] = d;
    }
    (inf.dim(root), inf.warnings)
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

    /// The dimension of a child, computed before its parent (free if it was not).
    pub(super) fn dim(&self, id: NodeId) -> D {
        self.dims.get(id as usize).copied().flatten()
    }

    /// The dimension of node `id` from its children's.
    fn node(&mut self, id: NodeId) -> D {
        let node = self.ast.node(id);
        match &node.kind {
            Kind::Num(_) | Kind::Error => None,
            Kind::Name(n) => self.name(id, *n),
            Kind::Unary(_, a) => self.dim(*a),
            Kind::Binary(op, a, b) => self.binary(*op, *a, *b, id),
            // The test is compared with zero: any dimension will do.
            Kind::If([_, neg, zero, pos]) => {
                let arms = [
                    (self.dim(*neg), *neg, "the negative branch"),
                    (self.dim(*zero), *zero, "the zero branch"),
                    (self.dim(*pos), *pos, "the positive branch"),
                ];
                self.agree("IF", &arms)
            }
            Kind::Vector([x, y, z]) => {
                let parts = [
                    (self.dim(*x), *x, "the x component"),
                    (self.dim(*y), *y, "the y component"),
                    (self.dim(*z), *z, "the z component"),
                ];
                self.agree("this vector", &parts)
            }
            Kind::Call { args, .. } => {
                let args = self.ast.call_args(*args);
                self.call(id, args)
            }
        }
    }

    /// The builtin node `id` resolved to.
    fn builtin(&self, id: NodeId) -> Option<&'static Builtin> {
        self.resolved.get(id as usize).copied().flatten()
    }

    fn name(&self, id: NodeId, name: u32) -> D {
        match self.builtin(id).map(|b| b.role) {
            Some(Role::Time) => Some(Dim::TIME),
            // DTOR and RTOD convert between two units of angle: an angle stays an angle.
            // PI is a number like any other (`2*PI*TIME`, `PI*TIME`), and so is MODE.
            Some(Role::Constant(c)) if c == DTOR || c == RTOD => Some(Dim::NONE),
            Some(_) => None,
            None => self.scope.variable_dim(self.ast.name(name)),
        }
    }

    fn call(&mut self, id: NodeId, args: &[NodeId]) -> D {
        let b = self.builtin(id)?;
        match b.role {
            Role::Function(f) => self.function(f, b.name, args),
            Role::Mag => args.first().and_then(|&a| self.dim(a)),
            // The SPLINE's data say nothing about units: argument and value are free.
            Role::Spline(_) => None,
            Role::Measure(_) => {
                // Only VARVAL's id and an element force's comp matter.
                let integer = |i: usize| match self.ast.node(*args.get(i)?).kind {
                    Kind::Num(v) => Some(v as i64),
                    _ => None,
                };
                match super::measures::kind(b) {
                    MeasureKind::Fixed(d) => Some(d),
                    MeasureKind::Variable => integer(0).and_then(|id| self.scope.varval_dim(id)),
                    MeasureKind::Component => super::measures::component(integer(2)?),
                    MeasureKind::Free => None,
                }
            }
            Role::Constant(_) | Role::Time | Role::Mode | Role::Unsupported(_) => None,
        }
    }

    fn binary(&mut self, op: BinOp, a: NodeId, b: NodeId, id: NodeId) -> D {
        let (x, y) = (self.dim(a), self.dim(b));
        match op {
            BinOp::Add | BinOp::Sub => self.sum(op, (x, a), (y, b), id),
            BinOp::Mul | BinOp::Cross => x?.times(y?),
            BinOp::Div => x?.per(y?),
            BinOp::Pow => self.power((x, a), (y, b), id),
        }
    }

    /// `a + b`, `a - b`: both sides alike.
    #[inline]
    fn sum(&mut self, op: BinOp, (x, a): (D, NodeId), (y, b): (D, NodeId), id: NodeId) -> D {
        match (x, y) {
            (Some(p), Some(q)) if !p.agrees(q) => {
                self.sum_mismatch(op, (p, a), (q, b), id);
                None
            }
            _ => x.or(y),
        }
    }

    /// "`DZ(2,1) + VZ(2,1)` adds a length (meter) to a velocity (meter/second)".
    #[cold]
    #[inline(never)]
    fn sum_mismatch(
        &mut self,
        op: BinOp,
        (p, a): (Dim, NodeId),
        (q, b): (Dim, NodeId),
        id: NodeId,
    ) {
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
    }

    /// `a ** b`: a constant exponent scales the base's dimension; any other exponent
    /// needs a dimensionless base and a dimensionless exponent.
    #[inline(never)]
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
    #[inline(never)]
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
    #[cold]
    #[inline(never)]
    pub(super) fn mismatch(&mut self, what: &str, a: (Dim, NodeId, &str), b: (Dim, NodeId, &str)) {
        let (da, db) = (self.describe(a.0), self.describe(b.0));
        let msg = format!("{what}: {} is {da} but {} is {db}", a.2, b.2);
        let d = Diagnostic::warning(Code::UnitMismatch, self.span(b.1), msg)
            .with_label(self.span(a.1), format!("{}: {da}", a.2));
        self.warn(d);
    }

    /// Warns when `d` (the dimension of what `what` names, at node `at`) is not
    /// dimensionless or an angle, with the help `help` gives for it. The closures run only
    /// for a warning: this is asked of every SIN and EXP of every expression.
    pub(super) fn needs_number(
        &mut self,
        d: D,
        at: NodeId,
        what: impl FnOnce() -> String,
        help: impl FnOnce(&Self, Dim) -> Option<String>,
    ) {
        let Some(d) = d.filter(|d| !d.is_dimensionless()) else {
            return;
        };
        let msg = format!(
            "{} is {}; it must be dimensionless or an angle",
            what(),
            self.describe(d)
        );
        let mut diag = Diagnostic::warning(Code::UnitMismatch, self.span(at), msg);
        if let Some(h) = help(self, d) {
            diag = diag.with_help(h);
        }
        self.warn(diag);
    }
}
