//! One expression over named variables, compiled once and evaluated many times: what the
//! Python module's `mbfx.compile` and the C API's `mbfx_compile` hand out. The variables
//! are named in the order the caller gives them (values are passed in that order), TIME
//! comes with each point, and MODE is 4 (dynamics). No model: an expression that reads a
//! measure is a diagnostic here (a model's expressions go through [`super::loaded`]).
//!
//! ```
//! use mbfx::session::expression::{Column, Expression};
//! use mbfx::session::run::Engine;
//!
//! let e = Expression::compile("k*STEP(x, 0, 0, 1, 1) + TIME", &["x", "k"], Engine::Jit).unwrap();
//! assert_eq!(e.eval(&[0.5, 2.0], 0.25).unwrap(), [2.0 * 0.5 * 0.5 * (3.0 - 2.0 * 0.5) + 0.25]);
//! let g = e.gradient(&["k"]).unwrap(); // the value, then ∂/∂k
//! assert_eq!(g.outputs(), 2);
//! let mut out = vec![0.0; 3];
//! e.eval_columns(&[Column::Values(&[0.0, 0.5, 1.0]), Column::Const(2.0)], Column::Const(0.0), &mut out)
//!     .unwrap();
//! assert_eq!(out, [0.0, 1.0, 2.0]);
//! ```
//!
//! Both engines give the same bits (they run the same IR and runtime). The JIT engine
//! runs a point through machine code and many points ([`Expression::eval_columns`], from
//! 32 on) through the lane evaluator ([`crate::lanes`]: each instruction over a block of
//! points); the interpreter takes every point alone. The JIT also gives a stable C entry
//! ([`crate::jit::entry`]) that foreign code calls directly.

use super::run::Engine;
use crate::check::scope::check_variable_name;
use crate::check::units::Dim;
use crate::check::{self, Expect, Variables};
use crate::context::Context;
use crate::diag::{Code, Diagnostic};
use crate::interp::Program;
use crate::ir::deriv::{gradient, DerivError, Input};
use crate::ir::Function;
use crate::jit::{CompiledExpr, Jit, JitError};
use crate::lanes::Lanes;
use std::cell::RefCell;
use std::fmt;
use std::sync::Arc;

/// Why an expression could not be compiled or evaluated.
#[derive(Clone, Debug)]
pub enum ExprError {
    /// The text has errors (spans into it); warnings found with them come along.
    Diagnostics(Vec<Diagnostic>),
    /// A variable name is not a name, is a builtin, or is given twice.
    BadVariable {
        /// The name as given.
        name: String,
        /// Why it cannot be a variable.
        why: String,
    },
    /// A gradient was asked with respect to something that is neither a variable of
    /// the expression nor TIME.
    UnknownVariable(String),
    /// The expression cannot be differentiated (a library function without a second
    /// derivative, a spline beyond its second).
    Deriv(DerivError),
    /// The JIT could not compile it (never a user error).
    Jit(JitError),
    /// A point was given with the wrong number of values.
    Arity {
        /// How many variables the expression takes.
        expected: usize,
        /// How many values came.
        got: usize,
    },
    /// Columns of different lengths were given, or an output buffer of the wrong size.
    Length {
        /// What has the wrong length.
        what: &'static str,
        /// The length it must have.
        expected: usize,
        /// The length it has.
        got: usize,
    },
}

impl ExprError {
    /// The stable code of the error: the first error diagnostic's for text errors,
    /// else the code this kind of failure is reported under.
    pub fn code(&self) -> Code {
        match self {
            ExprError::Diagnostics(d) => d
                .iter()
                .find(|d| d.is_error())
                .or(d.first())
                .map_or(Code::CommandLine, |d| d.code),
            ExprError::Deriv(_) | ExprError::Jit(_) => Code::Unsupported,
            ExprError::BadVariable { .. }
            | ExprError::UnknownVariable(_)
            | ExprError::Arity { .. }
            | ExprError::Length { .. } => Code::CommandLine,
        }
    }

