//! One expression from text to value, the library side of `mbfx eval` and the REPL: check
//! it against the user's variables (and, with a model loaded, against the dataset's
//! markers and elements), compute the measures it reads at the model's assembled
//! configuration, evaluate it with the chosen engine and, when a value is not finite,
//! trace where it came from: a `W0401` warning at the first subexpression that went
//! non-finite, or the `E0402` error of an IF whose test is NaN (decision 2: the expression
//! then has no value). Both engines give the same bits; the trace runs in the interpreter.
//!
//! ```
//! use mbfx::check::Expect;
//! use mbfx::session::evaluate::Evaluator;
//! use mbfx::session::run::Engine;
//!
//! let mut e = Evaluator::new(Engine::Interp);
//! e.set_variable("k", 2.0);
//! e.time = 0.5;
//! let v = e.evaluate("k*STEP(TIME, 0, 0, 1, 1)", Expect::Any).unwrap();
//! assert_eq!(v.values, [1.0]);
//! assert!(v.warnings.is_empty() && v.fault.is_none());
//! ```

use super::loaded::LoadedModel;
use super::run::Engine;
use crate::check::{self, Checked, Expect, Variables};
use crate::context::Context;
use crate::diag::{Code, Diagnostic};
use crate::interp::Program;
use crate::ir::Function;
use crate::jit::{Jit, JitError};
use crate::mbd::MbdError;

/// What expressions are evaluated against, kept from one to the next: user variables,
/// TIME and MODE, the model they may read, the engine, and the JIT (made on first use).
pub struct Evaluator {
    variables: Variables,
    /// The variables' values, in slot order.
    values: Vec<f64>,
    /// The value of TIME.
    pub time: f64,
    /// The value of MODE (4, dynamics, unless set).
    pub mode: f64,
    /// The back end that evaluates.
    pub engine: Engine,
    model: Option<LoadedModel>,
    jit: Option<Jit>,
}

/// The value of an expression and what was found on the way.
#[derive(Debug)]
pub struct Evaluation {
    /// One value for a scalar, three for a vector.
    pub values: Vec<f64>,
    /// The checker's warnings (spans into the text).
    pub warnings: Vec<Diagnostic>,
    /// A `W0401` warning when a value is NaN or infinite, at the first subexpression that
    /// went non-finite.
    pub fault: Option<Diagnostic>,
}

/// Why an expression has no value.
#[derive(Debug)]
pub enum EvalError {
    /// Diagnostics about the text (spans into it): the checker's errors, or its warnings
    /// followed by the `E0402` error of an IF whose test is NaN.
    Diagnostics(Vec<Diagnostic>),
    /// The measures the expression reads cannot be computed from the model.
    Measures {
        /// The checker's warnings.
        warnings: Vec<Diagnostic>,
        /// Why the measures cannot be computed.
        error: MbdError,
    },
    /// The JIT could not compile the expression.
    Jit {
        /// The checker's warnings.
        warnings: Vec<Diagnostic>,
        /// Why the JIT failed.
        error: JitError,
    },
}

impl EvalError {
    /// The diagnostics about the text: errors, or the warnings found before the failure.
    pub fn diagnostics(&self) -> &[Diagnostic] {
        match self {
            EvalError::Diagnostics(d)
            | EvalError::Measures { warnings: d, .. }
            | EvalError::Jit { warnings: d, .. } => d,
        }
    }

    /// The failure that is not about the text, in words, if that is what stopped it.
    pub fn failure(&self) -> Option<String> {
        match self {
            EvalError::Diagnostics(_) => None,
            EvalError::Measures { error, .. } => Some(error.to_string()),
            EvalError::Jit { error, .. } => Some(error.to_string()),
        }
    }
}

impl Evaluator {
    /// No variables, TIME 0, MODE 4, no model.
    pub fn new(engine: Engine) -> Self {
        Evaluator {
            variables: Variables::new(),
            values: Vec::new(),
            time: 0.0,
            mode: 4.0,
            engine,
            model: None,
            jit: None,
        }
    }

    /// The user variables as a scope for the checker.
    pub fn variables(&self) -> &Variables {
        &self.variables
    }

    /// Each user variable's name and value, in the order they were first defined.
    pub fn values(&self) -> impl Iterator<Item = (&str, f64)> {
        let names = self.variables.names().iter().map(String::as_str);
        names.zip(self.values.iter().copied())
    }

