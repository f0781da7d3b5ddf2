//! Semantic checks, and lowering of a checked tree to the IR.
//!
//! One pass over the syntax tree resolves every name against the builtins table and a
//! [`Scope`] (user variables, splines, measures of a model), checks arity, ID and code
//! arguments (integer literals, decision 8), scalar/vector typing (spec §2.6), the IF
//! nesting limit (decision 2) and constant arguments (STEP x0 < x1, IMPACT domain, ...),
//! and emits IR through [`crate::ir::builder::Builder`]. It reports every error it finds;
//! an expression with errors yields no IR.

pub mod scope;
mod suggest;
pub use suggest::closest;
pub mod units;
mod validate;

use crate::diag::{has_errors, Code, Diagnostic, Span};
use crate::ir::builder::{Arith, Builder};
use crate::ir::{Function, Value};
use crate::syntax::ast::{Ast, BinOp, Kind, NodeId, UnOp};
use crate::syntax::parser;
use crate::vocab::builtins::{self, Builtin, Param, Role};
pub use scope::{EveryIdExists, MeasureCall, MeasureValue, Scope, SplineInfo, Variables};
use std::cell::RefCell;

/// Deepest nesting of arithmetic IFs (decision 2).
pub const MAX_IF_NESTING: usize = 9;

/// What type the whole expression must have.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Expect {
    /// Most contexts (FUNCTION=, GCON, MOTION, ...): a scalar.
    Scalar,
    /// `FXYZ=` / `TXYZ=`: a vector.
    Vector,
    /// Interactive evaluation: either.
    Any,
}

/// A checked and lowered expression, with any warnings.
#[derive(Debug)]
pub struct Checked {
    /// The lowered IR.
    pub function: Function,
    /// Warnings the checker found.
    pub warnings: Vec<Diagnostic>,
    /// The expression's physical dimension, when the scope asked for units to be
    /// checked ([`Scope::checks_units`]); `None` when it is free (or was not checked).
    pub dim: Option<units::Dim>,
}

/// Parses, checks and lowers `src`. On error, returns every diagnostic found (errors
/// and warnings). Runs in this thread's [`Session`], so that compiling many expressions
/// reuses the front end's buffers.
pub fn compile(src: &str, scope: &dyn Scope, expect: Expect) -> Result<Checked, Vec<Diagnostic>> {
    thread_local! {
        static SESSION: RefCell<Session> = RefCell::default();
    }
    SESSION.with(|cell| {
        let Ok(mut session) = cell.try_borrow_mut() else {
            // A scope that compiles from inside `compile`: a session of its own.
            return Session::default().compile(src, scope, expect);
        };
        if src.len() <= LARGE_SOURCE {
            return session.compile(src, scope, expect);
        }
        // Buffers sized for an unusually large expression are not kept.
        let result = session.compile(src, scope, expect);
        *session = Session::default();
        result
    })
}

/// Source length above which [`compile`] frees its session's buffers after use.
const LARGE_SOURCE: usize = 1 << 16;

/// The buffers of parsing, checking and lowering (tokens, syntax tree, IR tables), kept
/// between expressions: once they have grown, compiling allocates only for the diagnostics
/// and the [`Function`] it returns.
#[derive(Default)]
pub struct Session {
    parse: parser::Session,
    ir: Builder,
    ifs: Vec<Span>,
    ids: Vec<i64>,
    spans: Vec<Span>,
    values: Vec<Value>,
    /// The units check's table of node dimensions.
    dims: Vec<Option<units::Dim>>,
    /// The builtin each node resolved to.
    resolved: Vec<Option<&'static Builtin>>,
}

impl Session {
    /// A session with empty buffers.
    pub fn new() -> Self {
        Self::default()
    }