    /// The diagnostics about the text, if that is what failed.
    pub fn diagnostics(&self) -> &[Diagnostic] {
        match self {
            ExprError::Diagnostics(d) => d,
            _ => &[],
        }
    }
}

impl fmt::Display for ExprError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ExprError::Diagnostics(d) => {
                let mut errors = d.iter().filter(|d| d.is_error()).map(|d| &d.message);
                match errors.next() {
                    Some(m) => write!(f, "{m}"),
                    None => write!(f, "the expression has errors"),
                }
            }
            ExprError::BadVariable { name, why } => write!(f, "variable `{name}`: {why}"),
            ExprError::UnknownVariable(name) => {
                write!(f, "`{name}` is not a variable of the expression (nor TIME)")
            }
            ExprError::Deriv(e) => write!(f, "{e}"),
            ExprError::Jit(e) => write!(f, "{e}"),
            ExprError::Arity { expected, got } => {
                write!(
                    f,
                    "the expression takes {expected} values, {got} were given"
                )
            }
            ExprError::Length {
                what,
                expected,
                got,
            } => write!(f, "{what} has length {got}, expected {expected}"),
        }
    }
}

impl std::error::Error for ExprError {}

pub use crate::lanes::Column;

/// The C entry of an expression's machine code, and its signature in C words.
pub use crate::jit::{EntryFn, ENTRY_SIGNATURE};

/// The dimensions of `units` (name, dimension as text: `"velocity"`, `"m/s"`), read for
/// [`Expression::compile_with_dims`]; the first that does not read, as (name, why).
pub fn dims_of(units: &[(String, String)]) -> Result<Vec<(&str, Dim)>, (String, String)> {
    (units.iter())
        .map(
            |(name, text)| match crate::check::units::parse::parse(text) {
                Ok(d) => Ok((name.as_str(), d)),
                Err(why) => Err((name.clone(), why)),
            },
        )
        .collect()
}

/// The compiled code of one expression.
#[derive(Clone)]
enum Compiled {
    Interp(Box<Program>),
    Jit(CompiledExpr),
}

/// A compiled expression over named variables (see the module docs). Cloning shares the
/// machine code; an expression may move to and be shared by other threads.
#[derive(Clone)]
pub struct Expression {
    text: String,
    variables: Vec<String>,
    engine: Engine,
    function: Function,
    code: Compiled,
    /// The variables (or TIME) the partials are taken in, for a gradient.
    wrt: Vec<String>,
    warnings: Vec<Diagnostic>,
    /// The dimension the caller gave each variable, in slot order (empty when none was
    /// given: the units check then did not run).
    dims: Vec<Option<Dim>>,
    /// The expression's dimension when the units check ran and fixed one.
    dim: Option<Dim>,
    /// The variable slots the code reads (from its instructions): the columns worth
    /// copying when it runs over many points.
    reads: Vec<u32>,
    /// The lane evaluator's form, which the JIT engine runs over many points at once
    /// (None with the interpreter, or when the lane evaluator cannot run the function).
    lanes: Option<Arc<Lanes>>,
}

impl fmt::Debug for Expression {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Expression")
            .field("text", &self.text)
            .field("variables", &self.variables)
            .field("engine", &self.engine)
            .field("wrt", &self.wrt)
            .finish()
    }
}

thread_local! {
    /// One JIT a thread, made on first use (its contexts are reused between compilations).
    static JIT: RefCell<Option<Jit>> = const { RefCell::new(None) };
}

/// Runs `f` with this thread's JIT.
fn with_jit<R>(f: impl FnOnce(&mut Jit) -> Result<R, JitError>) -> Result<R, JitError> {
    JIT.with(|cell| {
        let mut slot = cell
            .try_borrow_mut()
            .map_err(|_| JitError::Module("the JIT is busy on this thread".into()))?;
        if slot.is_none() {
            *slot = Some(Jit::new()?);
        }
        match slot.as_mut() {
            Some(jit) => f(jit),
            None => Err(JitError::Malformed(0)),
        }
    })
}