    /// Gives variable `name` the value `value`, defining it when it is new (names are
    /// case-insensitive: `x` and `X` are one variable).
    pub fn set_variable(&mut self, name: &str, value: f64) {
        let slot = self.variables.define(name) as usize;
        if slot == self.values.len() {
            self.values.push(value);
        } else {
            self.values[slot] = value;
        }
    }

    /// Gives the variable `name` (defined before) the dimension `dim`: expressions are then
    /// checked for units of measure. False when there is no such variable.
    pub fn set_dim(&mut self, name: &str, dim: crate::check::units::Dim) -> bool {
        self.variables.set_dim(name, dim)
    }

    /// The model expressions may read, if one is loaded.
    pub fn model(&self) -> Option<&LoadedModel> {
        self.model.as_ref()
    }

    /// Loads `model` (or unloads with `None`); returns the one loaded before.
    pub fn set_model(&mut self, model: Option<LoadedModel>) -> Option<LoadedModel> {
        std::mem::replace(&mut self.model, model)
    }

    /// The JIT, made on first use.
    pub fn jit(&mut self) -> Result<&mut Jit, JitError> {
        if self.jit.is_none() {
            self.jit = Some(Jit::new()?);
        }
        self.jit.as_mut().ok_or(JitError::Malformed(0))
    }

    /// Checks and lowers `text` against the variables and the model (whose VARIABLEs are
    /// inlined where the text reads them).
    pub fn compile(&mut self, text: &str, expect: Expect) -> Result<Checked, Vec<Diagnostic>> {
        match self.model.as_mut() {
            Some(m) => m.compile(text, &self.variables, expect),
            None => check::compile(text, &self.variables, expect),
        }
    }

    /// Runs `run` with the evaluation context of `f`: TIME, MODE, the variables, and the
    /// measures `f` reads at the model's assembled configuration with its splines.
    pub fn in_context<R>(
        &mut self,
        f: &Function,
        run: impl FnOnce(&Context) -> R,
    ) -> Result<R, MbdError> {
        let measures = match self.model.as_mut() {
            Some(m) => m.measures_for(f)?,
            None => Vec::new(),
        };
        let splines = self.model.as_ref().map_or(&[][..], |m| m.splines());
        let ctx = Context::new(self.time, &self.values)
            .with_mode(self.mode)
            .with_measures(&measures)
            .with_splines(splines);
        Ok(run(&ctx))
    }

    /// [`Evaluator::evaluate`] of an expression of any kind (scalar or vector).
    pub fn evaluate_any(&mut self, text: &str) -> Result<Evaluation, EvalError> {
        self.evaluate(text, Expect::Any)
    }

    /// Compiles and evaluates `text` with the engine chosen; see the module's summary.
    pub fn evaluate(&mut self, text: &str, expect: Expect) -> Result<Evaluation, EvalError> {
        let checked = self.compile(text, expect).map_err(EvalError::Diagnostics)?;
        let warnings = checked.warnings;
        let code = match self.engine {
            Engine::Jit => match self.jit().and_then(|j| j.compile(&checked.function)) {
                Ok(code) => Some(code),
                Err(error) => return Err(EvalError::Jit { warnings, error }),
            },
            Engine::Interp => None,
        };
        let program = Program::new(checked.function);
        let run = |ctx: &Context| {
            let mut out = vec![0.0; program.function().outputs.len()];
            match &code {
                Some(code) => code.eval_into(ctx, &mut out),
                None => program.eval_into(ctx, &mut out),
            }
            let fault = out
                .iter()
                .any(|v| !v.is_finite())
                .then(|| fault_diagnostic(&program, ctx))
                .flatten();
            (out, fault)
        };
        let (values, fault) = match self.in_context(program.function(), run) {
            Ok(done) => done,
            Err(error) => return Err(EvalError::Measures { warnings, error }),
        };
        match fault {
            Some(d) if d.is_error() => {
                let mut diagnostics = warnings;
                diagnostics.push(d);
                Err(EvalError::Diagnostics(diagnostics))
            }
            fault => Ok(Evaluation {
                values,
                warnings,
                fault,
            }),
        }
    }
}