    /// Parses, checks and lowers `src` (see [`compile`]).
    pub fn compile(
        &mut self,
        src: &str,
        scope: &dyn Scope,
        expect: Expect,
    ) -> Result<Checked, Vec<Diagnostic>> {
        let parsed = self.parse.parse(src, true);
        let mut diags = parsed.diagnostics;
        let root = match parsed.root {
            Some(r) if !has_errors(&diags) => r,
            _ => return Err(diags),
        };
        let ast: &Ast = parsed.ast;
        self.ir.clear();
        self.ifs.clear();
        self.resolved.clear();
        self.resolved.resize(ast.nodes.len(), None);
        let mut c = Checker {
            ast,
            scope,
            b: &mut self.ir,
            diags,
            ifs: &mut self.ifs,
            if_limit_reported: false,
            level: 0,
            ids: &mut self.ids,
            spans: &mut self.spans,
            resolved: &mut self.resolved,
            fixes_a_dimension: false,
        };
        let lowered = c.expr(root);
        diags = c.diags;
        let fixes_a_dimension = c.fixes_a_dimension;
        let outputs = &mut self.values;
        outputs.clear();
        match (lowered, expect) {
            (Some(Lowered::S(v)), Expect::Scalar | Expect::Any) => outputs.push(v),
            (Some(Lowered::V(v)), Expect::Vector | Expect::Any) => outputs.extend(v),
            (Some(l), _) => {
                let (want, got) = if matches!(l, Lowered::S(_)) {
                    ("a vector", "a scalar")
                } else {
                    ("a scalar", "a vector")
                };
                diags.push(
                    Diagnostic::error(
                        Code::Type,
                        ast.node(root).span(),
                        format!("the expression must be {want}, but this is {got}"),
                    )
                    .with_help("only FXYZ= and TXYZ= take vector expressions"),
                );
            }
            (None, _) => {}
        }
        if has_errors(&diags) || outputs.is_empty() {
            crate::diag::cap(&mut diags);
            return Err(diags);
        }
        // Units only read the tree, and only a tree without errors.
        let mut dim = None;
        if fixes_a_dimension && scope.checks_units() {
            let tree = units::Tree {
                src,
                ast,
                root,
                resolved: &self.resolved,
            };
            let names = scope.unit_names();
            let (d, warnings) = units::infer(&tree, scope, names, &mut self.dims);
            dim = d;
            diags.extend(warnings);
        }
        Ok(Checked {
            function: self.ir.finish(outputs),
            warnings: diags,
            dim,
        })
    }
}

/// A lowered subexpression: one scalar or three.
#[derive(Clone, Copy)]
enum Lowered {
    S(Value),
    V([Value; 3]),
}

struct Checker<'a> {
    ast: &'a Ast,
    scope: &'a dyn Scope,
    b: &'a mut Builder,
    diags: Vec<Diagnostic>,
    /// Spans of the IFs enclosing the node being checked, outermost first.
    ifs: &'a mut Vec<Span>,
    if_limit_reported: bool,
    /// Recursion depth of [`Checker::expr`].
    level: u32,
    /// Scratch for the ID arguments of a measure and their spans.
    ids: &'a mut Vec<i64>,
    spans: &'a mut Vec<Span>,
    /// The builtin each name and call node resolved to, by node id.
    resolved: &'a mut Vec<Option<&'static Builtin>>,
    /// True once a node that can fix a dimension was resolved
    /// ([`units::fixes_a_dimension`]): without one, the units check has nothing to do.
    fixes_a_dimension: bool,
}