impl Expression {
    /// Checks `text` with `variables` in scope (in that order; names are
    /// case-insensitive and must be distinct) and compiles it with `engine`.
    pub fn compile(text: &str, variables: &[&str], engine: Engine) -> Result<Self, ExprError> {
        Self::compile_with_dims(text, variables, &[], engine)
    }

    /// [`Expression::compile`], with the dimensions of some variables given as (name,
    /// dimension): the text is then checked for units of measure, and a quantity that
    /// does not fit is a warning (W0312) among [`Expression::warnings`].
    pub fn compile_with_dims(
        text: &str,
        variables: &[&str],
        dims: &[(&str, Dim)],
        engine: Engine,
    ) -> Result<Self, ExprError> {
        let mut scope = Variables::new();
        for (k, &name) in variables.iter().enumerate() {
            if let Err(why) = check_variable_name(name) {
                return Err(ExprError::BadVariable {
                    name: name.to_string(),
                    why: why.message(name),
                });
            }
            if scope.define(name) as usize != k {
                return Err(ExprError::BadVariable {
                    name: name.to_string(),
                    why: "given twice (names are case-insensitive)".into(),
                });
            }
        }
        for &(name, dim) in dims {
            if !scope.set_dim(name, dim) {
                return Err(ExprError::BadVariable {
                    name: name.to_string(),
                    why: "has a dimension but is not one of the variables".into(),
                });
            }
        }
        let checked = check::compile(text, &scope, Expect::Any).map_err(ExprError::Diagnostics)?;
        let names: Vec<String> = variables.iter().map(|v| v.to_string()).collect();
        let mut e = Self::build(
            text.to_string(),
            names,
            engine,
            checked.function,
            Vec::new(),
            checked.warnings,
        )?;
        if !dims.is_empty() {
            e.dims = variables
                .iter()
                .map(|v| scope.dim(&v.to_ascii_uppercase()))
                .collect();
            e.dim = checked.dim;
        }
        Ok(e)
    }

    fn build(
        text: String,
        variables: Vec<String>,
        engine: Engine,
        function: Function,
        wrt: Vec<String>,
        warnings: Vec<Diagnostic>,
    ) -> Result<Self, ExprError> {
        let code = match engine {
            Engine::Interp => Compiled::Interp(Box::new(Program::new(function.clone()))),
            Engine::Jit => {
                let n = variables.len();
                let compiled = with_jit(|jit| match jit.compile_with_entry(&function, n)? {
                    Some(code) => Ok(code),
                    // No model here, so no measure: the checker let none through.
                    None => jit.compile(&function),
                })
                .map_err(ExprError::Jit)?;
                Compiled::Jit(compiled)
            }
        };
        let reads = crate::ir::builder::collect_uses(&function).vars;
        let lanes = match engine {
            Engine::Jit => Lanes::new(&function).map(Arc::new),
            Engine::Interp => None,
        };
        Ok(Expression {
            lanes,
            text,
            variables,
            engine,
            function,
            code,
            wrt,
            warnings,
            dims: Vec::new(),
            dim: None,
            reads,
        })
    }

    /// The dimension given to each variable, in slot order; empty when none was given.
    pub fn dims(&self) -> &[Option<Dim>] {
        &self.dims
    }

    /// The expression's dimension, when variables were given dimensions and the units
    /// check fixed one (`None` when it is free or was not checked).
    pub fn dim(&self) -> Option<Dim> {
        self.dim
    }

    /// [`Expression::dim`] in words: "a velocity (length/time)".
    pub fn dim_name(&self) -> Option<String> {
        self.dim
            .map(|d| crate::check::units::names::describe(d, None))
    }