/// The warning (or, for a NaN IF test, the error) for a non-finite result: where the
/// first non-finite value came from.
fn fault_diagnostic(p: &Program, ctx: &Context) -> Option<Diagnostic> {
    let f = p.first_fault(ctx)?;
    Some(if f.nan_if_test {
        let d = Diagnostic::error(
            Code::NanIfTest,
            f.span,
            "the test of this IF is NaN, so no branch applies",
        )
        .with_note("decision 2: a NaN test selects no branch; the expression has no value");
        match f.cause {
            Some(cause) => d.with_label(cause, "the first non-finite value, before the IF"),
            None => d,
        }
    } else {
        Diagnostic::warning(
            Code::NonFinite,
            f.span,
            format!("this subexpression is {:?}", f.value),
        )
        .with_note("the result follows IEEE arithmetic; a simulation stops at the first such value")
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::session::DimRequest;

    /// A pendulum hinged at the origin whose bob marker 20 starts at (0.6, 0.8, 0).
    const PENDULUM: &str = "pendulum\nPART/1, GROUND\nMARKER/10, PART = 1\n\
        PART/2, MASS = 1, CM = 20\nMARKER/20, PART = 2, QP = 0.6, 0.8, 0\n\
        MARKER/21, PART = 2\nJOINT/1, REVOLUTE, I = 21, J = 10\nEND\n";

    fn with_pendulum(engine: Engine) -> Evaluator {
        let Ok(m) = LoadedModel::load(PENDULUM, DimRequest::Auto) else {
            panic!("the pendulum loads");
        };
        let mut e = Evaluator::new(engine);
        e.set_model(Some(m));
        e
    }

    #[test]
    fn both_engines_give_the_same_bits_with_measures_variables_and_time() {
        // SIN(4*TIME): a number gives TIME its coefficient (SIN of a bare time would be a
        // units warning).
        let text = "k*DX(20, 10) + SIN(4*TIME)/DY(20, 10) + [1, 2, 3]*UVX(20)";
        let mut got = Vec::new();
        for engine in [Engine::Interp, Engine::Jit] {
            let mut e = with_pendulum(engine);
            e.set_variable("k", 3.0);
            e.set_variable("K", 2.0);
            e.time = 0.25;
            let v = e.evaluate(text, Expect::Any).unwrap();
            assert!(v.warnings.is_empty() && v.fault.is_none(), "{v:?}");
            got.push(v.values[0].to_bits());
        }
        assert_eq!(got[0], got[1]);
        // k was redefined (names are case-insensitive): 2·0.6 + sin(1)/0.8 + 1.
        let want = 2.0 * 0.6 + 1.0f64.sin() / 0.8 + 1.0;
        assert!((f64::from_bits(got[0]) - want).abs() < 1e-12);
    }

    #[test]
    fn a_nan_if_test_is_an_error_and_other_non_finite_values_a_warning() {
        for engine in [Engine::Interp, Engine::Jit] {
            let mut e = Evaluator::new(engine);
            e.set_variable("a", f64::NAN);
            let Err(EvalError::Diagnostics(d)) = e.evaluate("IF(a: 1, 2, 3)", Expect::Any) else {
                panic!("a NaN IF test has no value");
            };
            assert_eq!(d.last().map(|d| d.code), Some(Code::NanIfTest), "{d:?}");
            let v = e.evaluate("2 + LOG(0)", Expect::Any).unwrap();
            assert_eq!(v.values, [f64::NEG_INFINITY]);
            let fault = v.fault.expect("a warning for -inf");
            assert_eq!((fault.code, fault.span), (Code::NonFinite, 4..10));
        }
    }

    #[test]
    fn the_kind_asked_for_holds_with_a_model_too() {
        let mut e = with_pendulum(Engine::Interp);
        let Err(EvalError::Diagnostics(d)) = e.evaluate("UVX(20)", Expect::Scalar) else {
            panic!("a vector is not a scalar");
        };
        assert_eq!(d[0].code, Code::Type, "{d:?}");
        assert_eq!(e.evaluate("UVX(20)", Expect::Any).unwrap().values.len(), 3);
    }

    #[test]
    fn the_context_holds_the_measures_a_function_reads() {
        let mut e = with_pendulum(Engine::Interp);
        let c = e.compile("DM(20, 10)", Expect::Any).unwrap();
        let p = Program::new(c.function);
        let v = e.in_context(p.function(), |ctx| p.eval(ctx)).unwrap();
        assert!((v - 1.0).abs() < 1e-12, "{v}");
        assert!(e.set_model(None).is_some());
        let Err(EvalError::Diagnostics(d)) = e.evaluate("DM(20, 10)", Expect::Any) else {
            panic!("no model, no measures");
        };
        assert_eq!(d[0].code, Code::NeedsModel, "{d:?}");
    }
}