impl Checker<'_> {
    fn error(&mut self, d: Diagnostic) {
        self.diags.push(d);
    }

    fn span(&self, id: NodeId) -> Span {
        self.ast.node(id).span()
    }

    /// Lowers a subexpression that must be scalar; `what` names it in the error message
    /// (built only when there is an error).
    fn scalar(&mut self, id: NodeId, what: impl FnOnce() -> String) -> Option<Value> {
        match self.expr(id)? {
            Lowered::S(v) => Some(v),
            Lowered::V(_) => {
                let span = self.span(id);
                self.error(
                    Diagnostic::error(
                        Code::Type,
                        span,
                        format!("{} must be a scalar, but this is a vector", what()),
                    )
                    .with_help(
                        "take a component with a dot product, e.g. DXYZ(i,j)*UVX(k), or MAG(v)",
                    ),
                );
                None
            }
        }
    }

    fn expr(&mut self, id: NodeId) -> Option<Lowered> {
        self.level += 1;
        let lowered = crate::stack::every_few_levels(self.level, || self.expr_inner(id));
        self.level -= 1;
        lowered
    }

    fn expr_inner(&mut self, id: NodeId) -> Option<Lowered> {
        let node = self.ast.node(id);
        let span = node.span();
        match &node.kind {
            Kind::Num(v) => Some(Lowered::S(self.b.constant(*v, span))),
            Kind::Error => None,
            Kind::Name(n) => {
                let name = self.ast.name(*n);
                let b = self.resolve(id, name);
                self.name(name, b, span).map(Lowered::S)
            }
            Kind::Call {
                name,
                name_end,
                args,
            } => {
                let name_span = node.start as usize..*name_end as usize;
                let name = self.ast.name(*name);
                let b = self.resolve(id, name);
                self.call(name, b, name_span, self.ast.call_args(*args), span)
            }
            Kind::If(parts) => self.if_(*parts, span).map(Lowered::S),
            Kind::Vector(parts) => {
                let mut out = [0; 3];
                let mut ok = true;
                for (slot, &p) in out.iter_mut().zip(parts) {
                    match self.scalar(p, || "a vector component".into()) {
                        Some(v) => *slot = v,
                        None => ok = false,
                    }
                }
                ok.then_some(Lowered::V(out))
            }
            Kind::Unary(op, a) => {
                let inner = self.expr(*a)?;
                Some(match (op, inner) {
                    (UnOp::Plus, l) => l,
                    (UnOp::Neg, Lowered::S(v)) => Lowered::S(self.b.neg(v, span)),
                    (UnOp::Neg, Lowered::V(v)) => {
                        Lowered::V(v.map(|c| self.b.neg(c, span.clone())))
                    }
                })
            }
            Kind::Binary(op, a, c) => self.binary(*op, *a, *c, span),
        }
    }

    /// Looks `name` (of node `id`) up in the builtins table, and records what it found
    /// for the units check, which reads the tree again.
    fn resolve(&mut self, id: NodeId, name: &str) -> Option<&'static Builtin> {
        let b = builtins::lookup(name);
        if let Some(slot) = self.resolved.get_mut(id as usize) {
            *slot = b;
        }
        self.fixes_a_dimension = self.fixes_a_dimension || units::fixes_a_dimension(b);
        b
    }

    fn name(&mut self, name: &str, b: Option<&'static Builtin>, span: Span) -> Option<Value> {
        if let Some(b) = b {
            match b.role {
                Role::Constant(c) => return Some(self.b.constant(c, span)),
                Role::Time => return Some(self.b.time(span)),
                Role::Mode => return Some(self.b.mode(span)),
                _ => {
                    let d = Diagnostic::error(
                        Code::Misuse,
                        span,
                        format!("`{name}` is a function; call it with arguments"),
                    )
                    .with_help(format!("write {}", b.signature()));
                    self.error(d);
                    return None;
                }
            }
        }
        if name == "IF" {
            let d = Diagnostic::error(Code::Misuse, span, "IF needs its arguments")
                .with_help("write IF(test: negative, zero, positive)");
            self.error(d);
            return None;
        }
        if let Some(slot) = self.scope.variable(name) {
            return Some(self.b.var(slot, span));
        }
        let mut d = Diagnostic::error(Code::UnknownName, span, format!("unknown name `{name}`"));
        let variables = self.scope.variable_names();
        let candidates = builtins::BUILTINS
            .iter()
            .filter(|b| !b.is_callable())
            .map(|b| b.name)
            .chain(variables.iter().map(String::as_str));
        if let Some(s) = suggest::closest(name, candidates) {
            d = d.with_help(format!("did you mean `{s}`?"));
        } else if name.starts_with('.') {
            d = d.with_note("Adams View names are resolved by the model that defines them");
        } else {
            d = d.with_help(
                "define it as a variable (mbfx eval --var NAME=VALUE, or :let in the REPL)",
            );
        }
        self.error(d);
        None
    }

    fn if_(&mut self, [test, neg, zero, pos]: [NodeId; 4], span: Span) -> Option<Value> {
        self.ifs.push(span.clone());
        if self.ifs.len() > MAX_IF_NESTING && !self.if_limit_reported {
            self.if_limit_reported = true;
            let outer = self.ifs[0].clone();
            let d = Diagnostic::error(
                Code::IfTooDeep,
                outer,
                format!("arithmetic IFs nest deeper than {MAX_IF_NESTING} levels"),
            )
            .with_label(span.clone(), "this IF is level 10")
            .with_help("replace inner IFs by STEP, MIN, MAX or a VARIABLE");
            self.error(d);
        }
        let t = self.scalar(test, || "the IF test".into());
        let mut arms = Vec::with_capacity(3);
        let mut ok = t.is_some();
        for arm in [neg, zero, pos] {
            self.b.begin_block();
            let v = self.scalar(arm, || "an IF branch".into());
            ok &= v.is_some();
            let result = v.unwrap_or(0);
            arms.push(self.b.end_block(result));
        }
        self.ifs.pop();
        let t = t?;
        if !ok {
            return None;
        }
        let [a, b, c]: [crate::ir::Block; 3] = arms.try_into().ok()?;
        Some(self.b.if_(t, [a, b, c], span))
    }

    fn binary(&mut self, op: BinOp, a: NodeId, c: NodeId, span: Span) -> Option<Lowered> {
        let l = self.expr(a);
        let r = self.expr(c);
        let (l, r) = (l?, r?);
        use Lowered::{S, V};
        let arith = |op| match op {
            BinOp::Add => Arith::Add,
            BinOp::Sub => Arith::Sub,
            BinOp::Mul => Arith::Mul,
            _ => Arith::Div,
        };
        let type_error = |msg: &str, help: &str| {
            Diagnostic::error(Code::Type, span.clone(), msg.to_string()).with_help(help.to_string())
        };
        match (op, l, r) {
            (BinOp::Pow, S(x), S(y)) => Some(S(self.pow(x, y, span))),
            (BinOp::Pow, ..) => {
                self.error(type_error(
                    "`**` takes scalars only",
                    "a vector has no power; use MAG(v) or a dot product",
                ));
                None
            }
            (BinOp::Cross, V(x), V(y)) => Some(V(self.cross(x, y, span))),
            // Two scalars: the remainder of C and FORTRAN, which is MOD here.
            (BinOp::Cross, S(_), S(_)) => {
                let d = type_error(
                    "`%` is the cross product of two vectors, not a remainder",
                    "for the remainder of a divided by b write MOD(a, b)",
                );
                self.error(d);
                None
            }
            (BinOp::Cross, ..) => {
                let d = type_error(
                    "`%` is the cross product of two vectors",
                    "note that `v*v%v` means `(v*v)%v`; write `v*(v%v)`",
                );
                self.error(d);
                None
            }
            (BinOp::Add | BinOp::Sub | BinOp::Mul | BinOp::Div, S(x), S(y)) => {
                Some(S(self.b.arith(arith(op), x, y, span)))
            }
            (BinOp::Add | BinOp::Sub, V(x), V(y)) => {
                let f = arith(op);
                Some(V(
                    [0, 1, 2].map(|i| self.b.arith(f, x[i], y[i], span.clone()))
                ))
            }
            (BinOp::Add | BinOp::Sub, ..) => {
                self.error(type_error(
                    "cannot add or subtract a scalar and a vector",
                    "both sides must be scalars, or both vectors",
                ));
                None
            }
            (BinOp::Mul, S(s), V(v)) | (BinOp::Mul, V(v), S(s)) => {
                Some(V(v.map(|c| self.b.arith(Arith::Mul, s, c, span.clone()))))
            }
            (BinOp::Mul, V(x), V(y)) => Some(S(self.dot(x, y, span))),
            (BinOp::Div, V(v), S(s)) => {
                Some(V(v.map(|c| self.b.arith(Arith::Div, c, s, span.clone()))))
            }
            (BinOp::Div, ..) => {
                self.error(type_error(
                    "cannot divide by a vector",
                    "divide a vector by a scalar only",
                ));
                None
            }
        }
    }

    /// `a ** b`. An exponent that is an integer constant from -4 to 4 is computed by
    /// multiplication (FORTRAN's integer power; exact for negative bases), any other
    /// exponent by the runtime's `pow`.
    fn pow(&mut self, a: Value, b: Value, span: Span) -> Value {
        match self.b.get_const(b) {
            Some(n) if n.fract() == 0.0 && n.abs() <= 4.0 => {
                let k = n.abs() as u32;
                let p = match k {
                    0 => self.b.constant(1.0, span.clone()),
                    1 => a,
                    2 => self.b.arith(Arith::Mul, a, a, span.clone()),
                    3 => {
                        let sq = self.b.arith(Arith::Mul, a, a, span.clone());
                        self.b.arith(Arith::Mul, sq, a, span.clone())
                    }
                    _ => {
                        let sq = self.b.arith(Arith::Mul, a, a, span.clone());
                        self.b.arith(Arith::Mul, sq, sq, span.clone())
                    }
                };
                if n < 0.0 {
                    let one = self.b.constant(1.0, span.clone());
                    self.b.arith(Arith::Div, one, p, span)
                } else {
                    p
                }
            }
            _ => self.b.call(crate::vocab::func::Func::Pow, vec![a, b], span),
        }
    }

    fn dot(&mut self, x: [Value; 3], y: [Value; 3], span: Span) -> Value {
        let p = [0, 1, 2].map(|i| self.b.arith(Arith::Mul, x[i], y[i], span.clone()));
        let s = self.b.arith(Arith::Add, p[0], p[1], span.clone());
        self.b.arith(Arith::Add, s, p[2], span)
    }

    fn cross(&mut self, x: [Value; 3], y: [Value; 3], span: Span) -> [Value; 3] {
        [(1, 2), (2, 0), (0, 1)].map(|(i, j)| {
            let a = self.b.arith(Arith::Mul, x[i], y[j], span.clone());
            let b = self.b.arith(Arith::Mul, x[j], y[i], span.clone());
            self.b.arith(Arith::Sub, a, b, span.clone())
        })
    }

    fn call(
        &mut self,
        name: &str,
        b: Option<&'static Builtin>,
        name_span: Span,
        args: &[NodeId],
        span: Span,
    ) -> Option<Lowered> {
        let Some(b) = b else {
            let mut d = Diagnostic::error(
                Code::UnknownFunction,
                name_span,
                format!("unknown function `{name}`"),
            );
            let callable = builtins::BUILTINS
                .iter()
                .filter(|b| b.is_callable())
                .map(|b| b.name);
            if let Some(s) = suggest::closest(name, callable) {
                d = d.with_help(format!("did you mean `{s}`?"));
            }
            self.error(d);
            for &a in args {
                let _ = self.expr(a);
            }
            return None;
        };
        if !b.is_callable() {
            let d = Diagnostic::error(
                Code::Misuse,
                span,
                format!("`{name}` is a constant, not a function"),
            )
            .with_help(format!("write `{name}` without parentheses"));
            self.error(d);
            return None;
        }
        if let Role::Unsupported(why) = b.role {
            self.error(Diagnostic::error(Code::Unsupported, span, why.to_string()));
            return None;
        }
        if args.len() < b.min_args() || args.len() > b.max_args() {
            self.error(arity_error(b, args.len(), span));
            for &a in args {
                if b.params.first() != Some(&Param::Id) {
                    let _ = self.expr(a);
                }
            }
            return None;
        }
        match b.role {
            Role::Function(func) => {
                let mut vals = Vec::with_capacity(args.len());
                let mut ok = true;
                for (i, &a) in args.iter().enumerate() {
                    match self.scalar(a, || format!("argument {} of {name}", i + 1)) {
                        Some(v) => vals.push(v),
                        None => ok = false,
                    }
                }
                if !ok {
                    return None;
                }
                let problems = validate::constant_arguments(
                    func,
                    |i| vals.get(i).and_then(|&v| self.b.get_const(v)),
                    |i| args.get(i).map_or_else(|| span.clone(), |&a| self.span(a)),
                    &span,
                );
                let failed = has_errors(&problems);
                self.diags.extend(problems);
                if failed {
                    return None;
                }
                Some(Lowered::S(self.b.call(func, vals, span)))
            }
            Role::Mag => match self.expr(args[0])? {
                Lowered::V(v) => {
                    let sq = self.dot(v, v, span.clone());
                    Some(Lowered::S(self.b.sqrt(sq, span)))
                }
                Lowered::S(_) => {
                    let s = self.span(args[0]);
                    self.error(
                        Diagnostic::error(Code::Type, s, "MAG takes a vector")
                            .with_help("use ABS for a scalar"),
                    );
                    None
                }
            },
            Role::Spline(kind) => self.spline(b, kind, args, span),
            Role::Measure(_) => self.measure(b, args, span),
            Role::Constant(_) | Role::Time | Role::Mode | Role::Unsupported(_) => None,
        }
    }

    /// Reads an ID or code argument: an integer literal within range (decision 8).
    fn integer_arg(&mut self, b: &Builtin, index: usize, arg: NodeId) -> Option<i64> {
        let param = b.params.get(index).copied().unwrap_or(Param::Id);
        let (lo, hi, what) = match param {
            Param::Code(lo, hi) => (lo, hi, "an integer code"),
            _ => (0, i64::from(i32::MAX), "an ID (a non-negative integer)"),
        };
        let value = match &self.ast.node(arg).kind {
            // In range first: then the integer test is an exact round trip through i64.
            Kind::Num(v) if *v >= lo as f64 && *v <= hi as f64 && (*v as i64) as f64 == *v => {
                Some(*v as i64)
            }
            _ => None,
        };
        if value.is_none() {
            let span = self.span(arg);
            let range = if hi == i64::MAX {
                format!("at least {lo}")
            } else {
                format!("{lo} to {hi}")
            };
            let d = Diagnostic::error(
                Code::IntegerArgument,
                span,
                format!(
                    "argument {} of {} must be {what}, written as an integer literal ({range})",
                    index + 1,
                    b.name
                ),
            )
            .with_help(format!("signature: {}", b.signature()));
            self.error(d);
        }
        value
    }

    fn spline(
        &mut self,
        b: &Builtin,
        kind: builtins::SplineKind,
        args: &[NodeId],
        span: Span,
    ) -> Option<Lowered> {
        let x = self.scalar(args[0], || "the x argument".into());
        let z = self.scalar(args[1], || "the z argument".into());
        let id = self.integer_arg(b, 2, args[2]);
        let iord = match args.get(3) {
            Some(&a) => self.integer_arg(b, 3, a),
            None => Some(0),
        };
        let (x, z, id, iord) = (x?, z?, id?, iord?);
        let info = self.scope.spline(id);
        let on_curve = self.b.get_const(z) == Some(0.0) && info.is_none_or(|i| !i.surface);
        if iord != 0 && !on_curve {
            let d = Diagnostic::error(
                Code::Domain,
                self.span(args[3]),
                format!("{}: a derivative order (iord) is allowed only when interpolating a curve (z = 0)", b.name),
            );
            self.error(d);
            return None;
        }
        let Some(info) = info else {
            let d = Diagnostic::error(
                Code::UndefinedElement,
                self.span(args[2]),
                format!("SPLINE/{id} is not defined"),
            )
            .with_note(format!(
                "{} interpolates SPLINE data supplied by a model",
                b.name
            ));
            self.error(d);
            return None;
        };
        Some(Lowered::S(
            self.b.spline(kind, x, z, info.index, iord as u8, span),
        ))
    }

    fn measure(&mut self, b: &'static Builtin, args: &[NodeId], span: Span) -> Option<Lowered> {
        // Every argument is checked (and diagnosed) before any failure counts.
        let mut ok = true;
        self.ids.clear();
        for (i, &a) in args.iter().enumerate() {
            match self.integer_arg(b, i, a) {
                Some(id) => self.ids.push(id),
                None => ok = false,
            }
        }
        if !ok {
            return None;
        }
        self.spans.clear();
        self.spans
            .extend(args.iter().map(|&a| self.ast.node(a).span()));
        let call = MeasureCall {
            builtin: b,
            ids: self.ids,
            arg_spans: self.spans,
            span: span.clone(),
        };
        match self.scope.measure(&call) {
            Ok(MeasureValue::Scalar(slot)) => Some(Lowered::S(self.b.measure(slot, span))),
            Ok(MeasureValue::Vector(slots)) => {
                Some(Lowered::V(slots.map(|s| self.b.measure(s, span.clone()))))
            }
            Err(d) => {
                self.error(d);
                None
            }
        }
    }
}