    /// (name, dimension as text) of each variable given a dimension; the text reads back
    /// to the same dimension with [`dims_of`] (`"1"` for a dimensionless one).
    pub fn unit_texts(&self) -> Vec<(String, String)> {
        let given = self.variables.iter().zip(self.dims());
        given
            .filter_map(|(n, d)| {
                let unit = crate::check::units::names::unit((*d)?, None);
                let unit = if unit.is_empty() { "1".into() } else { unit };
                Some((n.clone(), unit))
            })
            .collect()
    }

    /// The expression's text.
    pub fn text(&self) -> &str {
        &self.text
    }

    /// The variables, in the order values are given.
    pub fn variables(&self) -> &[String] {
        &self.variables
    }

    /// The engine that runs it.
    pub fn engine(&self) -> Engine {
        self.engine
    }

    /// The checker's warnings (spans into the text).
    pub fn warnings(&self) -> &[Diagnostic] {
        &self.warnings
    }

    /// For a gradient, the names its partials are taken in (empty otherwise).
    pub fn wrt(&self) -> &[String] {
        &self.wrt
    }

    /// Values per point: 1 for a scalar, 3 for a vector, and for a gradient those then
    /// each output's partials in `wrt` order.
    pub fn outputs(&self) -> usize {
        self.function.outputs.len()
    }

    /// The typed IR it was compiled from.
    pub fn function(&self) -> &Function {
        &self.function
    }

    /// The value and partials of this expression with respect to `wrt` (variables of
    /// the expression, or `TIME`): a new expression with the same variables and engine
    /// whose outputs are this one's, then each output's partials in `wrt` order.
    pub fn gradient(&self, wrt: &[&str]) -> Result<Expression, ExprError> {
        let mut inputs = Vec::with_capacity(wrt.len());
        for &name in wrt {
            let upper = name.to_ascii_uppercase();
            let input = match self
                .variables
                .iter()
                .position(|v| v.to_ascii_uppercase() == upper)
            {
                Some(k) => Input::Var(k as u32),
                None if upper == "TIME" => Input::Time,
                None => return Err(ExprError::UnknownVariable(name.to_string())),
            };
            inputs.push(input);
        }
        let function = gradient(&self.function, &inputs).map_err(ExprError::Deriv)?;
        Self::build(
            self.text.clone(),
            self.variables.clone(),
            self.engine,
            function,
            wrt.iter().map(|w| w.to_string()).collect(),
            self.warnings.clone(),
        )
        .map(|mut g| {
            // Each partial has a dimension of its own: the gradient as a whole has none.
            g.dims = self.dims.clone();
            g
        })
    }

    /// Every output at one point: `vars` in [`Expression::variables`] order.
    pub fn eval(&self, vars: &[f64], time: f64) -> Result<Vec<f64>, ExprError> {
        let mut out = vec![0.0; self.outputs()];
        self.eval_into(vars, time, &mut out)?;
        Ok(out)
    }

    /// [`Expression::eval`] into `out`, which holds [`Expression::outputs`] values.
    pub fn eval_into(&self, vars: &[f64], time: f64, out: &mut [f64]) -> Result<(), ExprError> {
        if vars.len() != self.variables.len() {
            return Err(ExprError::Arity {
                expected: self.variables.len(),
                got: vars.len(),
            });
        }
        if out.len() != self.outputs() {
            return Err(ExprError::Length {
                what: "the output buffer",
                expected: self.outputs(),
                got: out.len(),
            });
        }
        self.run(&Context::new(time, vars), out);
        Ok(())
    }

    /// The first output at one point (the value of a scalar expression).
    pub fn eval_scalar(&self, vars: &[f64], time: f64) -> Result<f64, ExprError> {
        if vars.len() != self.variables.len() {
            return Err(ExprError::Arity {
                expected: self.variables.len(),
                got: vars.len(),
            });
        }
        let ctx = Context::new(time, vars);
        Ok(match &self.code {
            Compiled::Jit(c) if self.outputs() == 1 => c.eval(&ctx),
            _ => {
                let mut out = vec![0.0; self.outputs()];
                self.run(&ctx, &mut out);
                out[0]
            }
        })
    }

    #[inline(always)]
    fn run(&self, ctx: &Context, out: &mut [f64]) {
        match &self.code {
            Compiled::Interp(p) => p.eval_into(ctx, out),
            Compiled::Jit(c) => c.eval_into(ctx, out),
        }
    }

    /// Evaluates at many points: `columns` holds one column per variable (in order) and
    /// `time` one for TIME; every column of values has the same length n (with none, n
    /// is 1). `out` holds n·[`Expression::outputs`] values, point after point. The JIT
    /// engine runs 32 points or more through the lane evaluator.
    pub fn eval_columns(
        &self,
        columns: &[Column],
        time: Column,
        out: &mut [f64],
    ) -> Result<usize, ExprError> {
        if columns.len() != self.variables.len() {
            return Err(ExprError::Arity {
                expected: self.variables.len(),
                got: columns.len(),
            });
        }
        let mut n = None;
        for c in columns.iter().chain(std::iter::once(&time)) {
            match (n, c.points()) {
                (_, None) => {}
                (None, Some(len)) => n = Some(len),
                (Some(a), Some(b)) if a != b => {
                    return Err(ExprError::Length {
                        what: "a column",
                        expected: a,
                        got: b,
                    })
                }
                _ => {}
            }
        }
        let n = n.unwrap_or(1);
        let k = self.outputs();
        if out.len() != n * k {
            return Err(ExprError::Length {
                what: "the output buffer",
                expected: n * k,
                got: out.len(),
            });
        }
        if let Compiled::Jit(code) = &self.code {
            if let Some(lanes) = self.lanes.as_deref().filter(|_| n >= LANES_FROM) {
                if lanes.eval(columns, time, n, out) {
                    return Ok(n);
                }
            }
            if k == 1 && rows_of_machine_code(code, &self.reads, columns, time, out) {
                return Ok(n);
            }
        }
        let mut vars = vec![0.0; columns.len()];
        for (i, o) in out.chunks_exact_mut(k).enumerate() {
            for (v, c) in vars.iter_mut().zip(columns) {
                *v = c.at(i);
            }
            self.run(&Context::new(time.at(i), &vars), o);
        }
        Ok(n)
    }

    /// The stable C entry of the machine code ([`crate::jit::entry`]: its signature is
    /// [`crate::jit::ENTRY_SIGNATURE`]); None with the interpreter. The pointer is valid
    /// while this expression (or a clone of it) lives.
    pub fn entry(&self) -> Option<EntryFn> {
        match &self.code {
            Compiled::Jit(c) => c.entry(),
            Compiled::Interp(_) => None,
        }
    }
}

/// Fewest points for which [`Expression::eval_columns`] takes the lane evaluator over
/// machine code (below it, filling the block's slots costs more than it saves).
const LANES_FROM: usize = 32;

/// Points a batch of [`rows_of_machine_code`] gathers at once: its rows stay in L1.
const CHUNK: usize = 256;