fn arity_error(b: &Builtin, found: usize, span: Span) -> Diagnostic {
    let expected = if b.min_args() == b.max_args() {
        format!("{}", b.min_args())
    } else {
        format!("{} to {}", b.min_args(), b.max_args())
    };
    let plural = if b.max_args() == 1 { "" } else { "s" };
    Diagnostic::error(
        Code::Arity,
        span,
        format!(
            "{} takes {expected} argument{plural}, found {found}",
            b.name
        ),
    )
    .with_help(format!("signature: {}", b.signature()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A scope that compiles an expression of its own while answering, as a host that
    /// defines variables by expressions might.
    struct Reentrant;

    impl Scope for Reentrant {
        fn variable(&self, name: &str) -> Option<u32> {
            let inner = compile("2*PI", &Variables::new(), Expect::Scalar).ok()?;
            (name == "X" && inner.function.outputs.len() == 1).then_some(0)
        }
    }

    #[test]
    fn compile_may_be_called_from_inside_compile() {
        let checked = compile("X + 1", &Reentrant, Expect::Scalar).expect("checks");
        assert_eq!(checked.function.uses.vars, [0]);
        // The thread's session is usable again afterwards.
        assert!(compile("SIN(", &Variables::new(), Expect::Scalar).is_err());
        assert!(compile("COS(0)", &Variables::new(), Expect::Scalar).is_ok());
    }
}