/// A scalar expression's machine code over columns ([`CompiledExpr::eval_rows`]): one
/// column of values is read where it lies; otherwise the columns the code `reads` are
/// gathered into rows a chunk at a time (the others are never touched: memory traffic
/// is what bounds a cheap expression over a million points). False when the code cannot
/// be called so (the caller takes the general path).
fn rows_of_machine_code(
    code: &CompiledExpr,
    reads: &[u32],
    columns: &[Column],
    time: Column,
    out: &mut [f64],
) -> bool {
    if let [Column::Values(x)] = columns {
        return match time {
            Column::Const(t) => code.eval_rows(x, 1, |_| t, out),
            Column::Values(t) => code.eval_rows(x, 1, |i| t[i], out),
        };
    }
    let width = columns.len();
    let mut rows = vec![0.0; CHUNK * width];
    for (c, chunk) in out.chunks_mut(CHUNK).enumerate() {
        let first = c * CHUNK;
        // Column by column: one match a column, then a plain strided copy.
        for &k in reads {
            let (k, col) = (k as usize, &columns[k as usize]);
            let slots = rows[k..].iter_mut().step_by(width).take(chunk.len());
            match col {
                Column::Const(x) => slots.for_each(|s| *s = *x),
                Column::Values(v) => {
                    for (s, x) in slots.zip(&v[first..first + chunk.len()]) {
                        *s = *x;
                    }
                }
            }
        }
        let fits = match time {
            Column::Const(t) => code.eval_rows(&rows, width, |_| t, chunk),
            Column::Values(t) => {
                let t = &t[first..first + chunk.len()];
                code.eval_rows(&rows, width, |i| t[i], chunk)
            }
        };
        if !fits {
            return false;
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_engines_and_the_entry_give_the_same_bits() {
        let text = "IF(x - 1: SIN(x)*y, 0, EXP(-x)) + TIME**2 + ATAN2(y, x)";
        let points = [(0.5, 2.0, 0.0), (1.0, -3.0, 1.5), (2.5, 0.25, -2.0)];
        let jit = Expression::compile(text, &["x", "y"], Engine::Jit).unwrap();
        let interp = Expression::compile(text, &["x", "y"], Engine::Interp).unwrap();
        assert!(interp.entry().is_none());
        let entry = jit.entry().expect("the JIT gives an entry");
        for (x, y, t) in points {
            let a = jit.eval_scalar(&[x, y], t).unwrap();
            let b = interp.eval_scalar(&[x, y], t).unwrap();
            let args = [x, y, t];
            // SAFETY: three values for two variables and TIME; a scalar writes no output.
            let c = unsafe { entry(3, args.as_ptr(), std::ptr::null_mut()) };
            assert_eq!((a.to_bits(), a.to_bits()), (b.to_bits(), c.to_bits()));
            // The closed form, from the spec's IF and the libm functions.
            let want = if x < 1.0 {
                x.sin() * y
            } else if x == 1.0 {
                0.0
            } else {
                (-x).exp()
            } + t * t
                + y.atan2(x);
            assert!(
                (a - want).abs() <= 1e-15 * want.abs().max(1.0),
                "{a} vs {want}"
            );
        }
    }

    #[test]
    fn the_entry_refuses_short_inputs_and_a_missing_output_buffer() {
        let e = Expression::compile("x + y", &["x", "y"], Engine::Jit).unwrap();
        let entry = e.entry().unwrap();
        let args = [1.0, 2.0];
        // SAFETY: the entry reads nothing when n is below the variable count.
        let short = unsafe { entry(1, args.as_ptr(), std::ptr::null_mut()) };
        assert!(short.is_nan());
        // SAFETY: two variables, no TIME (0).
        let sum = unsafe { entry(2, args.as_ptr(), std::ptr::null_mut()) };
        assert_eq!(sum, 3.0);
        let g = e.gradient(&["x", "y"]).unwrap();
        let entry = g.entry().unwrap();
        // SAFETY: a gradient writes outputs, so a NULL buffer is refused before any read.
        let refused = unsafe { entry(2, args.as_ptr(), std::ptr::null_mut()) };
        assert!(refused.is_nan());
        let mut out = [0.0; 3];
        // SAFETY: three outputs fit in `out`.
        let v = unsafe { entry(2, args.as_ptr(), out.as_mut_ptr()) };
        assert_eq!((v, out), (3.0, [3.0, 1.0, 1.0]));
    }

    #[test]
    fn gradients_take_variables_and_time_by_name() {
        for engine in [Engine::Interp, Engine::Jit] {
            let e = Expression::compile("x**3*SIN(TIME)", &["X"], engine).unwrap();
            let g = e.gradient(&["x", "time"]).unwrap();
            let (x, t) = (2.0f64, 0.5f64);
            let got = g.eval(&[x], t).unwrap();
            let want = [
                x.powi(3) * t.sin(),
                3.0 * x * x * t.sin(),
                x.powi(3) * t.cos(),
            ];
            for (a, b) in got.iter().zip(want) {
                assert!((a - b).abs() < 1e-14, "{got:?} vs {want:?}");
            }
            assert!(matches!(
                e.gradient(&["z"]),
                Err(ExprError::UnknownVariable(_))
            ));
        }
    }

    #[test]
    fn bad_variables_and_inputs_are_errors() {
        let bad = |vars: &[&str]| Expression::compile("1", vars, Engine::Interp).unwrap_err();
        assert!(matches!(bad(&["PI"]), ExprError::BadVariable { .. }));
        assert!(matches!(bad(&["1x"]), ExprError::BadVariable { .. }));
        assert!(matches!(bad(&["x", "X"]), ExprError::BadVariable { .. }));
        let e = Expression::compile("x + ", &["x"], Engine::Jit).unwrap_err();
        assert!(
            !e.diagnostics().is_empty() && e.code() == Code::UnexpectedEnd,
            "{e:?}"
        );
        let e = Expression::compile("x*y", &["x", "y"], Engine::Jit).unwrap();
        assert!(matches!(e.eval(&[1.0], 0.0), Err(ExprError::Arity { .. })));
        let mut out = [0.0; 2];
        let cols = [
            Column::Values(&[1.0, 2.0]),
            Column::Values(&[1.0, 2.0, 3.0]),
        ];
        let r = e.eval_columns(&cols, Column::Const(0.0), &mut out);
        assert!(matches!(r, Err(ExprError::Length { .. })));
    }

    #[test]
    fn machine_code_over_columns_skips_unread_ones_across_chunks() {
        // y is never read; 1000 points span four chunks of rows.
        let e = Expression::compile("x*z - TIME", &["x", "y", "z"], Engine::Jit).unwrap();
        let n = 1000;
        let x: Vec<f64> = (0..n).map(|i| i as f64).collect();
        let z: Vec<f64> = (0..n).map(|i| 0.5 * i as f64 - 3.0).collect();
        let t: Vec<f64> = (0..n).map(|i| 0.25 * i as f64).collect();
        let mut out = vec![0.0; n];
        let cols = [Column::Values(&x), Column::Values(&[]), Column::Values(&z)];
        // A column of the wrong length is refused even when unread.
        assert!(e.eval_columns(&cols, Column::Values(&t), &mut out).is_err());
        let cols = [Column::Values(&x), Column::Const(7.0), Column::Values(&z)];
        e.eval_columns(&cols, Column::Values(&t), &mut out).unwrap();
        for i in 0..n {
            assert_eq!(out[i], x[i] * z[i] - t[i], "point {i}");
        }
        let one = Expression::compile("2*y + TIME", &["y"], Engine::Jit).unwrap();
        let mut out = vec![0.0; n];
        one.eval_columns(&[Column::Values(&z)], Column::Const(1.0), &mut out)
            .unwrap();
        assert!(out.iter().zip(&z).all(|(o, z)| *o == 2.0 * z + 1.0));
    }

    #[test]
    fn columns_broadcast_constants_and_match_single_points() {
        for engine in [Engine::Interp, Engine::Jit] {
            let e = Expression::compile("[x, y, TIME]*[1, 2, 3]", &["x", "y"], engine).unwrap();
            let xs = [0.0, 1.0, -2.5];
            let ts = [0.0, 0.5, 1.0];
            let mut out = [0.0; 3];
            let n = e
                .eval_columns(
                    &[Column::Values(&xs), Column::Const(4.0)],
                    Column::Values(&ts),
                    &mut out,
                )
                .unwrap();
            assert_eq!(n, 3);
            for i in 0..3 {
                let one = e.eval_scalar(&[xs[i], 4.0], ts[i]).unwrap();
                assert_eq!(out[i].to_bits(), one.to_bits());
                assert_eq!(out[i], xs[i] + 8.0 + 3.0 * ts[i]);
            }
        }
    }
}
